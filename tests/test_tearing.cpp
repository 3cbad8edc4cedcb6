// The cloth tearing by itself (`simulation.tearing`): a notched sheet pulled apart by keyed pins
// tears from the notch across into two pieces, a high limit does not tear, runs repeat bit for bit,
// the keys are read and refused as the other simulation keys are.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <stb_image_write.h>

#include "catch.h"
#include "cli_support.h"
#include "random_meshes.h"
#include "remesh_checks.h"
#include "tear/bench.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/device.h"
#include "tear/error.h"
#include "tear/make_sheet.h"
#include "tear/run_cuts.h"
#include "tear/simulation.h"
#include "tear/validate_mesh.h"
#include "tear/write_mesh.h"
#include "tear_cracks.h"
#include "test_support.h"

namespace {

using tear::index_t;
namespace fs = std::filesystem;
using tear::test::TempDir;

constexpr int pull_frames = 24;

/// A sheet [0,1]² notched by a slit from its bottom border to (0.5, 0.25) in frame 1, its left and
/// right strips pulled apart by keyed pins (0.15 m each way over `pull_frames` frames), tearing at
/// `stretch`.
std::string pull_script(double stretch, const std::string& more_keys = "", const std::string& more_simulation = "") {
  const std::string frames = std::to_string(pull_frames);
  return R"({"version": 1, "frames": )" + frames + R"(,
    "cuts": [{"frame": 1, "space": "rest-xy", "polyline": [[0.5, -0.1], [0.5, 0.25]]}],
    "simulation": {"gravity": [0, 0, 0], "substeps": 4, "iterations": 40,)" + more_simulation + R"(
      "pins": [
        {"box": {"min": [-1, -1, -1], "max": [0.04, 2, 1]},
         "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": )" +
         frames + R"(, "offset": [-0.15, 0, 0]}]},
        {"box": {"min": [0.96, -1, -1], "max": [2, 2, 1]},
         "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": )" +
         frames + R"(, "offset": [0.15, 0, 0]}]}],
      "tearing": {"stretch": )" +
         std::to_string(stretch) + more_keys + R"(}}})";
}

/// The tearing keys that vary the limits, all at once (`pull_script`'s `more_keys`), with the
/// strength map they name written into `dir`: a soft band a twentieth weaker along u = 0.5.
std::string every_limit_key(const TempDir& dir) {
  std::vector<unsigned char> texels(64 * 4);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 64; ++i)
      texels[j * 64 + i] = static_cast<unsigned char>(
          std::lround(255 * (1 - 0.05 * std::exp(-std::pow(((i + 0.5) / 64 - 0.5) / 0.1, 2)))));
  REQUIRE(stbi_write_png((dir / "weak.png").string().c_str(), 64, 4, 1, texels.data(), 64) != 0);
  return R"(, "weave": {"warp": [0, 1], "weft_strength": 0.95}, "seam_strength": 0.95, "variation": 0.05,
    "seed": 7, "strength_map": "weak.png")";
}

tear::Mesh pull_sheet() {
  tear::SheetOptions sheet;
  sheet.face_count = 800;
  return tear::make_sheet(sheet);
}

struct PullResult {
  index_t tear_events = 0;
  double torn_length = 0;
  index_t pieces = 0;
  bool sides_apart = false;  ///< no piece holds nodes of both pinned strips
  bool edge_nodes = false;   ///< a node made by tearing lies strictly inside an input edge
};

PullResult pull(double stretch) {
  const tear::Mesh mesh = pull_sheet();
  const double area = tear::test::total_area(mesh);
  const tear::CutScript script = tear::parse_cut_script(pull_script(stretch), "pull.json");
  tear::Cloth cloth(mesh, tear::test::test_device());
  PullResult result;
  index_t nodes_after_notch = 0;
  tear::run_cuts(cloth, script, pull_frames, [&](const tear::FrameResult& frame, const tear::Cloth& c) {
    INFO("frame " << frame.frame);
    if (frame.frame == 1) nodes_after_notch = frame.stats.nodes_after;
    CHECK(frame.tearing);
    CHECK(frame.tear_events >= 0);
    CHECK(frame.torn_length >= 0);
    CHECK((frame.tear_events > 0) == (frame.torn_length > 0));
    result.tear_events += frame.tear_events;
    result.torn_length += frame.torn_length;
    // A valid oriented manifold (no bow-ties) whose rest shape keeps its area.
    tear::Mesh rest_shape = c.mesh();
    rest_shape.node_pos = c.node_rest();
    const tear::MeshReport report = tear::validate_mesh(rest_shape, c.topology(), tear::test::test_device());
    INFO(report.describe());
    CHECK(report.ok());
    CHECK(std::abs(tear::test::total_area(rest_shape) - area) <= 1e-5 * area);
    REQUIRE(c.state_is_finite());
  });
  const tear::Mesh m = cloth.mesh();
  const std::vector<index_t> piece = tear::test::node_piece_roots(m);
  std::vector<index_t> roots(piece);
  std::sort(roots.begin(), roots.end());
  result.pieces = static_cast<index_t>(std::unique(roots.begin(), roots.end()) - roots.begin());
  const std::vector<float> rest = cloth.node_rest();
  std::vector<index_t> left, right;
  for (index_t n = 0; n < m.node_count(); ++n) {
    if (rest[3 * n] <= 0.04f) left.push_back(piece[n]);
    if (rest[3 * n] >= 0.96f) right.push_back(piece[n]);
  }
  std::sort(left.begin(), left.end());
  std::sort(right.begin(), right.end());
  std::vector<index_t> both;
  std::set_intersection(left.begin(), left.end(), right.begin(), right.end(), std::back_inserter(both));
  result.sides_apart = !left.empty() && !right.empty() && both.empty();
  // Nodes made by tearing (after the notch's, appended after them) inside an input edge: on input
  // edge 1 or 2 (origin weight b1 or b2 exactly 0, as zero weights stay exact) strictly inside it.
  for (index_t n = nodes_after_notch; n < m.node_count(); ++n) {
    const float b1 = m.node_origin_bary[2 * n], b2 = m.node_origin_bary[2 * n + 1];
    if ((b1 == 0.0f && b2 > 1e-4f && b2 < 1 - 1e-4f) || (b2 == 0.0f && b1 > 1e-4f && b1 < 1 - 1e-4f))
      result.edge_nodes = true;
  }
  return result;
}

}  // namespace

