#include "tear/run_cuts.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "tear/checkpoint.h"
#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/frame_sink.h"
#include "tear/frame_writer.h"
#include "tear/simulation.h"
#include "tear/usd_layer.h"
#include "tear/validate_mesh.h"
#include "tear/write_mesh.h"

#include "check_mesh.h"

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

/// What a checkpoint of this run is made from: the mesh as read (its file and the reading options),
/// the script file (or, for a script made in memory, its name), the device and the options given.
RunInputs run_inputs(const Mesh& mesh, const CutScript& script, const RunOptions& options) {
  RunInputs inputs;
  std::string bytes;
  for (const auto* floats : {&mesh.node_pos, &mesh.corner_uv, &mesh.corner_normal})
    bytes.append(reinterpret_cast<const char*>(floats->data()), floats->size() * sizeof(float));
  bytes.append(reinterpret_cast<const char*>(mesh.face_nodes.data()), mesh.face_nodes.size() * sizeof(index_t));
  inputs.mesh_digest = digest_bytes(bytes);
  std::error_code error;
  inputs.script_digest =
      std::filesystem::is_regular_file(script.path, error) ? digest_file(script.path) : digest_bytes(script.path);
  // The output pattern and first frame number too: a resumed run must go on writing the same files.
  inputs.options = "tear " TEAR_VERSION ";device=" + std::string(to_string(options.device)) +
                   ";output=" + options.output_pattern + ";start-frame=" + std::to_string(options.start_frame) +
                   (options.result_options.empty() ? "" : ";" + options.result_options);
  return inputs;
}

/// The sink the pattern names: a USD layer (one for the run, or one per frame), else a file per frame.
std::unique_ptr<FrameSink> make_sink(const FramePattern& pattern, const CutScript& script, const RunOptions& options) {
  if (!is_usd_path(pattern.pattern())) return std::make_unique<FrameFiles>(pattern);
  UsdLayerOptions usd;
  // One time code per frame: the simulation's frame rate, or film's.
  usd.frames_per_second = script.simulation ? script.simulation->fps : 24.0;
  usd.up_axis = options.up_axis;
  usd.meters_per_unit = options.meters_per_unit;
  return std::make_unique<UsdLayer>(pattern, usd);
}

nlohmann::json frame_report(const FrameResult& frame, const Cloth& cloth) {
  return {{"frame", frame.output_frame}, {"nodes", cloth.node_count()},  {"faces", cloth.face_count()},
          {"pieces", cloth.piece_count()},
          {"cuts", frame.cut_count},     {"remesh_ms", frame.remesh_ms}, {"simulation_ms", frame.simulation_ms},
          {"min_angle_deg", nullptr}};
}

/// The frame's tearing, in the report of a simulation that tears.
void add_tearing(nlohmann::json& entry, const FrameResult& frame) {
  if (!frame.tearing) return;
  entry["tear_events"] = frame.tear_events;
  entry["torn_length_m"] = frame.torn_length;
}

/// Meshes of this many faces or more are measured on the OpenMP threads.
constexpr std::int64_t parallel_faces = 4096;

/// The cross product of two of face `f`'s edges: its normal scaled by twice its area.
Vec3 face_cross(const Mesh& mesh, std::size_t f) {
  const index_t* nodes = &mesh.face_nodes[3 * f];
  const Vec3 p0 = node_at(mesh.node_pos, nodes[0]);
  return cross(sub(node_at(mesh.node_pos, nodes[1]), p0), sub(node_at(mesh.node_pos, nodes[2]), p0));
}

/// Per node the sum of its faces' cross products (the area-weighted normal), summed in face order
/// on one thread: the same sums whatever the number of threads of the passes that read them.
std::vector<Vec3> node_normal_sums(const Mesh& mesh) {
  std::vector<Vec3> node_sum(static_cast<std::size_t>(mesh.node_count()), Vec3{0, 0, 0});
  const std::size_t face_count = static_cast<std::size_t>(mesh.face_count());
  for (std::size_t f = 0; f < face_count; ++f) {
    const Vec3 c = face_cross(mesh, f);
    const index_t* nodes = &mesh.face_nodes[3 * f];
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) node_sum[nodes[k]][a] += c[a];
  }
  return node_sum;
}

}  // namespace

