// `tear run` and `tear validate`: the frame loop through the library and through the binary.
#include <stdlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "catch.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "tear/make_sheet.h"
#include "tear/read_mesh.h"
#include "tear/run_cuts.h"
#include "tear/validate_mesh.h"
#include "tear/write_mesh.h"
#include "cli_support.h"
#include "test_support.h"

namespace fs = std::filesystem;
using tear::test::test_device;

using tear::test::quoted;
using tear::test::read_bytes;
using tear::test::regular_sheet;
using tear::test::Run;
using tear::test::TempDir;

namespace {

std::size_t count_lines_starting(const std::string& text, const std::string& prefix) {
  std::size_t count = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(prefix, 0) == 0) ++count;
  return count;
}

/// The four kinds of cut, one per frame, off the sheet's grid lines (a 10 x 10 grid of 0.1 m).
const char* const four_kinds_script = R"({ "version": 1, "frames": 4, "cuts": [
  { "frame": 1, "space": "rest-xy", "polyline": [[-0.1, 0.53], [0.56, 0.53]] },
  { "frame": 2, "space": "uv", "polyline": [[0.47, -0.1], [0.47, 0.33]] },
  { "frame": 3, "blade": { "polyline": [[0.74, 0, -1], [0.74, 0, 2]], "direction": [0, 1, 0] } },
  { "frame": 4, "plane": { "point": [0, 0.86, 0], "normal": [0, 1, 0] } } ] })";

/// Folder with the 200-face sheet (`sheet.obj`) and the four-kinds script (`script.json`).
struct RunFixture {
  TempDir dir;
  fs::path mesh, script, out;
  std::string device = tear::to_string(test_device());
  RunFixture() {
    mesh = dir / "sheet.obj";
    tear::write_mesh(regular_sheet(), mesh.string());
    script = dir.file("script.json", four_kinds_script);
    out = dir / "out";
  }
  Run run(const std::string& more) const {
    return dir.tear("run --device " + device + " " + quoted(mesh) + " " + quoted(script) + " " + more);
  }
  Run run_into(const fs::path& folder) const { return run("-o " + quoted(folder / "cloth.####.obj")); }
};

std::vector<std::string> file_names(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

/// A failed run: the exit code, one line on stderr naming `name`, nothing on stdout, no output folder.
void check_refused(const Run& run, int exit_code, const std::string& name, const fs::path& out) {
  INFO("stderr: " << run.err);
  CHECK(run.exit_code == exit_code);
  CHECK(run.out.empty());
  CHECK(count_lines_starting(run.err, "tear: ") == 1);
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK(run.err.find(name) != std::string::npos);
  CHECK_FALSE(fs::exists(out));
}

/// One frame, one cut: the plane x = 0, which applies to any mesh.
const char* const one_plane_script =
    R"({ "version": 1, "frames": 1,
         "cuts": [ { "frame": 1, "plane": { "point": [0, 0, 0], "normal": [1, 0, 0] } } ] })";

/// Three triangles on one edge: a fin, which the remesher cannot cut.
const char* const fin_obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";

}  // namespace

TEST_CASE("run_cuts: frame by frame, each frame valid, frame 1 adds faces", "[run]") {
  const tear::Mesh mesh = regular_sheet();
  const tear::CutScript script = tear::parse_cut_script(four_kinds_script, "script.json");
  tear::Cloth cloth(mesh, test_device());
  std::vector<int> frames;
  tear::run_cuts(cloth, script, script.frames, [&](const tear::FrameResult& frame, const tear::Cloth& cut) {
    INFO("frame " << frame.frame);
    frames.push_back(frame.frame);
    CHECK(frame.cut_count == 1);
    CHECK(frame.path.empty());
    CHECK(frame.stats.faces_after > frame.stats.faces_before);
    CHECK(frame.stats.faces_after == cut.face_count());
    const tear::MeshReport report = tear::validate_mesh(cut.mesh(), test_device());
    INFO(report.describe());
    CHECK(report.ok());
  });
  CHECK(frames == std::vector<int>{1, 2, 3, 4});
}

