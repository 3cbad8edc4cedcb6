// Pins and colliders moved by keyframes: the `keys` of the script, the offset between keys and at
// each substep, a keyed pin followed exactly, a moving sphere pushing a sheet, determinism and
// resuming mid-motion.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "catch.h"
#include "cli_support.h"
#include "random_meshes.h"
#include "simulation_support.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "tear/make_sheet.h"
#include "tear/simulation.h"
#include "tear/write_mesh.h"
#include "test_support.h"

namespace {

using tear::index_t;
using tear::Key;
using tear::PdSolver;
using tear::SimulationOptions;
namespace fs = std::filesystem;
using tear::test::TempDir;
using Offset = std::array<double, 3>;

using tear::test::horizontal_sheet;
using tear::test::parse_simulation;

bool all_finite(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

}  // namespace

// ---- the script ----------------------------------------------------------------------------------

TEST_CASE("keys: pins and colliders read their keys", "[keys]") {
  const SimulationOptions o = parse_simulation(R"({"pins": [
      {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "keys": [{"frame": 0, "offset": [0, 0, 0]},
                                                             {"frame": 12, "offset": [0.5, 0, -1]}]},
      {"nodes": [3]}, {"keys": [{"frame": 4.0, "offset": [1, 2, 3]}], "nodes": [1, 2]}],
    "colliders": [{"sphere": {"center": [0, 1, 0], "radius": 0.5}, "keys": [{"frame": 1, "offset": [0, -2, 0]}]},
                  {"plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}}]})");
  REQUIRE(o.pins.size() == 3);
  REQUIRE(o.pins[0].keys.size() == 2);
  CHECK(o.pins[0].keys[0].frame == 0);
  CHECK(o.pins[0].keys[1].frame == 12);
  CHECK(o.pins[0].keys[1].offset == Offset{0.5, 0, -1});
  CHECK(o.pins[1].keys.empty());
  REQUIRE(o.pins[2].keys.size() == 1);
  CHECK(o.pins[2].keys[0].frame == 4);
  CHECK(o.pins[2].nodes == std::vector<index_t>{1, 2});
  REQUIRE(o.colliders.size() == 2);
  REQUIRE(o.colliders[0].keys.size() == 1);
  CHECK(o.colliders[0].keys[0].offset == Offset{0, -2, 0});
  CHECK(o.colliders[0].point == Offset{0, 1, 0});
  CHECK(o.colliders[1].keys.empty());
}

TEST_CASE("keys: every error names the file and the key path", "[keys]") {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"pins": [{"box": {"min": [0,0,0], "max": [1,1,1]}, "key": []}]})",
       "simulation.pins[0].key: unknown key (expected box, nodes or keys)"},
      {R"({"pins": [{"keys": [{"frame": 0, "offset": [0,0,0]}]}]})",
       "simulation.pins[0]: expected exactly one of \"box\" or \"nodes\", got an object"},
      {R"({"pins": [{"nodes": [0], "keys": []}]})",
       "simulation.pins[0].keys: expected a non-empty array of keys {\"frame\": F, \"offset\": [x, y, z]}, got an "
       "empty array"},
      {R"({"pins": [{"nodes": [0], "keys": {"frame": 0}}]})",
       "simulation.pins[0].keys: expected a non-empty array of keys {\"frame\": F, \"offset\": [x, y, z]}, got an "
       "object"},
      {R"({"pins": [{"nodes": [0]}, {"nodes": [0], "keys": [3]}]})",
       "simulation.pins[1].keys[0]: expected an object, got 3"},
      {R"({"pins": [{"nodes": [0], "keys": [{"frame": 1, "offset": [0,0,0], "ease": "in"}]}]})",
       "simulation.pins[0].keys[0].ease: unknown key (expected frame or offset)"},
      {R"({"pins": [{"nodes": [0], "keys": [{"offset": [0,0,0]}]}]})",
       "simulation.pins[0].keys[0].frame: missing (expected an integer in 0..1000000)"},
      {R"({"pins": [{"nodes": [0], "keys": [{"frame": 1}]}]})",
       "simulation.pins[0].keys[0].offset: missing (expected an array of 3 numbers)"},
      {R"({"pins": [{"nodes": [0], "keys": [{"frame": -1, "offset": [0,0,0]}]}]})",
       "simulation.pins[0].keys[0].frame: expected an integer in 0..1000000, got -1"},
      {R"({"pins": [{"nodes": [0], "keys": [{"frame": 1.5, "offset": [0,0,0]}]}]})",
       "simulation.pins[0].keys[0].frame: expected an integer in 0..1000000, got 1.5"},
      {R"({"pins": [{"nodes": [0], "keys": [{"frame": 1000001, "offset": [0,0,0]}]}]})",
       "simulation.pins[0].keys[0].frame: expected an integer in 0..1000000, got 1000001"},
      {R"({"pins": [{"nodes": [0]}, {"nodes": [0], "keys": [{"frame": 0, "offset": [0,0,0]},
          {"frame": 3, "offset": [0,0,0]}, {"frame": 2, "offset": [0,0,0]}]}]})",
       "simulation.pins[1].keys[2].frame: expected a frame after the previous key's (3), got 2"},
      {R"({"pins": [{"nodes": [0], "keys": [{"frame": 3, "offset": [0,0,0]}, {"frame": 3, "offset": [1,0,0]}]}]})",
       "simulation.pins[0].keys[1].frame: expected a frame after the previous key's (3), got 3"},
      {R"({"pins": [{"nodes": [0], "keys": [{"frame": 3, "offset": [0,0]}]}]})",
       "simulation.pins[0].keys[0].offset: expected an array of 3 numbers, got an array of 2 elements"},
      {R"({"pins": [{"nodes": [0], "keys": [{"frame": 3, "offset": [0,"1",0]}]}]})",
       "simulation.pins[0].keys[0].offset[1]: expected a number, got \"1\""},
      {R"({"pins": [{"nodes": [0], "keys": [{"frame": 3, "offset": [0,0,-2e9]}]}]})",
       "simulation.pins[0].keys[0].offset[2]: expected a number in [-1e+09, 1e+09] (metres), got -2000000000.0"},
      {R"({"colliders": [{"plane": {"point": [0,0,0], "normal": [0,1,0]}, "keys": null}]})",
       "simulation.colliders[0].keys: expected a non-empty array of keys {\"frame\": F, \"offset\": [x, y, z]}, got "
       "null"},
      {R"({"colliders": [{"sphere": {"center": [0,0,0], "radius": 1}, "keys": [{"frame": 2, "offset": [0,1e20,0]}]}]})",
       "simulation.colliders[0].keys[0].offset[1]: expected a number in [-1e+09, 1e+09] (metres), got 1e+20"},
      {R"({"colliders": [{"sphere": {"center": [0,0,0], "radius": 1}, "keys": [{"frame": 2, "offset": [0,0,0]},
          {"frame": 1, "offset": [0,0,0]}]}]})",
       "simulation.colliders[0].keys[1].frame: expected a frame after the previous key's (2), got 1"},
      {R"({"colliders": [{"keys": [{"frame": 2, "offset": [0,0,0]}]}]})",
       "simulation.colliders[0]: expected exactly one of \"plane\", \"sphere\" or \"mesh\", got an object"},
      {R"({"colliders": [{"sphere": {"center": [0,0,0], "radius": 1}, "keys": [{"frame": 2, "offset": [0,0,0]}],
          "spin": 1}]})",
       "simulation.colliders[0].spin: unknown key (expected plane, sphere, mesh, pivot or keys)"},
  };
  for (const auto& [text, message] : cases) {
    INFO(text);
    try {
      parse_simulation(text, "script.json");
      FAIL("parsed without an error");
    } catch (const tear::Error& e) {
      CHECK(e.kind() == tear::ErrorKind::input);
      CHECK(std::string(e.what()) == std::string("script.json: ") + message);
    }
  }
  // More pins than a node's byte can name.
  std::string many = R"({"pins": [)";
  for (int i = 0; i < 256; ++i) many += std::string(i ? "," : "") + R"({"nodes": [0]})";
  CHECK_THROWS_WITH(parse_simulation(many + "]}", "script.json"),
                    "script.json: simulation.pins: expected at most 255 pins, got an array of 256 elements");
}