FaceQuality face_quality(const Mesh& mesh) {
  const index_t face_count = mesh.face_count();
  const kernels::face_degenerate degenerate{mesh.node_pos.data(), mesh.face_nodes.data(), degenerate_area_ratio};
  // At a corner, the node's sum of area-weighted normals less the face's own is the normal of the
  // other faces there.
  const std::vector<Vec3> node_sum = node_normal_sums(mesh);
  std::int64_t degenerate_faces = 0, inverted_faces = 0;
#pragma omp parallel for schedule(static) reduction(+ : degenerate_faces, inverted_faces) if (face_count >= parallel_faces)
  for (index_t f = 0; f < face_count; ++f) {
    degenerate_faces += degenerate(f);
    const index_t* nodes = &mesh.face_nodes[3 * static_cast<std::size_t>(f)];
    if (nodes[0] == nodes[1] || nodes[1] == nodes[2] || nodes[2] == nodes[0]) continue;
    const Vec3 own = face_cross(mesh, static_cast<std::size_t>(f));
    int against = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 others = sub(node_sum[nodes[k]], own);
      if (dot(others, own) < 0) ++against;
    }
    if (against >= 2) ++inverted_faces;
  }
  FaceQuality quality;
  quality.degenerate = static_cast<index_t>(degenerate_faces);
  quality.inverted = static_cast<index_t>(inverted_faces);
  return quality;
}

std::string FaceQuality::describe() const {
  std::string text;
  if (degenerate > 0) text = std::to_string(degenerate) + (degenerate == 1 ? " degenerate face" : " degenerate faces");
  if (inverted > 0)
    text += (text.empty() ? "" : " and ") + std::to_string(inverted) + (inverted == 1 ? " inverted face" : " inverted faces");
  return text;
}

std::vector<float> area_weighted_corner_normals(const Mesh& mesh) {
  const index_t face_count = mesh.face_count();
  const std::vector<Vec3> node_sum = node_normal_sums(mesh);
  std::vector<float> corner_normal(9 * static_cast<std::size_t>(face_count), 0.0f);
#pragma omp parallel for schedule(static) if (face_count >= parallel_faces)
  for (index_t f = 0; f < face_count; ++f) {
    for (int k = 0; k < 3; ++k) {
      Vec3 n = node_sum[mesh.face_nodes[3 * static_cast<std::size_t>(f) + k]];
      if (!(norm(n) > 0)) n = face_cross(mesh, static_cast<std::size_t>(f));
      const double length = norm(n);
      if (!(length > 0)) continue;
      for (int a = 0; a < 3; ++a) corner_normal[9 * static_cast<std::size_t>(f) + 3 * k + a] = float(n[a] / length);
    }
  }
  return corner_normal;
}

double min_face_angle_deg(const std::vector<index_t>& face_nodes, const std::vector<float>& node_pos) {
  const double pi = 3.14159265358979323846;
  const double none = std::numeric_limits<double>::infinity();
  const std::int64_t face_count = static_cast<std::int64_t>(face_nodes.size() / 3);
  // A minimum is exact in any order: the same value for any number of threads.
  double min_angle = none;
#pragma omp parallel for reduction(min : min_angle) schedule(static) if (face_count >= parallel_faces)
  for (std::int64_t face = 0; face < face_count; ++face) {
    const std::size_t f = 3 * static_cast<std::size_t>(face);
    const Vec3 p[3] = {node_at(node_pos, face_nodes[f]), node_at(node_pos, face_nodes[f + 1]),
                       node_at(node_pos, face_nodes[f + 2])};
    if (!(norm(cross(sub(p[1], p[0]), sub(p[2], p[0]))) > 0)) continue;
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = sub(p[(k + 1) % 3], p[k]), v = sub(p[(k + 2) % 3], p[k]);
      // atan2 stays accurate near 0 and 180 degrees, where acos does not.
      const double angle = std::atan2(norm(cross(u, v)), dot(u, v)) * (180.0 / pi);
      if (angle < min_angle) min_angle = angle;
    }
  }
  return min_angle == none ? std::numeric_limits<double>::quiet_NaN() : min_angle;
}

void check_cuttable(const Mesh& mesh, const std::string& mesh_path, Device device) {
  const MeshReport report = validate_mesh(mesh, device);
  if (!report.cuttable()) throw input_error(mesh_path, "cannot be cut: " + report.describe());
}

void check_run_inputs(const CutScript& script, const Mesh& mesh, const std::string& mesh_path, Device device) {
  check_script_against_mesh(script, mesh, mesh_path);
  check_cuttable(mesh, mesh_path, device);
  // The simulation block, and its node pins against this mesh.
  if (script.simulation) resolve_pins(*script.simulation, mesh.node_pos, mesh.node_count());
}

