// Identity of a cloth through cuts and frames (docs/identity.md): node indices persist, cuts
// append, origins give back rest positions, velocities are carried, torn edges are the cuts'.
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "catch.h"
#include "random_meshes.h"
#include "remesh_checks.h"
#include "tear/cloth.h"
#include "tear/make_sheet.h"
#include "tear/run_cuts.h"
#include "tear/simulation.h"
#include "test_support.h"
#include "write_new_nodes.h"

using tear::CutLine;
using tear::index_t;
using tear::Mesh;
using tear::test::cut_rest_xy;

namespace {

/// A random cut across or into the unit square (some end inside: slits; some cross others).
CutLine random_cut(tear::test::Random& random) {
  std::vector<std::array<double, 2>> points;
  const int count = 2 + static_cast<int>(random.uniform() * 3);
  for (int i = 0; i < count; ++i) points.push_back({random.uniform(-0.2, 1.2), random.uniform(-0.2, 1.2)});
  return cut_rest_xy(points);
}

/// Every node's rest position from its origin: the input face's rest positions weighted.
void check_origins(const Mesh& input, const Mesh& m, const std::vector<float>& node_rest) {
  REQUIRE(m.node_origin_face.size() == std::size_t(m.node_count()));
  REQUIRE(m.node_origin_bary.size() == 2 * std::size_t(m.node_count()));
  double worst = 0;
  for (index_t n = 0; n < m.node_count(); ++n) {
    const index_t f = m.node_origin_face[n];
    REQUIRE(f >= 0);
    REQUIRE(f < input.face_count());
    const double u = m.node_origin_bary[2 * n], v = m.node_origin_bary[2 * n + 1];
    CHECK(u >= -1e-6);
    CHECK(v >= -1e-6);
    CHECK(u + v <= 1 + 1e-6);
    for (int d = 0; d < 3; ++d) {
      const double p0 = input.node_pos[3 * input.face_nodes[3 * f] + d], p1 = input.node_pos[3 * input.face_nodes[3 * f + 1] + d],
                   p2 = input.node_pos[3 * input.face_nodes[3 * f + 2] + d];
      const double x = (1 - u - v) * p0 + u * p1 + v * p2;
      worst = std::max(worst, std::abs(x - node_rest[3 * n + d]));
    }
  }
  CHECK(worst <= 1e-5);
}

}  // namespace

TEST_CASE("identity: a cut keeps every node's index and appends what it makes", "[identity]") {
  const std::uint64_t seed = tear::test::test_seed(9001);
  INFO("seed " << seed << " (TEAR_TEST_SEED reruns it)");
  tear::test::Random random(seed);
  for (int trial = 0; trial < 8; ++trial) {
    tear::SheetOptions sheet;
    sheet.face_count = 2 * static_cast<index_t>(random.uniform(40, 400));
    sheet.seed = seed + trial;
    const Mesh input = tear::make_sheet(sheet);
    tear::Cloth cloth(input, tear::test::test_device());
    tear::CutOptions options;
    options.check_writes = true;  // every writer writes exactly the slots its scan gave it
    for (int frame = 0; frame < 4; ++frame) {
      const std::vector<float> rest_before = cloth.node_rest();
      const index_t nodes_before = cloth.node_count();
      std::vector<CutLine> cuts = {random_cut(random)};
      if (random.chance(0.5)) cuts.push_back(random_cut(random));
      const tear::CutStats stats = cloth.cut(cuts, options);
      INFO("trial " << trial << " frame " << frame);
      REQUIRE(stats.nodes_after >= nodes_before);
      const std::vector<float> rest_after = cloth.node_rest();
      // The first nodes are the nodes before, bit for bit, at the same index.
      CHECK(std::vector<float>(rest_after.begin(), rest_after.begin() + 3 * std::size_t(nodes_before)) == rest_before);
      // A copy of an old node keeps its source's position; the provenance says so.
      const tear::CutProvenance p = cloth.provenance();
      if (stats.nodes_after != nodes_before || stats.faces_after != stats.faces_before) {
        REQUIRE(p.node_source.size() == 3 * std::size_t(stats.nodes_after));
        for (index_t n = 0; n < nodes_before; ++n) CHECK(p.node_source[3 * n] == n);
      }
      tear::test::check_valid_after_cut(cloth, tear::test::total_area(input), tear::test::test_device());
    }
    const Mesh m = cloth.mesh();
    check_origins(input, m, cloth.node_rest());
    // Input nodes name a face they belong to, at its corner.
    for (index_t n = 0; n < input.node_count(); ++n) {
      const index_t f = m.node_origin_face[n];
      const double u = m.node_origin_bary[2 * n], v = m.node_origin_bary[2 * n + 1];
      const int corner = u == 1 ? 1 : v == 1 ? 2 : 0;
      CHECK(input.face_nodes[3 * f + corner] == n);
    }
  }
}