// ---- the offset over time ------------------------------------------------------------------------

TEST_CASE("keys: the offset is held before the first key and after the last, linear between", "[keys]") {
  const std::vector<Key> keys = {{2, {0, 0, 0}}, {4, {1, -2, 0.5}}, {8, {1, 2, 0.5}}};
  CHECK(tear::key_offset({}, 3.0) == Offset{0, 0, 0});
  CHECK(tear::key_offset(keys, 0.0) == Offset{0, 0, 0});
  CHECK(tear::key_offset(keys, 1.75) == Offset{0, 0, 0});
  CHECK(tear::key_offset(keys, 2.0) == Offset{0, 0, 0});
  CHECK(tear::key_offset(keys, 3.0) == Offset{0.5, -1, 0.25});
  CHECK(tear::key_offset(keys, 4.0) == Offset{1, -2, 0.5});
  CHECK(tear::key_offset(keys, 7.0) == Offset{1, 1, 0.5});
  CHECK(tear::key_offset(keys, 8.0) == Offset{1, 2, 0.5});
  CHECK(tear::key_offset(keys, 1e6) == Offset{1, 2, 0.5});
  // One key: held throughout.
  CHECK(tear::key_offset({{5, {1, 1, 1}}}, 0.0) == Offset{1, 1, 1});
  CHECK(tear::key_offset({{5, {1, 1, 1}}}, 9.0) == Offset{1, 1, 1});
}

