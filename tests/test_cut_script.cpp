#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

#include "catch.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "test_support.h"

namespace {

// The example of docs/cut-script.md, exactly as written there.
const char* const reference_script = R"({ "version": 1, "frames": 4,
  "snap": 0.15,
  "cuts": [
    { "frame": 1, "space": "rest-xy", "polyline": [[-0.1, 0.5], [1.1, 0.5]] },
    { "frame": 2, "space": "uv",      "polyline": [[0.5, -0.1], [0.5, 0.4], [0.8, 1.1]] },
    { "frame": 3, "blade": { "polyline": [[0.4, 0, -1], [0.4, 0, 2]], "direction": [0, 1, 0] } },
    { "frame": 4, "plane": { "point": [0, 0.7, 0], "normal": [0, 1, 0] } } ] })";

// A script of 4 frames around `cuts`, the text between the brackets of "cuts".
std::string with_cuts(const std::string& cuts) { return R"({"version": 1, "frames": 4, "cuts": [)" + cuts + "]}"; }

// The message of the input error `text` raises; fails the test when it parses or raises another kind.
std::string input_error_of(const std::string& text, const std::string& path = "bad.json") {
  try {
    tear::parse_cut_script(text, path);
  } catch (const tear::Error& e) {
    CHECK(e.kind() == tear::ErrorKind::input);
    return e.what();
  }
  FAIL("parsed without an error: " << text);
  return {};
}

// A 1 x 1 square of two faces in the xy plane (z = 0), with or without UVs.
tear::Mesh square(bool with_uv) {
  tear::Mesh m;
  m.node_pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  m.face_nodes = {0, 1, 2, 0, 2, 3};
  if (with_uv) m.corner_uv = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
  return m;
}

}  // namespace

TEST_CASE("cut_script: the reference example parses to its values", "[script]") {
  const tear::CutScript s = tear::parse_cut_script(reference_script, "shot.json");
  CHECK(s.version == 1);
  CHECK(s.frames == 4);
  CHECK(s.snap == 0.15);
  CHECK(s.path == "shot.json");
  CHECK_FALSE(s.simulation.has_value());
  REQUIRE(s.cuts.size() == 4);

  const tear::Cut& slit = s.cuts[0];
  CHECK(slit.frame == 1);
  CHECK(slit.kind == tear::CutKind::polyline);
  CHECK(slit.space == tear::CutSpace::rest_xy);
  CHECK(slit.key_path == "cuts[0]");
  CHECK(slit.polyline2 == std::vector<std::array<double, 2>>{{-0.1, 0.5}, {1.1, 0.5}});
  CHECK(slit.polyline3.empty());

  const tear::Cut& uv = s.cuts[1];
  CHECK(uv.frame == 2);
  CHECK(uv.kind == tear::CutKind::polyline);
  CHECK(uv.space == tear::CutSpace::uv);
  CHECK(uv.key_path == "cuts[1]");
  CHECK(uv.polyline2 == std::vector<std::array<double, 2>>{{0.5, -0.1}, {0.5, 0.4}, {0.8, 1.1}});

  const tear::Cut& blade = s.cuts[2];
  CHECK(blade.frame == 3);
  CHECK(blade.kind == tear::CutKind::blade);
  CHECK(blade.space == tear::CutSpace::world);
  CHECK(blade.key_path == "cuts[2]");
  CHECK(blade.polyline3 == std::vector<std::array<double, 3>>{{0.4, 0, -1}, {0.4, 0, 2}});
  CHECK(blade.direction == std::array<double, 3>{0, 1, 0});
  CHECK(blade.polyline2.empty());

  const tear::Cut& plane = s.cuts[3];
  CHECK(plane.frame == 4);
  CHECK(plane.kind == tear::CutKind::plane);
  CHECK(plane.space == tear::CutSpace::world);
  CHECK(plane.key_path == "cuts[3]");
  CHECK(plane.point == std::array<double, 3>{0, 0.7, 0});
  CHECK(plane.normal == std::array<double, 3>{0, 1, 0});
}

