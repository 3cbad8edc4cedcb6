// The simulation in the frame loop: cuts, then a projective-dynamics step per frame; the normals of
// moved frames; the run report.
#include <stdlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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

/// Top edge pinned by a box, node 0 (the bottom-left corner) by index; at frame 2 a cut right across
/// the sheet between its grid rows separates the bottom part, which then hangs from node 0 alone.
const char* const hanging_script = R"({ "version": 1, "frames": 4,
  "cuts": [ { "frame": 2, "space": "rest-xy", "polyline": [[-0.1, 0.53], [1.1, 0.53]] } ],
  "simulation": { "substeps": 1, "iterations": 20,
                  "pins": [ { "box": { "min": [-1, 0.999, -1], "max": [2, 1.001, 1] } }, { "nodes": [0] } ] } })";

bool pinned_at_rest(const float* rest) {
  return rest[1] == 1.0f || (rest[0] == 0.0f && rest[1] == 0.0f && rest[2] == 0.0f);
}

}  // namespace

TEST_CASE("run_cuts: with a simulation block free nodes fall, pinned nodes stay, pins survive the cut", "[run]") {
  const tear::CutScript script = tear::parse_cut_script(hanging_script, "hanging.json");
  tear::Cloth cloth(regular_sheet(), test_device());
  std::vector<tear::index_t> faces;
  double lowest_drop = 0;
  tear::run_cuts(cloth, script, script.frames, [&](const tear::FrameResult& frame, const tear::Cloth& moved) {
    INFO("frame " << frame.frame);
    CHECK(frame.simulated);
    CHECK(frame.simulation_ms >= 0);
    faces.push_back(moved.face_count());
    const tear::Mesh mesh = moved.mesh();
    const std::vector<float> rest = moved.node_rest();
    const tear::MeshReport report = tear::validate_mesh(mesh, test_device());
    INFO(report.describe());
    CHECK(report.ok());
    int pinned = 0, corner_copies = 0;
    double drop = 0;
    for (tear::index_t n = 0; n < mesh.node_count(); ++n) {
      const float* r = &rest[3 * n];
      const float* p = &mesh.node_pos[3 * n];
      for (int a = 0; a < 3; ++a) REQUIRE(std::isfinite(p[a]));
      if (pinned_at_rest(r)) {
        ++pinned;
        if (r[1] == 0.0f) ++corner_copies;
        CHECK(p[0] == r[0]);
        CHECK(p[1] == r[1]);
        CHECK(p[2] == r[2]);
      } else {
        drop = std::max(drop, double(r[1]) - p[1]);
      }
    }
    CHECK(pinned == 12);  // the 11 nodes of the top row and the corner
    CHECK(corner_copies == 1);
    CHECK(drop > 0);
    lowest_drop = drop;
  });
  REQUIRE(faces.size() == 4);
  CHECK(faces[1] > faces[0]);
  // Four frames (1/6 s) of a part hanging from one corner: it swings down by centimetres.
  CHECK(lowest_drop > 0.01);
}

TEST_CASE("run_cuts: a simulation block error names its key path before the first frame", "[run]") {
  // The block's keys are checked when the script is parsed; what needs the mesh, here.
  CHECK_THROWS_WITH(tear::parse_cut_script(
                        R"({ "version": 1, "frames": 2, "simulation": { "chebyshev": { "rho": 2 } } })", "bad.json"),
                    Catch::Contains("bad.json: simulation.chebyshev.rho"));
  const tear::CutScript script = tear::parse_cut_script(
      R"({ "version": 1, "frames": 2, "simulation": { "pins": [ { "nodes": [0, 121] } ] } })", "bad.json");
  tear::Cloth cloth(regular_sheet(), test_device());
  int frames = 0;
  try {
    tear::run_cuts(cloth, script, 2, [&](const tear::FrameResult&, const tear::Cloth&) { ++frames; });
    FAIL("no error");
  } catch (const tear::Error& e) {
    CHECK(e.kind() == tear::ErrorKind::input);
    CHECK(std::string(e.what()) ==
          "bad.json: simulation.pins[0].nodes[1]: node 121 is out of range (the mesh has 121 nodes)");
  }
  CHECK(frames == 0);
}

TEST_CASE("run_cuts: without a simulation block nothing moves", "[run]") {
  const tear::CutScript script = tear::parse_cut_script(R"({ "version": 1, "frames": 2 })", "still.json");
  const tear::Mesh mesh = regular_sheet();
  tear::Cloth cloth(mesh, test_device());
  tear::run_cuts(cloth, script, 2, [&](const tear::FrameResult& frame, const tear::Cloth& still) {
    CHECK_FALSE(frame.simulated);
    CHECK(frame.simulation_ms == 0);
    CHECK(still.node_pos() == mesh.node_pos);
  });
}