int run_cuts(Cloth& cloth, const CutScript& script, int frame_count, const FrameCallback& on_frame, int first_frame,
             const volatile std::sig_atomic_t* stop) {
  check_frame_count(script, frame_count);
  if (script.simulation && !cloth.simulated()) cloth.simulate(*script.simulation);
  const CutOptions cut_options{script.snap};
  // The cuts ordered by frame (script order within one), walked once: not every cut looked at for
  // every frame, which a script of 100,000 cuts over 1,000,000 frames would make 1e11 looks.
  std::vector<const Cut*> by_frame;
  by_frame.reserve(script.cuts.size());
  for (const Cut& cut : script.cuts) by_frame.push_back(&cut);
  std::stable_sort(by_frame.begin(), by_frame.end(), [](const Cut* a, const Cut* b) { return a->frame < b->frame; });
  auto next_cut = std::lower_bound(by_frame.begin(), by_frame.end(), first_frame,
                                   [](const Cut* cut, int frame) { return cut->frame < frame; });
  for (int frame = first_frame; frame <= frame_count; ++frame) {
    std::vector<const Cut*> cuts;
    for (; next_cut != by_frame.end() && (*next_cut)->frame == frame; ++next_cut) cuts.push_back(*next_cut);
    FrameResult result;
    result.frame = frame;
    result.output_frame = frame;
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
    if (cloth.simulated()) {
      const Clock::time_point start = Clock::now();
      // Stopped inside the frame: the frame is dropped, the cloth part way through it.
      if (!cloth.step_frame(frame, stop)) return frame - 1;
      // Waits for the step (for its time) and stops before a frame of NaNs is handed on.
      if (!cloth.state_is_finite())
        throw runtime_error(script.path + ": frame " + std::to_string(frame) +
                            ": the simulation diverged (a position or velocity is not finite); lower the stiffness "
                            "or raise the substeps or iterations");
      result.simulated = true;
      result.simulation_ms = ms_since(start);
      result.tearing = script.simulation && script.simulation->tearing.enabled();
      const TearStats torn = cloth.last_tear();
      result.tear_events = torn.events;
      result.torn_length = torn.length;
    }
    result.nodes_end = cloth.node_count();
    result.faces_end = cloth.face_count();
    if (on_frame) on_frame(result, cloth);
  }
  return frame_count;
}

namespace {

/// The first frame a run computes: 1, or, resuming from a checkpoint that exists, the frame after
/// the checkpoint's, with the cloth as that frame left it.
int resume_point(Cloth& cloth, const Mesh& mesh, const CutScript& script, const RunOptions& options,
                 const RunInputs& inputs) {
  if (options.checkpoint_path.empty() || !options.resume || !std::filesystem::exists(options.checkpoint_path)) return 1;
  const Checkpoint checkpoint = read_checkpoint(options.checkpoint_path);
  const std::string why = inputs_mismatch(checkpoint.inputs, inputs);
  if (!why.empty()) throw input_error(options.checkpoint_path, "cannot resume from this checkpoint: " + why);
  if (script.simulation) cloth.simulate(*script.simulation);
  if (checkpoint.frame > script.frames)
    throw input_error(options.checkpoint_path, "cannot resume from this checkpoint: it names frame " +
                                                   std::to_string(checkpoint.frame) + ", outside the script's frames 1.." +
                                                   std::to_string(script.frames));
  cloth.load_state(checkpoint.cloth_state, options.checkpoint_path);
  check_checkpoint_cloth(options.checkpoint_path, checkpoint.frame, cloth, mesh, script);
  return checkpoint.frame + 1;
}

/// What a run measures and reports as its frames go by.
struct RunTotals {
  nlohmann::json frames = nlohmann::json::array();
  double setup_ms = 0, remesh_ms = 0, simulation_ms = 0, download_ms = 0, write_wait_ms = 0;
  double min_angle = 0;  // of the rest shape, for the report
  bool min_angle_known = false;
};

/// The report's entry of a frame, as `written` numbers it.
void add_frame_report(RunTotals& totals, const FrameResult& written, const Cloth& cloth) {
  nlohmann::json entry = frame_report(written, cloth);
  add_tearing(entry, written);
  // The remesher's quality is a property of the rest shape (without simulation also the shape
  // written), which only cuts and tears change: measured again after those.
  if (!totals.min_angle_known || written.cut_count > 0 || written.tear_events > 0) {
    totals.min_angle = min_face_angle_deg(cloth.face_nodes(), cloth.node_rest());
    totals.min_angle_known = true;
  }
  if (std::isfinite(totals.min_angle)) entry["min_angle_deg"] = totals.min_angle;
  totals.frames.push_back(entry);
}

void write_report(const std::string& mesh_path, const CutScript& script, const RunOptions& options,
                  const RunTotals& totals, const RunSummary& summary) {
  const nlohmann::json report = {{"mesh", mesh_path},
                                 {"script", script.path},
                                 {"device", to_string(options.device)},
                                 {"device_name", device_name(options.device)},
                                 {"frames", totals.frames},
                                 {"totals",
                                  {{"frames", summary.frames},
                                   {"input_ms", options.input_ms},
                                   {"setup_ms", totals.setup_ms},
                                   {"remesh_ms", totals.remesh_ms},
                                   {"simulation_ms", totals.simulation_ms},
                                   {"download_ms", totals.download_ms},
                                   {"write_wait_ms", totals.write_wait_ms},
                                   {"wall_ms", summary.wall_ms}}}};
  create_folder_of(options.report_path);
  write_file_atomically(options.report_path, report.dump(2) + "\n");
}

/// Hands each frame the loop computed to the writer: its mesh queued for download, its report
/// entry, and the checkpoint to write once it is on disk; stops the run when asked to.
class FrameHandOver {
 public:
  FrameHandOver(const RunOptions& options, int frame_count, const RunInputs& inputs, FrameSink& sink,
                FrameWriter& writer, RunTotals& totals, RunSummary& summary, int first_frame)
      : checkpointed_(first_frame - 1),
        options_(options),
        frame_count_(frame_count),
        inputs_(inputs),
        sink_(sink),
        writer_(writer),
        totals_(totals),
        summary_(summary) {}