TEST_CASE("tearing: a notched sheet pulled apart tears from the notch across into two pieces", "[tearing]") {
  const PullResult r = pull(1.3);
  INFO("events " << r.tear_events << ", torn " << r.torn_length << " m, pieces " << r.pieces);
  CHECK(r.tear_events > 0);
  CHECK(r.torn_length > 0.5);  // at least the 0.75 m ligament, less what snapping and nodes take
  CHECK(r.pieces == 2);  // the halves, no shreds
  CHECK(r.sides_apart);
  CHECK(r.edge_nodes);
}

TEST_CASE("tearing: the same pull with a high limit does not tear", "[tearing]") {
  const PullResult r = pull(100);
  CHECK(r.tear_events == 0);
  CHECK(r.torn_length == 0);
  CHECK(r.pieces == 1);
  CHECK_FALSE(r.sides_apart);
}

/// Self-collision of the torn pieces (`pull_script`'s `more_simulation`).
const char* const self_collision = R"("collision": {"self": true, "thickness": 0.004, "friction": 0.2},)";

TEST_CASE("tearing: a tearing run gives the same bytes twice and when resumed, and reports its tears", "[tearing]") {
  // With the limit alone, with every key that varies it (grain, seams, noise, a painted map), and
  // with those and self-collision.
  const int keys = GENERATE(0, 1, 2);
  const bool every_key = keys > 0;
  INFO((keys == 0 ? "the limit alone" : keys == 1 ? "every limit key" : "every limit key and self-collision"));
  TempDir dir;
  tear::write_mesh(pull_sheet(), (dir / "sheet.obj").string());
  const fs::path script = dir.file(
      "pull.json", pull_script(1.3, every_key ? every_limit_key(dir) : "", keys == 2 ? self_collision : ""));
  const std::string device = tear::to_string(tear::test::test_device());
  const std::string inputs = tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(script);
  const auto run = [&](const std::string& folder, const std::string& extra = "") {
    return dir.tear("run " + inputs + " -v -o " + tear::test::quoted(dir / folder / "f.####.ply") + " --device " +
                    device + " --report " + tear::test::quoted(dir / folder / "report.json") + extra);
  };
  const tear::test::Run a = run("a");
  REQUIRE(a.exit_code == 0);
  REQUIRE(run("b").exit_code == 0);
  // Stopped mid-tear and resumed: the bytes of the run never stopped.
  const std::string checkpoint = " --checkpoint " + tear::test::quoted(dir / "pull.ckpt");
  REQUIRE(run("c", " --frames 14" + checkpoint).exit_code == 0);
  REQUIRE(run("c", checkpoint + " --resume").exit_code == 0);
  CHECK(a.out.find(" tear events (") != std::string::npos);
  for (int f = 1; f <= pull_frames; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "f.%04d.ply", f);
    INFO(name);
    const std::string bytes = tear::test::read_bytes(dir / "a" / name);
    REQUIRE_FALSE(bytes.empty());
    CHECK(bytes == tear::test::read_bytes(dir / "b" / name));
    CHECK(bytes == tear::test::read_bytes(dir / "c" / name));
  }
  const nlohmann::json report = nlohmann::json::parse(tear::test::read_bytes(dir / "a" / "report.json"));
  index_t events = 0;
  double length = 0;
  for (const auto& frame : report["frames"]) {
    events += frame["tear_events"].get<index_t>();
    length += frame["torn_length_m"].get<double>();
  }
  CHECK(events > 0);
  CHECK(length > 0);
}