TEST_CASE("identity: write_new_nodes' example: node 2 split, an edge point with two copies", "[identity]") {
  // kernels/write_new_nodes.h's opening example, run on the host.
  const std::vector<index_t> node_extra_offset = {0, 0, 0, 1, 1};
  const std::vector<index_t> edge_nodes = {1, 3};
  const std::vector<float> edge_point_t = {0.25f};
  const std::vector<index_t> edge_new_offset = {1, 3};  // after the node's extra copy
  std::vector<index_t> source(3 * 7, -9);
  std::vector<float> weight(3 * 7, -9);
  const tear::kernels::NodeSources out{source.data(), weight.data()};
  for (index_t n = 0; n < 4; ++n) tear::kernels::write_node_sources{node_extra_offset.data(), 4, out}(n);
  tear::kernels::write_edge_sources{edge_nodes.data(), edge_point_t.data(), edge_new_offset.data(), 4, out}(0);
  CHECK(source == std::vector<index_t>{0, -1, -1, 1, -1, -1, 2, -1, -1, 3, -1, -1, 2, -1, -1, 1, 3, -1, 1, 3, -1});
  CHECK(weight[3 * 5] == 0.75f);
  CHECK(weight[3 * 5 + 1] == 0.25f);
  CHECK(weight[3 * 6] == 0.75f);
}

TEST_CASE("identity: a run's frames keep their nodes' indices from frame to frame", "[identity]") {
  tear::SheetOptions sheet;
  sheet.face_count = 800;
  const Mesh input = tear::make_sheet(sheet);
  const tear::CutScript script = tear::parse_cut_script(R"({
    "version": 1, "frames": 6,
    "cuts": [
      {"frame": 2, "polyline": [[-0.1, 0.5], [1.1, 0.55]], "space": "rest-xy"},
      {"frame": 4, "polyline": [[0.5, -0.1], [0.45, 1.1]], "space": "rest-xy"},
      {"frame": 4, "polyline": [[0.2, 0.2], [0.8, 0.8]], "space": "rest-xy"}],
    "simulation": {"pins": [{"box": {"min": [-1, 0.99, -1], "max": [2, 2, 1]}}]}
  })", "crossing.json");
  tear::Cloth cloth(input, tear::test::test_device());
  std::vector<float> previous_rest;
  int frames = 0;
  tear::run_cuts(cloth, script, script.frames, [&](const tear::FrameResult& frame, const tear::Cloth& c) {
    ++frames;
    const std::vector<float> rest = c.node_rest();
    INFO("frame " << frame.frame);
    REQUIRE(rest.size() >= previous_rest.size());
    CHECK(std::vector<float>(rest.begin(), rest.begin() + previous_rest.size()) == previous_rest);
    previous_rest = rest;
    const Mesh m = c.mesh();
    check_origins(input, m, rest);
    // Pinned nodes (the top row and their copies) have not moved.
    const std::vector<std::uint8_t> pinned = c.node_pinned();
    const std::vector<float> pos = c.node_pos();
    for (index_t n = 0; n < c.node_count(); ++n)
      if (pinned[n])
        for (int d = 0; d < 3; ++d) CHECK(pos[3 * n + d] == rest[3 * n + d]);
  });
  CHECK(frames == 6);
  CHECK(previous_rest.size() > input.node_pos.size());
}