TEST_CASE("cut_script: defaults, integral floats and the simulation block parsed with the script", "[script]") {
  SECTION("snap and cuts may be left out") {
    const auto s = tear::parse_cut_script(R"({"version": 1, "frames": 3})", "a.json");
    CHECK(s.snap == tear::default_snap);
    CHECK(s.cuts.empty());
    CHECK_FALSE(s.simulation.has_value());
    CHECK(s.cuts_of_frame(1).empty());
  }
  SECTION("4.0 is the integer 4") {
    const auto s = tear::parse_cut_script(R"({"version": 1.0, "frames": 4.0, "snap": 0})", "a.json");
    CHECK(s.frames == 4);
    CHECK(s.snap == 0);
  }
  SECTION("simulation is read into its options, unknown keys refused") {
    const auto s = tear::parse_cut_script(
        R"({"version": 1, "frames": 2, "simulation": {"gravity": [0, -9.8, 0], "substeps": 2}})", "a.json");
    REQUIRE(s.simulation.has_value());
    CHECK(s.simulation->gravity == std::array<double, 3>{0, -9.8, 0});
    CHECK(s.simulation->substeps == 2);
    CHECK(s.simulation->iterations == 100);
    CHECK(s.simulation->source == "a.json");
    CHECK_THROWS_WITH(
        tear::parse_cut_script(R"({"version": 1, "frames": 2, "simulation": {"anything": {"x": "y"}}})", "a.json"),
        Catch::Contains("a.json: simulation.anything: unknown key"));
  }
}

TEST_CASE("cut_script: directions too long or too short to square are still directions", "[script]") {
  // A blade along [0, 0, 1e-320] was refused as parallel to its own segments (the sine underflowed),
  // and the squared length of [1e308, 1e308, 0] overflows.
  const auto s = tear::parse_cut_script(with_cuts(R"(
      {"frame": 1, "blade": {"polyline": [[0, 0, 0], [1, 0, 0]], "direction": [0, 0, 1e-320]}},
      {"frame": 1, "blade": {"polyline": [[-1e308, 0, 0], [1e308, 0, 0]], "direction": [1e308, 1e308, 0]}},
      {"frame": 2, "plane": {"point": [0, 0, 0], "normal": [1e308, 1e308, 0]}})"),
                                        "a.json");
  REQUIRE(s.cuts.size() == 3);
  CHECK(s.cuts[0].direction == std::array<double, 3>{0, 0, 1e-320});
  // Parallel is still parallel, whatever the scale.
  CHECK_THROWS_WITH(tear::parse_cut_script(with_cuts(R"(
      {"frame": 1, "blade": {"polyline": [[0, 0, 0], [0, 0, 1e-300]], "direction": [0, 0, 1e-320]}})"),
                                           "a.json"),
                    Catch::Contains("a.json: cuts[0].blade: every segment of the polyline is parallel"));
}