TEST_CASE("tearing: the bench's tear part times the pull scene's parts, and the CLI prints them", "[tearing][bench]") {
  tear::BenchOptions options;
  options.resolutions = {tear::DemoResolution::low};
  options.repeats = 1;
  options.warmup = 0;
  const std::vector<tear::TearBenchRow> rows = tear::run_tear_bench(options, tear::test::test_device());
  REQUIRE(rows.size() == 1);
  const tear::TearBenchRow& r = rows[0];
  INFO(tear::to_json(r));
  CHECK(r.frames == tear::demo_frames);
  CHECK(r.faces_start == tear::demo_face_count(tear::DemoResolution::low));
  CHECK(r.faces_end > r.faces_start);
  CHECK(r.tear_events > 0);
  CHECK(r.solver_ms > 0);
  CHECK(r.check_ms > 0);
  // The strain rate limit runs after every substep, and a view is waited for after every tear:
  // both parts of the check.
  CHECK(r.limit_ms > 0);
  CHECK(r.view_ms > 0);
  CHECK(r.limit_ms + r.view_ms <= r.check_ms);
  CHECK(r.apply_ms > 0);
  CHECK(r.rebuild_ms > 0);
  CHECK(r.frame_ms_mean >= r.solver_ms + r.check_ms + r.apply_ms);
  CHECK(r.tear_fraction == Approx((r.check_ms + r.apply_ms + r.rebuild_ms) / r.solver_ms));

  TempDir dir;
  const tear::test::Run bad = dir.tear("bench --device cpu --only tears --repeats 1 --warmup 0");
  CHECK(bad.exit_code == 1);
  CHECK(bad.err.find("expected remesh, pd, scene, tear, collide or io") != std::string::npos);
}