TEST_CASE("keys: each substep of a frame sees the offset at its own end", "[keys]") {
  // Substep s of S in frame f ends at f - 1 + (s + 1)/S; the last at exactly f.
  CHECK(tear::substep_end_time(1, 0, 4) == 0.25);
  CHECK(tear::substep_end_time(3, 1, 4) == 2.5);
  CHECK(tear::substep_end_time(3, 3, 4) == 3.0);
  CHECK(tear::substep_end_time(3, -1, 4) == 2.0);  // the start of frame 3: the end of frame 2
  const std::vector<Key> keys = {{0, {0, 0, 0}}, {2, {0, 4, 0}}};
  const double expected[8] = {0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4};
  for (int frame = 1; frame <= 2; ++frame)
    for (int s = 0; s < 4; ++s) {
      INFO("frame " << frame << " substep " << s);
      CHECK(tear::key_offset(keys, tear::substep_end_time(frame, s, 4))[1] == expected[4 * (frame - 1) + s]);
    }
}

TEST_CASE("keys: random keys are continuous, pass through every key and stay within each segment", "[keys]") {
  const std::uint64_t seed = tear::test::test_seed(31);
  INFO("seed " << seed << " (TEAR_TEST_SEED reruns it)");
  tear::test::Random random(seed);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Key> keys;
    int frame = static_cast<int>(random.uniform() * 3);
    const int count = 1 + static_cast<int>(random.uniform() * 5);
    for (int k = 0; k < count; ++k) {
      Key key;
      key.frame = frame;
      for (double& x : key.offset) x = random.uniform() * 2 - 1;
      keys.push_back(key);
      frame += 1 + static_cast<int>(random.uniform() * 6);
    }
    INFO("trial " << trial);
    for (const Key& key : keys) CHECK(tear::key_offset(keys, key.frame) == key.offset);
    CHECK(tear::key_offset(keys, keys.front().frame - 0.5) == keys.front().offset);
    CHECK(tear::key_offset(keys, keys.back().frame + 0.5) == keys.back().offset);
    for (std::size_t k = 0; k + 1 < keys.size(); ++k) {
      const double t = keys[k].frame + random.uniform() * (keys[k + 1].frame - keys[k].frame);
      const Offset o = tear::key_offset(keys, t);
      for (int a = 0; a < 3; ++a) {
        CHECK(o[a] >= std::min(keys[k].offset[a], keys[k + 1].offset[a]) - 1e-12);
        CHECK(o[a] <= std::max(keys[k].offset[a], keys[k + 1].offset[a]) + 1e-12);
        // Continuous: a step of 1e-9 frames moves the offset by at most the segment's slope × 1e-9.
        const double slope = std::abs(keys[k + 1].offset[a] - keys[k].offset[a]) / (keys[k + 1].frame - keys[k].frame);
        CHECK(std::abs(tear::key_offset(keys, t + 1e-9)[a] - o[a]) <= slope * 1e-9 + 1e-12);
      }
    }
  }
}