  void operator()(const FrameResult& frame, const Cloth& cut_cloth) {
    FrameResult written = frame;
    written.output_frame = options_.start_frame + frame.frame - 1;
    written.path = sink_.path_of(written.output_frame);
    // Queuing the frame's copy to the host is all this thread does of its output: the copy runs
    // beside the next frames, and the writer's thread waits for it, computes the normals (those the
    // cloth carries are not copied then), encodes the frame and writes its file.
    const bool normals = frame.simulated && cut_cloth.has_corner_normals();
    const Clock::time_point download_start = Clock::now();
    PendingMesh out = cut_cloth.mesh_later(!normals);
    totals_.download_ms += ms_since(download_start);
    const bool reported = !options_.report_path.empty();
    if (reported) add_frame_report(totals_, written, cut_cloth);
    totals_.remesh_ms += frame.remesh_ms;
    totals_.simulation_ms += frame.simulation_ms;
    summary_.frames = frame.frame;
    summary_.faces = cut_cloth.face_count();
    const bool checkpoints = !options_.checkpoint_path.empty();
    const bool stopping = options_.stop && *options_.stop;
    const bool checkpoint =
        checkpoints && (stopping || frame.frame == frame_count_ || frame.frame % checkpoint_every() == 0);
    // The cloth as this frame left it, saved now (the cloth moves on) and written once the frame,
    // and every frame before it, is on disk: a resumed run never skips a frame.
    std::string state = checkpoint ? cut_cloth.save_state() : std::string();
    // The frame's faces are checked where it is written (on the host, beside the run); what is found
    // goes into its report entry and, when something is wrong, to a warning or a stop (--strict)
    // once the frame is on disk.
    auto quality = std::make_shared<FaceQuality>();
    const std::size_t entry = totals_.frames.size() - (reported ? 1 : 0);
    const Clock::time_point hand_over_start = Clock::now();
    writer_.write(
        written.output_frame, std::move(out), normals,
        [&options = options_, &inputs = inputs_, &totals = totals_, written, checkpoint, state = std::move(state),
         quality, reported, entry]() mutable {
          if (reported) {
            totals.frames[entry]["degenerate_faces"] = quality->degenerate;
            totals.frames[entry]["inverted_faces"] = quality->inverted;
          }
          if (options.on_frame) options.on_frame(written);
          if (quality->any()) {
            const std::string what = "frame " + std::to_string(written.output_frame) + " has " + quality->describe();
            if (options.strict) throw runtime_error(written.path + ": " + what + " (--strict)");
            if (options.on_warning) options.on_warning(written.path + ": " + what);
          }
          if (checkpoint)
            write_checkpoint(options.checkpoint_path, Checkpoint{written.frame, inputs, std::move(state)});
        },
        [quality](const Mesh& mesh) { *quality = face_quality(mesh); });
    totals_.write_wait_ms += ms_since(hand_over_start);
    if (checkpoint) checkpointed_ = frame.frame;
    if (stopping) {
      writer_.finish();
      throw Error(ErrorKind::interrupted,
                  "stopped after frame " + std::to_string(frame.frame) + " of " + std::to_string(frame_count_) +
                      (checkpoints ? "; '--resume' goes on from " + options_.checkpoint_path : std::string()));
    }
  }