TEST_CASE("run_cuts: frames without cuts leave the cloth as it is", "[run]") {
  const tear::CutScript script = tear::parse_cut_script(
      R"({ "version": 1, "frames": 3,
           "cuts": [ { "frame": 2, "space": "rest-xy", "polyline": [[-1, 0.47], [2, 0.47]] } ] })",
      "s.json");
  const tear::Mesh mesh = regular_sheet();
  tear::Cloth cloth(mesh, test_device());
  std::vector<tear::index_t> faces;
  tear::run_cuts(cloth, script, 3, [&](const tear::FrameResult& frame, const tear::Cloth& cut) {
    CHECK(frame.cut_count == (frame.frame == 2 ? 1 : 0));
    faces.push_back(cut.face_count());
  });
  REQUIRE(faces.size() == 3);
  CHECK(faces[0] == mesh.face_count());
  CHECK(faces[1] > faces[0]);
  CHECK(faces[2] == faces[1]);
}

TEST_CASE("run_cuts: a frame count outside the script is a usage error", "[run]") {
  const tear::CutScript script = tear::parse_cut_script(four_kinds_script, "script.json");
  tear::Cloth cloth(regular_sheet(), test_device());
  for (int frames : {0, 5}) {
    try {
      tear::run_cuts(cloth, script, frames, {});
      FAIL("no error for " << frames << " frames");
    } catch (const tear::Error& e) {
      CHECK(e.kind() == tear::ErrorKind::usage);
      CHECK(std::string(e.what()).find("script.json") != std::string::npos);
    }
  }
}

TEST_CASE("run_to_files: one file per frame, named by the pattern", "[run]") {
  TempDir dir;
  const tear::CutScript script = tear::parse_cut_script(four_kinds_script, "script.json");
  tear::RunOptions options;
  options.output_pattern = (dir / "out/f{frame:02}/cloth.##.ply").string();
  options.device = test_device();
  std::vector<std::string> paths;
  options.on_frame = [&](const tear::FrameResult& frame) {
    paths.push_back(frame.path);
    REQUIRE(fs::exists(frame.path));
    CHECK(tear::read_mesh(frame.path).face_count() == frame.faces_end);
  };
  tear::run_to_files(regular_sheet(), "sheet", script, options);
  CHECK(paths ==
        std::vector<std::string>{(dir / "out/f01/cloth.01.ply").string(), (dir / "out/f02/cloth.02.ply").string(),
                                 (dir / "out/f03/cloth.03.ply").string(), (dir / "out/f04/cloth.04.ply").string()});
}

TEST_CASE("run_to_files: a mesh that cannot be cut is refused before any output", "[run]") {
  TempDir dir;
  const fs::path fin = dir.file("fin.obj", fin_obj);
  const tear::CutScript script = tear::parse_cut_script(one_plane_script, "script.json");
  tear::RunOptions options;
  options.output_pattern = (dir / "out/cloth.####.obj").string();
  options.device = test_device();
  const tear::Mesh mesh = tear::read_mesh(fin.string());
  try {
    tear::run_to_files(mesh, fin.string(), script, options);
    FAIL("no error");
  } catch (const tear::Error& e) {
    CHECK(e.kind() == tear::ErrorKind::input);
    CHECK(std::string(e.what()).rfind(fin.string() + ": cannot be cut: ", 0) == 0);
    CHECK(std::string(e.what()).find("non-manifold") != std::string::npos);
  }
  CHECK_FALSE(fs::exists(dir / "out"));
}