TEST_CASE("tearing: the keys are read with their defaults", "[tearing]") {
  const auto parse = [](const std::string& block) {
    return *tear::parse_cut_script(R"({"version": 1, "frames": 1, "snap": 0.1, "simulation": )" + block + "}", "s.json")
                .simulation;
  };
  const tear::SimulationOptions off = parse("{}");
  CHECK_FALSE(off.tearing.enabled());
  const tear::SimulationOptions on = parse(R"({"tearing": {"stretch": 1.25}})");
  CHECK(on.tearing.enabled());
  CHECK(on.tearing.stretch == 1.25);
  CHECK(on.tearing.max_faces_per_step == 64);
  CHECK(on.tearing.snap == 0.1);  // the script's
  const tear::SimulationOptions capped = parse(R"({"tearing": {"stretch": 1000, "max_faces_per_step": 3}})");
  CHECK(capped.tearing.max_faces_per_step == 3);
  // The face budget: 8 times the faces the simulation starts with, at least 100,000; or as given.
  CHECK(on.tearing.max_faces == 0);
  CHECK(on.tearing.face_budget(800) == 100000);
  CHECK(on.tearing.face_budget(50000) == 400000);
  CHECK(on.tearing.face_budget(500000000) == 715827882);
  const tear::SimulationOptions budget = parse(R"({"tearing": {"stretch": 2, "max_faces": 1000}})");
  CHECK(budget.tearing.face_budget(50000) == 1000);
}

TEST_CASE("tearing: a tear past tearing.max_faces stops the run, naming the key", "[tearing]") {
  // The budget: the faces after the pull's first tear. The frame of its next tear passes it, so
  // the run stops there, the frames before it on disk.
  std::vector<index_t> faces;
  {
    tear::Cloth cloth(pull_sheet(), tear::test::test_device());
    tear::run_cuts(cloth, tear::parse_cut_script(pull_script(1.3), "pull.json"), pull_frames,
                   [&](const tear::FrameResult&, const tear::Cloth& c) { faces.push_back(c.face_count()); });
  }
  std::size_t first = 1;
  while (first < faces.size() && faces[first] == faces[first - 1]) ++first;
  std::size_t next = first + 1;
  while (next < faces.size() && faces[next] == faces[first]) ++next;
  REQUIRE(next < faces.size());
  const index_t budget = faces[first];
  const std::string stopped = std::to_string(next + 1), last_written = std::to_string(next);
  INFO("faces after the first tear (frame " << first + 1 << "): " << budget << "; next tear in frame " << stopped);
  TempDir dir;
  tear::write_mesh(pull_sheet(), (dir / "sheet.obj").string());
  std::string script = pull_script(1.3);
  const std::string stretch = "\"stretch\": ";
  script.insert(script.find(stretch), "\"max_faces\": " + std::to_string(budget) + ", ");
  const fs::path path = dir.file("pull.json", script);
  const tear::test::Run run =
      dir.tear("run " + tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(path) + " -o " +
               tear::test::quoted(dir / "out" / "f.####.ply") + " --device " + tear::to_string(tear::test::test_device()));
  INFO(run.err);
  CHECK(run.exit_code == 3);
  CHECK(run.err.rfind("tear: ", 0) == 0);
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK(run.err.find("pull.json: frame ") != std::string::npos);
  CHECK(run.err.find(": simulation.tearing.max_faces: tearing left the cloth with ") != std::string::npos);
  CHECK(run.err.find(" faces, over the limit of " + std::to_string(budget) +
                     "; raise tearing.max_faces, or tearing.stretch so that less tears") != std::string::npos);
  // The frames before the one that passed it are on disk.
  const auto frame_file = [&](const std::string& frame) {
    return dir / "out" / ("f." + std::string(4 - frame.size(), '0') + frame + ".ply");
  };
  CHECK(run.err.find("pull.json: frame " + stopped + ": ") != std::string::npos);
  CHECK(fs::exists(frame_file(last_written)));
  CHECK_FALSE(fs::exists(frame_file(stopped)));
  // The library: a budget set on the options, a runtime Error.
  const tear::Mesh mesh = pull_sheet();
  tear::Cloth cloth(mesh, tear::test::test_device());
  const tear::CutScript pull = tear::parse_cut_script(pull_script(1.3), "pull.json");
  tear::SimulationOptions small = *pull.simulation;
  small.tearing.max_faces = mesh.face_count() + 10;
  cloth.simulate(small);
  try {
    tear::run_cuts(cloth, pull, pull_frames, {});
    FAIL("tore past the budget");
  } catch (const tear::Error& e) {
    CHECK(e.kind() == tear::ErrorKind::runtime);
    CHECK(std::string(e.what()).find("simulation.tearing.max_faces") != std::string::npos);
  }
}