  /// The run was stopped inside frame `frame`, which is dropped: once the frames before it are on
  /// disk (with their checkpoints), stops as after the frame before ("stopped after frame 11 of
  /// 48, inside frame 12 (...)"). The checkpoint is the last one written, of the frame before with
  /// `checkpoint_every` 1; resuming computes `frame` again, and any frames after the checkpoint's.
  [[noreturn]] void stopped_inside(int frame) {
    writer_.finish();
    const std::string count = std::to_string(frame_count_);
    std::string message =
        frame > 1 ? "stopped after frame " + std::to_string(frame - 1) + " of " + count + ", inside frame " +
                        std::to_string(frame) + " (dropped: it is computed again on resume)"
                  : "stopped inside frame 1 of " + count + ", before any frame was written";
    if (!options_.checkpoint_path.empty() && checkpointed_ > 0) {
      message += "; '--resume' goes on from " + options_.checkpoint_path;
      if (checkpointed_ != frame - 1) message += " (its frame " + std::to_string(checkpointed_) + ")";
    } else if (!options_.checkpoint_path.empty()) {
      message += "; '--resume' starts from frame 1";
    }
    throw Error(ErrorKind::interrupted, message);
  }

 private:
  int checkpoint_every() const { return std::max(options_.checkpoint_every, 1); }

  int checkpointed_;  // the frame of the checkpoint last written (or resumed from); 0: none
  const RunOptions& options_;
  int frame_count_;
  const RunInputs& inputs_;
  FrameSink& sink_;
  FrameWriter& writer_;
  RunTotals& totals_;
  RunSummary& summary_;
};

/// The frame loop with its frames handed to `writer`, which is finished (every frame on disk)
/// before this returns or throws.
void run_frames(Cloth& cloth, const CutScript& script, int frame_count, int first_frame, FrameHandOver& hand_over,
                FrameWriter& writer, RunTotals& totals, const volatile std::sig_atomic_t* stop) {
  try {
    const int done = run_cuts(cloth, script, frame_count, std::ref(hand_over), first_frame, stop);
    if (done < frame_count) hand_over.stopped_inside(done + 1);
    const Clock::time_point finish_start = Clock::now();
    writer.finish();
    totals.write_wait_ms += ms_since(finish_start);
  } catch (...) {
    // An error of the frame loop itself (a simulation that diverged) leaves the frames handed over
    // before it on disk, as writing them one after the other did. A failure of the writer (or of
    // `on_frame`) is thrown again by `finish`, and is not the one to report twice.
    try {
      writer.finish();
    } catch (...) {
    }
    throw;
  }
}

}  // namespace

RunSummary run_to_files(const Mesh& mesh, const std::string& mesh_path, const CutScript& script,
                        const RunOptions& options) {
  const Clock::time_point start = Clock::now();
  // Everything that can be refused is refused before the first folder or file is created.
  const int frame_count = options.plan_checked ? (options.frames == 0 ? script.frames : options.frames)
                                               : check_run_plan(mesh, mesh_path, script, options).frame_count;
  const FramePattern pattern(options.output_pattern);
  RunTotals totals;
  RunSummary summary;
  const std::unique_ptr<FrameSink> sink = make_sink(pattern, script, options);
  Cloth cloth(mesh, options.device);
  const RunInputs inputs = options.checkpoint_path.empty() ? RunInputs{} : run_inputs(mesh, script, options);
  const int first_frame = resume_point(cloth, mesh, script, options, inputs);
  totals.setup_ms = ms_since(start);
  // Declared after the sink: it is gone (its threads ended, the temporary files of frames it did
  // not rename removed) before the sink goes.
  FrameWriter writer(*sink, FrameWriterOptions{options.writer_threads});
  FrameHandOver hand_over(options, frame_count, inputs, *sink, writer, totals, summary, first_frame);
  run_frames(cloth, script, frame_count, first_frame, hand_over, writer, totals, options.stop);
  const Clock::time_point sink_start = Clock::now();
  sink->finish();
  totals.write_wait_ms += ms_since(sink_start);
  summary.wall_ms = ms_since(start);
  if (!options.report_path.empty()) write_report(mesh_path, script, options, totals, summary);
  return summary;
}

}  // namespace tear
