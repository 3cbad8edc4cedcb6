// `tear demo`: the paper's scene generated, torn and simulated with no input files.
#include <stdlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "remesh_checks.h"
#include "cli_support.h"
#include "tear/demo_scene.h"
#include "tear/error.h"
#include "tear/read_mesh.h"
#include "tear/simulation.h"
#include "tear/validate_mesh.h"
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

namespace {

/// Edges of one face only.
std::size_t boundary_edges(const tear::Mesh& m) {
  std::map<std::pair<tear::index_t, tear::index_t>, int> uses;
  for (std::size_t f = 0; f < m.face_nodes.size(); f += 3)
    for (int k = 0; k < 3; ++k) {
      const tear::index_t a = m.face_nodes[f + k], b = m.face_nodes[f + (k + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  return static_cast<std::size_t>(std::count_if(uses.begin(), uses.end(), [](const auto& e) { return e.second == 1; }));
}

fs::path frame_file(const fs::path& folder, int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "f.%04d.ply", frame);
  return folder / name;
}

/// `tear demo --scene SCENE` at the low resolution, every frame written as PLY (node ids, so the
/// frames read back with the cloth's topology) with a report.
Run run_scene(const TempDir& dir, const std::string& scene, const std::string& folder) {
  return dir.tear("demo --scene " + scene + " --device " + std::string(tear::to_string(tear::test::test_device())) +
                  " -o " + tear::test::quoted(dir / folder / "f.####.ply") + " --report " +
                  tear::test::quoted(dir / folder / "report.json"));
}

/// Every frame a valid manifold: no bow-ties, oriented, finite.
void check_frames_valid(const fs::path& folder) {
  for (int frame = 1; frame <= tear::demo_frames; ++frame) {
    INFO("frame " << frame);
    const tear::Mesh m = tear::read_mesh(frame_file(folder, frame).string());
    const tear::MeshReport report = tear::validate_mesh(m, tear::test::test_device());
    INFO(report.describe());
    CHECK(report.readable());
    CHECK(report.non_manifold_edges == 0);
    CHECK(report.non_manifold_nodes == 0);
    CHECK(report.inconsistent_edges == 0);
    CHECK(report.duplicate_faces == 0);
  }
}

std::int64_t tear_events(const fs::path& report_path) {
  const nlohmann::json report = nlohmann::json::parse(read_bytes(report_path));
  std::int64_t events = 0;
  for (const auto& frame : report["frames"]) events += frame["tear_events"].get<std::int64_t>();
  return events;
}

}  // namespace

TEST_CASE("demo_script: the pull and punch scenes tear, the punch sheet lies horizontal", "[run]") {
  CHECK(tear::parse_demo_scene("paper") == tear::DemoScene::paper);
  CHECK(std::string(tear::to_string(tear::parse_demo_scene("punch"))) == "punch");
  CHECK_THROWS_AS(tear::parse_demo_scene("rip"), tear::Error);
  for (tear::DemoScene scene : {tear::DemoScene::pull, tear::DemoScene::punch}) {
    INFO(tear::to_string(scene));
    const tear::CutScript script = tear::demo_script(scene);
    CHECK(script.frames == tear::demo_frames);
    REQUIRE(script.simulation.has_value());
    CHECK(script.simulation->tearing.enabled());
    CHECK(script.simulation->tearing.stretch == tear::demo_tear_stretch);
    const tear::Mesh sheet = tear::make_demo_mesh(scene, tear::DemoResolution::low);
    CHECK(sheet.face_count() == 2822);
    const std::vector<std::uint8_t> pinned = tear::resolve_pins(*script.simulation, sheet.node_pos, sheet.node_count());
    for (tear::index_t n = 0; n < sheet.node_count(); ++n) {
      const float x = sheet.node_pos[3 * n], y = sheet.node_pos[3 * n + 1], z = sheet.node_pos[3 * n + 2];
      if (scene == tear::DemoScene::punch) {
        CHECK(y == 0.0f);
        CHECK(bool(pinned[n]) == (x == 0.0f || x == 1.0f || z == 0.0f || z == 1.0f));
      } else {
        CHECK(bool(pinned[n]) == (x <= 0.04f || x >= 0.96f));
      }
    }
  }
  CHECK(tear::demo_script(tear::DemoScene::pull).cuts.size() == 1);
  CHECK(tear::demo_script(tear::DemoScene::punch).cuts.empty());
  CHECK(tear::demo_script(tear::DemoScene::punch).simulation->colliders.size() == 1);
  // The paper's scene is demo_script().
  CHECK(tear::demo_script(tear::DemoScene::paper).cuts.size() == 6);
}

TEST_CASE("demo --scene pull: tears into pieces, the pinned sides apart, every frame valid", "[run][tearing]") {
  TempDir dir;
  const Run run = run_scene(dir, "pull", "pull");
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  CHECK(run.out.rfind("demo: 48 frames, 2822 -> ", 0) == 0);
  check_frames_valid(dir / "pull");
  CHECK(tear_events(dir / "pull" / "report.json") > 0);

  const tear::Mesh last = tear::read_mesh(frame_file(dir / "pull", tear::demo_frames).string());
  const std::vector<tear::index_t> piece = tear::test::node_piece_roots(last);
  std::vector<tear::index_t> roots(piece);
  std::sort(roots.begin(), roots.end());
  CHECK(std::unique(roots.begin(), roots.end()) - roots.begin() >= 2);
  // At the last frame the pinned strips (rest x <= 0.04 and >= 0.96) have moved out by
  // demo_pull_distance: their nodes are the only ones that far out.
  const float reach = float(0.04 - tear::demo_pull_distance) + 1e-4f;
  std::vector<tear::index_t> left, right;
  for (tear::index_t n = 0; n < last.node_count(); ++n) {
    const float x = last.node_pos[3 * n];
    if (x <= reach) left.push_back(piece[n]);
    if (x >= 1 - reach) right.push_back(piece[n]);
  }
  REQUIRE_FALSE(left.empty());
  REQUIRE_FALSE(right.empty());
  std::sort(left.begin(), left.end());
  std::sort(right.begin(), right.end());
  std::vector<tear::index_t> both;
  std::set_intersection(left.begin(), left.end(), right.begin(), right.end(), std::back_inserter(both));
  CHECK(both.empty());
}

TEST_CASE("demo --scene punch: the sphere tears a hole, the same bytes twice", "[run][tearing]") {
  TempDir dir;
  const Run a = run_scene(dir, "punch", "a");
  INFO(a.err);
  REQUIRE(a.exit_code == 0);
#if !defined(TEAR_SANITIZED)
  // The sanitizers look at the code, which one run goes through (the other builds compare two).
  REQUIRE(run_scene(dir, "punch", "b").exit_code == 0);
#endif
  check_frames_valid(dir / "a");
  CHECK(tear_events(dir / "a" / "report.json") > 0);
  const tear::Mesh first = tear::read_mesh(frame_file(dir / "a", 1).string());
  const tear::Mesh last = tear::read_mesh(frame_file(dir / "a", tear::demo_frames).string());
  INFO("boundary edges " << boundary_edges(first) << " -> " << boundary_edges(last));
  CHECK(boundary_edges(last) > boundary_edges(first));
#if !defined(TEAR_SANITIZED)
  for (int frame = 1; frame <= tear::demo_frames; ++frame) {
    INFO("frame " << frame);
    const std::string bytes = read_bytes(frame_file(dir / "a", frame));
    REQUIRE_FALSE(bytes.empty());
    CHECK(bytes == read_bytes(frame_file(dir / "b", frame)));
  }
#endif
}

TEST_CASE("demo: a wrong scene is a usage error on one line, nothing written", "[run]") {
  TempDir dir;
  const Run run = dir.tear("demo --device cpu --scene rip -o " + tear::test::quoted(dir / "out"));
  CHECK(run.exit_code == 1);
  CHECK(run.out.empty());
  CHECK(run.err.rfind("tear: ", 0) == 0);
  CHECK(run.err.find("--scene") != std::string::npos);
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(dir / "out"));
}
