#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "catch.h"
#include "tear/error.h"
#include "tear/read_mesh.h"
#include "test_support.h"

namespace {

/// Two triangles sharing the edge (1,0,0)-(0,1,0), stored with the shared nodes duplicated and
/// the second copy moved by `offset` along x.
tear::Mesh split_quad(float offset) {
  tear::Mesh mesh;
  mesh.node_pos = {0,          0, 0, 1, 0, 0, 0,          1, 0,   // face 0
                   1 + offset, 0, 0, 1, 1, 0, 0 + offset, 1, 0};  // face 1
  mesh.face_nodes = {0, 1, 2, 3, 4, 5};
  return mesh;
}

/// A grid of `nx` by `ny` quads (two triangles each), nodes shared, jittered positions.
tear::Mesh grid(int nx, int ny, std::mt19937& rng) {
  std::uniform_real_distribution<float> jitter(-0.01f, 0.01f);
  tear::Mesh mesh;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      mesh.node_pos.insert(mesh.node_pos.end(), {0.1f * i + jitter(rng), 0.1f * j + jitter(rng), jitter(rng)});
    }
  }
  auto node = [&](int i, int j) { return static_cast<tear::index_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      mesh.face_nodes.insert(mesh.face_nodes.end(), {node(i, j), node(i + 1, j), node(i + 1, j + 1)});
      mesh.face_nodes.insert(mesh.face_nodes.end(), {node(i, j), node(i + 1, j + 1), node(i, j + 1)});
    }
  }
  return mesh;
}

std::vector<float> corner_positions(const tear::Mesh& mesh) {
  std::vector<float> out;
  for (tear::index_t node : mesh.face_nodes) {
    out.insert(out.end(), mesh.node_pos.begin() + 3 * node, mesh.node_pos.begin() + 3 * node + 3);
  }
  return out;
}

}  // namespace

TEST_CASE("weld_nodes: identical positions weld, the lowest index is kept", "[weld]") {
  tear::Mesh mesh = split_quad(0.0f);
  mesh.corner_uv = {0, 0, 1, 0, 0, 1, 0.5f, 0, 1, 1, 0, 1};
  tear::weld_nodes(mesh, 0.0);
  CHECK(mesh.node_count() == 4);
  CHECK(mesh.face_nodes == std::vector<tear::index_t>{0, 1, 2, 1, 3, 2});
  CHECK(mesh.node_pos == std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  // Corner attributes stay per corner: the seam in UV survives.
  CHECK(mesh.corner_uv == std::vector<float>{0, 0, 1, 0, 0, 1, 0.5f, 0, 1, 1, 0, 1});
}

TEST_CASE("weld_nodes: nodes 1e-7 apart weld with tolerance 1e-6 and not with 0", "[weld]") {
  tear::Mesh exact = split_quad(1e-7f);
  REQUIRE(exact.node_pos[9] != exact.node_pos[3]);
  tear::weld_nodes(exact, 0.0);
  CHECK(exact.node_count() == 6);

  tear::Mesh close = split_quad(1e-7f);
  tear::weld_nodes(close, 1e-6);
  CHECK(close.node_count() == 4);
  CHECK(close.face_nodes == std::vector<tear::index_t>{0, 1, 2, 1, 3, 2});
  // The group takes its lowest-index node's position.
  CHECK(close.node_pos[3] == 1.0f);

  tear::Mesh far = split_quad(1e-5f);
  tear::weld_nodes(far, 1e-6);
  CHECK(far.node_count() == 6);
}

TEST_CASE("weld_nodes: tolerance links chains of close nodes into one group", "[weld]") {
  // a-b and b-c are within tolerance, a-c is not: the documented rule welds all three.
  tear::Mesh mesh;
  mesh.node_pos = {0, 0, 0, 5, 0, 0, 0, 5, 0, 0.6f, 0, 0, 1.2f, 0, 0};
  mesh.face_nodes = {0, 1, 2, 3, 1, 2, 4, 1, 2};
  tear::weld_nodes(mesh, 0.7);
  CHECK(mesh.node_count() == 3);
  CHECK(mesh.node_pos == std::vector<float>{0, 0, 0, 5, 0, 0, 0, 5, 0});
  CHECK(mesh.face_nodes == std::vector<tear::index_t>{0, 1, 2, 0, 1, 2, 0, 1, 2});
}

TEST_CASE("weld_nodes: unused nodes and collapsed faces are dropped", "[weld]") {
  tear::Mesh mesh;
  mesh.node_pos = {9, 9, 9, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0};
  mesh.face_nodes = {1, 2, 3, 2, 4, 3};  // the second face collapses: nodes 2 and 4 coincide
  mesh.corner_normal = {0, 0, 1, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 1, 0, 0};
  tear::weld_nodes(mesh, 0.0);
  CHECK(mesh.node_count() == 3);
  CHECK(mesh.face_nodes == std::vector<tear::index_t>{0, 1, 2});
  CHECK(mesh.node_pos == std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  CHECK(mesh.corner_normal == std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1});
}

TEST_CASE("weld_nodes: non-finite coordinates weld with nothing", "[weld]") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (double tolerance : {0.0, 1e-3}) {
    INFO("tolerance " << tolerance);
    tear::Mesh mesh;
    mesh.node_pos = {nan, 0, 0, 1, 0, 0, 0, 1, 0, nan, 0, 0, inf, 0, 0, inf, 0, 0};
    mesh.face_nodes = {0, 1, 2, 3, 1, 2, 4, 1, 2, 5, 1, 2};
    tear::weld_nodes(mesh, tolerance);
    CHECK(mesh.node_count() == 6);
    CHECK(mesh.face_count() == 4);
  }
}

