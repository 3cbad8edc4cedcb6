#include "tear/run_cuts.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/simulation.h"
#include "tear/validate_mesh.h"
#include "tear/write_mesh.h"

namespace tear {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void check_frame_count(const CutScript& script, int frame_count) {
  if (frame_count < 1 || frame_count > script.frames)
    throw Error(ErrorKind::usage, script.path + ": cannot run " + std::to_string(frame_count) +
                                      " frames (expected 1.." + std::to_string(script.frames) +
                                      ", the frames of the script)");
}

void create_folder_of(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (folder.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw runtime_error(folder.string() + ": cannot create the output folder: " + error.message());
}

/// The options with only the pins of one kind.
SimulationOptions with_pins_of(const SimulationOptions& options, Pin::Kind kind) {
  SimulationOptions only = options;
  only.pins.clear();
  for (const Pin& pin : options.pins)
    if (pin.kind == kind) only.pins.push_back(pin);
  return only;
}

/// The simulation of a run: the solver of the cloth's current mesh and the `nodes` pins carried
/// through the cuts.
class FrameSimulation {
 public:
  FrameSimulation(const SimulationOptions& options, const Cloth& cloth)
      : options_(options),
        box_pins_(with_pins_of(options, Pin::Kind::box)),
        node_listed_(resolve_pins(with_pins_of(options, Pin::Kind::nodes), cloth.node_rest(), cloth.node_count())) {}

  /// Rebuilds the solver when the cloth's mesh is not the one it was built for, then steps a frame.
  void step(Cloth& cloth, bool mesh_changed) {
    if (!solver_ || mesh_changed) rebuild(cloth);
    solver_->step(cloth);
  }

 private:
  void rebuild(const Cloth& cloth) {
    const index_t node_count = cloth.node_count();
    if (solver_) {
      // After a cut: the provenance (a download) is only needed while a listed pin is left to carry.
      if (std::find(node_listed_.begin(), node_listed_.end(), 1) != node_listed_.end())
        carry_listed_pins(cloth.provenance(), node_count);
      else
        node_listed_.assign(static_cast<std::size_t>(node_count), 0);
    }
    const std::vector<float> node_rest = cloth.node_rest();
    std::vector<std::uint8_t> node_pinned = resolve_pins(box_pins_, node_rest, node_count);
    for (index_t n = 0; n < node_count; ++n) node_pinned[n] |= node_listed_[n];
    solver_ = std::make_unique<PdSolver>(cloth, options_, node_pinned);
  }

  /// A new node stays pinned when its only source (weight 1) was: the copies of a pinned node. A node
  /// interpolated between several old ones lies on a cut edge or inside a face, and is free.
  void carry_listed_pins(const CutProvenance& provenance, index_t node_count) {
    std::vector<std::uint8_t> carried(static_cast<std::size_t>(node_count), 0);
    if (provenance.node_source.size() == 3 * carried.size()) {
      for (index_t n = 0; n < node_count; ++n) {
        const index_t* source = &provenance.node_source[3 * static_cast<std::size_t>(n)];
        const float* weight = &provenance.node_source_weight[3 * static_cast<std::size_t>(n)];
        int used = 0;
        index_t only = -1;
        for (int k = 0; k < 3; ++k)
          if (source[k] >= 0 && weight[k] != 0.0f) {
            ++used;
            only = source[k];
          }
        if (used == 1 && only < static_cast<index_t>(node_listed_.size()) && node_listed_[only]) carried[n] = 1;
      }
    }
    node_listed_.swap(carried);
  }

  SimulationOptions options_;
  SimulationOptions box_pins_;
  std::vector<std::uint8_t> node_listed_;  // [node_count] pinned by a `nodes` pin, on the current mesh
  std::unique_ptr<PdSolver> solver_;
};

using Vec3 = std::array<double, 3>;

Vec3 node_at(const std::vector<float>& node_pos, index_t n) {
  const std::size_t i = 3 * static_cast<std::size_t>(n);
  return {node_pos[i], node_pos[i + 1], node_pos[i + 2]};
}
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

nlohmann::json frame_report(const FrameResult& frame, const Cloth& cloth) {
  return {{"frame", frame.frame},    {"nodes", cloth.node_count()},  {"faces", cloth.face_count()},
          {"cuts", frame.cut_count}, {"remesh_ms", frame.remesh_ms}, {"simulation_ms", frame.simulation_ms},
          {"min_angle_deg", nullptr}};
}

}  // namespace

std::vector<float> area_weighted_corner_normals(const Mesh& mesh) {
  const index_t face_count = mesh.face_count();
  // The cross product of two edges is the face normal scaled by twice its area: summing them
  // weights each face by its area.
  std::vector<Vec3> face_cross(static_cast<std::size_t>(face_count));
  std::vector<Vec3> node_sum(static_cast<std::size_t>(mesh.node_count()), Vec3{0, 0, 0});
  for (index_t f = 0; f < face_count; ++f) {
    const index_t* nodes = &mesh.face_nodes[3 * static_cast<std::size_t>(f)];
    const Vec3 p0 = node_at(mesh.node_pos, nodes[0]);
    face_cross[f] = cross(sub(node_at(mesh.node_pos, nodes[1]), p0), sub(node_at(mesh.node_pos, nodes[2]), p0));
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) node_sum[nodes[k]][a] += face_cross[f][a];
  }
  std::vector<float> corner_normal(9 * static_cast<std::size_t>(face_count), 0.0f);
  for (index_t f = 0; f < face_count; ++f) {
    for (int k = 0; k < 3; ++k) {
      Vec3 n = node_sum[mesh.face_nodes[3 * static_cast<std::size_t>(f) + k]];
      if (!(norm(n) > 0)) n = face_cross[f];
      const double length = norm(n);
      if (!(length > 0)) continue;
      for (int a = 0; a < 3; ++a) corner_normal[9 * static_cast<std::size_t>(f) + 3 * k + a] = float(n[a] / length);
    }
  }
  return corner_normal;
}