TEST_CASE("tearing: every error names the file and the key path", "[tearing]") {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"tearing": 1.5})", "simulation.tearing: expected an object, got 1.5"},
      {R"({"tearing": {}})", "simulation.tearing.stretch: missing (expected a number in (1, 1000] (stretch ratio))"},
      {R"({"tearing": {"stretch": 1}})",
       "simulation.tearing.stretch: expected a number in (1, 1000] (stretch ratio), got 1"},
      {R"({"tearing": {"stretch": 0.5}})",
       "simulation.tearing.stretch: expected a number in (1, 1000] (stretch ratio), got 0.5"},
      {R"({"tearing": {"stretch": 1001}})",
       "simulation.tearing.stretch: expected a number in (1, 1000] (stretch ratio), got 1001"},
      {R"({"tearing": {"stretch": "2"}})",
       "simulation.tearing.stretch: expected a number in (1, 1000] (stretch ratio), got \"2\""},
      {R"({"tearing": {"stretch": 2, "max_faces_per_step": 0}})",
       "simulation.tearing.max_faces_per_step: expected an integer in 1..100000000 (crack advances per substep), got 0"},
      {R"({"tearing": {"stretch": 2, "max_faces_per_step": 2.5}})",
       "simulation.tearing.max_faces_per_step: expected an integer in 1..100000000 (crack advances per substep), got 2.5"},
      {R"({"tearing": {"stretch": 2, "toughness": 3}})",
       "simulation.tearing.toughness: unknown key (expected stretch, start, radius, step, min_piece, "
       "max_faces_per_step, max_faces, weave, seam_strength, variation, seed, strength_map or strain_rate_limit)"},
      {R"({"tearing": {"stretch": 2, "strain_rate_limit": -0.1}})",
       "simulation.tearing.strain_rate_limit: expected a number in [0, 1] (fraction of a face's altitude per substep), "
       "got -0.1"},
      {R"({"tearing": {"stretch": 2, "strain_rate_limit": 1.5}})",
       "simulation.tearing.strain_rate_limit: expected a number in [0, 1] (fraction of a face's altitude per substep), "
       "got 1.5"},
      {R"({"tearing": {"stretch": 2, "max_faces": 0}})",
       "simulation.tearing.max_faces: expected an integer in 1..715827882 (faces the cloth may tear to), got 0"},
      {R"({"tearing": {"stretch": 2, "max_faces": 1e12}})",
       "simulation.tearing.max_faces: expected an integer in 1..715827882 (faces the cloth may tear to), got 1000000000000.0"},
  };
  for (const auto& [text, message] : cases) {
    INFO(text);
    try {
      tear::parse_cut_script(std::string(R"({"version": 1, "frames": 1, "simulation": )") + text + "}", "script.json");
      FAIL("parsed without an error");
    } catch (const tear::Error& e) {
      CHECK(e.kind() == tear::ErrorKind::input);
      CHECK(std::string(e.what()) == std::string("script.json: ") + message);
    }
  }
}