TEST_CASE("weld_nodes: rejects a negative tolerance and out-of-range nodes", "[weld]") {
  tear::Mesh mesh = split_quad(0.0f);
  try {
    tear::weld_nodes(mesh, -1.0);
    FAIL("no error");
  } catch (const tear::Error& e) {
    CHECK(e.kind() == tear::ErrorKind::usage);
  }
  mesh.face_nodes[4] = 17;
  CHECK_THROWS_AS(tear::weld_nodes(mesh, 0.0), tear::Error);
}

TEST_CASE("weld_nodes: a mesh split per corner and shuffled welds back to the same topology", "[weld]") {
  const auto seed = tear::test::test_seed(20240611);
  INFO("seed " << seed);
  std::mt19937 rng(static_cast<unsigned>(seed));
  for (int round = 0; round < 20; ++round) {
    const tear::Mesh original = grid(1 + static_cast<int>(rng() % 9), 1 + static_cast<int>(rng() % 9), rng);
    // One node per corner, numbered in a random order.
    std::vector<tear::index_t> corner_order(original.face_nodes.size());
    std::iota(corner_order.begin(), corner_order.end(), 0);
    std::shuffle(corner_order.begin(), corner_order.end(), rng);
    tear::Mesh split;
    split.node_pos.resize(3 * corner_order.size());
    split.face_nodes.resize(corner_order.size());
    for (std::size_t n = 0; n < corner_order.size(); ++n) {
      const tear::index_t corner = corner_order[n];
      const tear::index_t node = original.face_nodes[corner];
      std::copy_n(original.node_pos.begin() + 3 * node, 3, split.node_pos.begin() + 3 * n);
      split.face_nodes[corner] = static_cast<tear::index_t>(n);
    }
    for (double tolerance : {0.0, 1e-6}) {
      tear::Mesh welded = split;
      tear::weld_nodes(welded, tolerance);
      CHECK(welded.node_count() == original.node_count());
      CHECK(welded.face_count() == original.face_count());
      CHECK(corner_positions(welded) == corner_positions(original));
      // Same connectivity: corners sharing a node in the original share one after welding, and only those.
      std::vector<tear::index_t> to_welded(original.node_count(), tear::none);
      bool consistent = true;
      for (std::size_t c = 0; c < original.face_nodes.size(); ++c) {
        tear::index_t& mapped = to_welded[original.face_nodes[c]];
        if (mapped == tear::none) mapped = welded.face_nodes[c];
        consistent = consistent && mapped == welded.face_nodes[c];
      }
      std::sort(to_welded.begin(), to_welded.end());
      CHECK(consistent);
      CHECK(std::adjacent_find(to_welded.begin(), to_welded.end()) == to_welded.end());
      // Deterministic: welding again gives the same arrays.
      tear::Mesh again = split;
      tear::weld_nodes(again, tolerance);
      CHECK(again.node_pos == welded.node_pos);
      CHECK(again.face_nodes == welded.face_nodes);
    }
  }
}

TEST_CASE("weld_nodes_by_id: same id one node, nodes in ascending id, whatever the positions", "[weld]") {
  tear::Mesh mesh = split_quad(0.25f);  // the copies of the shared edge are 0.25 apart
  mesh.node_vel = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0, 4, 0, 0, 5, 0, 0};
  mesh.node_origin_face = {0, 0, 0, 1, 1, 1};
  mesh.node_origin_bary = {0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0};
  // Vertices 1 and 3 are one node (id 1), 2 and 5 another (id 0); id 7 is a gap.
  tear::weld_nodes_by_id(mesh, {3, 1, 0, 1, 7, 0});
  CHECK(mesh.node_count() == 4);
  CHECK(mesh.face_nodes == std::vector<tear::index_t>{2, 1, 0, 1, 3, 0});
  // Each node takes its lowest-index vertex's values.
  CHECK(mesh.node_pos == std::vector<float>{0, 1, 0, 1, 0, 0, 0, 0, 0, 1, 1, 0});
  CHECK(mesh.node_vel == std::vector<float>{2, 0, 0, 1, 0, 0, 0, 0, 0, 4, 0, 0});
  CHECK(mesh.node_origin_face == std::vector<tear::index_t>{0, 0, 0, 1});
  CHECK(mesh.node_origin_bary == std::vector<float>{0, 1, 1, 0, 0, 0, 0, 1});

  tear::Mesh bad = split_quad(0.0f);
  CHECK_THROWS_AS(tear::weld_nodes_by_id(bad, {0, 1, 2}), tear::Error);
  CHECK_THROWS_AS(tear::weld_nodes_by_id(bad, {0, 1, 2, 3, -1, 5}), tear::Error);
}

