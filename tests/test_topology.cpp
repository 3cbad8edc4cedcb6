#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "build_topology.h"
#include "catch.h"
#include "random_meshes.h"
#include "reference_topology.h"
#include "tear/device.h"
#include "tear/make_sheet.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"
#include "test_support.h"

namespace {

using tear::index_t;
using Indices = std::vector<index_t>;
using Flags = std::vector<std::uint8_t>;

tear::Mesh make_mesh(std::vector<float> node_pos, Indices face_nodes) {
  tear::Mesh m;
  m.node_pos = std::move(node_pos);
  m.face_nodes = std::move(face_nodes);
  return m;
}

// Every array spelled out, so a literal test states the conventions, not just agrees with the
// reference.
struct Expected {
  index_t edge_count;
  Indices edge_nodes, edge_faces, edge_face_count, face_edges, node_face_offset, node_faces;
  Flags edge_boundary, node_boundary;
};

void check_topology(const tear::Mesh& mesh, const Expected& e) {
  const tear::Topology t = tear::build_topology(mesh, tear::test::test_device());
  CHECK(t.node_count == mesh.node_count());
  CHECK(t.face_count == mesh.face_count());
  CHECK(t.edge_count == e.edge_count);
  CHECK(t.edge_nodes == e.edge_nodes);
  CHECK(t.edge_faces == e.edge_faces);
  CHECK(t.edge_face_count == e.edge_face_count);
  CHECK(t.face_edges == e.face_edges);
  CHECK(t.node_face_offset == e.node_face_offset);
  CHECK(t.node_faces == e.node_faces);
  CHECK(t.edge_boundary == e.edge_boundary);
  CHECK(t.node_boundary == e.node_boundary);
  // The reference must state the same conventions as the literal arrays.
  CHECK(tear::test::topology_difference(tear::test::reference_topology(mesh), t) == "");
}

}  // namespace

TEST_CASE("topology: single triangle", "[topology]") {
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
  // Local edge k is opposite local node k: edge 0 = (1, 2), edge 1 = (0, 2), edge 2 = (0, 1).
  check_topology(m, {3,
                     {0, 1, 0, 2, 1, 2},
                     {0, -1, 0, -1, 0, -1},
                     {1, 1, 1},
                     {2, 1, 0},
                     {0, 1, 2, 3},
                     {0, 0, 0},
                     {1, 1, 1},
                     {1, 1, 1}});
}

TEST_CASE("topology: quad of two faces shares its diagonal", "[topology]") {
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3});
  check_topology(m, {5,
                     {0, 1, 0, 2, 0, 3, 1, 2, 2, 3},
                     {0, -1, 0, 1, 1, -1, 0, -1, 1, -1},
                     {1, 2, 1, 1, 1},
                     {3, 1, 0, 4, 2, 1},
                     {0, 2, 3, 5, 6},
                     {0, 1, 0, 0, 1, 1},
                     {1, 0, 1, 1, 1},
                     {1, 1, 1, 1}});
}

TEST_CASE("topology: closed fan has an interior node", "[topology]") {
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0}, {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1});
  check_topology(m, {8,
                     {0, 1, 0, 2, 0, 3, 0, 4, 1, 2, 1, 4, 2, 3, 3, 4},
                     {0, 3, 0, 1, 1, 2, 2, 3, 0, -1, 3, -1, 1, -1, 2, -1},
                     {2, 2, 2, 2, 1, 1, 1, 1},
                     {4, 1, 0, 6, 2, 1, 7, 3, 2, 5, 0, 3},
                     {0, 4, 6, 8, 10, 12},
                     {0, 1, 2, 3, 0, 3, 0, 1, 1, 2, 2, 3},
                     {0, 0, 0, 0, 1, 1, 1, 1},
                     {0, 1, 1, 1, 1}});
}

TEST_CASE("topology: strip of three faces", "[topology]") {
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 2, 0, 0, 0.5f, 1, 0, 1.5f, 1, 0}, {0, 1, 3, 1, 4, 3, 1, 2, 4});
  check_topology(m, {7,
                     {0, 1, 0, 3, 1, 2, 1, 3, 1, 4, 2, 4, 3, 4},
                     {0, -1, 0, -1, 2, -1, 0, 1, 1, 2, 2, -1, 1, -1},
                     {1, 1, 1, 2, 2, 1, 1},
                     {3, 1, 0, 6, 3, 4, 5, 4, 2},
                     {0, 1, 4, 5, 7, 9},
                     {0, 0, 1, 2, 2, 0, 1, 1, 2},
                     {1, 1, 1, 0, 0, 1, 1},
                     {1, 1, 1, 1, 1}});
}