TEST_CASE("tear_cracks: a triangle stretched along x has its stretch along x", "[tearing]") {
  // The example of kernels/tear_cracks.h.
  const index_t face_nodes[] = {0, 1, 2};
  const float node_rest[] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, node_pos[] = {0, 0, 0, 1.5f, 0, 0, 0, 1, 0};
  double r[3];
  CHECK(tear::kernels::face_principal_stretch(face_nodes, node_rest, node_pos, 0, r) == Approx(1.5));
  CHECK(std::abs(r[0]) == Approx(1.0));
  CHECK(r[1] == Approx(0.0).margin(1e-12));
  CHECK(tear::kernels::face_principal_stretch(face_nodes, node_rest, node_rest, 0) == Approx(1.0));
  const tear::kernels::face_stretch_of of{face_nodes, node_rest, node_pos};
  CHECK(of(0) == Approx(1.5));
}

TEST_CASE("tearing properties: random sheets pulled at random tear into valid meshes, the same twice",
          "[tearing][property]") {
  const std::uint64_t base = tear::test::test_seed(1);
  const bool one_seed = std::getenv("TEAR_TEST_SEED") != nullptr;
  int torn_seeds = 0;
  for (int i = 0; i < (one_seed ? 1 : 8); ++i) {
    const std::uint64_t seed = base + std::uint64_t(i);
    INFO("seed " << seed);
    tear::test::Random random(seed);
    const tear::Mesh mesh = tear::test::random_sheet(random.bits(), 300);
    double size = 0;
    for (std::size_t a = 0; a < mesh.node_pos.size(); a += 3) size = std::max<double>(size, mesh.node_pos[a]);
    const double area = tear::test::total_area(mesh);
    // Two opposite strips pulled apart along a random direction, with a random notch or none.
    const bool along_x = random.chance(0.5);
    const double pull = random.uniform(0.1, 0.5) * size, lift = random.uniform(-0.2, 0.2) * size;
    // Limits the pulls pass (the stretch is smoothed over a tenth of the sheet, so it has no
    // single-face peaks to pass).
    const double stretch = random.uniform(1.02, 1.25);
    const int cap = random.chance(0.3) ? 1 + random.below(4) : 64;
    const int frames = 6;
    const auto box = [&](bool low) {
      const double lo = low ? -1 : 0.9 * size, hi = low ? 0.1 * size : 2 * size;
      return along_x
                 ? "{\"min\": [" + std::to_string(lo) + ", -1e3, -1], \"max\": [" + std::to_string(hi) + ", 1e3, 1]}"
                 : "{\"min\": [-1e3, " + std::to_string(lo) + ", -1], \"max\": [1e3, " + std::to_string(hi) + ", 1]}";
    };
    const auto offset = [&](double sign) {
      return along_x ? "[" + std::to_string(sign * pull) + ", 0, " + std::to_string(lift) + "]"
                     : "[0, " + std::to_string(sign * pull) + ", " + std::to_string(lift) + "]";
    };
    std::string cuts;
    if (random.chance(0.5)) {
      const double at = random.uniform(0.3, 0.7) * size, depth = random.uniform(0.1, 0.4) * size;
      cuts = along_x
                 ? "[[" + std::to_string(at) + ", -1], [" + std::to_string(at) + ", " + std::to_string(depth) + "]]"
                 : "[[-1, " + std::to_string(at) + "], [" + std::to_string(depth) + ", " + std::to_string(at) + "]]";
      cuts = R"("cuts": [{"frame": 1, "space": "rest-xy", "polyline": )" + cuts + "}],";
    }
    const std::string script_text =
        R"({"version": 1, "frames": )" + std::to_string(frames) + "," + cuts +
        R"("simulation": {"gravity": [0, -9.81, 0], "substeps": 2, "iterations": 20, "pins": [{"box": )" + box(true) +
        R"(, "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 4, "offset": )" + offset(-1) + R"(}]}, {"box": )" +
        box(false) + R"(, "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 4, "offset": )" + offset(1) +
        R"(}]}], "tearing": {"stretch": )" + std::to_string(stretch) + R"(, "radius": )" + std::to_string(0.1 * size) +
        R"(, "max_faces_per_step": )" +
        std::to_string(cap) + "}}}";
    INFO(script_text);
    const tear::CutScript script = tear::parse_cut_script(script_text, "random.json");
    std::vector<tear::Mesh> runs[2];
    index_t events = 0;
    for (auto& run : runs) {
      tear::Cloth cloth(mesh, tear::test::test_device());
      tear::run_cuts(cloth, script, frames, [&](const tear::FrameResult& frame, const tear::Cloth& c) {
        INFO("frame " << frame.frame);
        CHECK(frame.tear_events <= cap * 2);  // at most `cap` advances per substep
        events += frame.tear_events;
        tear::Mesh rest_shape = c.mesh();
        run.push_back(rest_shape);
        rest_shape.node_pos = c.node_rest();
        const tear::MeshReport report = tear::validate_mesh(rest_shape, c.topology(), tear::test::test_device());
        INFO(report.describe());
        CHECK(report.ok());
        CHECK(std::abs(tear::test::total_area(rest_shape) - area) <= 1e-5 * area);
        tear::test::check_uv_is_xy(rest_shape, size);
        REQUIRE(c.state_is_finite());
      });
    }
    for (int f = 0; f < frames; ++f) {
      INFO("frame " << f + 1);
      CHECK(runs[0][f].face_nodes == runs[1][f].face_nodes);
      CHECK(runs[0][f].node_pos == runs[1][f].node_pos);
    }
    if (events > 0) ++torn_seeds;
  }
  if (!one_seed) CHECK(torn_seeds >= 4);  // most pulls tear
}