double min_face_angle_deg(const std::vector<index_t>& face_nodes, const std::vector<float>& node_pos) {
  const double pi = 3.14159265358979323846;
  double min_angle = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t f = 0; f + 2 < face_nodes.size(); f += 3) {
    const Vec3 p[3] = {node_at(node_pos, face_nodes[f]), node_at(node_pos, face_nodes[f + 1]),
                       node_at(node_pos, face_nodes[f + 2])};
    if (!(norm(cross(sub(p[1], p[0]), sub(p[2], p[0]))) > 0)) continue;
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = sub(p[(k + 1) % 3], p[k]), v = sub(p[(k + 2) % 3], p[k]);
      // atan2 stays accurate near 0 and 180 degrees, where acos does not.
      const double angle = std::atan2(norm(cross(u, v)), dot(u, v)) * (180.0 / pi);
      if (!(angle >= min_angle)) min_angle = angle;
    }
  }
  return min_angle;
}

void check_cuttable(const Mesh& mesh, const std::string& mesh_path, Device device) {
  const MeshReport report = validate_mesh(mesh, device);
  if (!report.ok()) throw input_error(mesh_path, "cannot be cut: " + report.describe());
}

void check_run_inputs(const CutScript& script, const Mesh& mesh, const std::string& mesh_path, Device device) {
  check_script_against_mesh(script, mesh, mesh_path);
  check_cuttable(mesh, mesh_path, device);
  // The simulation block, and its node pins against this mesh.
  if (script.simulation) resolve_pins(*script.simulation, mesh.node_pos, mesh.node_count());
}