TEST_CASE("topology: sheet with a hole has an inner boundary", "[topology]") {
  // Outer square 0..3, inner square 4..7 (the hole), two faces per side.
  const auto m = make_mesh({-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0, -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0},
                           {0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7});
  check_topology(
      m, {16,
          {0, 1, 0, 3, 0, 4, 0, 5, 1, 2, 1, 5, 1, 6, 2, 3, 2, 6, 2, 7, 3, 4, 3, 7, 4, 5, 4, 7, 5, 6, 6, 7},
          {0, -1, 6, -1, 1, 6, 0, 1, 2, -1, 0, 3, 2, 3, 4, -1, 2, 5, 4, 5, 6, 7, 4, 7, 1, -1, 7, -1, 3, -1, 5, -1},
          {1, 1, 2, 2, 1, 2, 2, 1, 2, 2, 2, 2, 1, 1, 1, 1},
          {5, 3, 0, 12, 2, 3, 8, 6, 4, 14, 5, 6, 11, 9, 7, 15, 8, 9, 2, 10, 1, 13, 11, 10},
          {0, 3, 6, 9, 12, 15, 18, 21, 24},
          {0, 1, 6, 0, 2, 3, 2, 4, 5, 4, 6, 7, 1, 6, 7, 0, 1, 3, 2, 3, 5, 4, 5, 7},
          {1, 1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 1, 1, 1, 1},
          {1, 1, 1, 1, 1, 1, 1, 1}});
}

TEST_CASE("topology: fin puts three faces on one edge", "[topology]") {
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 0.5f, 1, 0, 0.5f, -1, 0, 0.5f, 0, 1}, {0, 1, 2, 1, 0, 3, 0, 1, 4});
  // edge_faces keeps the first two faces of the edge; edge_face_count says there are three.
  check_topology(m, {7,
                     {0, 1, 0, 2, 0, 3, 0, 4, 1, 2, 1, 3, 1, 4},
                     {0, 1, 0, -1, 1, -1, 2, -1, 0, -1, 1, -1, 2, -1},
                     {3, 1, 1, 1, 1, 1, 1},
                     {4, 1, 0, 2, 5, 0, 6, 3, 0},
                     {0, 3, 6, 7, 8, 9},
                     {0, 1, 2, 0, 1, 2, 0, 1, 2},
                     {0, 1, 1, 1, 1, 1, 1},
                     {1, 1, 1, 1, 1}});
}

TEST_CASE("topology: bow-tie shares a node and no edge", "[topology]") {
  const auto m = make_mesh({0, 0, 0, 1, -0.5f, 0, 1, 0.5f, 0, -1, 0.5f, 0, -1, -0.5f, 0}, {0, 1, 2, 0, 3, 4});
  check_topology(m, {6,
                     {0, 1, 0, 2, 0, 3, 0, 4, 1, 2, 3, 4},
                     {0, -1, 0, -1, 1, -1, 1, -1, 0, -1, 1, -1},
                     {1, 1, 1, 1, 1, 1},
                     {4, 1, 0, 5, 3, 2},
                     {0, 2, 3, 4, 5, 6},
                     {0, 1, 0, 0, 1, 1},
                     {1, 1, 1, 1, 1, 1},
                     {1, 1, 1, 1, 1}});
}

TEST_CASE("topology: tetrahedron is closed", "[topology]") {
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
  check_topology(m, {6,
                     {0, 1, 0, 2, 0, 3, 1, 2, 1, 3, 2, 3},
                     {0, 1, 0, 2, 1, 2, 0, 3, 1, 3, 2, 3},
                     {2, 2, 2, 2, 2, 2},
                     {3, 0, 1, 4, 2, 0, 5, 1, 2, 5, 4, 3},
                     {0, 3, 6, 9, 12},
                     {0, 1, 2, 0, 1, 3, 0, 2, 3, 1, 2, 3},
                     {0, 0, 0, 0, 0, 0},
                     {0, 0, 0, 0}});
}

TEST_CASE("topology: a face repeating a node lists it twice", "[topology]") {
  // Garbage in, but the arrays still follow the conventions: the pair (0, 1) is local edges 0
  // and 1 of face 0, the pair (0, 0) its local edge 2.
  const auto m = make_mesh({0, 0, 0, 1, 0, 0}, {0, 0, 1});
  check_topology(m, {2, {0, 0, 0, 1}, {0, -1, 0, 0}, {1, 2}, {1, 1, 0}, {0, 2, 3}, {0, 0, 0}, {1, 0}, {1, 0}});
}