TEST_CASE("run: four cut kinds write four frames, frame 1 with more faces", "[run]") {
  RunFixture fixture;
  const Run run = fixture.run_into(fixture.out);
  INFO("stderr: " << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK(run.out.empty());  // quiet by default
  CHECK(run.err.empty());
  CHECK(file_names(fixture.out) ==
        std::vector<std::string>{"cloth.0001.obj", "cloth.0002.obj", "cloth.0003.obj", "cloth.0004.obj"});
  std::vector<std::size_t> faces;
  for (int frame = 1; frame <= 4; ++frame) {
    const std::string text = read_bytes(fixture.out / ("cloth.000" + std::to_string(frame) + ".obj"));
    faces.push_back(count_lines_starting(text, "f "));
    CHECK(count_lines_starting(text, "vt ") > 0);  // the sheet's UVs and normals are carried
    CHECK(count_lines_starting(text, "vn ") > 0);
  }
  CHECK(faces[0] > 200);
  for (int i = 1; i < 4; ++i) CHECK(faces[i] > faces[i - 1]);  // each frame's cut splits faces
  const tear::Mesh last = tear::read_mesh((fixture.out / "cloth.0004.obj").string());
  CHECK(tear::validate_mesh(last, test_device()).ok());
}

TEST_CASE("run: two runs give byte-identical files", "[run]") {
  RunFixture fixture;
  REQUIRE(fixture.run_into(fixture.dir / "a").exit_code == 0);
  REQUIRE(fixture.run_into(fixture.dir / "b").exit_code == 0);
  const std::vector<std::string> names = file_names(fixture.dir / "a");
  REQUIRE(names.size() == 4);
  CHECK(file_names(fixture.dir / "b") == names);
  for (const std::string& name : names) {
    INFO(name);
    CHECK(read_bytes(fixture.dir / "a" / name) == read_bytes(fixture.dir / "b" / name));
  }
}

TEST_CASE("run: --frames runs the first N frames, --verbose prints one line per frame", "[run]") {
  RunFixture fixture;
  const Run run = fixture.run("--frames 2 --verbose -o " + quoted(fixture.out / "c.{frame}.glb"));
  INFO("stderr: " << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK(file_names(fixture.out) == std::vector<std::string>{"c.1.glb", "c.2.glb"});
  CHECK(count_lines_starting(run.out, "frame 1/2: 1 cut, ") == 1);
  CHECK(count_lines_starting(run.out, "frame 2/2: 1 cut, ") == 1);
  CHECK(std::count(run.out.begin(), run.out.end(), '\n') == 2);
  CHECK(run.out.find((fixture.out / "c.2.glb").string()) != std::string::npos);
}

TEST_CASE("run: a mesh without normals gives frames without normals", "[run]") {
  RunFixture fixture;
  tear::Mesh mesh = regular_sheet();
  mesh.corner_normal.clear();
  tear::write_mesh(mesh, fixture.mesh.string());
  REQUIRE(fixture.run_into(fixture.out).exit_code == 0);
  const std::string text = read_bytes(fixture.out / "cloth.0001.obj");
  CHECK(count_lines_starting(text, "vn ") == 0);
  CHECK(count_lines_starting(text, "vt ") > 0);
}

TEST_CASE("run: a pattern without frame number names the file of a one-frame run", "[run]") {
  RunFixture fixture;
  const Run many = fixture.run("-o " + quoted(fixture.out / "cloth.obj"));
  check_refused(many, 1, "cloth.obj", fixture.out);
  CHECK(many.err.find("4 frames") != std::string::npos);
  const Run one = fixture.run("--frames 1 -o " + quoted(fixture.out / "cloth.obj"));
  INFO("stderr: " << one.err);
  REQUIRE(one.exit_code == 0);
  CHECK(file_names(fixture.out) == std::vector<std::string>{"cloth.obj"});
}

TEST_CASE("run: a script syntax error is refused with file:line:column, nothing written", "[run]") {
  RunFixture fixture;
  fixture.dir.file("script.json", "{ \"version\": 1,\n  \"frames\": 4 x }\n");
  const Run run = fixture.run_into(fixture.out);
  check_refused(run, 2, "script.json", fixture.out);
  CHECK(std::regex_search(run.err, std::regex("script\\.json:2:[0-9]+: syntax error")));
}

TEST_CASE("run: a cut frame out of range is refused, nothing written", "[run]") {
  RunFixture fixture;
  fixture.dir.file("script.json",
                   R"({ "version": 1, "frames": 2,
           "cuts": [ { "frame": 3, "plane": { "point": [0, 0.5, 0], "normal": [0, 1, 0] } } ] })");
  const Run run = fixture.run_into(fixture.out);
  check_refused(run, 2, "script.json", fixture.out);
  CHECK(run.err.find("cuts[0].frame") != std::string::npos);
}

TEST_CASE("run: --frames beyond the script is a usage error, nothing written", "[run]") {
  RunFixture fixture;
  check_refused(fixture.run("--frames 5 -o " + quoted(fixture.out / "c.####.obj")), 1, "script.json", fixture.out);
  check_refused(fixture.run("--frames 0 -o " + quoted(fixture.out / "c.####.obj")), 1, "--frames", fixture.out);
  check_refused(fixture.run("--frames x -o " + quoted(fixture.out / "c.####.obj")), 1, "--frames", fixture.out);
}

TEST_CASE("run: a uv cut on a mesh without UVs is refused, nothing written", "[run]") {
  RunFixture fixture;
  tear::Mesh mesh = regular_sheet();
  mesh.corner_uv.clear();
  tear::write_mesh(mesh, fixture.mesh.string());
  const Run run = fixture.run_into(fixture.out);
  check_refused(run, 2, "script.json", fixture.out);
  CHECK(run.err.find("cuts[1]") != std::string::npos);
  CHECK(run.err.find("sheet.obj") != std::string::npos);
}

TEST_CASE("run: a non-manifold mesh is refused, nothing written", "[run]") {
  RunFixture fixture;
  fixture.dir.file("sheet.obj", fin_obj);
  fixture.dir.file("script.json",
                   R"({ "version": 1, "frames": 1,
           "cuts": [ { "frame": 1, "space": "rest-xy", "polyline": [[-1, 0.3], [2, 0.3]] } ] })");
  const Run run = fixture.run_into(fixture.out);
  check_refused(run, 2, "sheet.obj: cannot be cut: ", fixture.out);
  CHECK(run.err.find("non-manifold") != std::string::npos);
}

