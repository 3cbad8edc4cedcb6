// USD output: one layer holding every frame as time samples (or one per frame), its metadata, its
// temporaries, and frame numbers from --start-frame. tests/check_usd_layer.py reads the layers
// back with USD itself.
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "cli_support.h"
#include "remesh_checks.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/run_cuts.h"
#include "tear/usd_layer.h"
#include "tear/write_mesh.h"
#include "test_support.h"

namespace fs = std::filesystem;
using tear::Mesh;
using tear::UsdLayer;
using tear::test::quoted;
using tear::test::read_bytes;
using tear::test::regular_sheet;
using tear::test::Run;
using tear::test::TempDir;
using tear::test::test_device;

namespace {

std::vector<std::string> file_names(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

/// The line of `text` that starts with `prefix` after its indentation; empty when there is none.
std::string line_starting(const std::string& text, const std::string& prefix) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t start = line.find_first_not_of(' ');
    if (start != std::string::npos && line.compare(start, prefix.size(), prefix) == 0) return line.substr(start);
  }
  return {};
}

/// The samples of attribute `name` (`points`, `primvars:st`, ...): the lines between its
/// `.timeSamples = {` and the closing brace.
std::vector<std::string> samples_of(const std::string& text, const std::string& name) {
  const std::size_t open = text.find(" " + name + ".timeSamples = {\n");
  REQUIRE(open != std::string::npos);
  std::vector<std::string> samples;
  std::istringstream lines(text.substr(text.find('\n', open) + 1));
  for (std::string line; std::getline(lines, line) && line != "    }";) samples.push_back(line.substr(8));
  return samples;
}

/// The triangle of the header's example: (0,0), (1,0), (0,1) with UVs equal to positions.
Mesh triangle() {
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.face_nodes = {0, 1, 2};
  mesh.corner_uv = {0, 0, 1, 0, 0, 1};
  return mesh;
}

/// Four frames of the 200-face sheet: a cut at frames 2 and 3, simulated at 30 fps.
const char* const torn_script = R"({ "version": 1, "frames": 4,
  "cuts": [ { "frame": 2, "space": "rest-xy", "polyline": [[-0.1, 0.53], [0.56, 0.53]] },
            { "frame": 3, "space": "rest-xy", "polyline": [[0.47, -0.1], [0.47, 0.33]] } ],
  "simulation": { "fps": 30, "substeps": 1, "iterations": 10,
                  "pins": [ { "box": { "min": [-1, 0.999, -1], "max": [2, 1.001, 1] } } ] } })";

tear::RunOptions usd_run(const fs::path& layer) {
  tear::RunOptions options;
  options.output_pattern = layer.string();
  options.device = test_device();
  return options;
}

}  // namespace