// ---- pins ------------------------------------------------------------------------------------------

TEST_CASE("keys: a keyed pin holds its node at rest + offset, moving at the offset's rate", "[keys]") {
  const tear::Mesh mesh = horizontal_sheet(200);
  // Node 0 is the corner at the origin; the other corner of its edge stays still.
  SimulationOptions o = parse_simulation(R"({"substeps": 4, "pins": [
      {"nodes": [0], "keys": [{"frame": 2, "offset": [0, 0, 0]}, {"frame": 6, "offset": [0, 0.2, -0.4]},
                              {"frame": 8, "offset": [0.1, 0.2, -0.4]}]},
      {"box": {"min": [0.99, -1, -0.001], "max": [1.01, 1, 0.001]}}]})");
  PdSolver solver(mesh.face_nodes, mesh.node_pos, mesh.node_count(), o, tear::test::test_device());
  REQUIRE(solver.node_pinned()[0] == 1);
  const double h = 1.0 / (24 * 4);
  for (int frame = 1; frame <= 10; ++frame) {
    solver.step();
    const std::vector<float> pos = solver.node_pos(), vel = solver.node_vel();
    REQUIRE(all_finite(pos));
    const Offset now = tear::key_offset(o.pins[0].keys, frame);
    const Offset before = tear::key_offset(o.pins[0].keys, tear::substep_end_time(frame, 2, 4));
    INFO("frame " << frame);
    for (int a = 0; a < 3; ++a) {
      CHECK(pos[a] == mesh.node_pos[a] + static_cast<float>(now[a]));
      CHECK(vel[a] == Approx((now[a] - before[a]) / h).margin(1e-5));
    }
    // The still pin's nodes have not moved.
    for (index_t n = 0; n < mesh.node_count(); ++n)
      if (solver.node_pinned()[n] == 2) CHECK(pos[3 * n] == mesh.node_pos[3 * n]);
  }
  // Between frames 2 and 6 the corner moves at 0.05 m/frame in y: 1.2 m/s at 24 fps.
  PdSolver again(mesh.face_nodes, mesh.node_pos, mesh.node_count(), o, tear::test::test_device());
  for (int frame = 1; frame <= 4; ++frame) again.step();
  CHECK(again.node_vel()[1] == Approx(1.2).epsilon(1e-5));
  CHECK(again.node_vel()[2] == Approx(-2.4).epsilon(1e-5));
}

