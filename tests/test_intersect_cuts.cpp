// The intersection's broad phase: a bounded path whose box misses a face skips the face in one
// test instead of one per segment. Over seeded random sheets and paths (through nodes, a hair off
// them, closed, unbounded, in the rest plane and in UV space), the crossings with that test and
// without it are the same bits. TEAR_TEST_SEED reruns one failing seed.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "../kernels/intersect_cuts.h"
#include "catch.h"
#include "random_meshes.h"
#include "test_support.h"

using namespace tear;
using tear::test::Random;

namespace {

struct Crossings {
  std::vector<double> half_hit_sum;
  std::vector<index_t> half_hit_count;
  std::vector<std::uint16_t> face_pairs;
};

struct Paths {
  std::vector<kernels::CutPath> cuts;
  std::vector<double> x, y;
};

/// One random path: 2 to 12 points, each a node's 2D place (sometimes a hair off it) or a random
/// point around the sheet; a closed loop or an unbounded end now and then.
void add_random_path(Random& random, const Mesh& mesh, bool uv, Paths& paths) {
  kernels::CutPath p{};
  p.source = uv ? kernels::CutSource::corner_uv : kernels::CutSource::node_rest;
  p.axis_u[0] = 1;
  p.axis_v[1] = 1;
  p.point_begin = static_cast<index_t>(paths.x.size());
  const index_t count = 2 + random.below(11);
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (index_t n = 0; n < mesh.node_count(); ++n)
    for (int a = 0; a < 2; ++a) {
      lo[a] = std::min(lo[a], double(mesh.node_pos[3 * n + a]));
      hi[a] = std::max(hi[a], double(mesh.node_pos[3 * n + a]));
    }
  const index_t faces = static_cast<index_t>(mesh.face_count());
  for (index_t i = 0; i < count; ++i) {
    double q[2];
    if (random.chance(0.6)) {  // at a corner of a random face, in the path's own coordinates
      const index_t corner = 3 * random.below(faces) + random.below(3);
      const index_t node = mesh.face_nodes[corner];
      for (int a = 0; a < 2; ++a)
        q[a] = uv ? double(mesh.corner_uv[2 * corner + a]) : double(mesh.node_pos[3 * node + a]);
      const double span = uv ? 1.0 : hi[0] - lo[0];  // UVs span [0, 1]
      if (random.chance(0.5))  // a hair off it: inside or outside the crossing tolerances
        for (double& v : q) v += (random.chance(0.5) ? 1 : -1) * random.uniform(0.0, 4e-6) * span;
    } else {
      for (int a = 0; a < 2; ++a) {  // UVs span [0, 1]
        const double l = uv ? 0.0 : lo[a], h = uv ? 1.0 : hi[a];
        q[a] = random.uniform(l - 0.2 * (h - l), h + 0.2 * (h - l));
      }
    }
    paths.x.push_back(q[0]);
    paths.y.push_back(q[1]);
  }
  if (count > 2 && random.chance(0.2)) {  // closed: its last point is its first
    paths.x.back() = paths.x[p.point_begin];
    paths.y.back() = paths.y[p.point_begin];
  }
  p.point_count = count;
  p.unbounded = random.chance(0.2) ? 1 + random.below(3) : 0;
  kernels::set_path_box(p, paths.x.data(), paths.y.data());
  paths.cuts.push_back(p);
}

/// The crossings of `paths`; with `without_path_box`, every path's box grown to the whole plane, so
/// that every face goes through every segment's own box.
Crossings intersect(const Mesh& mesh, Paths paths, bool without_path_box) {
  if (without_path_box)
    for (kernels::CutPath& cut : paths.cuts)
      for (int a = 0; a < 2; ++a) {
        cut.box_lo[a] = -std::numeric_limits<double>::infinity();
        cut.box_hi[a] = std::numeric_limits<double>::infinity();
      }
  const std::size_t faces = mesh.face_count();
  Crossings c;
  c.half_hit_sum.assign(3 * faces, -1);
  c.half_hit_count.assign(3 * faces, -1);
  c.face_pairs.assign(faces, 0xffff);
  kernels::intersect_cuts op{mesh.face_nodes.data(),
                             mesh.corner_uv.empty() ? nullptr : mesh.corner_uv.data(),
                             mesh.node_pos.data(),
                             mesh.node_pos.data(),
                             paths.cuts.data(),
                             static_cast<index_t>(paths.cuts.size()),
                             paths.x.data(),
                             paths.y.data(),
                             c.half_hit_sum.data(),
                             c.half_hit_count.data(),
                             c.face_pairs.data()};
  for (std::size_t f = 0; f < faces; ++f) op(static_cast<index_t>(f));
  return c;
}

}  // namespace

TEST_CASE("intersect_cuts: a path's box skips the faces its segments' boxes would, crossings unchanged",
          "[remesh][property]") {
  const std::uint64_t first = tear::test::test_seed(9100);
  const bool one = std::getenv("TEAR_TEST_SEED") != nullptr;
  std::size_t skipped = 0, crossed = 0, faces = 0;  // skipped: (face, path) pairs
  for (std::uint64_t seed = first; seed < first + (one ? 1 : 150); ++seed) {
    INFO("seed " << seed << " (TEAR_TEST_SEED=" << seed << " reruns it)");
    Random random(seed);
    const Mesh mesh = tear::test::random_sheet(seed, 300);
    REQUIRE(!mesh.corner_uv.empty());
    Paths paths;
    const index_t path_count = 1 + random.below(4);
    for (index_t i = 0; i < path_count; ++i) add_random_path(random, mesh, random.chance(0.3), paths);
    const Crossings with_box = intersect(mesh, paths, false);
    const Crossings without = intersect(mesh, paths, true);
    CHECK(std::memcmp(with_box.half_hit_sum.data(), without.half_hit_sum.data(),
                      sizeof(double) * with_box.half_hit_sum.size()) == 0);
    CHECK(with_box.half_hit_count == without.half_hit_count);
    CHECK(with_box.face_pairs == without.face_pairs);
    // What the comparison covered: faces a path's box let skip, and faces crossed.
    for (index_t f = 0; f < mesh.face_count(); ++f) {
      ++faces;
      crossed += without.face_pairs[f] != 0 || without.half_hit_count[3 * f] + without.half_hit_count[3 * f + 1] +
                                                       without.half_hit_count[3 * f + 2] >
                                                   0;
      for (const kernels::CutPath& cut : paths.cuts) {
        kernels::Vec2 c[3];
        for (int k = 0; k < 3; ++k)
          c[k] = kernels::project_corner(cut, 3 * f + k, mesh.face_nodes[3 * f + k],
                                         mesh.corner_uv.data(), mesh.node_pos.data(), mesh.node_pos.data());
        const double lo_x = std::min({c[0].x, c[1].x, c[2].x}), hi_x = std::max({c[0].x, c[1].x, c[2].x});
        const double lo_y = std::min({c[0].y, c[1].y, c[2].y}), hi_y = std::max({c[0].y, c[1].y, c[2].y});
        skipped += kernels::path_box_misses(cut, lo_x, hi_x, lo_y, hi_y, 0.0);
      }
    }
  }
  INFO("faces " << faces << ", crossed " << crossed << ", (face, path) pairs a path's box skips " << skipped);
  CHECK(crossed > faces / 20);
  CHECK(skipped > faces / 4);
}
