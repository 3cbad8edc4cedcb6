#include <cmath>
#include <random>
#include <vector>

#include "catch.h"
#include "tear/triangulate_polygon.h"
#include "test_support.h"

namespace {

/// Twice the signed area in the xy plane of the polygon or triangle through `corners`.
double signed_area(const std::vector<float>& pos, const std::vector<tear::index_t>& corners) {
  double area = 0.0;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const float* a = &pos[3 * corners[k]];
    const float* b = &pos[3 * corners[(k + 1) % corners.size()]];
    area += static_cast<double>(a[0]) * b[1] - static_cast<double>(b[0]) * a[1];
  }
  return area;
}

/// Checks the triangles of a simple polygon in the xy plane: n - 2 of them, each corner used in
/// range, each counter-clockwise like the polygon, and together exactly its area.
void check_tiles(const std::vector<float>& pos, const std::vector<tear::index_t>& triangles) {
  const auto n = static_cast<tear::index_t>(pos.size() / 3);
  REQUIRE(triangles.size() == 3 * static_cast<std::size_t>(n - 2));
  std::vector<tear::index_t> outline(n);
  for (tear::index_t k = 0; k < n; ++k) outline[k] = k;
  double total = 0.0;
  for (std::size_t t = 0; t < triangles.size(); t += 3) {
    for (int k = 0; k < 3; ++k) REQUIRE((triangles[t + k] >= 0 && triangles[t + k] < n));
    const double area = signed_area(pos, {triangles[t], triangles[t + 1], triangles[t + 2]});
    INFO("triangle " << t / 3);
    CHECK(area > 0.0);
    total += area;
  }
  CHECK(total == Approx(signed_area(pos, outline)));
}

}  // namespace

TEST_CASE("triangulate_polygon: a triangle stays, a convex polygon becomes a fan from corner 0", "[io]") {
  const std::vector<float> triangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  CHECK(tear::triangulate_polygon(triangle.data(), 3) == std::vector<tear::index_t>{0, 1, 2});
  const std::vector<float> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  CHECK(tear::triangulate_polygon(quad.data(), 4) == std::vector<tear::index_t>{0, 1, 2, 0, 2, 3});
  // A hexagon, tilted out of every coordinate plane: still a fan.
  std::vector<float> hexagon;
  for (int k = 0; k < 6; ++k) {
    const float a = static_cast<float>(k) * 3.14159265f / 3.0f;
    hexagon.insert(hexagon.end(), {std::cos(a), std::sin(a) * 0.8f, std::sin(a) * 0.6f});
  }
  CHECK(tear::triangulate_polygon(hexagon.data(), 6) == std::vector<tear::index_t>{0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5});
  CHECK(tear::triangulate_polygon(quad.data(), 2).empty());
}

TEST_CASE("triangulate_polygon: the header's L-shaped hexagon is clipped ear by ear", "[io]") {
  const std::vector<float> l_shape = {0, 0, 0, 2, 0, 0, 2, 1, 0, 1, 1, 0, 1, 2, 0, 0, 2, 0};
  const std::vector<tear::index_t> triangles = tear::triangulate_polygon(l_shape.data(), 6);
  CHECK(triangles == std::vector<tear::index_t>{0, 1, 2, 0, 2, 3, 5, 0, 3, 3, 4, 5});
  check_tiles(l_shape, triangles);
}

TEST_CASE("triangulate_polygon: concave polygons of either orientation and plane tile exactly", "[io]") {
  const auto seed = tear::test::test_seed(4242);
  INFO("seed " << seed);
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::uniform_real_distribution<float> radius(0.3f, 1.0f);
  for (int round = 0; round < 200; ++round) {
    // A star-shaped polygon (simple, usually concave) around the origin.
    const int n = 4 + static_cast<int>(rng() % 20);
    std::vector<float> pos;
    for (int k = 0; k < n; ++k) {
      const float a = 2.0f * 3.14159265f * static_cast<float>(k) / static_cast<float>(n);
      const float r = radius(rng);
      pos.insert(pos.end(), {r * std::cos(a), r * std::sin(a), 0.0f});
    }
    INFO("round " << round << ", " << n << " corners");
    check_tiles(pos, tear::triangulate_polygon(pos.data(), n));

    // The same outline clockwise: triangles come out clockwise too (they keep its orientation).
    std::vector<float> reversed;
    for (int k = n - 1; k >= 0; --k) reversed.insert(reversed.end(), pos.begin() + 3 * k, pos.begin() + 3 * k + 3);
    const std::vector<tear::index_t> back = tear::triangulate_polygon(reversed.data(), n);
    REQUIRE(back.size() == 3 * static_cast<std::size_t>(n - 2));
    for (std::size_t t = 0; t < back.size(); t += 3)
      CHECK(signed_area(reversed, {back[t], back[t + 1], back[t + 2]}) < 0.0);

    // In the yz plane: the projection follows the normal.
    std::vector<float> turned;
    for (int k = 0; k < n; ++k) turned.insert(turned.end(), {0.0f, pos[3 * k], pos[3 * k + 1]});
    std::vector<float> flat;
    for (int k = 0; k < n; ++k) flat.insert(flat.end(), {turned[3 * k + 1], turned[3 * k + 2], 0.0f});
    check_tiles(flat, tear::triangulate_polygon(turned.data(), n));
  }
}

TEST_CASE("triangulate_polygon: degenerate and self-intersecting outlines still give n - 2 triangles", "[io]") {
  const std::vector<float> collinear = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0, 4, 0, 0};
  CHECK(tear::triangulate_polygon(collinear.data(), 5).size() == 9);
  const std::vector<float> bow_tie = {0, 0, 0, 1, 1, 0, 1, 0, 0, 0, 1, 0, 0.5f, 2, 0};
  CHECK(tear::triangulate_polygon(bow_tie.data(), 5).size() == 9);
  const float nan = std::nanf("");
  const std::vector<float> broken = {0, 0, 0, nan, 0, 0, 1, 1, 0, 0, 1, 0};
  CHECK(tear::triangulate_polygon(broken.data(), 4) == std::vector<tear::index_t>{0, 1, 2, 0, 2, 3});
}