TEST_CASE("keys: a keyed box pin follows its keys through cuts, holding what a cut makes inside it", "[keys]") {
  tear::SheetOptions sheet;
  sheet.face_count = 600;
  const tear::Mesh mesh = tear::make_sheet(sheet);  // [0,1]² in the xy plane
  tear::Cloth cloth(mesh, tear::test::test_device());
  SimulationOptions o = parse_simulation(R"({"pins": [
      {"box": {"min": [-1, 0.95, -1], "max": [2, 2, 1]},
       "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 6, "offset": [0.3, 0.1, 0.2]}]}]})");
  cloth.simulate(o);
  for (int frame = 1; frame <= 8; ++frame) {
    if (frame == 3) {
      // A cut across the box: the nodes it makes inside it are held too.
      tear::CutLine line;
      line.polyline = {{0.31, 1.1}, {0.52, 0.9}};
      const index_t before = cloth.node_count();
      cloth.cut({line});
      REQUIRE(cloth.node_count() > before);
    }
    cloth.step_frame(frame);
    const std::vector<float> pos = cloth.node_pos(), rest = cloth.node_rest();
    const std::vector<std::uint8_t> pinned = cloth.node_pinned();
    const Offset offset = tear::key_offset(o.pins[0].keys, frame);
    INFO("frame " << frame);
    index_t held = 0;
    for (index_t n = 0; n < cloth.node_count(); ++n) {
      const bool in_box = rest[3 * n + 1] >= 0.95;
      CHECK(bool(pinned[n]) == in_box);
      if (!pinned[n]) continue;
      ++held;
      for (int a = 0; a < 3; ++a) CHECK(pos[3 * n + a] == rest[3 * n + a] + static_cast<float>(offset[a]));
    }
    CHECK(held > 0);
    REQUIRE(cloth.state_is_finite());
  }
}

// ---- colliders -------------------------------------------------------------------------------------

TEST_CASE("keys: a sphere moved up through a sheet held at its edges pushes it up", "[keys]") {
  const tear::Mesh mesh = horizontal_sheet(800);
  // The sheet held along x = 0 and x = 1; the sphere starts below it and rises 0.35 m in 12 frames
  // (0.7 m/s), then stays. (Lifted much higher, the stretched sheet's pull drags its nodes past the
  // sphere's centre within a substep and it snaps through: collisions are resolved after the step.)
  const double radius = 0.2;
  const SimulationOptions o = parse_simulation(R"({"pins": [
      {"box": {"min": [-0.01, -1, -1], "max": [0.01, 1, 2]}}, {"box": {"min": [0.99, -1, -1], "max": [1.01, 1, 2]}}],
    "colliders": [{"sphere": {"center": [0.5, -0.3, 0.5], "radius": 0.2},
                   "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 12, "offset": [0, 0.35, 0]}]}]})");
  PdSolver solver(mesh.face_nodes, mesh.node_pos, mesh.node_count(), o, tear::test::test_device());
  index_t centre = -1;
  for (index_t n = 0; n < mesh.node_count(); ++n)
    if (mesh.node_pos[3 * n] == 0.5f && mesh.node_pos[3 * n + 2] == 0.5f) centre = n;
  REQUIRE(centre >= 0);
  for (int frame = 1; frame <= 24; ++frame) {
    solver.step();
    const std::vector<float> pos = solver.node_pos(), vel = solver.node_vel();
    INFO("frame " << frame);
    REQUIRE(all_finite(pos));
    REQUIRE(all_finite(vel));
    const double cy = -0.3 + tear::key_offset(o.colliders[0].keys, frame)[1];
    for (index_t n = 0; n < mesh.node_count(); ++n) {
      const double dx = pos[3 * n] - 0.5, dy = pos[3 * n + 1] - cy, dz = pos[3 * n + 2] - 0.5;
      INFO("node " << n);
      REQUIRE(std::sqrt(dx * dx + dy * dy + dz * dz) >= radius - 1e-5);
    }
    if (frame == 12) {
      // Pushed on top of the sphere, moving up with it.
      CHECK(pos[3 * centre + 1] == Approx(cy + radius).margin(0.01));
      CHECK(vel[3 * centre + 1] == Approx(0.7).margin(0.01));
    }
  }
  // At rest on top of the sphere after it stopped.
  CHECK(solver.node_pos()[3 * centre + 1] == Approx(0.25).margin(0.01));
}

// ---- runs ------------------------------------------------------------------------------------------

namespace {

/// A hanging sheet whose top edge is carried sideways and back while a sphere swings through it,
/// cut twice along the way.
const char* keyed_script = R"({
  "version": 1, "frames": 16,
  "cuts": [
    {"frame": 4, "space": "rest-xy", "polyline": [[-0.1, 0.55], [0.6, 0.5]]},
    {"frame": 9, "space": "rest-xy", "polyline": [[1.1, 0.3], [0.3, 0.45]]}],
  "simulation": {"iterations": 30,
    "pins": [{"box": {"min": [-1, 0.99, -1], "max": [2, 2, 1]},
              "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 6, "offset": [0.2, 0, 0.1]},
                       {"frame": 12, "offset": [0, 0.05, 0]}]}],
    "colliders": [{"sphere": {"center": [0.5, 0.4, -0.4], "radius": 0.15},
                   "keys": [{"frame": 2, "offset": [0, 0, 0]}, {"frame": 10, "offset": [0, 0, 0.8]}]}]}
})";

