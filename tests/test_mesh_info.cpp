// compute_mesh_info on tiny literal meshes with known counts, and on random grids with holes
// against an independent brute-force count.
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "tear/mesh_info.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"
#include "test_support.h"

namespace {

using tear::index_t;
using tear::Mesh;
using tear::MeshInfo;

MeshInfo info_of(const Mesh& mesh) {
  const tear::Device device = tear::test::test_device();
  const tear::Topology topology = tear::build_topology(mesh, device);
  return tear::compute_mesh_info(mesh, topology, tear::validate_mesh(mesh, topology, device));
}

/// A W x H grid of unit quads in the z = 0 plane, two counter-clockwise triangles per quad; node
/// (i, j) is j * (W + 1) + i. `keep(i, j)` says which quads stay.
template <class Keep>
Mesh grid(int width, int height, Keep keep) {
  Mesh mesh;
  for (int j = 0; j <= height; ++j)
    for (int i = 0; i <= width; ++i) mesh.node_pos.insert(mesh.node_pos.end(), {float(i), float(j), 0.0f});
  auto node = [&](int i, int j) { return index_t(j * (width + 1) + i); };
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      if (!keep(i, j)) continue;
      mesh.face_nodes.insert(mesh.face_nodes.end(), {node(i, j), node(i + 1, j), node(i + 1, j + 1)});
      mesh.face_nodes.insert(mesh.face_nodes.end(), {node(i, j), node(i + 1, j + 1), node(i, j + 1)});
    }
  return mesh;
}

Mesh triangle() {
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.face_nodes = {0, 1, 2};
  return mesh;
}

}  // namespace

TEST_CASE("mesh_info: single triangle", "[info]") {
  const MeshInfo info = info_of(triangle());
  CHECK(info.nodes == 3);
  CHECK(info.faces == 1);
  CHECK(info.edges == 3);
  CHECK(info.boundary_edges == 3);
  CHECK(info.boundary_loops == 1);
  CHECK(info.components == 1);
  CHECK(info.euler_characteristic == 1);
  CHECK(info.non_manifold_edges == 0);
  CHECK(info.non_manifold_nodes == 0);
  CHECK(info.degenerate_faces == 0);
  CHECK(info.inconsistent_edges == 0);
  CHECK(info.area == Approx(0.5));
  CHECK(info.min_angle_deg == Approx(45.0));
  CHECK_FALSE(info.has_uv);
  CHECK_FALSE(info.has_normals);
  CHECK(info.bbox_min == std::array<double, 3>{0, 0, 0});
  CHECK(info.bbox_max == std::array<double, 3>{1, 1, 0});
}

TEST_CASE("mesh_info: quad of two triangles", "[info]") {
  const MeshInfo info = info_of(grid(1, 1, [](int, int) { return true; }));
  CHECK(info.nodes == 4);
  CHECK(info.faces == 2);
  CHECK(info.edges == 5);
  CHECK(info.boundary_edges == 4);
  CHECK(info.boundary_loops == 1);
  CHECK(info.components == 1);
  CHECK(info.euler_characteristic == 1);
  CHECK(info.area == Approx(1.0));
  CHECK(info.min_angle_deg == Approx(45.0));
}

TEST_CASE("mesh_info: open fan of three triangles", "[info]") {
  Mesh mesh;
  // Centre node 0, rim nodes 1..4 on a half circle of radius 1.
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0.5f, 0.866025f, 0, -0.5f, 0.866025f, 0, -1, 0, 0};
  mesh.face_nodes = {0, 1, 2, 0, 2, 3, 0, 3, 4};
  const MeshInfo info = info_of(mesh);
  CHECK(info.edges == 7);
  CHECK(info.boundary_edges == 5);
  CHECK(info.boundary_loops == 1);
  CHECK(info.components == 1);
  CHECK(info.euler_characteristic == 1);
  CHECK(info.non_manifold_nodes == 0);
  CHECK(info.min_angle_deg == Approx(60.0).margin(1e-3));
  CHECK(info.area == Approx(3 * std::sqrt(3.0) / 4).epsilon(1e-5));
}

TEST_CASE("mesh_info: strip of eight triangles", "[info]") {
  const MeshInfo info = info_of(grid(4, 1, [](int, int) { return true; }));
  CHECK(info.nodes == 10);
  CHECK(info.faces == 8);
  CHECK(info.edges == 17);
  CHECK(info.boundary_edges == 10);
  CHECK(info.boundary_loops == 1);
  CHECK(info.components == 1);
  CHECK(info.euler_characteristic == 1);
  CHECK(info.area == Approx(4.0));
  CHECK(info.bbox_max == std::array<double, 3>{4, 1, 0});
}

TEST_CASE("mesh_info: 4x4 sheet with a hole", "[info]") {
  const MeshInfo info = info_of(grid(4, 4, [](int i, int j) { return !(i == 1 && j == 1); }));
  CHECK(info.nodes == 25);
  CHECK(info.faces == 30);
  CHECK(info.edges == 55);
  CHECK(info.boundary_edges == 20);
  CHECK(info.boundary_loops == 2);
  CHECK(info.components == 1);
  CHECK(info.euler_characteristic == 0);
  CHECK(info.non_manifold_nodes == 0);
  CHECK(info.area == Approx(15.0));
}

