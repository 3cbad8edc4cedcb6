#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "catch.h"
#include "random_meshes.h"
#include "reference_topology.h"
#include "tear/make_sheet.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"
#include "test_support.h"

namespace {

using tear::index_t;

tear::Mesh make_mesh(std::vector<float> node_pos, std::vector<index_t> face_nodes) {
  tear::Mesh m;
  m.node_pos = std::move(node_pos);
  m.face_nodes = std::move(face_nodes);
  return m;
}

tear::MeshReport validate(const tear::Mesh& mesh) { return tear::validate_mesh(mesh, tear::test::test_device()); }

bool mentions(const tear::MeshReport& report, const std::string& words) {
  return report.describe().find(words) != std::string::npos;
}

tear::Mesh quad() { return make_mesh({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3}); }

tear::Mesh tetrahedron() {
  return make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
}

// Three faces on the edge (0, 1).
tear::Mesh fin() {
  return make_mesh({0, 0, 0, 1, 0, 0, 0.5f, 1, 0, 0.5f, -1, 0, 0.5f, 0, 1}, {0, 1, 2, 1, 0, 3, 0, 1, 4});
}

// Two faces meeting only at node 0.
tear::Mesh bowtie() {
  return make_mesh({0, 0, 0, 1, -0.5f, 0, 1, 0.5f, 0, -1, 0.5f, 0, -1, -0.5f, 0}, {0, 1, 2, 0, 3, 4});
}

}  // namespace

TEST_CASE("validate_mesh: clean meshes are ok", "[validate]") {
  std::vector<std::pair<const char*, tear::Mesh>> meshes = {
      {"triangle", make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2})},
      {"quad", quad()},
      {"closed fan", make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0}, {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1})},
      {"tetrahedron", tetrahedron()},
      {"octahedron", tear::test::octahedron()},
      {"subdivided octahedron", tear::test::subdivided_octahedron(3)},
      {"empty", tear::Mesh{}},
      {"unused node", make_mesh({0, 0, 0, 5, 5, 5, 1, 0, 0, 0, 1, 0}, {0, 2, 3})},
  };
  tear::SheetOptions regular;
  regular.irregular = false;
  meshes.emplace_back("regular sheet", tear::make_sheet(regular));
  meshes.emplace_back("irregular sheet", tear::make_sheet());
  tear::TubeOptions tube;
  tube.welded = true;
  meshes.emplace_back("welded tube", tear::make_tube(tube));
  for (const auto& [name, mesh] : meshes) {
    INFO(name);
    const tear::MeshReport report = validate(mesh);
    CHECK(tear::test::report_counts(report) == tear::test::report_counts(tear::MeshReport{}));
    CHECK(report.ok());
    CHECK(report.readable());
    CHECK(report.describe() == "no problems");
  }
}

TEST_CASE("validate_mesh: node indices out of range", "[validate]") {
  const auto device = tear::test::test_device();
  // Faces 1 and 2 are out of range (index 4, index -1); face 3 has two bad indices but counts once.
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, {0, 1, 2, 1, 4, 2, -1, 0, 1, 7, 8, 3});
  const tear::MeshReport indices = tear::check_indices(m, device);
  CHECK(indices.indices_out_of_range == 3);
  CHECK(indices.non_finite_nodes == 0);
  CHECK_FALSE(indices.readable());
  CHECK_FALSE(indices.ok());
  CHECK(mentions(indices, "3 faces with a node index out of range"));

  const tear::MeshReport one = tear::check_indices(make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 3}), device);
  CHECK(one.indices_out_of_range == 1);
  CHECK(mentions(one, "1 face with a node index out of range"));
}

TEST_CASE("validate_mesh: check_indices needs no topology", "[validate]") {
  // Indices at the extremes of index_t: building edges or a node CSR from them would read far
  // outside any array, so only face_nodes may be read here.
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0},
                           {0, 1, 2, std::numeric_limits<index_t>::max(), std::numeric_limits<index_t>::min(), 1});
  CHECK(tear::check_indices(m, tear::test::test_device()).indices_out_of_range == 1);
}