TEST_CASE("run: an unknown output extension is a usage error before any input is read", "[run]") {
  RunFixture fixture;
  check_refused(fixture.run("-o " + quoted(fixture.out / "c.####.stl")), 1, ".stl", fixture.out);
  const Run no_mesh = fixture.dir.tear("run --device cpu " + quoted(fixture.dir / "missing.obj") + " " +
                                       quoted(fixture.script) + " -o " + quoted(fixture.out / "c.####.stl"));
  check_refused(no_mesh, 1, ".stl", fixture.out);
  check_refused(fixture.run("-o " + quoted(fixture.out / "c.{frame:4}.obj")), 1, "{frame:4}", fixture.out);
}

TEST_CASE("run: an output folder that cannot be created is a runtime failure naming it", "[run]") {
  RunFixture fixture;
  const Run run = fixture.run("-o /proc/x/####.obj");
  INFO("stderr: " << run.err);
  CHECK(run.exit_code == 3);
  CHECK(run.out.empty());
  CHECK(count_lines_starting(run.err, "tear: /proc/x") == 1);
  CHECK_FALSE(fs::exists("/proc/x"));
}

TEST_CASE("validate: a good script, alone and against a mesh", "[run]") {
  RunFixture fixture;
  const Run alone = fixture.dir.tear("validate " + quoted(fixture.script));
  INFO("stderr: " << alone.err);
  CHECK(alone.exit_code == 0);
  CHECK(alone.out == fixture.script.string() + ": ok (4 cuts over 4 frames)\n");
  CHECK(alone.err.empty());
  const Run with_mesh = fixture.dir.tear("validate --device " + fixture.device + " " + quoted(fixture.script) + " " +
                                         quoted(fixture.mesh));
  INFO("stderr: " << with_mesh.err);
  CHECK(with_mesh.exit_code == 0);
  CHECK(with_mesh.out == fixture.script.string() + ": ok (4 cuts over 4 frames)\n");
  const fs::path one = fixture.dir.file("one.json", one_plane_script);
  CHECK(fixture.dir.tear("validate " + quoted(one)).out == one.string() + ": ok (1 cut over 1 frame)\n");
}

