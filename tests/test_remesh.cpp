#include <cmath>

#include "catch.h"
#include "remesh_checks.h"
#include "tear/cloth.h"
#include "tear/make_sheet.h"
#include "test_support.h"

using namespace tear;
using tear::test::check_valid_after_cut;
using tear::test::test_device;
using tear::test::total_area;

namespace {

CutLine rest_xy(std::vector<std::array<double, 2>> points) {
  CutLine line;
  line.source = CutLine::Source::node_rest;
  line.polyline = std::move(points);
  return line;
}

Mesh regular_sheet(index_t faces) {
  SheetOptions o;
  o.face_count = faces;
  o.irregular = false;
  return make_sheet(o);
}

}  // namespace

TEST_CASE("remesh: a straight cut across the sheet makes two pieces") {
  const Mesh mesh = regular_sheet(200);
  Cloth cloth(mesh, test_device());
  const double area = total_area(mesh);
  const CutStats stats = cloth.cut({rest_xy({{-0.1, 0.55}, {1.1, 0.55}})});
  CHECK(stats.nodes_after > stats.nodes_before);
  const MeshInfo info = check_valid_after_cut(cloth, area, test_device());
  CHECK(info.components == 2);
  CHECK(info.boundary_loops == 2);
}

TEST_CASE("remesh: a cut missing the mesh changes nothing") {
  const Mesh mesh = regular_sheet(200);
  Cloth cloth(mesh, test_device());
  const CutStats stats = cloth.cut({rest_xy({{2, 2}, {3, 3}})});
  CHECK(stats.nodes_after == stats.nodes_before);
  CHECK(stats.faces_after == stats.faces_before);
  CHECK(cloth.mesh().face_nodes == mesh.face_nodes);
}

TEST_CASE("remesh: a slit inside the cloth opens a hole") {
  const Mesh mesh = regular_sheet(200);
  Cloth cloth(mesh, test_device());
  const double area = total_area(mesh);
  cloth.cut({rest_xy({{0.23, 0.37}, {0.71, 0.58}})});
  const MeshInfo info = check_valid_after_cut(cloth, area, test_device());
  CHECK(info.components == 1);
  CHECK(info.boundary_loops == 2);
}

TEST_CASE("remesh: a slit from the border") {
  const Mesh mesh = regular_sheet(200);
  Cloth cloth(mesh, test_device());
  const double area = total_area(mesh);
  cloth.cut({rest_xy({{-0.1, 0.43}, {0.62, 0.47}})});
  const MeshInfo info = check_valid_after_cut(cloth, area, test_device());
  CHECK(info.components == 1);
  CHECK(info.boundary_loops == 1);
}

TEST_CASE("remesh: two crossing cuts in one frame make four pieces") {
  const Mesh mesh = regular_sheet(200);
  Cloth cloth(mesh, test_device());
  const double area = total_area(mesh);
  cloth.cut({rest_xy({{-0.1, 0.53}, {1.1, 0.41}}), rest_xy({{0.47, -0.1}, {0.61, 1.1}})});
  const MeshInfo info = check_valid_after_cut(cloth, area, test_device());
  CHECK(info.components == 4);
}

TEST_CASE("remesh: the paper's scene stays valid frame after frame") {
  const CutScript script = read_cut_script(tear::test::source_path("examples/paper_scene.json"));
  for (index_t faces : {2822, 9022}) {
    SheetOptions o;
    o.face_count = faces;
    const Mesh mesh = make_sheet(o);
    Cloth cloth(mesh, test_device());
    const double area = total_area(mesh);
    for (int frame = 1; frame <= script.frames; ++frame) {
      std::vector<CutLine> lines;
      for (const Cut* cut : script.cuts_of_frame(frame)) lines.push_back(to_cut_line(*cut));
      INFO("faces " << faces << ", frame " << frame);
      const CutStats stats = cloth.cut(lines, {script.snap});
      CHECK(stats.faces_after > stats.faces_before);
      const MeshInfo info = check_valid_after_cut(cloth, area, test_device());
      // Slits that never reach the border leave one piece, except that where five or six cuts
      // cross at one point (finer than one element: one cut point per edge and face) a fragment
      // of a few faces may come loose.
      const std::vector<double> pieces = tear::test::component_areas(cloth.mesh());
      const double typical_face = area / faces;
      CHECK(pieces.front() > area - 4 * typical_face);
      if (frame <= 4) CHECK(pieces.size() == 1);
      CHECK(info.min_angle_deg >= 5.0);  // the quality snap's angle (CutOptions::quality_angle_deg)
    }
  }
}