TEST_CASE("usd_layer: the header's example, a triangle cut through a corner in frame 2", "[usd]") {
  TempDir dir;
  tear::Cloth cloth(triangle(), test_device());
  UsdLayer layer(tear::FramePattern((dir / "tri.usda").string()));
  layer.write(1, cloth.mesh());
  cloth.cut({tear::test::cut_rest_xy({{-0.5, -0.5}, {1, 1}})});
  layer.write(2, cloth.mesh());
  CHECK_FALSE(fs::exists(dir / "tri.usda"));  // only at `finish`
  layer.finish();
  CHECK(file_names(dir.path) == std::vector<std::string>{"tri.usda"});
  const std::string text = read_bytes(dir / "tri.usda");
  CHECK(text.rfind("#usda 1.0\n(\n    defaultPrim = \"cloth\"\n", 0) == 0);
  CHECK(line_starting(text, "endTimeCode") == "endTimeCode = 2");
  CHECK(line_starting(text, "framesPerSecond") == "framesPerSecond = 24");
  CHECK(line_starting(text, "metersPerUnit") == "metersPerUnit = 1");
  CHECK(line_starting(text, "startTimeCode") == "startTimeCode = 1");
  CHECK(line_starting(text, "timeCodesPerSecond") == "timeCodesPerSecond = 24");
  CHECK(line_starting(text, "upAxis") == "upAxis = \"Y\"");
  CHECK(text.find("\ndef Mesh \"cloth\"\n{\n") != std::string::npos);
  CHECK(samples_of(text, "faceVertexCounts") == std::vector<std::string>{"1: [3],", "2: [3, 3],"});
  CHECK(samples_of(text, "faceVertexIndices") == std::vector<std::string>{"1: [0, 1, 2],", "2: [4, 2, 3, 0, 1, 5],"});
  CHECK(samples_of(text, "points") ==
        std::vector<std::string>{"1: [(0, 0, 0), (1, 0, 0), (0, 1, 0)],",
                                 "2: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 0), (0.5, 0.5, 0), (0.5, 0.5, 0)],"});
  CHECK(samples_of(text, "extent") ==
        std::vector<std::string>{"1: [(0, 0, 0), (1, 1, 0)],", "2: [(0, 0, 0), (1, 1, 0)],"});
  CHECK(samples_of(text, "primvars:st") ==
        std::vector<std::string>{"1: [(0, 0), (1, 0), (0, 1)],",
                                 "2: [(0.5, 0.5), (0, 1), (0, 0), (0, 0), (1, 0), (0.5, 0.5)],"});
  CHECK(samples_of(text, "primvars:st:indices") == std::vector<std::string>{"1: [0, 1, 2],", "2: [0, 1, 2, 3, 4, 5],"});
  CHECK(samples_of(text, "primvars:id") == std::vector<std::string>{"1: [0, 1, 2],", "2: [0, 1, 2, 3, 4, 5],"});
  CHECK(samples_of(text, "primvars:rest") == samples_of(text, "points"));  // no simulation: the rest shape
  CHECK(samples_of(text, "primvars:piece") == std::vector<std::string>{"1: [0],", "2: [0, 1],"});
  CHECK(samples_of(text, "accelerations") ==
        std::vector<std::string>{"1: [(0, 0, 0), (0, 0, 0), (0, 0, 0)],",
                                 "2: [(0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0)],"});
  CHECK(text.find("    point3f[] primvars:rest (\n        interpolation = \"vertex\"\n    )\n") != std::string::npos);
  CHECK(text.find("    int[] primvars:id (\n        interpolation = \"vertex\"\n    )\n") != std::string::npos);
  CHECK(text.find("    int[] primvars:piece (\n        interpolation = \"uniform\"\n    )\n") != std::string::npos);
  // Node 3 is node 0's copy, 4 and 5 the two sides of the cut edge's point: 3 -> 4 and 5 -> 0.
  CHECK(samples_of(text, "primvars:tear_edge") == std::vector<std::string>{"1: [0, 0, 0],", "2: [0, 0, 1, 0, 0, 1],"});
  CHECK(text.find("    texCoord2f[] primvars:st (\n        interpolation = \"faceVarying\"\n    )\n") !=
        std::string::npos);
  CHECK(text.find("normals") == std::string::npos);  // the triangle has none
  CHECK(text.substr(text.size() - 8) == "    }\n}\n");
}

TEST_CASE("usd_layer: tear_edge marks the corner whose edge to the next corner is torn", "[usd]") {
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  mesh.face_nodes = {0, 1, 2, 0, 2, 3};
  mesh.torn_edge_nodes = {3, 0, 1, 2};  // either order
  mesh.node_vel = {1, 2, 3, 0, 0, 0, 0, 0, 0, -0.5f, 0, 0};
  const std::string text = tear::usda_layer_text(mesh, 7);
  CHECK(samples_of(text, "primvars:tear_edge") == std::vector<std::string>{"7: [0, 1, 0, 0, 0, 1],"});
  CHECK(samples_of(text, "velocities") ==
        std::vector<std::string>{"7: [(1, 2, 3), (0, 0, 0), (0, 0, 0), (-0.5, 0, 0)],"});
  CHECK(line_starting(text, "startTimeCode") == "startTimeCode = 7");
  CHECK(line_starting(text, "endTimeCode") == "endTimeCode = 7");
  mesh.node_vel.clear();  // unknown velocities are written as 0
  CHECK(samples_of(tear::usda_layer_text(mesh, 7), "velocities") ==
        std::vector<std::string>{"7: [(0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0)],"});
}