TEST_CASE("identity: free fall: every node's velocity is g t, new nodes' too", "[identity]") {
  tear::SheetOptions sheet;
  sheet.face_count = 400;
  const Mesh input = tear::make_sheet(sheet);
  tear::Cloth cloth(input, tear::test::test_device());
  tear::SimulationOptions o;
  o.damping = 0;
  o.fps = 24;
  cloth.simulate(o);
  CHECK(cloth.mesh().node_vel == std::vector<float>(input.node_pos.size(), 0.0f));  // at rest before the first step
  const int frames = 6;
  for (int f = 1; f <= frames; ++f) {
    if (f == 3) cloth.cut({cut_rest_xy({{-0.1, 0.3}, {1.1, 0.6}})});
    cloth.step();
  }
  const Mesh m = cloth.mesh();
  REQUIRE(m.node_count() > input.node_count());
  const double t = frames / o.fps;
  for (index_t n = 0; n < m.node_count(); ++n) {
    INFO("node " << n);
    CHECK(std::abs(m.node_vel[3 * n] - 0.0) < 1e-3);
    CHECK(std::abs(m.node_vel[3 * n + 1] - (-9.81 * t)) < 1e-3 * 9.81 * t);
    CHECK(std::abs(m.node_vel[3 * n + 2] - 0.0) < 1e-3);
  }
}

TEST_CASE("identity: torn edges are the borders a cut made, and only those", "[identity]") {
  tear::SheetOptions sheet;
  sheet.face_count = 600;
  sheet.irregular = false;
  const Mesh input = tear::make_sheet(sheet);
  tear::Cloth cloth(input, tear::test::test_device());
  CHECK(cloth.mesh().torn_edge_nodes.empty());
  // A slit from the left border to the middle: two torn sides, each about 0.6 long.
  cloth.cut({cut_rest_xy({{-0.2, 0.37}, {0.6, 0.41}})});
  const Mesh m = cloth.mesh();
  const tear::Topology t = cloth.topology();
  std::set<std::pair<index_t, index_t>> border;
  for (index_t e = 0; e < t.edge_count; ++e)
    if (t.edge_faces[2 * e + 1] < 0) border.insert(std::minmax(t.edge_nodes[2 * e], t.edge_nodes[2 * e + 1]));
  REQUIRE(!m.torn_edge_nodes.empty());
  double torn_length = 0;
  std::set<std::pair<index_t, index_t>> torn;
  for (std::size_t i = 0; i < m.torn_edge_nodes.size(); i += 2) {
    const index_t a = m.torn_edge_nodes[i], b = m.torn_edge_nodes[i + 1];
    CHECK(border.count(std::minmax(a, b)) == 1);  // only border edges
    torn.insert(std::minmax(a, b));
    double len2 = 0;
    for (int d = 0; d < 3; ++d) len2 += std::pow(m.node_pos[3 * a + d] - m.node_pos[3 * b + d], 2);
    torn_length += std::sqrt(len2);
  }
  CHECK(torn.size() * 2 == m.torn_edge_nodes.size());  // each edge once
  // The slit inside the sheet runs from x = 0 to x = 0.6, rising 0.04 per 0.8: both sides torn.
  CHECK(std::abs(torn_length - 2 * std::hypot(0.6, 0.6 * 0.04 / 0.8)) < 0.05);
  // Every border edge not torn lies on the square's outline.
  for (const auto& [a, b] : border) {
    if (torn.count({a, b})) continue;
    const float* pa = &m.node_pos[3 * a];
    const float* pb = &m.node_pos[3 * b];
    const bool on_outline = (pa[0] == 0 && pb[0] == 0) || (pa[0] == 1 && pb[0] == 1) || (pa[1] == 0 && pb[1] == 0) ||
                            (pa[1] == 1 && pb[1] == 1);
    CHECK(on_outline);
  }
}