TEST_CASE("validate_mesh: stops after the index checks when an index is out of range", "[validate]") {
  // Without face 2, the mesh would have a degenerate face (0, 0, 1) and a fin; none of that may be
  // counted, since topology cannot be built.
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 0.5f, 1, 0, 0.5f, -1, 0, 0.5f, 0, 1},
                           {0, 1, 2, 1, 0, 3, 0, 1, 1000000, 0, 1, 4, 0, 0, 1});
  const tear::MeshReport report = validate(m);
  CHECK(report.indices_out_of_range == 1);
  CHECK(report.degenerate_faces == 0);
  CHECK(report.non_manifold_edges == 0);
  CHECK(report.non_manifold_nodes == 0);
  CHECK(report.inconsistent_edges == 0);
  CHECK(tear::test::report_counts(report) == tear::test::report_counts(tear::test::reference_validate_mesh(m)));
}

TEST_CASE("validate_mesh: NaN and infinite coordinates", "[validate]") {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const auto device = tear::test::test_device();
  // Node 1 NaN in x, node 2 +inf in y, node 3 -inf in z and NaN in y (counted once), node 0 fine.
  const auto m = make_mesh({0, 0, 0, nan, 0, 0, 0, inf, 0, 1, nan, -inf}, {0, 1, 2, 0, 2, 3});
  const tear::MeshReport indices = tear::check_indices(m, device);
  CHECK(indices.non_finite_nodes == 3);
  CHECK(indices.indices_out_of_range == 0);
  CHECK_FALSE(indices.readable());
  CHECK(mentions(indices, "3 nodes with a non-finite coordinate"));
  const tear::MeshReport report = validate(m);
  CHECK(report.non_finite_nodes == 3);
  CHECK_FALSE(report.ok());
  // Areas of non-finite faces mean nothing: no face is called degenerate for them.
  CHECK(report.degenerate_faces == 0);

  const tear::MeshReport one = validate(make_mesh({0, 0, 0, 1, 0, 0, 0, -inf, 0}, {0, 1, 2}));
  CHECK(one.non_finite_nodes == 1);
  CHECK(mentions(one, "1 node with a non-finite coordinate"));
}

TEST_CASE("validate_mesh: degenerate faces by the area ratio", "[validate]") {
  // Face 0 is fine; face 1 has three collinear nodes; face 2 three nodes at one point; face 3 a
  // zero-length edge; face 4 is a sliver of height 1e-13 on a base of 1 (twice the area 1e-13 <=
  // 1e-12 * 1); face 5 a sliver of height 1e-11 (above the ratio, not degenerate).
  const auto m = make_mesh({0, 0, 0, 1, 0, 0, 0,    1,      0,   // 0-2
                            0, 0, 1, 1, 1, 1, 2,    2,      1,   // 3-5 collinear
                            3, 3, 3, 3, 3, 3, 3,    3,      3,   // 6-8 one point
                            5, 0, 0, 5, 0, 0, 6,    1,      0,   // 9-11 zero-length edge
                            0, 0, 2, 1, 0, 2, 0.5f, 1e-13f, 2,   // 12-14
                            0, 0, 3, 1, 0, 3, 0.5f, 1e-11f, 3},  // 15-17
                           {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17});
  const tear::MeshReport report = validate(m);
  CHECK(report.degenerate_faces == 4);
  CHECK(report.thin_faces == 1);  // face 5: 1e-11 is above the degenerate ratio, under the thin one
  CHECK(report.non_manifold_edges == 0);
  CHECK(report.non_manifold_nodes == 0);
  CHECK(report.inconsistent_edges == 0);
  CHECK(report.readable());
  CHECK_FALSE(report.ok());
  CHECK(mentions(report, "4 degenerate faces"));
  CHECK(report.degenerate_faces == tear::test::reference_validate_mesh(m).degenerate_faces);

  const auto repeated = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 1, 1, 2});
  CHECK(validate(repeated).degenerate_faces == 1);
  CHECK(mentions(validate(repeated), "1 degenerate face"));
}