TEST_CASE("usd_layer: floats are the shortest text that reads back to the same float", "[usd]") {
  const std::vector<float> values = {0.1f,        1e-8f,    -0.0f,      3.4028235e38f, 1.17549435e-38f, 1e-45f,
                                     123456.789f, -2.5e-5f, 0.3333333f, 16777217.0f,   1.0f / 3.0f,     7e22f};
  Mesh mesh;
  for (float v : values) mesh.node_pos.insert(mesh.node_pos.end(), {v, -v, v * 0.5f});
  tear::UsdLayerOptions options;
  options.frames_per_second = 23.976;
  options.meters_per_unit = 0.01;
  options.up_axis = tear::UpAxis::z;
  const std::string text = tear::usda_layer_text(mesh, 1, options);
  CHECK(line_starting(text, "framesPerSecond") == "framesPerSecond = 23.976");
  CHECK(line_starting(text, "timeCodesPerSecond") == "timeCodesPerSecond = 23.976");
  CHECK(line_starting(text, "metersPerUnit") == "metersPerUnit = 0.01");
  CHECK(line_starting(text, "upAxis") == "upAxis = \"Z\"");
  const std::string points = samples_of(text, "points").at(0);
  std::vector<float> back;
  for (std::size_t i = points.find('['); i < points.size(); ++i) {
    if (!(std::isdigit(static_cast<unsigned char>(points[i])) || points[i] == '-')) continue;
    float value = 0;
    const std::from_chars_result end = std::from_chars(points.data() + i, points.data() + points.size(), value);
    REQUIRE(end.ec == std::errc());
    back.push_back(value);
    i = static_cast<std::size_t>(end.ptr - points.data());
  }
  REQUIRE(back.size() == mesh.node_pos.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    INFO(i << ": " << mesh.node_pos[i]);
    CHECK(std::memcmp(&back[i], &mesh.node_pos[i], sizeof(float)) == 0);
  }
  CHECK(points.find("(0.1, -0.1, 0.05)") != std::string::npos);  // shortest, not 0.100000001
}

TEST_CASE("usd_layer: samples stream to temporaries beside the layer, renamed whole at the end", "[usd]") {
  TempDir dir;
  const tear::CutScript script = tear::parse_cut_script(torn_script, "torn.json");
  tear::RunOptions options = usd_run(dir / "out/shot.usda");
  options.start_frame = 1001;
  std::vector<int> numbers;
  const std::string points_temp = ".shot.usda.points.tmp." + std::to_string(::getpid()) + ".";
  options.on_frame = [&](const tear::FrameResult& frame) {
    numbers.push_back(frame.output_frame);
    CHECK(frame.path == (dir / "out/shot.usda").string());
    CHECK_FALSE(fs::exists(dir / "out/shot.usda"));
    // The layer's writer appends there, beside the run (the name ends in 16 random hex digits).
    bool found = false;
    for (const auto& entry : fs::directory_iterator(dir / "out"))
      found = found || entry.path().filename().string().rfind(points_temp, 0) == 0;
    CHECK(found);
  };
  const tear::RunSummary summary = tear::run_to_files(regular_sheet(), "sheet", script, options);
  CHECK(summary.frames == 4);
  CHECK(numbers == std::vector<int>{1001, 1002, 1003, 1004});
  CHECK(file_names(dir / "out") == std::vector<std::string>{"shot.usda"});

  const std::string text = read_bytes(dir / "out/shot.usda");
  CHECK(line_starting(text, "startTimeCode") == "startTimeCode = 1001");
  CHECK(line_starting(text, "endTimeCode") == "endTimeCode = 1004");
  CHECK(line_starting(text, "framesPerSecond") == "framesPerSecond = 30");
  CHECK(line_starting(text, "timeCodesPerSecond") == "timeCodesPerSecond = 30");
  // What moves at every time code; the rest only where it changes: the cuts of frames 2 and 3.
  for (const char* name : {"points", "velocities", "accelerations", "extent", "primvars:normals"}) {
    INFO(name);
    const std::vector<std::string> samples = samples_of(text, name);
    REQUIRE(samples.size() == 4);
    for (int i = 0; i < 4; ++i) CHECK(samples[i].rfind(std::to_string(1001 + i) + ": [", 0) == 0);
  }
  for (const char* name : {"faceVertexCounts", "faceVertexIndices", "primvars:normals:indices", "primvars:st",
                           "primvars:st:indices", "primvars:tear_edge", "primvars:piece", "primvars:rest",
                           "primvars:id"}) {
    INFO(name);
    const std::vector<std::string> samples = samples_of(text, name);
    REQUIRE(samples.size() == 3);
    for (int i = 0; i < 3; ++i) CHECK(samples[i].rfind(std::to_string(1001 + i) + ": [", 0) == 0);
  }
  // No torn edge before the first cut; some after it.
  CHECK(samples_of(text, "primvars:tear_edge")[0].find('1', 6) == std::string::npos);
  CHECK(samples_of(text, "primvars:tear_edge")[1].find(", 1") != std::string::npos);

  // The same run gives the same bytes, and a layer per frame holds that frame's samples.
  const fs::path again = dir / "again/shot.usda";
  tear::RunOptions same = usd_run(again);
  same.start_frame = 1001;
  tear::run_to_files(regular_sheet(), "sheet", script, same);
  CHECK(read_bytes(again) == text);
  tear::RunOptions per_frame = usd_run(dir / "frames/shot.####.usda");
  per_frame.start_frame = 1001;
  tear::run_to_files(regular_sheet(), "sheet", script, per_frame);
  CHECK(file_names(dir / "frames") ==
        std::vector<std::string>{"shot.1001.usda", "shot.1002.usda", "shot.1003.usda", "shot.1004.usda"});
  const std::string third = read_bytes(dir / "frames/shot.1003.usda");
  CHECK(line_starting(third, "startTimeCode") == "startTimeCode = 1003");
  CHECK(samples_of(third, "points") == std::vector<std::string>{samples_of(text, "points")[2]});
}