TEST_CASE("identity: corners at old nodes keep their UVs and normals bit for bit through a cut", "[identity][carry]") {
  // Normals as a file gives them: a few decimals, not of unit length, different at every corner.
  // A corner of a new face that lies at an old node of its parent keeps the parent's corner values
  // exactly (so faces no cut touches keep theirs, and the corners around a node stay as equal as
  // they were); a corner at a cut point gets interpolated values, its normal of unit length.
  const std::uint64_t seed = tear::test::test_seed(9017);
  INFO("seed " << seed << " (TEAR_TEST_SEED reruns it)");
  tear::test::Random random(seed);
  for (int trial = 0; trial < 6; ++trial) {
    tear::SheetOptions sheet;
    sheet.face_count = 2 * static_cast<index_t>(random.uniform(40, 300));
    sheet.seed = seed + trial;
    Mesh input = tear::make_sheet(sheet);
    input.corner_normal.resize(9 * std::size_t(input.face_count()));
    for (auto& c : input.corner_normal) c = static_cast<float>(std::round(random.uniform(-1, 1) * 1e4) / 1e4);
    for (index_t c = 0; c < 3 * input.face_count(); ++c) input.corner_normal[3 * c + 2] = 0.9f;  // never zero
    tear::Cloth cloth(input, tear::test::test_device());
    std::vector<CutLine> cuts = {random_cut(random), random_cut(random)};
    const tear::CutStats stats = cloth.cut(cuts, {});
    INFO("trial " << trial);
    if (stats.faces_after == stats.faces_before) continue;
    const Mesh m = cloth.mesh();
    const tear::CutProvenance p = cloth.provenance();
    REQUIRE(p.face_parent.size() == std::size_t(m.face_count()));
    REQUIRE(m.corner_normal.size() == 9 * std::size_t(m.face_count()));
    REQUIRE(m.corner_uv.size() == 6 * std::size_t(m.face_count()));
    int copied = 0, interpolated = 0;
    for (index_t f = 0; f < m.face_count(); ++f) {
      const index_t parent = p.face_parent[f];
      for (int k = 0; k < 3; ++k) {
        const index_t n = m.face_nodes[3 * f + k];
        // A copy of an old node: one source, weight 1.
        const bool copy = p.node_source[3 * n + 1] < 0 && p.node_source_weight[3 * n] == 1.f;
        int local = -1;
        for (int j = 0; j < 3 && copy; ++j)
          if (input.face_nodes[3 * parent + j] == p.node_source[3 * n]) local = j;
        const float* normal = &m.corner_normal[3 * (3 * f + k)];
        if (local >= 0) {
          ++copied;
          for (int d = 0; d < 3; ++d) CHECK(normal[d] == input.corner_normal[3 * (3 * parent + local) + d]);
          for (int d = 0; d < 2; ++d) CHECK(m.corner_uv[2 * (3 * f + k) + d] == input.corner_uv[2 * (3 * parent + local) + d]);
        } else {
          ++interpolated;
          CHECK(std::abs(std::sqrt(double(normal[0]) * normal[0] + double(normal[1]) * normal[1] + double(normal[2]) * normal[2]) - 1) < 1e-6);
        }
      }
    }
    CHECK(copied > 0);
    CHECK(interpolated > 0);
  }
}

TEST_CASE("identity: a frame taken later is the frame as it was when asked for, while the cloth goes on", "[identity]") {
  tear::SheetOptions sheet;
  sheet.face_count = 800;
  Mesh input = tear::make_sheet(sheet);
  input.corner_normal.assign(9 * std::size_t(input.face_count()), 0.0f);
  for (std::size_t c = 0; c < input.corner_normal.size(); c += 3) input.corner_normal[c + 2] = 1.0f;
  tear::Cloth cloth(input, tear::test::test_device());
  tear::SimulationOptions o;
  o.fps = 24;
  cloth.simulate(o);
  cloth.step();
  cloth.cut({cut_rest_xy({{-0.1, 0.3}, {0.7, 0.5}})});
  cloth.step();
  tear::PendingMesh later = cloth.mesh_later();
  tear::PendingMesh without_normals = cloth.mesh_later(false);
  cloth.mesh_later();  // dropped without being taken
  const Mesh now = cloth.mesh();
  REQUIRE(!now.torn_edge_nodes.empty());
  REQUIRE(!now.corner_uv.empty());
  REQUIRE(now.corner_normal.size() == 9 * std::size_t(now.face_count()));
  // The cloth goes on: cut again and stepped, so its arrays change (and grow) under the copies.
  cloth.cut({cut_rest_xy({{0.2, -0.1}, {0.6, 1.1}})});
  cloth.step();
  cloth.step();
  const Mesh after = cloth.mesh();
  REQUIRE(after.node_count() > now.node_count());
  REQUIRE(after.face_count() > now.face_count());

  const auto same_frame = [&](const Mesh& m, bool normals) {
    CHECK(m.node_pos == now.node_pos);
    CHECK(m.face_nodes == now.face_nodes);
    CHECK(m.corner_uv == now.corner_uv);
    CHECK(m.corner_normal == (normals ? now.corner_normal : std::vector<float>()));
    CHECK(m.node_vel == now.node_vel);
    CHECK(m.node_origin_face == now.node_origin_face);
    CHECK(m.node_origin_bary == now.node_origin_bary);
    CHECK(m.torn_edge_nodes == now.torn_edge_nodes);
  };
  same_frame(later.take(), true);
  same_frame(without_normals.take(), false);
  const Mesh again = later.take();
  CHECK(again.node_count() == 0);
  CHECK(again.face_count() == 0);
}