TEST_CASE("cut_script: cuts of one frame come together in script order", "[script]") {
  const auto s = tear::parse_cut_script(with_cuts(R"(
      {"frame": 2, "plane": {"point": [0, 0, 0], "normal": [1, 0, 0]}},
      {"frame": 1, "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}},
      {"frame": 2, "space": "rest-yz", "polyline": [[0, 0], [1, 1]]})"),
                                        "a.json");
  const auto frame2 = s.cuts_of_frame(2);
  REQUIRE(frame2.size() == 2);
  CHECK(frame2[0] == &s.cuts[0]);
  CHECK(frame2[1] == &s.cuts[2]);
  CHECK(frame2[1]->space == tear::CutSpace::rest_yz);
  REQUIRE(s.cuts_of_frame(1).size() == 1);
  CHECK(s.cuts_of_frame(1)[0]->normal == std::array<double, 3>{0, 1, 0});
  CHECK(s.cuts_of_frame(3).empty());
  CHECK(s.cuts_of_frame(0).empty());
}

TEST_CASE("cut_script: every error names the file and the exact key path", "[script]") {
  struct Bad {
    std::string text;
    std::string key_path;
    std::string what;  // a part of what the message says was expected or found
  };
  const std::string plane = R"({"frame": 1, "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}})";
  const std::vector<Bad> bad = {
      // the document
      {"[]", "(root)", "expected an object, got an empty array"},
      {R"({"frames": 1})", "version", "missing (expected 1)"},
      {R"({"version": 2, "frames": 1})", "version", "expected 1, got 2"},
      {R"({"version": "1", "frames": 1})", "version", "got \"1\""},
      {R"({"version": 1, "frames": 1, "frame": 1})", "frame", "unknown key"},
      {R"({"version": 1, "frames": 1, "a b": 1})", R"(["a b"])", "unknown key"},
      {R"({"version": 1, "frames": 1, "version": 1})", "version", "duplicate key"},
      {R"({"version": 1, "frames": 1, "simulation": [1]})", "simulation", "expected an object"},
      {R"({"version": 1, "frames": 1, "simulation": {"gravity": [0, -1e308, 0]}})", "simulation.gravity",
       "expected a vector of length at most 10000"},
      // frames
      {R"({"version": 1})", "frames", "missing (expected an integer in 1..1000000)"},
      {R"({"version": 1, "frames": 0})", "frames", "expected an integer in 1..1000000, got 0"},
      {R"({"version": 1, "frames": -3})", "frames", "got -3"},
      {R"({"version": 1, "frames": 2.5})", "frames", "got 2.5"},
      {R"({"version": 1, "frames": 1e10})", "frames", "expected an integer in 1..1000000"},
      {R"({"version": 1, "frames": 18446744073709551615})", "frames", "expected an integer in 1..1000000"},
      // a billion frames (a run that would not end, and a billion files) is taken for a mistake
      {R"({"version": 1, "frames": 1000000000})", "frames", "expected an integer in 1..1000000, got 1000000000"},
      {R"({"version": 1, "frames": 1000001})", "frames", "got 1000001"},
      {R"({"version": 1, "frames": true})", "frames", "got true"},
      // snap
      {R"({"version": 1, "frames": 1, "snap": 0.5})", "snap", "expected a number in [0, 0.5), got 0.5"},
      {R"({"version": 1, "frames": 1, "snap": -0.01})", "snap", "[0, 0.5)"},
      {R"({"version": 1, "frames": 1, "snap": "0.2"})", "snap", "expected a number, got \"0.2\""},
      {R"({"version": 1, "frames": 1, "snap": null})", "snap", "got null"},
      {R"({"version": 1, "frames": 1, "snap": 1e999})", "snap", "expected a finite number, got 1e999"},
      // cuts
      {R"({"version": 1, "frames": 1, "cuts": {}})", "cuts", "expected an array of cuts"},
      {with_cuts("3"), "cuts[0]", "expected an object, got 3"},
      {with_cuts(plane + R"(, {"frame": 1, "normal": [0, 1, 0]})"), "cuts[1].normal", "unknown key"},
      {with_cuts(R"({"plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}})"), "cuts[0].frame",
       "missing (expected an integer in 1..4)"},
      {with_cuts(R"({"frame": 0, "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}})"), "cuts[0].frame",
       "expected an integer in 1..4"},
      {with_cuts(R"({"frame": 5, "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}})"), "cuts[0].frame", "got 5"},
      {with_cuts(R"({"frame": "2", "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}})"), "cuts[0].frame",
       "got \"2\""},
      {with_cuts(R"({"frame": 1, "frame": 2, "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}})"), "cuts[0].frame",
       "duplicate key"},
      // which kind of cut
      {with_cuts(R"({"frame": 1})"), "cuts[0]", "got none"},
      {with_cuts(R"({"frame": 1, "blade": {"polyline": [[0, 0, 0], [1, 0, 0]], "direction": [0, 0, 1]},
                     "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}})"),
       "cuts[0]", "got \"blade\" and \"plane\""},
      {with_cuts(R"({"frame": 1, "space": "uv", "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}})"), "cuts[0]",
       "got \"polyline\" and \"plane\""},
      {with_cuts(R"({"frame": 1, "space": "uv"})"), "cuts[0].polyline", "missing"},
      {with_cuts(R"({"frame": 1, "polyline": [[0, 0], [1, 1]]})"), "cuts[0].space", "missing"},
      // polylines in 2D spaces
      {with_cuts(R"({"frame": 1, "space": "xy", "polyline": [[0, 0], [1, 1]]})"), "cuts[0].space",
       "unknown space \"xy\""},
      {with_cuts(R"({"frame": 1, "space": 3, "polyline": [[0, 0], [1, 1]]})"), "cuts[0].space", "got 3"},
      {with_cuts(R"({"frame": 1, "space": "uv", "polyline": [[0, 0]]})"), "cuts[0].polyline",
       "expected at least 2 points, got 1"},
      {with_cuts(R"({"frame": 1, "space": "uv", "polyline": "0 0 1 1"})"), "cuts[0].polyline",
       "expected an array of [u, v] points"},
      {with_cuts(R"({"frame": 1, "space": "uv", "polyline": [[0, 0], [1, 1, 0]]})"), "cuts[0].polyline[1]",
       "expected an array of 2 numbers, got an array of 3 elements"},
      {with_cuts(R"({"frame": 1, "space": "uv", "polyline": [[0, 0], 1]})"), "cuts[0].polyline[1]",
       "expected an array of 2 numbers, got 1"},
      {with_cuts(R"({"frame": 1, "space": "uv", "polyline": [[0, 0], ["1", 1]]})"), "cuts[0].polyline[1][0]",
       "expected a number"},
      {with_cuts(R"({"frame": 1, "space": "uv", "polyline": [[0, 0], [1, 1e999]]})"), "cuts[0].polyline[1][1]",
       "expected a finite number"},
      {with_cuts(R"({"frame": 1, "space": "uv", "polyline": [[0.5, 0.5], [0.5, 0.5]]})"), "cuts[0].polyline",
       "no length"},
      // blades
      {with_cuts(plane +
                 R"(, {"frame": 1, "blade": {"polyline": [[0, 0, 0], [1, 0, 0]], "direction": [0, 0, -1e999]}})"),
       "cuts[1].blade.direction[2]", "expected a finite number, got -1e999"},
      {with_cuts(R"({"frame": 1, "blade": {"polyline": [[0, 0, 0], [1, 0, 0]]}})"), "cuts[0].blade.direction",
       "missing"},
      {with_cuts(R"({"frame": 1, "blade": {"polyline": [[0, 0, 0], [1, 0, 0]], "direction": [0, 0, 0]}})"),
       "cuts[0].blade.direction", "expected a non-zero vector"},
      {with_cuts(R"({"frame": 1, "blade": {"polyline": [[0, 0, 0], [0, 0, 1], [0, 0, 1]], "direction": [0, 0, 2]}})"),
       "cuts[0].blade", "parallel to the direction"},
      {with_cuts(R"({"frame": 1, "blade": {"polyline": [[0, 0], [1, 0]], "direction": [0, 0, 1]}})"),
       "cuts[0].blade.polyline[0]", "expected an array of 3 numbers"},
      {with_cuts(R"({"frame": 1, "blade": {"polyline": [[0, 0, 0], [1, 0, 0]], "dir": [0, 0, 1]}})"),
       "cuts[0].blade.dir", "unknown key"},
      {with_cuts(R"({"frame": 1, "blade": [[0, 0, 0], [1, 0, 0]]})"), "cuts[0].blade", "expected an object"},
      // planes
      {with_cuts(R"({"frame": 1, "plane": {"point": [0, 0, 0], "normal": [0, 0, 0]}})"), "cuts[0].plane.normal",
       "expected a non-zero vector"},
      {with_cuts(R"({"frame": 1, "plane": {"normal": [0, 1, 0]}})"), "cuts[0].plane.point", "missing"},
      {with_cuts(R"({"frame": 1, "plane": {"point": [0, 0], "normal": [0, 1, 0]}})"), "cuts[0].plane.point",
       "expected an array of 3 numbers, got an array of 2 elements"},
      {with_cuts(R"({"frame": 1, "plane": {"point": [0, 0, 0], "normal": [0, 1, 0], "size": 2}})"),
       "cuts[0].plane.size", "unknown key"},
  };
  for (const Bad& b : bad) {
    INFO("script: " << b.text);
    const std::string message = input_error_of(b.text);
    INFO("message: " << message);
    CHECK(message.rfind("bad.json: " + b.key_path + ": ", 0) == 0);
    CHECK(message.find(b.what) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("cut_script: the message format is <file>: <key path>: <what>", "[script]") {
  const std::string text = with_cuts(R"({"frame": 1, "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}},
      {"frame": 1, "plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}},
      {"frame": 1, "space": "rest-xy", "polyline": [[0, 0]]})");
  CHECK(input_error_of(text, "shot.json") == "shot.json: cuts[2].polyline: expected at least 2 points, got 1");
}

TEST_CASE("cut_script: a syntax error gives its line and column", "[script]") {
  SECTION("ASCII") {
    const std::string text = "{\n  \"version\": 1,\n  \"frames\": 4 x\n}\n";
    const std::string message = input_error_of(text, "shot.json");
    INFO(message);
    CHECK(message.rfind("shot.json:3:15: syntax error: ", 0) == 0);
  }
  SECTION("the column counts characters, not bytes") {
    const std::string text = "{\n  \"version\": 1,\n  \"fr\xC3\xA4mes\": 4 x\n}\n";
    const std::string message = input_error_of(text, "shot.json");
    INFO(message);
    CHECK(message.rfind("shot.json:3:15: syntax error: ", 0) == 0);
  }
  SECTION("end of input") {
    const std::string text = "{\n  \"version\": 1,\n  \"frames\": 4,\n";
    const std::string message = input_error_of(text, "shot.json");
    INFO(message);
    CHECK(message.rfind("shot.json:4:1: syntax error: ", 0) == 0);
    CHECK(message.find("end of input") != std::string::npos);
  }
}

TEST_CASE("cut_script: every example in examples/scripts parses and together they cover each feature", "[script]") {
  namespace fs = std::filesystem;
  std::set<std::string> features;
  int example_count = 0;
  for (const auto& entry : fs::directory_iterator(tear::test::source_path("examples/scripts"))) {
    if (entry.path().extension() != ".json") continue;
    ++example_count;
    INFO(entry.path());
    const tear::CutScript s = tear::read_cut_script(entry.path().string());
    CHECK(!s.cuts.empty());
    for (const tear::Cut& cut : s.cuts) {
      features.insert(tear::to_string(cut.kind));
      if (cut.kind == tear::CutKind::polyline) features.insert(tear::to_string(cut.space));
    }
    for (int frame = 1; frame <= s.frames; ++frame)
      if (s.cuts_of_frame(frame).size() > 1) features.insert("several cuts in one frame");
  }
  CHECK(example_count >= 6);
  for (const char* feature : {"polyline", "blade", "plane", "uv", "rest-xy", "several cuts in one frame"}) {
    INFO(feature);
    CHECK(features.count(feature) == 1);
  }
}

TEST_CASE("cut_script: reading a file", "[script]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tear_cut_script_" + std::to_string(tear::test::test_seed(0)) +
                                                    "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "shot.json";
  {
    std::ofstream out(file);
    out << reference_script;
  }
  const tear::CutScript s = tear::read_cut_script(file.string());
  CHECK(s.path == file.string());
  CHECK(s.cuts.size() == 4);

  for (const fs::path& unreadable : {dir / "missing.json", dir}) {
    INFO(unreadable);
    try {
      tear::read_cut_script(unreadable.string());
      FAIL("read without an error");
    } catch (const tear::Error& e) {
      CHECK(e.kind() == tear::ErrorKind::input);
      CHECK(std::string(e.what()).rfind(unreadable.string() + ": ", 0) == 0);
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("cut_script: a script is checked against the mesh it will cut", "[script]") {
  const auto s = tear::parse_cut_script(with_cuts(R"(
      {"frame": 1, "space": "rest-xy", "polyline": [[0, 0.5], [1, 0.5]]},
      {"frame": 2, "space": "uv", "polyline": [[0.5, 0], [0.5, 1]]})"),
                                        "shot.json");
  CHECK_NOTHROW(tear::check_script_against_mesh(s, square(true), "cloth.obj"));
  try {
    tear::check_script_against_mesh(s, square(false), "cloth.obj");
    FAIL("a uv cut passed on a mesh without UVs");
  } catch (const tear::Error& e) {
    CHECK(e.kind() == tear::ErrorKind::input);
    const std::string message = e.what();
    INFO(message);
    CHECK(message.rfind("shot.json: cuts[1]: ", 0) == 0);
    CHECK(message.find("cloth.obj") != std::string::npos);
    CHECK(message.find("UVs") != std::string::npos);
  }

  const auto sideways = tear::parse_cut_script(with_cuts(R"(
      {"frame": 1, "space": "rest-xy", "polyline": [[0, 0.5], [1, 0.5]]},
      {"frame": 1, "space": "rest-xz", "polyline": [[0, 0.5], [1, 0.5]]})"),
                                               "shot.json");
  try {
    tear::check_script_against_mesh(sideways, square(true), "cloth.obj");
    FAIL("a rest-xz cut passed on a cloth flat in z");
  } catch (const tear::Error& e) {
    const std::string message = e.what();
    INFO(message);
    CHECK(message.rfind("shot.json: cuts[1]: ", 0) == 0);
    CHECK(message.find("cloth.obj") != std::string::npos);
    CHECK(message.find("along z") != std::string::npos);
  }
}

TEST_CASE("cut_script: rest plane axes", "[script]") {
  CHECK(tear::rest_plane_axes(tear::CutSpace::rest_xy) == std::array<int, 2>{0, 1});
  CHECK(tear::rest_plane_axes(tear::CutSpace::rest_xz) == std::array<int, 2>{0, 2});
  CHECK(tear::rest_plane_axes(tear::CutSpace::rest_yz) == std::array<int, 2>{1, 2});
}