TEST_CASE("usd_layer: a run that fails leaves neither the layer nor its temporaries", "[usd]") {
  TempDir dir;
  const tear::CutScript script = tear::parse_cut_script(torn_script, "torn.json");
  tear::RunOptions options = usd_run(dir / "out/shot.usda");
  options.on_frame = [&](const tear::FrameResult& frame) {
    if (frame.frame == 3) throw tear::runtime_error("stopped at frame 3");
  };
  CHECK_THROWS_AS(tear::run_to_files(regular_sheet(), "sheet", script, options), tear::Error);
  CHECK(fs::is_empty(dir / "out"));

  // The layer's name is a folder: the rename fails after every sample was written.
  fs::create_directories(dir / "busy/shot.usda");
  try {
    tear::run_to_files(regular_sheet(), "sheet", script, usd_run(dir / "busy/shot.usda"));
    FAIL("no error");
  } catch (const tear::Error& e) {
    CHECK(e.kind() == tear::ErrorKind::runtime);
    CHECK(std::string(e.what()).rfind((dir / "busy/shot.usda").string() + ": cannot write: ", 0) == 0);
  }
  CHECK(file_names(dir / "busy") == std::vector<std::string>{"shot.usda"});
  CHECK(fs::is_empty(dir / "busy/shot.usda"));
}

TEST_CASE("usd_layer: frames out of order, or with other corner attributes, are refused", "[usd]") {
  TempDir dir;
  UsdLayer out_of_order(tear::FramePattern((dir / "x.usda").string()));
  out_of_order.write(5, triangle());
  CHECK_FALSE(fs::is_empty(dir.path));
  CHECK_THROWS_AS(out_of_order.write(5, triangle()), tear::Error);
  CHECK(fs::is_empty(dir.path));  // a failed write removes the temporaries
  UsdLayer other_attributes(tear::FramePattern((dir / "y.usda").string()));
  other_attributes.write(1, triangle());
  Mesh bare = triangle();
  bare.corner_uv.clear();
  CHECK_THROWS_AS(other_attributes.write(2, bare), tear::Error);
  CHECK(fs::is_empty(dir.path));
  UsdLayer bad_arrays(tear::FramePattern((dir / "z.usda").string()));
  bare.corner_uv = {0, 0};
  CHECK_THROWS_AS(bad_arrays.write(1, bare), tear::Error);
  CHECK(fs::is_empty(dir.path));
  CHECK_THROWS_AS(UsdLayer(tear::FramePattern("x.obj")), tear::Error);
}

