// What is allowed but probably not meant: cuts that change nothing, sliver faces.
#include <algorithm>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "cli_support.h"
#include "tear/cut_script.h"
#include "tear/mesh_info.h"
#include "tear/script_warnings.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"
#include "tear/write_mesh.h"
#include "test_support.h"

using tear::test::quoted;
using tear::test::Run;
using tear::test::TempDir;

namespace {

/// A unit square whose bottom side has a node 3e-6 above its middle: the face on the bottom side
/// has an angle of 0.00034 degrees, twice its area 3e-6 of its longest edge squared (far above the
/// degenerate ratio). Blender's fill of an n-gon makes such faces.
tear::Mesh square_with_sliver() {
  tear::Mesh m;
  m.node_pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 3e-6f, 0};
  m.face_nodes = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
  return m;
}

/// The regular 200-face sheet (0.1 m cells) with a script of these cuts.
const char* const cuts_script = R"({ "version": 1, "frames": 2, "cuts": [
  { "frame": 1, "space": "rest-xy", "polyline": [[0.51, 0.51], [0.52, 0.52]] },
  { "frame": 1, "space": "rest-xy", "polyline": [[-0.1, 0.53], [0.56, 0.53]] },
  { "frame": 2, "space": "uv", "polyline": [[3, 3], [4, 4]] },
  { "frame": 2, "blade": { "polyline": [[5, 5, 0], [6, 6, 0]], "direction": [0, 0, 1] } } ] })";

}  // namespace

TEST_CASE("script_warnings: cuts that change nothing on the rest shape, by key path", "[warnings]") {
  const tear::CutScript script = tear::parse_cut_script(cuts_script, "shot.json");
  const auto warnings = tear::script_warnings(script, tear::test::regular_sheet(), "sheet.obj", tear::test::test_device());
  // The 1.4 cm slit lies inside the snap zones of its cell's nodes; the UV cut lies outside [0, 1]².
  // The blade misses the sheet too, but blades cut a pose a simulation moves: not tried.
  REQUIRE(warnings.size() == 2);
  CHECK(warnings[0].rfind("shot.json: cuts[0]: changes nothing on the rest shape of sheet.obj (", 0) == 0);
  CHECK(warnings[1].rfind("shot.json: cuts[2]: changes nothing on the rest shape of sheet.obj (", 0) == 0);
}

TEST_CASE("mesh_info: sliver faces are counted, a warning and not a defect", "[warnings]") {
  const tear::Mesh mesh = square_with_sliver();
  const auto device = tear::test::test_device();
  const tear::MeshReport report = tear::validate_mesh(mesh, device);
  CHECK(report.ok());
  const tear::MeshInfo info = tear::compute_mesh_info(mesh, tear::build_topology(mesh, device), report);
  CHECK(info.sliver_faces == 1);
  CHECK(info.min_angle_deg < 0.001);
  CHECK(nlohmann::json::parse(tear::to_json(info))["sliver_faces"] == 1);
  const tear::CutScript none = tear::parse_cut_script(R"({ "version": 1, "frames": 1 })", "s.json");
  const auto warnings = tear::script_warnings(none, mesh, "fill.obj", device);
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0].rfind("fill.obj: 1 sliver face (an angle under 1 deg, the smallest 0.000344 deg)", 0) == 0);
  CHECK(tear::compute_mesh_info(tear::test::regular_sheet(), tear::build_topology(tear::test::regular_sheet(), device),
                                tear::validate_mesh(tear::test::regular_sheet(), device))
            .sliver_faces == 0);
}

TEST_CASE("validate: warnings on standard error, the script still ok", "[warnings][cli]") {
  TempDir dir;
  const auto mesh = dir / "sheet.obj";
  tear::write_mesh(tear::test::regular_sheet(), mesh.string());
  const auto script = dir.file("shot.json", cuts_script);
  const Run r = dir.tear("validate --device cpu " + quoted(script) + " " + quoted(mesh));
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out == script.string() + ": ok (4 cuts over 2 frames)\n");
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 2);
  CHECK(r.err.find("tear: warning: " + script.string() + ": cuts[0]: changes nothing") == 0);
  CHECK(r.err.find("tear: warning: " + script.string() + ": cuts[2]: changes nothing") != std::string::npos);
  // Without a mesh nothing can be tried: no warning.
  CHECK(dir.tear("validate " + quoted(script)).err.empty());

  const auto fill = dir / "fill.obj";
  tear::write_mesh(square_with_sliver(), fill.string());
  const auto plane = dir.file("plane.json", R"({ "version": 1, "frames": 1,
      "cuts": [ { "frame": 1, "plane": { "point": [0.5, 0.7, 0], "normal": [0, 1, 0] } } ] })");
  const Run sliver = dir.tear("validate --device cpu " + quoted(plane) + " " + quoted(fill));
  CHECK(sliver.exit_code == 0);
  CHECK(sliver.err.rfind("tear: warning: " + fill.string() + ": 1 sliver face (an angle under 1 deg", 0) == 0);
  const Run info = dir.tear("info --device cpu " + quoted(fill));
  CHECK(info.out.find("sliver faces:         1 (an angle under 1 deg") != std::string::npos);
  CHECK(info.out.find("cuttable:             yes, with 1 sliver face (warning: see above)") != std::string::npos);
  CHECK(info.err.empty());
}

TEST_CASE("run: --verbose says when a frame's cuts changed nothing", "[warnings][cli]") {
  TempDir dir;
  const auto mesh = dir / "sheet.obj";
  tear::write_mesh(tear::test::regular_sheet(), mesh.string());
  const auto script = dir.file("shot.json", R"({ "version": 1, "frames": 2, "cuts": [
      { "frame": 1, "space": "rest-xy", "polyline": [[0.51, 0.51], [0.52, 0.52]] },
      { "frame": 2, "space": "rest-xy", "polyline": [[-0.1, 0.53], [0.56, 0.53]] } ] })");
  const Run r = dir.tear("run --device cpu -v " + quoted(mesh) + " " + quoted(script) + " -o " +
                         quoted(dir / "out/f.#.obj"));
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out.rfind("frame 1/2: 1 cut (changed nothing), 121 -> 121 nodes, 200 -> 200 faces, ", 0) == 0);
  CHECK(r.out.find("frame 2/2: 1 cut, 121 -> ") != std::string::npos);
}
