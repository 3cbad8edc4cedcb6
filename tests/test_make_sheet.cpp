#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <omp.h>

#include "catch.h"
#include "tear/error.h"
#include "tear/make_sheet.h"
#include "tear/read_mesh.h"
#include "tear/run_cuts.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"
#include "tear/write_mesh.h"
#include "test_support.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Point {
  double x, y, z;
};

Point node_point(const tear::Mesh& mesh, tear::index_t node) {
  const auto* p = &mesh.node_pos[3 * static_cast<std::size_t>(node)];
  return {p[0], p[1], p[2]};
}

Point face_corner(const tear::Mesh& mesh, std::size_t face, int k) {
  return node_point(mesh, mesh.face_nodes[3 * face + static_cast<std::size_t>(k)]);
}

Point sub(Point a, Point b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Point cross(Point a, Point b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(Point a, Point b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm(Point a) { return std::sqrt(dot(a, a)); }

// Signed area of the face's projection on the XY plane (positive: counter-clockwise seen from +z).
double signed_xy_area(const tear::Mesh& mesh, std::size_t face) {
  const Point a = face_corner(mesh, face, 0);
  const Point b = face_corner(mesh, face, 1);
  const Point c = face_corner(mesh, face, 2);
  return 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
}

double total_area(const tear::Mesh& mesh) {
  double area = 0.0;
  for (std::size_t f = 0; f < static_cast<std::size_t>(mesh.face_count()); ++f) {
    area += 0.5 * norm(cross(sub(face_corner(mesh, f, 1), face_corner(mesh, f, 0)),
                             sub(face_corner(mesh, f, 2), face_corner(mesh, f, 0))));
  }
  return area;
}

double min_angle_deg(const tear::Mesh& mesh) {
  double smallest = 180.0;
  for (std::size_t f = 0; f < static_cast<std::size_t>(mesh.face_count()); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Point o = face_corner(mesh, f, k);
      const Point u = sub(face_corner(mesh, f, (k + 1) % 3), o);
      const Point v = sub(face_corner(mesh, f, (k + 2) % 3), o);
      smallest = std::min(smallest, std::atan2(norm(cross(u, v)), dot(u, v)) * 180.0 / kPi);
    }
  }
  return smallest;
}

// n of the n x n grid and k centre nodes, as documented in make_sheet.h.
struct GridShape {
  std::int64_t n, k;
};
GridShape grid_shape(std::int64_t face_count) {
  std::int64_t n = 1;
  while (2 * (n + 1) * (n + 1) <= face_count) ++n;
  return {n, face_count / 2 - n * n};
}

tear::ErrorKind error_kind_of(const tear::SheetOptions& options) {
  try {
    tear::make_sheet(options);
  } catch (const tear::Error& e) {
    return e.kind();
  }
  return tear::ErrorKind::runtime;  // no error: not what the callers expect
}

tear::ErrorKind error_kind_of(const tear::TubeOptions& options) {
  try {
    tear::make_tube(options);
  } catch (const tear::Error& e) {
    return e.kind();
  }
  return tear::ErrorKind::runtime;
}

std::int64_t boundary_edge_count(const tear::Topology& topology) {
  return std::count(topology.edge_boundary.begin(), topology.edge_boundary.end(), std::uint8_t{1});
}

}  // namespace

TEST_CASE("make_sheet: the paper's Table 1 sizes are exact", "[sheet]") {
  struct Expected {
    tear::index_t face_count, node_count;
  };
  // 2822 = 2 (37^2 - 42) + 4 * 42, 9022 = 2 (67^2 - 22) + 4 * 22, 38298 = 2 (138^2 - 105) + 4 * 105.
  const Expected sizes[] = {{2822, 38 * 38 + 42}, {9022, 68 * 68 + 22}, {38298, 139 * 139 + 105}};
  for (const Expected& expected : sizes) {
    for (bool irregular : {true, false}) {
      INFO("faces " << expected.face_count << (irregular ? " irregular" : " regular"));
      tear::SheetOptions options;
      options.face_count = expected.face_count;
      options.irregular = irregular;
      const tear::Mesh mesh = tear::make_sheet(options);
      CHECK(mesh.face_count() == expected.face_count);
      CHECK(mesh.node_count() == expected.node_count);
      CHECK(mesh.corner_uv.size() == 6 * static_cast<std::size_t>(expected.face_count));
      CHECK(mesh.corner_normal.size() == 9 * static_cast<std::size_t>(expected.face_count));
      const tear::MeshReport report = tear::validate_mesh(mesh, tear::test::test_device());
      INFO(report.describe());
      CHECK(report.ok());
    }
  }
}

TEST_CASE("make_sheet: every even count but 6 is exact and valid", "[sheet]") {
  const tear::index_t counts[] = {2, 4, 8, 10, 12, 14, 16, 18, 20, 22, 34, 50, 98, 100, 998, 1000, 4096, 65536, 99998};
  for (tear::index_t face_count : counts) {
    for (bool irregular : {true, false}) {
      INFO("faces " << face_count << (irregular ? " irregular" : " regular"));
      tear::SheetOptions options;
      options.face_count = face_count;
      options.irregular = irregular;
      const tear::Mesh mesh = tear::make_sheet(options);
      const GridShape shape = grid_shape(face_count);
      CHECK(mesh.face_count() == face_count);
      CHECK(mesh.node_count() == (shape.n + 1) * (shape.n + 1) + shape.k);
      const tear::MeshReport report = tear::validate_mesh(mesh, tear::test::test_device());
      INFO(report.describe());
      CHECK(report.ok());
    }
  }
}

TEST_CASE("make_sheet: a million faces", "[sheet]") {
  tear::SheetOptions options;
  options.face_count = 1048576;
  const tear::Mesh mesh = tear::make_sheet(options);
  CHECK(mesh.face_count() == 1048576);
  CHECK(std::abs(total_area(mesh) - 1.0) <= 1e-9);
  CHECK(tear::validate_mesh(mesh, tear::test::test_device()).ok());
}

TEST_CASE("make_sheet: total area is size squared", "[sheet]") {
  const std::uint64_t seed = tear::test::test_seed(11);
  INFO("seed " << seed);
  for (double size : {1.0, 2.5, 0.3, 7.0}) {
    for (tear::index_t face_count : {2, 18, 2822, 9022}) {
      for (bool irregular : {true, false}) {
        INFO("size " << size << " faces " << face_count << (irregular ? " irregular" : " regular"));
        tear::SheetOptions options;
        options.face_count = face_count;
        options.irregular = irregular;
        options.seed = seed;
        options.size = size;
        const tear::Mesh mesh = tear::make_sheet(options);
        // The outline is exactly the square of side float(size).
        const double side = static_cast<float>(size);
        CHECK(std::abs(total_area(mesh) - side * side) <= 1e-9 * side * side);
        for (std::size_t f = 0; f < static_cast<std::size_t>(mesh.face_count()); ++f) {
          if (signed_xy_area(mesh, f) <= 0.0) FAIL("face " << f << " is not counter-clockwise");
        }
      }
    }
  }
}

TEST_CASE("make_sheet: smallest angle stays above the stated bound", "[sheet]") {
  const std::uint64_t first_seed = tear::test::test_seed(1);
  double smallest = 180.0;
  for (std::uint64_t seed = first_seed; seed < first_seed + 20; ++seed) {
    INFO("seed " << seed);
    for (tear::index_t face_count : {50, 2822, 38298}) {
      tear::SheetOptions options;
      options.face_count = face_count;
      options.seed = seed;
      const double angle = min_angle_deg(tear::make_sheet(options));
      CHECK(angle >= tear::sheet_min_angle_deg);
      smallest = std::min(smallest, angle);
    }
  }
  // The jitter is real: some triangle is well below the regular grid's 45 degrees.
  CHECK(smallest < 40.0);

  tear::SheetOptions regular;
  regular.irregular = false;
  for (tear::index_t face_count : {2, 8, 2822, 9022}) {
    regular.face_count = face_count;
    CHECK(min_angle_deg(tear::make_sheet(regular)) >= 45.0 - 1e-2);  // float rounding of the node positions
  }
}

TEST_CASE("make_sheet: uv is position over size and normals are +z at every corner", "[sheet]") {
  for (double size : {1.0, 3.0, 0.3}) {
    for (bool irregular : {true, false}) {
      tear::SheetOptions options;
      options.face_count = 9022;
      options.irregular = irregular;
      options.size = size;
      const tear::Mesh mesh = tear::make_sheet(options);
      REQUIRE(mesh.has_uv());
      REQUIRE(mesh.has_normals());
      for (std::size_t corner = 0; corner < mesh.face_nodes.size(); ++corner) {
        const Point p = node_point(mesh, mesh.face_nodes[corner]);
        const double u = mesh.corner_uv[2 * corner + 0];
        const double v = mesh.corner_uv[2 * corner + 1];
        if (std::abs(u - p.x / size) > 1e-7 || std::abs(v - p.y / size) > 1e-7 || p.z != 0.0) {
          FAIL("corner " << corner << ": uv (" << u << ", " << v << ") at (" << p.x << ", " << p.y << ", " << p.z
                         << ") with size " << size);
        }
        const float* normal = &mesh.corner_normal[3 * corner];
        if (normal[0] != 0.0f || normal[1] != 0.0f || normal[2] != 1.0f) FAIL("corner " << corner << ": normal not +z");
      }
    }
  }
}

TEST_CASE("make_sheet: the same options give the same mesh, another seed another one", "[sheet]") {
  tear::SheetOptions options;
  options.face_count = 38298;
  options.seed = tear::test::test_seed(5);
  INFO("seed " << options.seed);
  const tear::Mesh first = tear::make_sheet(options);
  const tear::Mesh second = tear::make_sheet(options);
  CHECK(first.node_pos == second.node_pos);
  CHECK(first.face_nodes == second.face_nodes);
  CHECK(first.corner_uv == second.corner_uv);
  CHECK(first.corner_normal == second.corner_normal);

  options.seed += 1;
  const tear::Mesh other = tear::make_sheet(options);
  CHECK(other.face_count() == first.face_count());
  CHECK(other.node_pos != first.node_pos);
  CHECK(other.face_nodes != first.face_nodes);

  // The regular sheet ignores the seed.
  options.irregular = false;
  const tear::Mesh regular = tear::make_sheet(options);
  options.seed += 1;
  CHECK(tear::make_sheet(options).node_pos == regular.node_pos);
  CHECK(tear::make_sheet(options).face_nodes == regular.face_nodes);
}

TEST_CASE("make_sheet: the border is exactly the square", "[sheet]") {
  const std::uint64_t seed = tear::test::test_seed(3);
  INFO("seed " << seed);
  for (tear::index_t face_count : {2, 10, 2822, 38298}) {
    for (bool irregular : {true, false}) {
      INFO("faces " << face_count << (irregular ? " irregular" : " regular"));
      tear::SheetOptions options;
      options.face_count = face_count;
      options.irregular = irregular;
      options.seed = seed;
      options.size = 2.0;
      const tear::Mesh mesh = tear::make_sheet(options);
      const tear::Topology topology = tear::build_topology(mesh, tear::test::test_device());
      const std::int64_t n = grid_shape(face_count).n;
      CHECK(boundary_edge_count(topology) == 4 * n);

      std::int64_t boundary_nodes = 0;
      std::int64_t corners = 0;
      for (tear::index_t node = 0; node < mesh.node_count(); ++node) {
        const Point p = node_point(mesh, node);
        const bool on_x = p.x == 0.0 || p.x == 2.0;
        const bool on_y = p.y == 0.0 || p.y == 2.0;
        CHECK(p.x >= 0.0);
        CHECK(p.x <= 2.0);
        CHECK(p.y >= 0.0);
        CHECK(p.y <= 2.0);
        if (topology.node_boundary[static_cast<std::size_t>(node)]) {
          ++boundary_nodes;
          if (!(on_x || on_y)) FAIL("boundary node " << node << " at (" << p.x << ", " << p.y << ") is inside");
          if (on_x && on_y) ++corners;
        } else if (on_x || on_y) {
          FAIL("interior node " << node << " at (" << p.x << ", " << p.y << ") is on the border");
        }
      }
      CHECK(boundary_nodes == 4 * n);
      CHECK(corners == 4);
    }
  }
}

TEST_CASE("make_sheet: irregular sheets jitter nodes and mix diagonals and centre nodes", "[sheet]") {
  tear::SheetOptions options;
  options.face_count = 2822;  // 37 x 37 quads, 42 with a centre node
  const tear::Mesh mesh = tear::make_sheet(options);
  const double cell = 1.0 / 37.0;
  std::int64_t off_grid = 0;
  std::int64_t border_slid = 0;
  for (std::int64_t j = 0; j <= 37; ++j) {
    for (std::int64_t i = 0; i <= 37; ++i) {
      const Point p = node_point(mesh, static_cast<tear::index_t>(j * 38 + i));
      const double dx = p.x - cell * static_cast<double>(i);
      const double dy = p.y - cell * static_cast<double>(j);
      // Within a quarter cell of its grid point, plus float rounding.
      CHECK(std::hypot(dx, dy) <= 0.25 * cell + 1e-6);
      const bool border = i == 0 || i == 37 || j == 0 || j == 37;
      if (!border && std::hypot(dx, dy) > 0.01 * cell) ++off_grid;
      if (border && std::hypot(dx, dy) > 0.01 * cell) ++border_slid;
    }
  }
  CHECK(off_grid > 36 * 36 * 9 / 10);
  CHECK(border_slid > 4 * 36 * 9 / 10);

  // Centre nodes: valence 4; grid interior nodes: 4 to 8 faces. Both diagonals appear.
  const tear::Topology topology = tear::build_topology(mesh, tear::test::test_device());
  std::int64_t four_valent_inside = 0;
  for (tear::index_t node = 38 * 38; node < mesh.node_count(); ++node) {
    const auto begin = topology.node_face_offset[static_cast<std::size_t>(node)];
    const auto end = topology.node_face_offset[static_cast<std::size_t>(node) + 1];
    if (end - begin == 4 && !topology.node_boundary[static_cast<std::size_t>(node)]) ++four_valent_inside;
  }
  CHECK(four_valent_inside == 42);
  std::int64_t diagonal_ac = 0;
  std::int64_t diagonal_bd = 0;
  for (std::size_t f = 0; f < static_cast<std::size_t>(mesh.face_count()); ++f) {
    const tear::index_t a = mesh.face_nodes[3 * f];
    const tear::index_t b = mesh.face_nodes[3 * f + 1];
    const tear::index_t c = mesh.face_nodes[3 * f + 2];
    if (a < 38 * 38 && b == a + 1 && c == a + 39) ++diagonal_ac;
    if (a < 38 * 38 && b == a + 1 && c == a + 38) ++diagonal_bd;
  }
  CHECK(diagonal_ac + diagonal_bd == 37 * 37 - 42);
  CHECK(diagonal_ac > 500);
  CHECK(diagonal_bd > 500);
}

TEST_CASE("make_sheet: counts and sizes that cannot be made are usage errors", "[sheet]") {
  for (tear::index_t face_count : {-2, 0, 1, 3, 5, 6, 7, 2823}) {
    INFO("faces " << face_count);
    tear::SheetOptions options;
    options.face_count = face_count;
    CHECK(error_kind_of(options) == tear::ErrorKind::usage);
  }
  for (double size : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    INFO("size " << size);
    tear::SheetOptions options;
    options.size = size;
    CHECK(error_kind_of(options) == tear::ErrorKind::usage);
  }
}

TEST_CASE("make_tube: split seam as exporters write it", "[sheet]") {
  tear::TubeOptions options;
  options.segments = 12;
  options.rings = 5;
  options.radius = 0.5;
  options.length = 2.0;
  const tear::Mesh mesh = tear::make_tube(options);
  CHECK(mesh.node_count() == 13 * 6);
  CHECK(mesh.face_count() == 2 * 12 * 5);
  const tear::MeshReport report = tear::validate_mesh(mesh, tear::test::test_device());
  INFO(report.describe());
  CHECK(report.ok());

  // The u = 1 column repeats the u = 0 column bit for bit, and nothing else coincides.
  for (tear::index_t r = 0; r <= 5; ++r) {
    for (int axis = 0; axis < 3; ++axis) {
      CHECK(mesh.node_pos[3 * static_cast<std::size_t>(r * 13) + axis] ==
            mesh.node_pos[3 * static_cast<std::size_t>(r * 13 + 12) + axis]);
    }
  }
  // Unwelded, the seam is cut open: the two end circles plus both sides of the seam.
  const tear::Topology topology = tear::build_topology(mesh, tear::test::test_device());
  CHECK(boundary_edge_count(topology) == 2 * 12 + 2 * 5);

  for (tear::index_t node = 0; node < mesh.node_count(); ++node) {
    const Point p = node_point(mesh, node);
    CHECK(std::hypot(p.x, p.z) == Approx(0.5).epsilon(1e-6));
    CHECK(p.y >= 0.0);
    CHECK(p.y <= 2.0);
  }
  // Faces point outwards: the face normal agrees with the radial direction at its centroid.
  for (std::size_t f = 0; f < static_cast<std::size_t>(mesh.face_count()); ++f) {
    const Point a = face_corner(mesh, f, 0);
    const Point b = face_corner(mesh, f, 1);
    const Point c = face_corner(mesh, f, 2);
    const Point normal = cross(sub(b, a), sub(c, a));
    const Point radial = {(a.x + b.x + c.x) / 3.0, 0.0, (a.z + b.z + c.z) / 3.0};
    if (dot(normal, radial) <= 0.0) FAIL("face " << f << " points inwards");
  }
  // Polygonal cross-section: 12 chords of 2 r sin(pi / 12), times the length.
  CHECK(total_area(mesh) == Approx(12 * 2 * 0.5 * std::sin(kPi / 12) * 2.0).epsilon(1e-6));
}

TEST_CASE("make_tube: welded tube is one closed band", "[sheet]") {
  tear::TubeOptions options;
  options.segments = 7;
  options.rings = 3;
  options.welded = true;
  const tear::Mesh mesh = tear::make_tube(options);
  CHECK(mesh.node_count() == 7 * 4);
  CHECK(mesh.face_count() == 2 * 7 * 3);
  const tear::MeshReport report = tear::validate_mesh(mesh, tear::test::test_device());
  INFO(report.describe());
  CHECK(report.ok());
  const tear::Topology topology = tear::build_topology(mesh, tear::test::test_device());
  CHECK(boundary_edge_count(topology) == 2 * 7);
  CHECK(topology.edge_count == 7 * 4 + 7 * 3 + 7 * 3);  // rings, columns, diagonals
  std::int64_t boundary_nodes = 0;
  for (std::uint8_t flag : topology.node_boundary) boundary_nodes += flag;
  CHECK(boundary_nodes == 2 * 7);
}

TEST_CASE("make_tube: welded and split tubes agree on geometry, uv and normals", "[sheet]") {
  tear::TubeOptions options;
  options.segments = 9;
  options.rings = 4;
  const tear::Mesh split = tear::make_tube(options);
  options.welded = true;
  const tear::Mesh welded = tear::make_tube(options);
  REQUIRE(split.face_count() == welded.face_count());
  CHECK(split.corner_uv == welded.corner_uv);
  CHECK(split.corner_normal == welded.corner_normal);
  bool seam_u_one = false;
  for (std::size_t corner = 0; corner < split.face_nodes.size(); ++corner) {
    const Point p = node_point(split, split.face_nodes[corner]);
    const Point q = node_point(welded, welded.face_nodes[corner]);
    CHECK(p.x == q.x);
    CHECK(p.y == q.y);
    CHECK(p.z == q.z);
    // The UV seam survives welding: corners at the seam position carry u = 0 or u = 1.
    if (split.face_nodes[corner] % 10 == 9) {
      CHECK(split.corner_uv[2 * corner] == 1.0f);
      seam_u_one = true;
    }
    const float u = split.corner_uv[2 * corner];
    const float v = split.corner_uv[2 * corner + 1];
    CHECK(u >= 0.0f);
    CHECK(u <= 1.0f);
    CHECK(v == Approx(p.y / options.length).margin(1e-6));
    const float* normal = &split.corner_normal[3 * corner];
    CHECK(normal[0] == Approx(p.x / options.radius).margin(1e-6));
    CHECK(normal[1] == 0.0f);
    CHECK(normal[2] == Approx(p.z / options.radius).margin(1e-6));
  }
  CHECK(seam_u_one);
}

TEST_CASE("make_tube: bad options are usage errors", "[sheet]") {
  tear::TubeOptions options;
  options.segments = 2;
  CHECK(error_kind_of(options) == tear::ErrorKind::usage);
  options = {};
  options.rings = 0;
  CHECK(error_kind_of(options) == tear::ErrorKind::usage);
  options = {};
  options.radius = 0.0;
  CHECK(error_kind_of(options) == tear::ErrorKind::usage);
  options = {};
  options.length = std::nan("");
  CHECK(error_kind_of(options) == tear::ErrorKind::usage);
  CHECK(tear::make_tube({}).face_count() == 2 * 32 * 16);
}

// The example meshes of examples/meshes/ that come from the generators. Hidden: run it on purpose
// with `tear_tests "[.generate-examples]"`, then review and commit the files.
TEST_CASE("examples: generate the sheet and tube meshes", "[.generate-examples]") {
  struct Sheet {
    const char* name;
    tear::index_t face_count;
  };
  // The paper's Table 1 resolutions.
  for (const Sheet& sheet : {Sheet{"sheet_low", 2822}, Sheet{"sheet_medium", 9022}, Sheet{"sheet_high", 38298}}) {
    tear::SheetOptions options;
    options.face_count = sheet.face_count;
    options.seed = 1;
    tear::write_mesh(tear::make_sheet(options),
                     tear::test::source_path(std::string("examples/meshes/") + sheet.name + ".obj"));
  }
  tear::write_mesh(tear::make_tube({}), tear::test::source_path("examples/meshes/tube.gltf"));
}

TEST_CASE("examples: the example meshes read back as examples/README.md describes", "[sheet]") {
  struct Example {
    const char* path;
    tear::index_t node_count, face_count;
    std::int64_t boundary_edges;
  };
  const Example examples[] = {
      {"examples/meshes/sheet_low.obj", 38 * 38 + 42, 2822, 4 * 37},
      {"examples/meshes/sheet_medium.obj", 68 * 68 + 22, 9022, 4 * 67},
      {"examples/meshes/sheet_high.obj", 139 * 139 + 105, 38298, 4 * 138},
      // Plane: 3 x 2 quads, its UV seam welded; tent: an open hexagonal pyramid.
      {"examples/meshes/blender_like.obj", 12 + 7, 2 * 6 + 6, 10 + 6},
      // Welded on import: 32 around, 17 rings of nodes; only the two end circles are open.
      {"examples/meshes/tube.gltf", 32 * 17, 2 * 32 * 16, 2 * 32},
  };
  for (const Example& example : examples) {
    INFO(example.path);
    const tear::Mesh mesh = tear::read_mesh(tear::test::source_path(example.path));
    CHECK(mesh.node_count() == example.node_count);
    CHECK(mesh.face_count() == example.face_count);
    CHECK(mesh.has_uv());
    CHECK(mesh.has_normals());
    const tear::MeshReport report = tear::validate_mesh(mesh, tear::test::test_device());
    INFO(report.describe());
    CHECK(report.ok());
    CHECK(boundary_edge_count(tear::build_topology(mesh, tear::test::test_device())) == example.boundary_edges);
  }

  // The sheets are make_sheet's output with seed 1, up to the OBJ round trip (which may renumber
  // the nodes, so corners are compared by position).
  const tear::Mesh generated = tear::make_sheet({});
  const tear::Mesh low = tear::read_mesh(tear::test::source_path("examples/meshes/sheet_low.obj"));
  REQUIRE(low.face_count() == generated.face_count());
  for (std::size_t corner = 0; corner < generated.face_nodes.size(); ++corner) {
    const Point p = node_point(low, low.face_nodes[corner]);
    const Point q = node_point(generated, generated.face_nodes[corner]);
    if (p.x != q.x || p.y != q.y || p.z != q.z) FAIL("corner " << corner << " differs from make_sheet's");
  }
}

TEST_CASE("make_sheet: the report's smallest angle is the sheet's, the same on any number of threads", "[sheet][report]") {
  tear::SheetOptions options;
  options.face_count = 40000;  // above the size the measurement is split among threads at
  const tear::Mesh sheet = tear::make_sheet(options);
  const double expected = min_angle_deg(sheet);
  const int available = omp_get_max_threads();
  for (int threads : {1, 2, 3, 8}) {
    INFO(threads << " threads");
    omp_set_num_threads(threads);
    const double angle = tear::min_face_angle_deg(sheet.face_nodes, sheet.node_pos);
    CHECK(angle == Approx(expected).epsilon(1e-12));
    omp_set_num_threads(1);
    CHECK(angle == tear::min_face_angle_deg(sheet.face_nodes, sheet.node_pos));
  }
  omp_set_num_threads(available);
  // Degenerate faces only: no angle.
  CHECK(std::isnan(tear::min_face_angle_deg({0, 1, 2}, {0, 0, 0, 1, 1, 1, 2, 2, 2})));
}