void run_cuts(Cloth& cloth, const CutScript& script, int frame_count, const FrameCallback& on_frame) {
  check_frame_count(script, frame_count);
  std::unique_ptr<FrameSimulation> simulation;
  if (script.simulation) simulation = std::make_unique<FrameSimulation>(*script.simulation, cloth);
  const CutOptions cut_options{script.snap};
  for (int frame = 1; frame <= frame_count; ++frame) {
    const std::vector<const Cut*> cuts = script.cuts_of_frame(frame);
    FrameResult result;
    result.frame = frame;
    result.cut_count = static_cast<int>(cuts.size());
    if (cuts.empty()) {
      result.stats.nodes_before = result.stats.nodes_after = cloth.node_count();
      result.stats.faces_before = result.stats.faces_after = cloth.face_count();
    } else {
      const Clock::time_point start = Clock::now();
      std::vector<CutLine> lines;
      lines.reserve(cuts.size());
      for (const Cut* cut : cuts) lines.push_back(to_cut_line(*cut));
      result.stats = cloth.cut(lines, cut_options);
      result.remesh_ms = ms_since(start);
    }
    if (simulation) {
      const Clock::time_point start = Clock::now();
      // A cut that splits nothing leaves the counts, the node numbering and the faces as they were.
      const bool mesh_changed = result.stats.nodes_after != result.stats.nodes_before ||
                                result.stats.faces_after != result.stats.faces_before;
      simulation->step(cloth, mesh_changed);
      synchronize(cloth.device());  // the step only queues work: wait for it, for the time
      result.simulated = true;
      result.simulation_ms = ms_since(start);
    }
    if (on_frame) on_frame(result, cloth);
  }
}

RunSummary run_to_files(const Mesh& mesh, const std::string& mesh_path, const CutScript& script,
                        const RunOptions& options) {
  const Clock::time_point start = Clock::now();
  // Everything that can be refused is refused before the first folder or file is created.
  const FramePattern pattern(options.output_pattern);
  const int frame_count = options.frames == 0 ? script.frames : options.frames;
  check_frame_count(script, frame_count);
  pattern.check(frame_count);
  check_run_inputs(script, mesh, mesh_path, options.device);

  nlohmann::json frames = nlohmann::json::array();
  double remesh_ms = 0, simulation_ms = 0;
  RunSummary summary;
  Cloth cloth(mesh, options.device);
  run_cuts(cloth, script, frame_count, [&](const FrameResult& frame, const Cloth& cut_cloth) {
    FrameResult written = frame;
    written.path = pattern.path(frame.frame);
    create_folder_of(written.path);
    Mesh out = cut_cloth.mesh();
    if (frame.simulated && out.has_normals()) out.corner_normal = area_weighted_corner_normals(out);
    write_mesh(out, written.path);
    if (!options.report_path.empty()) {
      nlohmann::json entry = frame_report(frame, cut_cloth);
      // The remesher's quality is a property of the rest shape; without simulation it is also the
      // written shape.
      const double min_angle = min_face_angle_deg(out.face_nodes, cut_cloth.node_rest());
      if (std::isfinite(min_angle)) entry["min_angle_deg"] = min_angle;
      frames.push_back(entry);
    }
    remesh_ms += frame.remesh_ms;
    simulation_ms += frame.simulation_ms;
    summary.frames = frame.frame;
    summary.faces = cut_cloth.face_count();
    if (options.on_frame) options.on_frame(written, cut_cloth);
  });
  summary.wall_ms = ms_since(start);

  if (!options.report_path.empty()) {
    const nlohmann::json report = {{"mesh", mesh_path},
                                   {"script", script.path},
                                   {"device", to_string(options.device)},
                                   {"device_name", device_name(options.device)},
                                   {"frames", frames},
                                   {"totals",
                                    {{"frames", summary.frames},
                                     {"remesh_ms", remesh_ms},
                                     {"simulation_ms", simulation_ms},
                                     {"wall_ms", summary.wall_ms}}}};
    create_folder_of(options.report_path);
    write_file_atomically(options.report_path, report.dump(2) + "\n");
  }
  return summary;
}

}  // namespace tear