TEST_CASE("validate: a bad script, a script the mesh cannot take, a mesh that cannot be cut", "[run]") {
  RunFixture fixture;
  const fs::path bad =
      fixture.dir.file("bad.json", R"({ "version": 1, "frames": 2, "cuts": [ { "frame": 1, "polylin": [] } ] })");
  check_refused(fixture.dir.tear("validate " + quoted(bad)), 2, "bad.json: cuts[0]", fixture.out);

  tear::Mesh no_uv = regular_sheet();
  no_uv.corner_uv.clear();
  const fs::path no_uv_path = fixture.dir / "no_uv.obj";
  tear::write_mesh(no_uv, no_uv_path.string());
  const Run uv = fixture.dir.tear("validate --device cpu " + quoted(fixture.script) + " " + quoted(no_uv_path));
  check_refused(uv, 2, "no_uv.obj", fixture.out);
  CHECK(uv.err.find("cuts[1]") != std::string::npos);

  const fs::path fin = fixture.dir.file("fin.obj", fin_obj);
  const fs::path plane = fixture.dir.file("plane.json", one_plane_script);
  check_refused(fixture.dir.tear("validate --device cpu " + quoted(plane) + " " + quoted(fin)), 2,
                "fin.obj: cannot be cut: ", fixture.out);
  check_refused(fixture.dir.tear("validate " + quoted(fixture.dir / "missing.json")), 2, "missing.json", fixture.out);

  // What `run` would refuse in the simulation block, `validate` refuses too: the schema alone, and
  // node pins against the mesh.
  const fs::path bad_rho = fixture.dir.file(
      "bad_rho.json", R"({ "version": 1, "frames": 1, "simulation": { "chebyshev": { "rho": 2 } } })");
  check_refused(fixture.dir.tear("validate " + quoted(bad_rho)), 2, "bad_rho.json: simulation.chebyshev.rho", fixture.out);
  const fs::path far_pin = fixture.dir.file(
      "far_pin.json", R"({ "version": 1, "frames": 1, "simulation": { "pins": [ { "nodes": [100000] } ] } })");
  CHECK(fixture.dir.tear("validate " + quoted(far_pin)).exit_code == 0);
  check_refused(fixture.dir.tear("validate --device cpu " + quoted(far_pin) + " " + quoted(fixture.mesh)), 2,
                "far_pin.json: simulation.pins[0]", fixture.out);
}

TEST_CASE("run: two faces on the same three nodes are refused before anything is written", "[run]") {
  // Closed, consistently oriented, manifold: it passed every other check, and the cut left bow-ties.
  RunFixture fixture;
  fixture.dir.file("sheet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n");
  fixture.dir.file("script.json",
                   R"({ "version": 1, "frames": 1,
           "cuts": [ { "frame": 1, "space": "rest-xy", "polyline": [[-1, 0.3], [2, 0.3]] } ] })");
  const Run run = fixture.run_into(fixture.out);
  check_refused(run, 2, "sheet.obj: cannot be cut: 2 faces on the same three nodes as another face", fixture.out);
  const Run info = fixture.dir.tear("info --device cpu " + quoted(fixture.mesh));
  CHECK(info.exit_code == 0);
  CHECK(info.out.find("duplicate faces:      2 (on the same three nodes as another face)") != std::string::npos);
  CHECK(info.out.find("cuttable:             no: 2 faces on the same three nodes") != std::string::npos);
}

TEST_CASE("face_quality: degenerate and inverted faces of a frame", "[run]") {
  tear::SheetOptions options;
  options.face_count = 200;
  options.irregular = false;
  tear::Mesh mesh = tear::make_sheet(options);
  CHECK_FALSE(tear::face_quality(mesh).any());
  // A fold of the whole sheet, or the sheet upside down, is no damage.
  tear::Mesh flipped = mesh;
  for (std::size_t n = 0; n < flipped.node_pos.size(); n += 3) flipped.node_pos[n] = -flipped.node_pos[n];
  CHECK_FALSE(tear::face_quality(flipped).any());
  // An inner node pushed past its neighbours turns faces over.
  const tear::index_t inner = 5 * 11 + 5;  // the middle of a regular 10 x 10 sheet
  REQUIRE(mesh.node_count() == 121);
  tear::Mesh pushed = mesh;
  pushed.node_pos[3 * inner] += 0.25f;
  const tear::FaceQuality turned = tear::face_quality(pushed);
  CHECK(turned.inverted > 0);
  CHECK(turned.degenerate == 0);
  // A node moved onto its neighbour's position leaves faces of no area.
  tear::Mesh squashed = mesh;
  for (int a = 0; a < 3; ++a) squashed.node_pos[3 * inner + a] = squashed.node_pos[3 * (inner + 1) + a];
  const tear::FaceQuality flat = tear::face_quality(squashed);
  CHECK(flat.degenerate == 2);
  CHECK(flat.describe().rfind("2 degenerate faces", 0) == 0);
  CHECK(tear::FaceQuality{1, 1}.describe() == "1 degenerate face and 1 inverted face");
}
