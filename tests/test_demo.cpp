// `tear demo`: the paper's scene generated, torn and simulated with no input files.
#include <stdlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "tear/demo_scene.h"
#include "tear/error.h"
#include "tear/read_mesh.h"
#include "tear/simulation.h"
#include "cli_support.h"
#include "test_support.h"

namespace fs = std::filesystem;

using tear::test::read_bytes;
using tear::test::Run;
using tear::test::TempDir;

TEST_CASE("demo_script: six cuts a third of a second apart, the top edge pinned", "[run]") {
  const tear::CutScript script = tear::demo_script();
  CHECK(script.frames == tear::demo_frames);
  REQUIRE(script.cuts.size() == 6);
  for (std::size_t i = 0; i < script.cuts.size(); ++i) {
    CHECK(script.cuts[i].frame == 4 + 8 * int(i));
    CHECK(script.cuts[i].space == tear::CutSpace::rest_xy);
  }
  REQUIRE(script.simulation.has_value());
  const tear::SimulationOptions& options = *script.simulation;
  CHECK(options.fps == 24);
  CHECK(options.gravity == std::array<double, 3>{0, -9.81, 0});
  CHECK(options.iterations == tear::SimulationOptions().iterations);
  for (tear::DemoResolution r : {tear::DemoResolution::low, tear::DemoResolution::high}) {
    INFO(tear::to_string(r));
    const tear::Mesh sheet = tear::make_demo_sheet(r);
    CHECK(sheet.face_count() == tear::demo_face_count(r));
    const std::vector<std::uint8_t> pinned = tear::resolve_pins(options, sheet.node_pos, sheet.node_count());
    int pinned_count = 0, top_count = 0;
    for (tear::index_t n = 0; n < sheet.node_count(); ++n) {
      const bool top = sheet.node_pos[3 * n + 1] == 1.0f;
      top_count += top;
      pinned_count += pinned[n];
      CHECK(bool(pinned[n]) == top);
    }
    CHECK(top_count > 10);
    CHECK(pinned_count == top_count);
  }
  CHECK(tear::demo_face_count(tear::DemoResolution::medium) == 9022);
  CHECK_THROWS_AS(tear::parse_demo_resolution("ultra"), tear::Error);
}

TEST_CASE("demo: writes every frame to the folder, prints one summary line, reports the cut", "[run]") {
  TempDir dir;
  const fs::path out = dir / "frames";
  const fs::path report = dir / "demo.json";
  const Run run = dir.tear("demo --device " + std::string(tear::to_string(tear::test::test_device())) +
                           " --resolution low --frames 5 -o '" + out.string() + "' --report '" + report.string() + "'");
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  CHECK(run.err.empty());
  CHECK(run.out.rfind("demo: 5 frames, 2822 -> ", 0) == 0);
  CHECK(std::count(run.out.begin(), run.out.end(), '\n') == 1);
  for (int frame = 1; frame <= 5; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "demo.%04d.obj", frame);
    INFO(name);
    CHECK(fs::exists(out / name));
  }
  CHECK_FALSE(fs::exists(out / "demo.0006.obj"));

  const tear::Mesh first = tear::read_mesh((out / "demo.0001.obj").string());
  const tear::Mesh last = tear::read_mesh((out / "demo.0005.obj").string());
  CHECK(first.face_count() == 2822);
  CHECK(last.face_count() > 2822);  // the first cut, at frame 4

  const nlohmann::json j = nlohmann::json::parse(read_bytes(report));
  REQUIRE(j["frames"].size() == 5);
  CHECK(j["frames"][3]["cuts"] == 1);
  CHECK(j["frames"][4]["faces"] == last.face_count());
  CHECK(j["totals"]["frames"] == 5);
  CHECK(j["script"] == "(demo scene)");
}

TEST_CASE("demo: a wrong resolution or frame count is a usage error, nothing written", "[run]") {
  TempDir dir;
  for (const char* args : {"--resolution ultra", "--frames 0", "--frames 49"}) {
    INFO(args);
    const Run run = dir.tear(std::string("demo --device cpu -o '") + (dir / "out").string() + "' " + args);
    CHECK(run.exit_code == 1);
    CHECK_FALSE(fs::exists(dir / "out"));
  }
}