TEST_CASE("Cloth: set_node_state replaces positions and velocities, keeps the rest shape", "[run]") {
  const tear::Mesh mesh = regular_sheet();
  tear::Cloth cloth(mesh, test_device());
  std::vector<float> pos = mesh.node_pos, vel(mesh.node_pos.size(), 0.0f);
  for (std::size_t i = 0; i < pos.size(); ++i) {
    pos[i] += 0.5f;
    vel[i] = float(i);
  }
  cloth.set_node_state(pos, vel);
  CHECK(cloth.node_pos() == pos);
  CHECK(cloth.node_vel() == vel);
  CHECK(cloth.node_rest() == mesh.node_pos);
  pos.pop_back();
  CHECK_THROWS_AS(cloth.set_node_state(pos, vel), tear::Error);
}

TEST_CASE("area_weighted_corner_normals: averaged across a shared edge, not across a torn one", "[run]") {
  // Two unit right triangles folded 90 degrees along the edge from (0,0,0) to (0,1,0): one in the
  // xy plane (normal +z), one in the yz plane (normal +x), oriented consistently.
  tear::Mesh joined;
  joined.node_pos = {0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1};
  joined.face_nodes = {0, 2, 1, 0, 1, 3};
  joined.corner_normal.assign(18, 0.0f);
  const std::vector<float> shared = tear::area_weighted_corner_normals(joined);
  REQUIRE(shared.size() == 18);
  const float h = float(1 / std::sqrt(2.0));
  // Corner 0 of face 0 is node 0, on the fold: the average of +z and +x (equal areas).
  CHECK(shared[0] == Approx(h));
  CHECK(shared[1] == Approx(0.0f).margin(1e-7));
  CHECK(shared[2] == Approx(h));
  // Corner 1 of face 0 is node 2, only in face 0: +z.
  CHECK(shared[3] == Approx(0.0f).margin(1e-7));
  CHECK(shared[5] == Approx(1.0f));

  // The same two faces torn apart along the fold: each keeps its own face normal everywhere.
  tear::Mesh torn = joined;
  torn.node_pos.insert(torn.node_pos.end(), {0, 0, 0, 0, 1, 0});
  torn.face_nodes = {0, 2, 1, 4, 5, 3};
  const std::vector<float> apart = tear::area_weighted_corner_normals(torn);
  for (int k = 0; k < 3; ++k) {
    INFO("corner " << k);
    CHECK(apart[3 * k + 2] == Approx(1.0f));
    CHECK(apart[9 + 3 * k + 0] == Approx(1.0f));
  }
}

TEST_CASE("run: a simulated run writes moved frames with normals of the moved shape", "[run]") {
  TempDir dir;
  const fs::path mesh = dir / "sheet.obj";
  tear::write_mesh(regular_sheet(), mesh.string());
  // Gravity across the sheet: it swings out of its plane, so the normals must turn.
  const fs::path script = dir.file("swing.json", R"({ "version": 1, "frames": 3,
    "simulation": { "substeps": 1, "iterations": 20, "gravity": [0, 0, -9.81],
                    "pins": [ { "box": { "min": [-1, 0.999, -1], "max": [2, 1.001, 1] } } ] } })");
  const Run run = dir.tear("run --device " + std::string(tear::to_string(test_device())) + " " + quoted(mesh) + " " +
                           quoted(script) + " -o " + quoted(dir / "out/f.#.obj"));
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const tear::Mesh last = tear::read_mesh((dir / "out/f.3.obj").string());
  REQUIRE(last.has_normals());
  double lowest_z = 0, least_z_normal = 1;
  for (tear::index_t n = 0; n < last.node_count(); ++n) lowest_z = std::min(lowest_z, double(last.node_pos[3 * n + 2]));
  CHECK(lowest_z < -0.01);
  for (tear::index_t f = 0; f < last.face_count(); ++f) {
    const float* p[3];
    for (int k = 0; k < 3; ++k) p[k] = &last.node_pos[3 * last.face_nodes[3 * f + k]];
    double u[3], v[3];
    for (int a = 0; a < 3; ++a) {
      u[a] = p[1][a] - p[0][a];
      v[a] = p[2][a] - p[0][a];
    }
    const double face_n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double face_len = std::sqrt(face_n[0] * face_n[0] + face_n[1] * face_n[1] + face_n[2] * face_n[2]);
    for (int k = 0; k < 3; ++k) {
      const float* c = &last.corner_normal[9 * f + 3 * k];
      CHECK(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) == Approx(1.0).epsilon(1e-4));
      // A smooth sheet: each corner normal leans close to its face's normal.
      CHECK((c[0] * face_n[0] + c[1] * face_n[1] + c[2] * face_n[2]) / face_len > 0.9);
      least_z_normal = std::min(least_z_normal, double(c[2]));
    }
  }
  // The carried normals were all (0, 0, 1).
  CHECK(least_z_normal < 0.999);
}