TEST_CASE("weld_nodes: torn edges follow their nodes and stay only on the boundary", "[weld]") {
  // Torn along the shared edge: both copies of it are boundary edges marked torn.
  tear::Mesh mesh = split_quad(0.0f);
  mesh.torn_edge_nodes = {1, 2, 3, 5};
  tear::Mesh kept = mesh;
  tear::drop_unused_nodes(kept);
  CHECK(kept.torn_edge_nodes == std::vector<tear::index_t>{1, 2, 3, 5});
  // Welding by position closes the tear: the edge is inside again and is no longer torn.
  tear::weld_nodes(mesh, 0.0);
  CHECK(mesh.node_count() == 4);
  CHECK(mesh.torn_edge_nodes.empty());
}

TEST_CASE("drop_unused_nodes: welds nothing, keeps order, drops what no face uses", "[weld]") {
  tear::Mesh mesh;
  mesh.node_pos = {9, 9, 9, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0};
  mesh.face_nodes = {1, 2, 3, 4, 2, 3, 1, 1, 2};  // the last face repeats a node
  mesh.node_vel = {9, 9, 9, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4};
  tear::drop_unused_nodes(mesh);
  CHECK(mesh.node_pos == std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0});
  CHECK(mesh.face_nodes == std::vector<tear::index_t>{0, 1, 2, 3, 1, 2});
  CHECK(mesh.node_vel == std::vector<float>{1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4});
}

TEST_CASE("weld_nodes: the report counts faces lost to corners joined, not vertices the file split", "[weld]") {
  // A split quad welds at its seam: nothing the file kept apart is joined.
  tear::Mesh seam = split_quad(0.0f);
  tear::WeldReport report;
  tear::weld_nodes(seam, 0.0, &report);
  CHECK(seam.face_count() == 2);
  CHECK_FALSE(report.any());
  CHECK(report.largest_coordinate == 1.0);

  // A grid 1e7 m from the origin with 0.1 m between nodes: float32 has steps of 1 there, so its
  // columns read as two positions, and only the faces across the step keep three nodes.
  std::mt19937 rng(3);
  tear::Mesh far = grid(10, 10, rng);
  for (std::size_t n = 0; n < far.node_pos.size(); n += 3) {
    const double x = 1e7 + 0.1 * static_cast<double>((n / 3) % 11);
    far.node_pos[n] = static_cast<float>(x);
    far.node_pos[n + 1] = static_cast<float>(0.1 * static_cast<double>((n / 3) / 11));
    far.node_pos[n + 2] = 0;
  }
  report = tear::WeldReport{};
  tear::weld_nodes(far, 0.0, &report);
  CHECK(far.face_count() == 20);
  CHECK(report.collapsed_faces == 180);
  CHECK(report.joined_nodes == 99);  // 121 nodes become 22
  CHECK(report.largest_coordinate == 1e7 + 1);
  CHECK(report.describe() ==
        "180 faces lost in reading: welding joined corners of theirs, different vertices in the file, into one node (99 "
        "nodes lost so); coordinates reach 1e+07, where float32 has steps of 1");

  // A tolerance longer than an edge joins the corners of a face too; a face the file itself made
  // with a repeated vertex is dropped without being counted.
  tear::Mesh close = split_quad(0.0f);
  close.node_pos[3] = 0.001f;  // node 1 near node 0
  close.face_nodes.insert(close.face_nodes.end(), {4, 4, 5});
  report = tear::WeldReport{};
  tear::weld_nodes(close, 0.01, &report);
  CHECK(report.collapsed_faces == 1);
  CHECK(report.joined_nodes == 1);

  // Ids: two corners of one face that carry one id.
  tear::Mesh ids = split_quad(0.5f);
  report = tear::WeldReport{};
  tear::weld_nodes_by_id(ids, {0, 1, 2, 1, 3, 3}, &report);
  CHECK(ids.face_count() == 1);
  CHECK(report.collapsed_faces == 1);
  CHECK(report.joined_nodes == 1);
}