TEST_CASE("frame_path: a USD layer without frame number holds any number of frames", "[usd]") {
  CHECK_NOTHROW(tear::FramePattern("out/shot.usda").check(48));
  CHECK_NOTHROW(tear::FramePattern("out/shot.USD").check(48));
  CHECK_NOTHROW(tear::FramePattern("out/shot.####.usda").check(48, 1001));
  CHECK(tear::is_usd_path("a.b/shot.UsDa"));
  CHECK_FALSE(tear::is_usd_path("a.usda/shot"));
  try {
    tear::FramePattern("out/c.####.stl").check(3);
    FAIL("no error");
  } catch (const tear::Error& e) {
    CHECK(std::string(e.what()).find("supported: .obj, .ply, .gltf, .glb, .usda, .usd") != std::string::npos);
  }
  CHECK(tear::parse_up_axis("z") == tear::UpAxis::z);
  CHECK_THROWS_AS(tear::parse_up_axis("X"), tear::Error);
}

TEST_CASE("run: --start-frame numbers files, -v lines and the report, the script frames staying 1-based", "[usd]") {
  TempDir dir;
  const fs::path mesh = dir / "sheet.obj";
  tear::write_mesh(regular_sheet(), mesh.string());
  const fs::path script = dir.file("torn.json", torn_script);
  const std::string inputs =
      "run --device " + std::string(tear::to_string(test_device())) + " " + quoted(mesh) + " " + quoted(script) + " ";
  const Run run = dir.tear(inputs + "--start-frame 1001 -v --report " + quoted(dir / "report.json") + " -o " +
                           quoted(dir / "out/c.####.obj"));
  INFO("stderr: " << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK(file_names(dir / "out") == std::vector<std::string>{"c.1001.obj", "c.1002.obj", "c.1003.obj", "c.1004.obj"});
  CHECK(run.out.rfind("frame 1001/1004: 0 cuts, ", 0) == 0);
  CHECK(run.out.find("\nframe 1002/1004: 1 cut, ") != std::string::npos);  // the script's frame 2
  const nlohmann::json report = nlohmann::json::parse(read_bytes(dir / "report.json"));
  CHECK(report["frames"][0]["frame"] == 1001);
  CHECK(report["frames"][3]["frame"] == 1004);
  CHECK(report["frames"][1]["cuts"] == 1);

  const Run layer =
      dir.tear(inputs + "--start-frame 0 --up-axis Z --meters-per-unit 0.01 -o " + quoted(dir / "usd/shot.usda"));
  INFO("stderr: " << layer.err);
  REQUIRE(layer.exit_code == 0);
  const std::string text = read_bytes(dir / "usd/shot.usda");
  CHECK(line_starting(text, "startTimeCode") == "startTimeCode = 0");
  CHECK(line_starting(text, "endTimeCode") == "endTimeCode = 3");
  CHECK(line_starting(text, "upAxis") == "upAxis = \"Z\"");
  CHECK(line_starting(text, "metersPerUnit") == "metersPerUnit = 0.01");

  for (const std::string bad :
       {"--start-frame -1 -o c.####.obj", "--start-frame x -o c.####.obj", "--start-frame 2147483647 -o c.####.obj",
        "--up-axis Z -o c.####.obj", "--meters-per-unit 0.01 -o c.####.ply", "--up-axis X -o c.usda",
        "--meters-per-unit 0 -o c.usda", "--meters-per-unit nan -o c.usda"}) {
    INFO(bad);
    const Run refused =
        dir.tear(inputs + bad.substr(0, bad.find("-o ") + 3) + quoted(dir / bad.substr(bad.find("-o ") + 3)));
    CHECK(refused.exit_code == 1);
    CHECK(refused.out.empty());
    CHECK(refused.err.rfind("tear: ", 0) == 0);
  }
  CHECK_FALSE(fs::exists(dir / "c.usda"));
  CHECK_FALSE(fs::exists(dir / "c.0001.obj"));

  // What a killed run left beside the layer (a process that no longer runs) goes with the next run.
  fs::create_directories(dir / "stale");
  dir.file("stale/.shot.usda.points.tmp.999999", "1: [");
  dir.file("stale/.shot.usda.tmp.999999", "#usda 1.0\n");
  dir.file("stale/.other.usda.points.tmp.999999", "not ours");
  const Run stale = dir.tear(inputs + "-o " + quoted(dir / "stale/shot.usda"));
  INFO("stderr: " << stale.err);
  REQUIRE(stale.exit_code == 0);
  CHECK(file_names(dir / "stale") == std::vector<std::string>{".other.usda.points.tmp.999999", "shot.usda"});

  // A folder where the layer goes: refused before any work (exit 2) naming it, nothing left beside it.
  fs::create_directories(dir / "busy/shot.usda");
  const Run busy = dir.tear(inputs + "-o " + quoted(dir / "busy/shot.usda"));
  CHECK(busy.exit_code == 2);
  CHECK(busy.err.rfind("tear: " + (dir / "busy/shot.usda").string() + ": cannot write", 0) == 0);
  CHECK(file_names(dir / "busy") == std::vector<std::string>{"shot.usda"});
}

TEST_CASE("demo: -o with a .usda writes one layer, with a frame pattern the frames, and --start-frame numbers them",
          "[usd]") {
  TempDir dir;
  const std::string device = " --device " + std::string(tear::to_string(test_device()));
  const Run layer = dir.tear("demo --frames 2 --start-frame 7 -o " + quoted(dir / "x.usda") + device);
  INFO("stderr: " << layer.err);
  REQUIRE(layer.exit_code == 0);
  CHECK(layer.out.find((dir / "x.usda").string()) != std::string::npos);
  const std::string text = read_bytes(dir / "x.usda");
  CHECK(line_starting(text, "startTimeCode") == "startTimeCode = 7");
  CHECK(line_starting(text, "endTimeCode") == "endTimeCode = 8");
  CHECK(line_starting(text, "framesPerSecond") == "framesPerSecond = 24");
  const Run ply = dir.tear("demo --frames 2 -o " + quoted(dir / "ply/d.####.ply") + device);
  REQUIRE(ply.exit_code == 0);
  CHECK(file_names(dir / "ply") == std::vector<std::string>{"d.0001.ply", "d.0002.ply"});
  const Run folder = dir.tear("demo --frames 1 --start-frame 1001 -o " + quoted(dir / "folder") + device);
  REQUIRE(folder.exit_code == 0);
  CHECK(file_names(dir / "folder") == std::vector<std::string>{"demo.1001.obj"});
}

TEST_CASE("usd_layer: accelerations from the frame before, and held values written again before a change", "[usd]") {
  TempDir dir;
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.face_nodes = {0, 1, 2};
  mesh.corner_uv = {0, 0, 1, 0, 0, 1};
  mesh.node_vel = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  tear::UsdLayerOptions options;
  options.frames_per_second = 24;
  UsdLayer layer(tear::FramePattern((dir / "a.usda").string()), options);
  layer.write(1, mesh);
  mesh.node_vel = {1, 2, 3, 0, 0, 0, 0, 0, -1};
  layer.write(2, mesh);
  layer.write(3, mesh);
  mesh.corner_uv[0] = 0.5f;  // the UVs change at frame 4 only
  layer.write(4, mesh);
  layer.finish();
  const std::string text = read_bytes(dir / "a.usda");
  CHECK(samples_of(text, "accelerations") ==
        std::vector<std::string>{"1: [(0, 0, 0), (0, 0, 0), (0, 0, 0)],", "2: [(24, 48, 72), (0, 0, 0), (0, 0, -24)],",
                                 "3: [(0, 0, 0), (0, 0, 0), (0, 0, 0)],", "4: [(0, 0, 0), (0, 0, 0), (0, 0, 0)],"});
  // USD interpolates UVs between samples: the value held over frames 1-3 is written at 3 too.
  CHECK(samples_of(text, "primvars:st") == std::vector<std::string>{"1: [(0, 0), (1, 0), (0, 1)],",
                                                                    "3: [(0, 0), (1, 0), (0, 1)],",
                                                                    "4: [(0.5, 0), (1, 0), (0, 1)],"});
  // Integers are held, never interpolated: written where they change only.
  CHECK(samples_of(text, "faceVertexIndices") == std::vector<std::string>{"1: [0, 1, 2],"});
  CHECK(samples_of(text, "primvars:st:indices") == std::vector<std::string>{"1: [0, 1, 2],"});
  CHECK(samples_of(text, "points").size() == 4);
}