TEST_CASE("topology: empty mesh", "[topology]") {
  const tear::Mesh empty;
  check_topology(empty, {0, {}, {}, {}, {}, {0}, {}, {}, {}});
  const auto nodes_only = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {});
  check_topology(nodes_only, {0, {}, {}, {}, {}, {0, 0, 0, 0}, {}, {}, {0, 0, 0}});
}

TEST_CASE("topology: unused nodes have no faces and are not on the boundary", "[topology]") {
  // Node 1 (between used ones) and node 4 (last) are used by no face.
  const auto m = make_mesh({0, 0, 0, 9, 9, 9, 1, 0, 0, 0, 1, 0, 7, 7, 7}, {0, 2, 3});
  check_topology(m, {3,
                     {0, 2, 0, 3, 2, 3},
                     {0, -1, 0, -1, 0, -1},
                     {1, 1, 1},
                     {2, 1, 0},
                     {0, 1, 1, 2, 3, 3},
                     {0, 0, 0},
                     {1, 1, 1},
                     {1, 0, 1, 1, 0}});
}

TEST_CASE("topology: matches the serial reference on random meshes", "[topology]") {
  const std::uint64_t seed = tear::test::test_seed(20240611);
  for (std::uint64_t i = 0; i < 240; ++i) {
    const auto [name, mesh] = tear::test::random_mesh(seed + i);
    INFO("seed " << seed + i << " (" << name << ", " << mesh.node_count() << " nodes, " << mesh.face_count()
                 << " faces)");
    const tear::Topology t = tear::build_topology(mesh, tear::test::test_device());
    REQUIRE(tear::test::topology_difference(t, tear::test::reference_topology(mesh)) == "");
  }
}

TEST_CASE("topology: sheets whose scans take one tile or several or the whole device match the reference",
          "[topology]") {
  // The counts of a build are summed by one block on CUDA up to 32,768 values, tile by tile
  // (8,192 a tile), and by a device-wide scan beyond: node counts of about 150, 10,000 and 40,000.
  for (const index_t faces : {300, 20000, 80000}) {
    tear::SheetOptions o;
    o.face_count = faces;
    const tear::Mesh mesh = tear::make_sheet(o);
    INFO(faces << " faces, " << mesh.node_count() << " nodes");
    const tear::Topology t = tear::build_topology(mesh, tear::test::test_device());
    CHECK(tear::test::topology_difference(t, tear::test::reference_topology(mesh)) == "");
  }
}

TEST_CASE("topology: nodes of high valence match the serial reference", "[topology]") {
  // A node's edges are gathered in a short list; a node with more edges than it holds is
  // enumerated another way. Fans of 3 to 40 faces around node 0 (all its neighbours higher) and
  // around the highest node (all lower), a fin of many faces on one edge, and a face repeating the
  // centre.
  for (int fan = 3; fan <= 40; fan += fan < 12 ? 1 : 7) {
    for (const bool centre_first : {true, false}) {
      std::vector<float> pos{0, 0, 0};
      for (int i = 0; i < fan; ++i) {
        const float a = 6.2831853f * i / fan;
        pos.insert(pos.end(), {std::cos(a), std::sin(a), 0.0f});
      }
      const index_t n = static_cast<index_t>(pos.size() / 3);
      const auto id = [&](index_t v) { return centre_first ? v : n - 1 - v; };
      Indices faces;
      for (index_t i = 0; i < fan; ++i) faces.insert(faces.end(), {id(0), id(1 + i), id(1 + (i + 1) % fan)});
      for (index_t i = 0; i < fan / 3; ++i) faces.insert(faces.end(), {id(0), id(1), id(2 + i % (fan - 1))});  // fins
      faces.insert(faces.end(), {id(0), id(0), id(1)});  // a face repeating the centre
      const tear::Mesh mesh = make_mesh(pos, faces);
      INFO("fan of " << fan << (centre_first ? ", centre first" : ", centre last"));
      const tear::Topology t = tear::build_topology(mesh, tear::test::test_device());
      CHECK(tear::test::topology_difference(t, tear::test::reference_topology(mesh)) == "");
    }
  }
}