TEST_CASE("mesh_info: fin of three faces on one edge", "[info]") {
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0.5f, 1, 0, 0.5f, -1, 0, 0.5f, 0, 1};
  mesh.face_nodes = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  const MeshInfo info = info_of(mesh);
  CHECK(info.edges == 7);
  CHECK(info.non_manifold_edges == 1);
  CHECK(info.non_manifold_nodes == 2);  // both ends of the fin edge: no walk crosses it
  CHECK(info.boundary_edges == 6);
  CHECK(info.boundary_loops == 1);
  CHECK(info.components == 1);
  CHECK(info.euler_characteristic == 1);
}

TEST_CASE("mesh_info: bow-tie of two triangles sharing one node", "[info]") {
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0};
  mesh.face_nodes = {0, 1, 2, 0, 3, 4};
  const MeshInfo info = info_of(mesh);
  CHECK(info.nodes == 5);
  CHECK(info.edges == 6);
  CHECK(info.non_manifold_nodes == 1);
  CHECK(info.non_manifold_edges == 0);
  CHECK(info.boundary_edges == 6);
  CHECK(info.boundary_loops == 1);  // the two loops touch at the bow-tie node: one component
  CHECK(info.components == 1);      // faces sharing only a node are connected
  CHECK(info.euler_characteristic == 1);
}

TEST_CASE("mesh_info: closed tetrahedron", "[info]") {
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  mesh.face_nodes = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
  const MeshInfo info = info_of(mesh);
  CHECK(info.nodes == 4);
  CHECK(info.faces == 4);
  CHECK(info.edges == 6);
  CHECK(info.boundary_edges == 0);
  CHECK(info.boundary_loops == 0);
  CHECK(info.components == 1);
  CHECK(info.euler_characteristic == 2);
  CHECK(info.inconsistent_edges == 0);
  CHECK(info.non_manifold_nodes == 0);
  CHECK(info.area == Approx(1.5 + std::sqrt(3.0) / 2));
  CHECK(info.min_angle_deg == Approx(45.0));
}

TEST_CASE("mesh_info: two separate triangles", "[info]") {
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 0, 0, 6, 0, 0, 5, 1, 0};
  mesh.face_nodes = {0, 1, 2, 3, 4, 5};
  const MeshInfo info = info_of(mesh);
  CHECK(info.edges == 6);
  CHECK(info.boundary_edges == 6);
  CHECK(info.boundary_loops == 2);
  CHECK(info.components == 2);
  CHECK(info.euler_characteristic == 2);
  CHECK(info.bbox_min == std::array<double, 3>{0, 0, 0});
  CHECK(info.bbox_max == std::array<double, 3>{6, 1, 0});
}

TEST_CASE("mesh_info: flipped face makes inconsistent edges", "[info]") {
  Mesh mesh = grid(1, 1, [](int, int) { return true; });
  std::swap(mesh.face_nodes[4], mesh.face_nodes[5]);
  const MeshInfo info = info_of(mesh);
  CHECK(info.inconsistent_edges == 1);
  CHECK(info.components == 1);
}

TEST_CASE("mesh_info: degenerate faces are left out of the minimum angle", "[info]") {
  Mesh mesh = triangle();
  // A sliver with collinear nodes (zero area) and a face repeating a node.
  mesh.node_pos.insert(mesh.node_pos.end(), {2, 0, 0, 3, 0, 0});
  mesh.face_nodes.insert(mesh.face_nodes.end(), {1, 3, 4, 1, 1, 2});
  const MeshInfo info = info_of(mesh);
  CHECK(info.degenerate_faces == 2);
  CHECK(info.min_angle_deg == Approx(45.0));
  CHECK(info.area == Approx(0.5));
}

TEST_CASE("mesh_info: only degenerate faces leave the minimum angle undefined", "[info]") {
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  mesh.face_nodes = {0, 1, 2};
  const MeshInfo info = info_of(mesh);
  CHECK(info.degenerate_faces == 1);
  CHECK(std::isnan(info.min_angle_deg));
  CHECK(nlohmann::json::parse(tear::to_json(info))["min_angle_deg"].is_null());
}

TEST_CASE("mesh_info: per-corner attributes are reported", "[info]") {
  Mesh mesh = triangle();
  mesh.corner_uv = {0, 0, 1, 0, 0, 1};
  CHECK(info_of(mesh).has_uv);
  CHECK_FALSE(info_of(mesh).has_normals);
  mesh.corner_normal = {0, 0, 1, 0, 0, 1, 0, 0, 1};
  CHECK(info_of(mesh).has_normals);
}