TEST_CASE("validate_mesh: a face repeating a node is only a degenerate face", "[validate]") {
  // Face (0, 0, 1) alone: its two half-edges on the pair (0, 1) run 0 -> 1 and 1 -> 0, so the
  // pair is consistently oriented, and node 0 has one face, so one fan. The device kernels count
  // the same face twice at node 0 (a bow-tie) and find the same local edge for both "faces" of
  // the pair (an inconsistent edge).
  const auto m = make_mesh({0, 0, 0, 1, 0, 0}, {0, 0, 1});
  tear::MeshReport expected;
  expected.degenerate_faces = 1;
  CHECK(tear::test::report_counts(validate(m)) == tear::test::report_counts(expected));
  CHECK(tear::test::report_counts(tear::test::reference_validate_mesh(m)) == tear::test::report_counts(expected));
}

TEST_CASE("validate_mesh: non-manifold edges", "[validate]") {
  const tear::MeshReport three = validate(fin());
  CHECK(three.non_manifold_edges == 1);
  // Both ends of the fin's edge have three faces joined by no two-face edge.
  CHECK(three.non_manifold_nodes == 2);
  CHECK(three.inconsistent_edges == 0);
  CHECK(three.degenerate_faces == 0);
  CHECK(mentions(three, "1 non-manifold edge (more than two faces)"));
  CHECK(mentions(three, "2 non-manifold (bow-tie) nodes"));

  // Four faces on (0, 1) and, separately, three faces on (5, 6).
  const auto m = make_mesh({0, 0, 0, 1, 0,    0, 0.5f, 1,    0,  0.5f, -1,   0, 0.5f, 0,    1, 0, 0,
                            5, 1, 0, 5, 0.5f, 1, 5,    0.5f, -1, 5,    0.5f, 0, 6,    0.5f, 0, -1},
                           {0, 1, 2, 1, 0, 3, 0, 1, 4, 1, 0, 10, 5, 6, 7, 6, 5, 8, 5, 6, 9});
  const tear::MeshReport two = validate(m);
  CHECK(two.non_manifold_edges == 2);
  CHECK(two.non_manifold_nodes == 4);
  CHECK(mentions(two, "2 non-manifold edges (more than two faces)"));
}

TEST_CASE("validate_mesh: bow-tie nodes", "[validate]") {
  const tear::MeshReport report = validate(bowtie());
  CHECK(report.non_manifold_nodes == 1);
  CHECK(report.non_manifold_edges == 0);
  CHECK(report.inconsistent_edges == 0);
  CHECK(mentions(report, "1 non-manifold (bow-tie) node"));

  // Two closed fans of four faces meeting at their centre (a double cone): every edge has two
  // faces, still two fans at node 0.
  const auto cones =
      make_mesh({0, 0, 0, 1, 0, 1, 0, 1, 1, -1, 0, 1, 0, -1, 1, 1, 0, -1, 0, 1, -1, -1, 0, -1, 0, -1, -1},
                {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1, 0, 6, 5, 0, 7, 6, 0, 8, 7, 0, 5, 8});
  const tear::MeshReport double_cone = validate(cones);
  CHECK(double_cone.non_manifold_nodes == 1);
  CHECK(double_cone.non_manifold_edges == 0);
  CHECK(double_cone.inconsistent_edges == 0);
}

TEST_CASE("validate_mesh: inconsistently oriented faces", "[validate]") {
  // The quad's second face reversed: both faces run the diagonal from node 2 to node 0.
  auto flipped = quad();
  std::swap(flipped.face_nodes[4], flipped.face_nodes[5]);
  const tear::MeshReport report = validate(flipped);
  CHECK(report.inconsistent_edges == 1);
  CHECK(report.non_manifold_nodes == 0);
  CHECK(mentions(report, "1 edge with inconsistently oriented faces"));

  // One face of the tetrahedron reversed: its three edges disagree with the neighbours.
  auto tet = tetrahedron();
  std::swap(tet.face_nodes[10], tet.face_nodes[11]);
  const tear::MeshReport closed = validate(tet);
  CHECK(closed.inconsistent_edges == 3);
  CHECK(closed.non_manifold_edges == 0);
  CHECK(closed.non_manifold_nodes == 0);
  CHECK(mentions(closed, "3 edges with inconsistently oriented faces"));
}