TEST_CASE("topology: a node of thousands of faces and edges matches the serial reference", "[topology]") {
  // The first corner of a fanned polygon and the nodes of one triangle repeated: their runs of faces
  // are heap-sorted and their edges counted from their sorted half-edges (each had taken time
  // quadratic in its faces), beside nodes of a few faces gathered as usual.
  for (const bool centre_first : {true, false}) {
    const index_t fan = 5000, copies = 3000;
    std::vector<float> pos{0, 0, 0};
    for (index_t i = 0; i < fan; ++i) {
      const float a = 6.2831853f * static_cast<float>(i) / static_cast<float>(fan);
      pos.insert(pos.end(), {std::cos(a), std::sin(a), 0.0f});
    }
    for (const float x : {3.0f, 4.0f, 3.0f}) pos.insert(pos.end(), {x, x == 4.0f ? 0.0f : 1.0f, 0.0f});
    const index_t n = static_cast<index_t>(pos.size() / 3);
    const auto id = [&](index_t v) { return centre_first ? v : n - 1 - v; };
    Indices faces;
    for (index_t i = 0; i < fan; ++i) faces.insert(faces.end(), {id(0), id(1 + i), id(1 + (i + 1) % fan)});
    for (index_t i = 0; i < copies; ++i) faces.insert(faces.end(), {id(fan + 1), id(fan + 2), id(fan + 3)});
    // Shuffled, so that the runs do not arrive in order.
    tear::test::Random random(centre_first ? 5 : 6);
    for (std::size_t f = faces.size() / 3; f > 1; --f) {
      const std::size_t g = random.below(static_cast<index_t>(f));
      for (int k = 0; k < 3; ++k) std::swap(faces[3 * (f - 1) + k], faces[3 * g + k]);
    }
    const tear::Mesh mesh = make_mesh(pos, faces);
    INFO((centre_first ? "centre first" : "centre last"));
    const tear::Topology t = tear::build_topology(mesh, tear::test::test_device());
    CHECK(tear::test::topology_difference(t, tear::test::reference_topology(mesh)) == "");
    const tear::MeshReport report = tear::validate_mesh(mesh, tear::test::test_device());
    CHECK(report.duplicate_faces == copies);
  }
}

TEST_CASE("topology: the sorting networks sort every input of zeros and ones", "[topology]") {
  // A comparator network sorts every input when it sorts every input of zeros and ones.
  auto check = [](auto sort, int size) {
    for (std::uint32_t bits = 0; bits < (1u << size); ++bits) {
      std::vector<int> v(static_cast<std::size_t>(size));
      for (int i = 0; i < size; ++i) v[static_cast<std::size_t>(i)] = (bits >> i) & 1;
      sort(v.data());
      INFO(size << " values, input bits " << bits);
      REQUIRE(std::is_sorted(v.begin(), v.end()));
    }
  };
  check([](int* v) { tear::kernels::sort_network<8>(v); }, 8);
  check([](int* v) { tear::kernels::sort_network<16>(v); }, 16);
  check([](int* v) { tear::kernels::sort_network<2>(v); }, 2);
  // 32 values: 2^32 inputs are too many; seeded random zeros and ones, and permutations.
  const std::uint64_t seed = tear::test::test_seed(1999);
  INFO("seed " << seed);
  tear::test::Random random(seed);
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<std::uint64_t> v(32);
    const bool binary = trial % 2 == 0;
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = binary ? random.bits() & 1 : i;
    if (!binary) random.shuffle(v);
    tear::kernels::sort_network<32>(v.data());
    INFO("trial " << trial);
    REQUIRE(std::is_sorted(v.begin(), v.end()));
  }
}