TEST_CASE("mesh_info: json has exactly the documented keys", "[info]") {
  const nlohmann::json j = nlohmann::json::parse(tear::to_json(info_of(grid(2, 1, [](int, int) { return true; }))));
  std::set<std::string> keys;
  for (const auto& item : j.items()) keys.insert(item.key());
  const std::set<std::string> expected = {"nodes",
                                          "faces",
                                          "edges",
                                          "boundary_edges",
                                          "boundary_loops",
                                          "components",
                                          "pieces",
                                          "euler_characteristic",
                                          "non_manifold_edges",
                                          "non_manifold_nodes",
                                          "degenerate_faces",
                                          "inconsistent_edges",
                                          "duplicate_faces",
                                          "sliver_faces",
                                          "thin_faces",
                                          "imprecise_faces",
                                          "area",
                                          "has_uv",
                                          "has_normals",
                                          "min_angle_deg",
                                          "bbox_min",
                                          "bbox_max"};
  CHECK(keys == expected);
  CHECK(j["faces"] == 4);
  CHECK(j["edges"] == 9);
  CHECK(j["area"].get<double>() == Approx(2.0));
  CHECK(j["has_uv"] == false);
  CHECK(j["bbox_max"] == nlohmann::json::array({2.0, 1.0, 0.0}));
}

TEST_CASE("mesh_info: empty mesh", "[info]") {
  const MeshInfo info = info_of(Mesh{});
  CHECK(info.nodes == 0);
  CHECK(info.components == 0);
  CHECK(info.boundary_loops == 0);
  CHECK(info.area == 0.0);
  const nlohmann::json j = nlohmann::json::parse(tear::to_json(info));
  CHECK(j["bbox_min"].is_null());
  CHECK(j["min_angle_deg"].is_null());
}

namespace {

/// Breadth-first search over an explicit adjacency list: the number of connected components among
/// the vertices `used` marks.
int count_groups(const std::vector<std::vector<int>>& adjacent, const std::vector<bool>& used) {
  std::vector<bool> seen(adjacent.size(), false);
  int groups = 0;
  for (std::size_t start = 0; start < adjacent.size(); ++start) {
    if (!used[start] || seen[start]) continue;
    ++groups;
    std::vector<int> queue = {int(start)};
    seen[start] = true;
    while (!queue.empty()) {
      const int v = queue.back();
      queue.pop_back();
      for (int w : adjacent[v])
        if (!seen[w]) seen[w] = true, queue.push_back(w);
    }
  }
  return groups;
}

}  // namespace

TEST_CASE("mesh_info: random grids with holes match a brute-force count", "[info]") {
  const std::uint64_t seed = tear::test::test_seed(20240611);
  INFO("seed " << seed);
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < 60; ++trial) {
    INFO("trial " << trial);
    const int width = 1 + int(rng() % 8), height = 1 + int(rng() % 8);
    const double hole_rate = std::uniform_real_distribution<double>(0.0, 0.6)(rng);
    std::vector<bool> kept(width * height);
    for (auto&& k : kept) k = std::uniform_real_distribution<double>(0.0, 1.0)(rng) >= hole_rate;
    const Mesh mesh = grid(width, height, [&](int i, int j) { return kept[j * width + i]; });
    const MeshInfo info = info_of(mesh);

    // Faces are adjacent when they share a node: compare every pair.
    const int face_count = mesh.face_count();
    std::vector<std::vector<int>> face_adjacent(face_count);
    for (int f = 0; f < face_count; ++f)
      for (int g = f + 1; g < face_count; ++g) {
        bool share = false;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) share |= mesh.face_nodes[3 * f + a] == mesh.face_nodes[3 * g + b];
        if (share) face_adjacent[f].push_back(g), face_adjacent[g].push_back(f);
      }
    // Edges with one face are boundary; their nodes and adjacency give the loops.
    std::map<std::pair<int, int>, int> edge_faces;
    for (int f = 0; f < face_count; ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = mesh.face_nodes[3 * f + k], b = mesh.face_nodes[3 * f + (k + 1) % 3];
        ++edge_faces[{std::min(a, b), std::max(a, b)}];
      }
    std::vector<std::vector<int>> node_adjacent(mesh.node_count());
    std::vector<bool> on_boundary(mesh.node_count(), false);
    int boundary_edges = 0;
    for (const auto& [edge, faces] : edge_faces) {
      if (faces != 1) continue;
      ++boundary_edges;
      node_adjacent[edge.first].push_back(edge.second);
      node_adjacent[edge.second].push_back(edge.first);
      on_boundary[edge.first] = on_boundary[edge.second] = true;
    }

    CHECK(info.faces == face_count);
    CHECK(info.edges == std::int64_t(edge_faces.size()));
    CHECK(info.components == count_groups(face_adjacent, std::vector<bool>(face_count, true)));
    CHECK(info.boundary_edges == boundary_edges);
    CHECK(info.boundary_loops == count_groups(node_adjacent, on_boundary));
    CHECK(info.euler_characteristic == info.nodes - std::int64_t(edge_faces.size()) + face_count);
    CHECK(info.area == Approx(double(face_count) / 2));
    CHECK(info.non_manifold_edges == 0);
  }
}