TEST_CASE("validate_mesh: faces on the same three nodes", "[validate]") {
  // Two faces on one triangle, oppositely oriented: closed, consistently oriented and manifold, but a
  // cut through it leaves the two faces joined at the cut's ends (bow-ties), so it is refused.
  const auto pillow = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 1});
  const tear::MeshReport report = validate(pillow);
  tear::MeshReport expected;
  expected.duplicate_faces = 2;
  CHECK(tear::test::report_counts(report) == tear::test::report_counts(expected));
  CHECK_FALSE(report.ok());
  CHECK(mentions(report, "2 faces on the same three nodes as another face"));
  CHECK(tear::test::report_counts(tear::test::reference_validate_mesh(pillow)) == tear::test::report_counts(expected));

  // The same pair as a component of its own beside a good quad, and nodes listed in another order.
  const auto beside = make_mesh({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 5, 0, 0, 6, 0, 0, 5, 1, 0},
                                {0, 1, 2, 0, 2, 3, 4, 5, 6, 5, 4, 6});
  CHECK(validate(beside).duplicate_faces == 2);
  CHECK(validate(beside).non_manifold_nodes == 0);

  // A quad with one face repeated the other way round: also a fin on each of the face's edges.
  auto doubled = quad();
  doubled.face_nodes.insert(doubled.face_nodes.end(), {0, 2, 1});
  const tear::MeshReport fins = validate(doubled);
  CHECK(fins.duplicate_faces == 2);
  CHECK(fins.non_manifold_edges == 1);
  CHECK(tear::test::report_counts(fins) == tear::test::report_counts(tear::test::reference_validate_mesh(doubled)));

  // Closed surfaces of distinct faces are fine, and a face repeating a node is only degenerate.
  CHECK(validate(tetrahedron()).duplicate_faces == 0);
  CHECK(validate(make_mesh({0, 0, 0, 1, 0, 0}, {0, 0, 1, 0, 1, 0})).duplicate_faces == 0);
}

TEST_CASE("validate_mesh: faces too thin for single precision at their coordinates are not cut", "[validate]") {
  // The fuzz finding: a sliver 0.79 wide reaching a node 3.3e6 away, where float32 has steps of
  // 0.25 (at most 0.397): 2.4e-7 of its longest edge, over the thin limit, but 2 steps. Two cuts
  // left faces of 0.32 of a step, too thin to cut.
  const auto far = make_mesh({0.25f, 0, 0, 1, 0, 0, 0.5f, 0.75f, 0, 1, 0.25f, 3333330.0f}, {0, 1, 2, 0, 2, 3});
  const tear::MeshReport report = validate(far);
  CHECK(report.thin_faces == 0);
  CHECK(report.imprecise_faces == 1);
  CHECK(report.ok());
  CHECK_FALSE(report.cuttable());
  CHECK(mentions(report, "1 face too thin for single precision at its coordinates (height under 8 float32 steps"));
  CHECK(tear::test::report_counts(report) == tear::test::report_counts(tear::test::reference_validate_mesh(far)));
  // The 0.0003 degree sliver of the unit square below is cut at the origin; moved 1000 away, where a
  // step is 6e-5, its 3e-6 height is under one: not cut.
  for (const auto& [offset, imprecise] : {std::pair{0.0f, 0}, std::pair{1000.0f, 1}}) {
    const auto m = make_mesh({offset, 0, 0, offset + 1, 0, 0, offset + 1, 1, 0, offset, 1, 0, offset + 0.5f, 3e-6f, 0},
                             {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4});
    const tear::MeshReport moved = validate(m);
    INFO("offset " << offset);
    CHECK(moved.imprecise_faces == imprecise);
    CHECK(moved.cuttable() == (imprecise == 0));
    CHECK(tear::test::report_counts(moved) == tear::test::report_counts(tear::test::reference_validate_mesh(m)));
  }
}

