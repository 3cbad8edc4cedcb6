// The collision pass's broad phase (kernels/collision.h, collision_grid.h): over seeded random
// vertices, faces and edges moving by anything from a hair to many cells in a substep, the grid
// finds exactly the pairs, in the same order, that a scan of every query against every item finds.
// TEAR_TEST_SEED reruns one failing seed.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <random>
#include <vector>

#include "catch.h"
#include "collision.h"
#include "test_support.h"

namespace {

using tear::index_t;
namespace k = tear::kernels;

/// The cloth's items of one random scene: nodes at the substep's start and end, rest positions,
/// faces and edges (no pinned node, no collider mesh).
struct Scene {
  std::vector<float> x0, x1, rest;
  std::vector<std::uint8_t> pinned;
  std::vector<index_t> faces, edges;
  index_t nodes = 0;
  k::CollisionVertices vertices() const {
    return {x0.data(), x1.data(), rest.data(), pinned.data(), nullptr, nullptr, nodes, nodes};
  }
};

Scene random_scene(std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Scene s;
  s.nodes = 150 + static_cast<index_t>(random() % 150);
  for (index_t n = 0; n < s.nodes; ++n) {
    // Motions of a hair, of about a cell, of several cells, and past 64 cells (under `everywhere`).
    const float reach[4] = {0.001f, 0.05f, 0.2f, 6.0f};
    const float move = reach[random() % 4];
    for (int a = 0; a < 3; ++a) {
      const float x = unit(random) * (a == 1 ? 0.1f : 0.5f);
      s.x0.push_back(x);
      s.x1.push_back(x + move * (unit(random) - 0.5f));
      // Half the nodes rest where they start (neighbours in the fabric), the others anywhere.
      s.rest.push_back(n % 2 ? x : unit(random));
    }
  }
  s.pinned.assign(static_cast<std::size_t>(s.nodes), 0);
  const auto node = [&] { return static_cast<index_t>(random() % static_cast<std::uint64_t>(s.nodes)); };
  for (int f = 0; f < 200; ++f) {
    const index_t a = node(), b = node(), c = node();
    if (a == b || b == c || c == a) continue;
    s.faces.insert(s.faces.end(), {a, b, c});
  }
  for (int e = 0; e < 200; ++e) {
    const index_t a = node(), b = node();
    if (a != b) s.edges.insert(s.edges.end(), {a, b});
  }
  return s;
}

/// The grid's entries of `count` items, as the collision pass enters them (count, scan, write,
/// stable sort by key).
void enter(k::EnterItems e, index_t count, std::vector<std::uint64_t>& keys, std::vector<index_t>& items) {
  std::vector<index_t> offset(static_cast<std::size_t>(count) + 1, 0);
  e.count = offset.data();
  e.offset = nullptr;
  for (index_t i = 0; i < count; ++i) e(i);
  std::exclusive_scan(offset.begin(), offset.end(), offset.begin(), index_t(0));
  keys.assign(static_cast<std::size_t>(offset.back()), 0);
  items.assign(keys.size(), 0);
  e.offset = offset.data();
  e.keys = keys.data();
  e.items = items.data();
  for (index_t i = 0; i < count; ++i) e(i);
  std::vector<std::size_t> order(keys.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
  std::vector<std::uint64_t> sorted_keys;
  std::vector<index_t> sorted_items;
  for (std::size_t i : order) sorted_keys.push_back(keys[i]), sorted_items.push_back(items[i]);
  keys.swap(sorted_keys);
  items.swap(sorted_items);
}

/// Every query's pairs, in order, from `find` (counted, scanned, written).
std::vector<k::CollisionPair> pairs_of(k::find_pairs find, index_t queries) {
  std::vector<index_t> offset(static_cast<std::size_t>(queries) + 1, 0);
  find.count = offset.data();
  find.offset = nullptr;
  for (index_t i = 0; i < queries; ++i) find(i);
  std::exclusive_scan(offset.begin(), offset.end(), offset.begin(), index_t(0));
  std::vector<k::CollisionPair> pairs(static_cast<std::size_t>(offset.back()));
  find.offset = offset.data();
  find.pairs = pairs.data();
  for (index_t i = 0; i < queries; ++i) find(i);
  return pairs;
}

}  // namespace

TEST_CASE("collision grid: a box entered in every cell it meets gives each pair once, as a scan of all does",
          "[collision][property]") {
  const std::uint64_t first = tear::test::test_seed(4400);
  const bool one = std::getenv("TEAR_TEST_SEED") != nullptr;
  std::size_t found = 0, everywhere = 0, spread = 0;
  for (std::uint64_t seed = first; seed < first + (one ? 1 : 40); ++seed) {
    INFO("seed " << seed << " (TEAR_TEST_SEED=" << seed << " reruns it)");
    const Scene s = random_scene(seed);
    const k::CollisionVertices x = s.vertices();
    const index_t face_count = static_cast<index_t>(s.faces.size() / 3);
    const index_t edge_count = static_cast<index_t>(s.edges.size() / 2);
    const k::CollisionFaces faces{s.faces.data(), nullptr, face_count, face_count, s.nodes};
    const k::CollisionEdges edges{s.edges.data(), nullptr, edge_count, edge_count, s.nodes};
    const float thickness = 0.01f;
    k::CollisionGrid grid{};
    grid.inv_cell = 1.0f / 0.04f;
    const float half = 0.5f * static_cast<float>(k::CollisionGrid::side) * 0.04f;
    grid.origin = {0.25f - half, 0.05f - half, 0.25f - half};
    k::EnterItems e{x, edges, grid, thickness, false, nullptr, nullptr, nullptr, nullptr};
    std::vector<std::uint64_t> vertex_keys, edge_keys;
    std::vector<index_t> vertex_items, edge_items;
    enter(e, s.nodes, vertex_keys, vertex_items);
    e.of_edges = true;
    enter(e, edge_count, edge_keys, edge_items);
    everywhere += static_cast<std::size_t>(std::count(vertex_keys.begin(), vertex_keys.end(), k::CollisionGrid::everywhere));
    spread += vertex_keys.size() + edge_keys.size() - static_cast<std::size_t>(s.nodes + edge_count);
    const index_t queries = face_count + edge_count;
    k::find_pairs find{x,
                       faces,
                       edges,
                       grid,
                       {vertex_keys.data(), vertex_items.data(), static_cast<index_t>(vertex_keys.size())},
                       {edge_keys.data(), edge_items.data(), static_cast<index_t>(edge_keys.size())},
                       thickness,
                       0.01f * thickness,
                       true,
                       nullptr,
                       nullptr,
                       nullptr};
    const std::vector<k::CollisionPair> by_grid = pairs_of(find, queries);
    // The scan: every item once, under `everywhere`, which every query reads whole.
    std::vector<std::uint64_t> all_vertices(static_cast<std::size_t>(s.nodes), k::CollisionGrid::everywhere),
        all_edges(static_cast<std::size_t>(edge_count), k::CollisionGrid::everywhere);
    std::vector<index_t> vertex_ids(all_vertices.size()), edge_ids(all_edges.size());
    std::iota(vertex_ids.begin(), vertex_ids.end(), index_t(0));
    std::iota(edge_ids.begin(), edge_ids.end(), index_t(0));
    find.vertex_entries = {all_vertices.data(), vertex_ids.data(), s.nodes};
    find.edge_entries = {all_edges.data(), edge_ids.data(), edge_count};
    const std::vector<k::CollisionPair> by_scan = pairs_of(find, queries);
    REQUIRE(by_grid.size() == by_scan.size());
    const auto same = [](const k::CollisionPair& a, const k::CollisionPair& b) {
      return std::equal(a.v, a.v + 4, b.v) && a.edge_edge == b.edge_edge && a.thickness == b.thickness;
    };
    const auto differ = std::mismatch(by_grid.begin(), by_grid.end(), by_scan.begin(), same).first;
    INFO("first pair that differs: " << (differ - by_grid.begin()) << " of " << by_grid.size());
    CHECK(differ == by_grid.end());
    found += by_grid.size();
  }
  // The scenes reached every path: pairs, boxes entered in several cells, and under `everywhere`.
  CHECK(found > 1000);
  CHECK(spread > 1000);
  CHECK(everywhere > 10);
}