TEST_CASE("run: a simulation block error is refused with its key path, nothing written", "[run]") {
  TempDir dir;
  const fs::path mesh = dir / "sheet.obj";
  tear::write_mesh(regular_sheet(), mesh.string());
  const std::string device = tear::to_string(test_device());
  struct Case {
    const char* block;
    const char* key_path;
  };
  for (const Case& c : {Case{R"({ "chebyshev": { "rho": 2 } })", "simulation.chebyshev.rho"},
                        Case{R"({ "dampning": 0.1 })", "simulation"},
                        Case{R"({ "pins": [ { "nodes": [0, 121] } ] })", "simulation.pins[0].nodes[1]"}}) {
    INFO(c.block);
    const fs::path script =
        dir.file("bad.json", std::string(R"({ "version": 1, "frames": 2, "simulation": )") + c.block + " }");
    const fs::path out = dir / "out";
    const fs::path report = dir / "report.json";
    const Run run = dir.tear("run --device " + device + " " + quoted(mesh) + " " + quoted(script) + " -o " +
                             quoted(out / "f.#.obj") + " --report " + quoted(report));
    INFO("stderr: " << run.err);
    CHECK(run.exit_code == 2);
    CHECK(run.out.empty());
    CHECK(run.err.rfind("tear: ", 0) == 0);
    CHECK(run.err.find("bad.json: " + std::string(c.key_path)) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    CHECK_FALSE(fs::exists(report));
  }
}

TEST_CASE("run: --report writes the documented keys and one entry per frame", "[run]") {
  TempDir dir;
  const fs::path mesh = dir / "sheet.obj";
  tear::write_mesh(regular_sheet(), mesh.string());
  const fs::path script = dir.file("cuts.json", R"({ "version": 1, "frames": 3, "cuts": [
    { "frame": 2, "space": "rest-xy", "polyline": [[-0.1, 0.53], [0.56, 0.53]] },
    { "frame": 2, "space": "rest-xy", "polyline": [[0.47, -0.1], [0.47, 0.33]] } ],
    "simulation": { "substeps": 1, "iterations": 10,
                    "pins": [ { "box": { "min": [-1, 0.999, -1], "max": [2, 1.001, 1] } } ] } })");
  const fs::path report_path = dir / "reports/run.json";
  const std::string device = tear::to_string(test_device());
  const Run run = dir.tear("run --device " + device + " " + quoted(mesh) + " " + quoted(script) + " -o " +
                           quoted(dir / "out/f.#.obj") + " --report " + quoted(report_path));
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  REQUIRE(fs::exists(report_path));
  const nlohmann::json report = nlohmann::json::parse(read_bytes(report_path));
  for (const char* key : {"frames", "totals", "device", "device_name", "mesh", "script"}) {
    INFO(key);
    CHECK(report.contains(key));
  }
  CHECK(report["device"] == device);
  CHECK(report["device_name"] == tear::device_name(test_device()));
  CHECK(report["mesh"] == mesh.string());
  CHECK(report["script"] == script.string());
  const nlohmann::json& frames = report["frames"];
  REQUIRE(frames.is_array());
  REQUIRE(frames.size() == 3);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    INFO("frame entry " << i);
    const nlohmann::json& f = frames[i];
    for (const char* key : {"frame", "nodes", "faces", "cuts", "remesh_ms", "simulation_ms", "min_angle_deg"}) {
      INFO(key);
      REQUIRE(f.contains(key));
    }
    CHECK(f["frame"] == int(i) + 1);
    CHECK(f["cuts"] == (i == 1 ? 2 : 0));
    CHECK(f["simulation_ms"].get<double>() > 0);
    CHECK(f["remesh_ms"].get<double>() >= 0);
    CHECK(f["min_angle_deg"].get<double>() > 0);
    CHECK(f["min_angle_deg"].get<double>() <= 60);
    const tear::Mesh written = tear::read_mesh((dir / ("out/f." + std::to_string(i + 1) + ".obj")).string());
    CHECK(f["faces"] == written.face_count());
  }
  CHECK(frames[0]["faces"] == 200);
  CHECK(frames[0]["nodes"] == 121);
  CHECK(frames[1]["faces"].get<int>() > 200);
  CHECK(frames[1]["nodes"].get<int>() > 121);
  CHECK(frames[0]["remesh_ms"] == 0);
  CHECK(frames[1]["remesh_ms"].get<double>() > 0);
  const nlohmann::json& totals = report["totals"];
  CHECK(totals["frames"] == 3);
  double simulation_ms = 0;
  for (const auto& f : frames) simulation_ms += f["simulation_ms"].get<double>();
  CHECK(totals["simulation_ms"].get<double>() == Approx(simulation_ms));
  CHECK(totals["remesh_ms"].get<double>() == Approx(frames[1]["remesh_ms"].get<double>()));
  CHECK(totals["wall_ms"].get<double>() >= simulation_ms);
  // The parts of the run on its own thread: each measured, none longer than the whole run (which
  // starts after the inputs are read).
  for (const char* part : {"setup_ms", "download_ms", "write_wait_ms"}) {
    INFO(part);
    CHECK(totals[part].get<double>() >= 0);
    CHECK(totals[part].get<double>() <= totals["wall_ms"].get<double>());
  }
  CHECK(totals["setup_ms"].get<double>() + totals["download_ms"].get<double>() + totals["write_wait_ms"].get<double>() +
            simulation_ms + totals["remesh_ms"].get<double>() <=
        totals["wall_ms"].get<double>());
  CHECK(totals["input_ms"].get<double>() > 0);  // the mesh and script read
  CHECK(totals["download_ms"].get<double>() > 0);
}