TEST_CASE("topology: a node's edges gathered in registers are the ones its list gathers", "[topology]") {
  // Every node of random meshes (soups with faces repeating nodes, fins, nodes of many faces) and of
  // fans of 3 to 20 faces: the register path (up to 8 faces, up to 16) either declines or visits
  // exactly the edges of the general one, in order.
  namespace k = tear::kernels;
  std::size_t taken = 0, declined = 0;
  auto compare = [&](const tear::Mesh& mesh) {
    const tear::Topology t = tear::build_topology(mesh, tear::Device::cpu);
    const index_t* fn = mesh.face_nodes.data();
    const index_t* offset = t.node_face_offset.data();
    const index_t* faces = t.node_faces.data();
    using Edge = std::vector<index_t>;  // end, count, first face, second face
    auto edge = [](const k::NodeEdge& e) { return Edge{e.end, e.count, e.face[0], e.face[1]}; };
    for (index_t n = 0; n < mesh.node_count(); ++n) {
      std::vector<Edge> small, general;
      const bool took =
          k::for_each_small_node_edge(fn, offset, faces, n, [&](const k::NodeEdge& e) { small.push_back(edge(e)); });
      (took ? taken : declined) += 1;
      if (!took) continue;
      k::NodeEdgeList list;
      list.gather(fn, offset, faces, n);
      if (!list.overflow)
        for (int j = 0; j < list.size; ++j) general.push_back(edge(list.edge[j]));
      else
        for (index_t end = k::next_edge_end(fn, offset, faces, n, -1); end >= 0;
             end = k::next_edge_end(fn, offset, faces, n, end))
          general.push_back(edge(k::edge_to(fn, offset, faces, n, end)));
      INFO("node " << n << " of " << offset[n + 1] - offset[n] << " faces");
      REQUIRE(small == general);
    }
  };
  const std::uint64_t seed = tear::test::test_seed(4242);
  for (std::uint64_t i = 0; i < 120; ++i) {
    const auto [name, mesh] = tear::test::random_mesh(seed + i);
    INFO("seed " << seed + i << " (" << name << ")");
    compare(mesh);
  }
  for (int fan = 3; fan <= 20; ++fan)
    for (const bool closed : {true, false})
      for (const bool centre_first : {true, false}) {
        std::vector<float> pos(3 * static_cast<std::size_t>(fan + 2), 0.0f);
        const index_t n = fan + 2;
        const auto id = [&](index_t v) { return centre_first ? v : n - 1 - v; };
        Indices faces;
        for (index_t i = 0; i < fan; ++i)
          faces.insert(faces.end(), {id(0), id(1 + i), id(closed ? 1 + (i + 1) % fan : 2 + i)});
        INFO("fan of " << fan << (closed ? ", closed" : ", open") << (centre_first ? ", centre first" : ", centre last"));
        compare(make_mesh(pos, faces));
      }
  INFO(taken << " nodes gathered in registers, " << declined << " declined");
  CHECK(taken > 1000);
  CHECK(declined > 10);
}

TEST_CASE("topology: renumbering nodes and faces keeps the edge and boundary counts", "[topology]") {
  const std::uint64_t seed = tear::test::test_seed(77);
  for (std::uint64_t i = 0; i < 30; ++i) {
    INFO("seed " << seed + i);
    const tear::Mesh sheet = tear::test::random_sheet(seed + i);
    const tear::Mesh permuted = tear::test::permute_mesh(sheet, seed + i);
    const auto device = tear::test::test_device();
    const tear::Topology a = tear::build_topology(sheet, device), b = tear::build_topology(permuted, device);
    CHECK(a.edge_count == b.edge_count);
    auto sum = [](const auto& flags) {
      index_t n = 0;
      for (auto f : flags) n += f;
      return n;
    };
    CHECK(sum(a.edge_boundary) == sum(b.edge_boundary));
    CHECK(sum(a.node_boundary) == sum(b.node_boundary));
    // A square sheet: Euler characteristic 1.
    CHECK(a.node_count - a.edge_count + a.face_count == 1);
  }
}

TEST_CASE("topology: CUDA and CPU backends agree", "[topology][parity]") {
  if (!tear::cuda_available()) {
    WARN("no GPU: parity not checked");
    return;
  }
  const std::uint64_t seed = tear::test::test_seed(31337);
  for (std::uint64_t i = 0; i < 200; ++i) {
    const auto [name, mesh] = tear::test::random_mesh(seed + i);
    INFO("seed " << seed + i << " (" << name << ")");
    const tear::Topology cpu = tear::build_topology(mesh, tear::Device::cpu);
    const tear::Topology cuda = tear::build_topology(mesh, tear::Device::cuda);
    REQUIRE(tear::test::topology_difference(cuda, cpu) == "");
    CHECK(tear::test::report_counts(tear::validate_mesh(mesh, tear::Device::cuda)) ==
          tear::test::report_counts(tear::validate_mesh(mesh, tear::Device::cpu)));
  }
  // Larger meshes too, where the GPU sorts take their multi-block paths.
  for (std::uint64_t i = 0; i < 4; ++i) {
    INFO("large sheet, seed " << seed + i);
    tear::SheetOptions options;
    options.face_count = 200000 + 2 * static_cast<index_t>(i);
    options.seed = seed + i;
    const tear::Mesh mesh = tear::test::permute_mesh(tear::make_sheet(options), seed + i);
    REQUIRE(tear::test::topology_difference(tear::build_topology(mesh, tear::Device::cuda),
                                            tear::build_topology(mesh, tear::Device::cpu)) == "");
  }
}