TEST_CASE("tearing: CUDA and CPU tear the pulled sheet alike", "[tearing][parity]") {
  if (!tear::cuda_available()) {
    WARN("no GPU: tearing parity not checked");
    return;
  }
  // The same pull on both backends, frame by frame: the same faces torn (same topology, node for
  // node), positions within the solver's parity bound.
  const int keys = GENERATE(0, 1, 2);
  const bool every_key = keys > 0;
  INFO((keys == 0 ? "the limit alone" : keys == 1 ? "every limit key" : "every limit key and self-collision"));
  TempDir dir;
  const tear::Mesh mesh = pull_sheet();
  const tear::CutScript script = tear::parse_cut_script(
      pull_script(1.3, every_key ? every_limit_key(dir) : "", keys == 2 ? self_collision : ""),
      (dir / "pull.json").string());
  std::vector<tear::Mesh> frames[2];
  int torn[2] = {0, 0};
  const tear::Device devices[2] = {tear::Device::cpu, tear::Device::cuda};
  for (int d = 0; d < 2; ++d) {
    tear::Cloth cloth(mesh, devices[d]);
    tear::run_cuts(cloth, script, pull_frames, [&](const tear::FrameResult& frame, const tear::Cloth& c) {
      torn[d] += frame.tear_events;
      frames[d].push_back(c.mesh());
    });
  }
  REQUIRE(frames[0].size() == frames[1].size());
  CHECK(torn[0] > 0);
  CHECK(torn[0] == torn[1]);
  for (std::size_t f = 0; f < frames[0].size(); ++f) {
    INFO("frame " << f + 1);
    REQUIRE(frames[0][f].face_nodes == frames[1][f].face_nodes);
    double worst = 0;
    for (std::size_t k = 0; k < frames[0][f].node_pos.size(); ++k)
      worst = std::max(worst, std::abs(double(frames[0][f].node_pos[k]) - frames[1][f].node_pos[k]));
    CHECK(worst <= 1e-3);
  }
}