std::string frame_name(int f) {
  return "f." + std::string(4 - std::to_string(f).size(), '0') + std::to_string(f) + ".ply";
}

}  // namespace

TEST_CASE("keys: a keyed run gives the same bytes twice, and resumed from a checkpoint mid-motion", "[keys]") {
  TempDir dir;
  tear::SheetOptions sheet;
  sheet.face_count = 800;
  tear::write_mesh(tear::make_sheet(sheet), (dir / "sheet.obj").string());
  const fs::path script = dir.file("shot.json", keyed_script);
  const std::string device = tear::to_string(tear::test::test_device());
  const std::string inputs = tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(script);
  const auto run = [&](const std::string& folder, const std::string& extra) {
    return dir.tear("run " + inputs + " -o " + tear::test::quoted(dir / folder / "f.####.ply") + " --device " + device +
                    extra);
  };
  REQUIRE(run("a", "").exit_code == 0);
  REQUIRE(run("b", "").exit_code == 0);
  // Stopped after frame 5 (the pin moving, the sphere too, a cut behind it), resumed to the end.
  const std::string checkpoint = " --checkpoint " + tear::test::quoted(dir / "shot.ckpt");
  REQUIRE(run("c", " --frames 5" + checkpoint).exit_code == 0);
  REQUIRE(fs::exists(dir / "shot.ckpt"));
  REQUIRE_FALSE(fs::exists(dir / "c" / frame_name(6)));
  REQUIRE(run("c", checkpoint + " --resume").exit_code == 0);
  for (int f = 1; f <= 16; ++f) {
    INFO(frame_name(f));
    const std::string a = tear::test::read_bytes(dir / "a" / frame_name(f));
    REQUIRE_FALSE(a.empty());
    CHECK(a == tear::test::read_bytes(dir / "b" / frame_name(f)));
    CHECK(a == tear::test::read_bytes(dir / "c" / frame_name(f)));
  }
}

TEST_CASE("keys: a cloth's frame count travels with its saved state", "[keys]") {
  const tear::Mesh mesh = horizontal_sheet(200);
  const SimulationOptions o = parse_simulation(R"({"pins": [{"nodes": [0],
      "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 6, "offset": [0, 0.6, 0]}]}]})");
  tear::Cloth whole(mesh, tear::test::test_device());
  whole.simulate(o);
  for (int f = 0; f < 5; ++f) whole.step();
  tear::Cloth first(mesh, tear::test::test_device());
  first.simulate(o);
  for (int f = 0; f < 3; ++f) first.step();
  const std::string state = first.save_state();
  tear::Cloth resumed(mesh, tear::test::test_device());
  resumed.simulate(o);
  resumed.load_state(state, "state");
  resumed.step();  // frame 4
  resumed.step();  // frame 5
  CHECK(resumed.node_pos() == whole.node_pos());
  CHECK(resumed.node_vel() == whole.node_vel());
  CHECK(whole.node_pos()[1] == Approx(0.5));
  CHECK_THROWS_AS(whole.step_frame(0), tear::Error);
}