TEST_CASE("validate_mesh: faces too thin to cut in single precision", "[validate]") {
  // A unit square's bottom side with a node above its middle at 3e-6 (a 0.0003 degree sliver: cut,
  // with a warning) and at 3e-9 (twice the area 3e-9 of the longest edge squared: a cut point on it
  // rounds onto its long side, and cutting it left a degenerate face).
  for (const auto& [height, thin] : {std::pair{3e-6f, 0}, std::pair{3e-9f, 1}}) {
    const auto m = make_mesh({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, height, 0},
                             {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4});
    const tear::MeshReport report = validate(m);
    INFO("height " << height);
    CHECK(report.thin_faces == thin);
    CHECK(report.degenerate_faces == 0);
    CHECK(report.ok() == (thin == 0));
    CHECK(tear::test::report_counts(report) == tear::test::report_counts(tear::test::reference_validate_mesh(m)));
  }
  CHECK(mentions(validate(make_mesh({0, 0, 0, 1, 0, 0, 0.5f, 3e-9f, 0}, {0, 1, 2})),
                 "1 face too thin to cut (height under 1e-7 of its longest edge)"));
}

TEST_CASE("validate_mesh: describe names every non-zero count", "[validate]") {
  tear::MeshReport report;
  report.indices_out_of_range = 1;
  report.non_finite_nodes = 2;
  report.degenerate_faces = 3;
  report.non_manifold_edges = 4;
  report.non_manifold_nodes = 5;
  report.inconsistent_edges = 6;
  report.duplicate_faces = 7;
  report.thin_faces = 8;
  const std::string text = report.describe();
  for (const char* part :
       {"1 face with a node index out of range", "2 nodes with a non-finite coordinate", "3 degenerate faces",
        "4 non-manifold edges", "5 non-manifold (bow-tie) nodes", "6 edges with inconsistently oriented faces",
        "7 faces on the same three nodes as another face", "8 faces too thin to cut"}) {
    INFO(part);
    CHECK(text.find(part) != std::string::npos);
  }
}

TEST_CASE("validate_mesh: the given topology and the convenience overload agree", "[validate]") {
  const auto device = tear::test::test_device();
  for (const tear::Mesh& mesh : {fin(), bowtie(), quad(), tear::test::random_soup(5, {false})}) {
    const tear::MeshReport with_topology = tear::validate_mesh(mesh, tear::build_topology(mesh, device), device);
    CHECK(tear::test::report_counts(with_topology) == tear::test::report_counts(tear::validate_mesh(mesh, device)));
  }
}

TEST_CASE("validate_mesh: matches the serial reference on random meshes", "[validate]") {
  // Faces repeating a node are left out: see "a face repeating a node is only a degenerate face".
  const std::uint64_t seed = tear::test::test_seed(424242);
  std::int64_t defects = 0;
  for (std::uint64_t i = 0; i < 240; ++i) {
    const auto [name, mesh] = tear::test::random_mesh(seed + i, {false});
    INFO("seed " << seed + i << " (" << name << ", " << mesh.node_count() << " nodes, " << mesh.face_count()
                 << " faces)");
    const tear::MeshReport expected = tear::test::reference_validate_mesh(mesh);
    REQUIRE(tear::test::report_counts(validate(mesh)) == tear::test::report_counts(expected));
    defects += expected.ok() ? 0 : 1;
  }
  // The generators must actually exercise the checks.
  CHECK(defects > 60);
}

TEST_CASE("validate_mesh: well-defined counts match the reference with repeated-node faces", "[validate]") {
  const std::uint64_t seed = tear::test::test_seed(99);
  for (std::uint64_t i = 0; i < 120; ++i) {
    const tear::Mesh mesh = tear::test::random_soup(seed + i);
    INFO("seed " << seed + i);
    const tear::MeshReport actual = validate(mesh), expected = tear::test::reference_validate_mesh(mesh);
    CHECK(actual.indices_out_of_range == expected.indices_out_of_range);
    CHECK(actual.non_finite_nodes == expected.non_finite_nodes);
    CHECK(actual.degenerate_faces == expected.degenerate_faces);
    CHECK(actual.non_manifold_edges == expected.non_manifold_edges);
  }
}

TEST_CASE("validate_mesh: random defects are counted like the reference, repeated-node faces included",
          "[validate]") {
  const std::uint64_t seed = tear::test::test_seed(99);
  for (std::uint64_t i = 0; i < 120; ++i) {
    const tear::Mesh mesh = tear::test::random_soup(seed + i);
    INFO("seed " << seed + i);
    REQUIRE(tear::test::report_counts(validate(mesh)) ==
            tear::test::report_counts(tear::test::reference_validate_mesh(mesh)));
  }
}
