// tear: the frame loop of a run: a script's cuts applied frame by frame, each frame written out.
#pragma once

#include <csignal>
#include <functional>
#include <string>
#include <vector>

#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/device.h"
#include "tear/mesh.h"
#include "tear/output_files.h"
#include "tear/usd_layer.h"

namespace tear {

/// Throws an input `Error` "<mesh_path>: cannot be cut: <what is wrong>" unless `mesh` passes every
/// check of `validate_mesh` (indices in range, finite coordinates, no degenerate face, no
/// non-manifold edge, no bow-tie node, consistent orientation, no two faces on the same three
/// nodes): the remesher needs an oriented manifold that a cut can split.
void check_cuttable(const Mesh& mesh, const std::string& mesh_path, Device device);

/// Every check of a run that needs no output: `check_script_against_mesh`, `check_cuttable`, and
/// the node pins of the script's `simulation` block within the mesh.
void check_run_inputs(const CutScript& script, const Mesh& mesh, const std::string& mesh_path, Device device);

/// What one frame of a run did.
struct FrameResult {
  int frame = 0;  ///< 1..frame_count: the script's frame (its `frame` keys count from 1)
  /// The frame's number in outputs (file names, USD time codes, the report, `-v` lines):
  /// `RunOptions::start_frame + frame - 1` in `run_to_files`, `frame` in `run_cuts`.
  int output_frame = 0;
  int cut_count = 0;         ///< cuts of the script at this frame (0: the frame repeats the previous mesh)
  CutStats stats;            ///< of the frame's `Cloth::cut`; counts only (before = after) when it had no cut
  std::string path;          ///< the file written, by `run_to_files`; empty in `run_cuts`
  bool simulated = false;    ///< the script has a `simulation` block: the frame was stepped after its cuts
  double remesh_ms = 0;      ///< wall time of the frame's cuts (0 without cuts)
  double simulation_ms = 0;  ///< wall time of the frame's step, solver rebuild (after a cut) included
  bool tearing = false;      ///< the simulation tears (`simulation.tearing`): the two below count
  index_t tear_events = 0;   ///< faces the frame's step tore (`TearStats::events`)
  double torn_length = 0;    ///< rest length of the frame's new crack segments, metres
  /// The cloth as the frame leaves it, after its cuts and tears (`stats` counts the cuts' only).
  index_t nodes_end = 0, faces_end = 0;
};

/// Called after each frame, with the cloth as the frame left it.
using FrameCallback = std::function<void(const FrameResult&, const Cloth&)>;

/// Called once a frame is on disk (`RunOptions::on_frame`); the cloth has moved on by then, so it
/// gets the frame's result only (`faces_end`: its face count).
using FrameWrittenCallback = std::function<void(const FrameResult&)>;

/// The frame loop: for frame 1..`frame_count`, applies that frame's cuts of `script` together
/// (`Cloth::cut` with `script.snap`), then calls `on_frame`. Frames without cuts leave the cloth
/// as it is and still call `on_frame`. `frame_count` must be in 1..script.frames (usage `Error`).
///
/// When the script has a `simulation` block (read by `parse_simulation` before the first frame, so
/// its errors come before any callback), the cloth simulates it (`Cloth::simulate`: `nodes` pins
/// name nodes of `cloth` as given and are carried through the cuts) and every frame then advances
/// the cloth by one frame (1/fps s, `Cloth::step`) on its backend. A state that is no longer finite
/// stops the run with a runtime `Error` naming the script and the frame, before `on_frame`.
///
/// `first_frame` > 1 goes on from a cloth that already went through frames 1..first_frame-1 (a
/// resumed run: `Cloth::load_state`); a cloth already simulated keeps its simulation.
///
/// `stop` (may be null) is looked at before every substep of a simulated frame
/// (`Cloth::step_frame`): once it is set the frame being stepped is dropped, before `on_frame`,
/// and the loop ends. Returns the last frame that `on_frame` was called for: `frame_count`, or
/// less when stopped (`first_frame` - 1 when stopped within the first frame).
int run_cuts(Cloth& cloth, const CutScript& script, int frame_count, const FrameCallback& on_frame,
             int first_frame = 1, const volatile std::sig_atomic_t* stop = nullptr);

/// Per-corner normals [face_count * 9] of `mesh` at its current positions: at each corner, the
/// area-weighted average of the normals of the faces around the corner's node, normalised. A torn
/// edge has a node on each side, so nothing is smoothed across a tear. A node whose faces have no
/// area keeps the corner's face normal, and a corner of a face of no area keeps (0, 0, 0).
std::vector<float> area_weighted_corner_normals(const Mesh& mesh);

/// The smallest angle, degrees, of the faces of `face_nodes` [face_count * 3] on the positions
/// `node_pos` [node_count * 3]; faces of no area are skipped; NaN when none is left.
double min_face_angle_deg(const std::vector<index_t>& face_nodes, const std::vector<float>& node_pos);

/// Faces of a frame that a cloth should not have (docs/cli.md, *Report*).
struct FaceQuality {
  /// Faces of a repeated node or of no area (`validate_mesh`'s test: squared double area at most
  /// `degenerate_area_ratio`² times the longest edge's length to the fourth power).
  index_t degenerate = 0;
  /// Faces turned over: the face's normal points against the summed normals of the other faces at
  /// two or three of its corners (a node pushed through the opposite edge, a face flipped among
  /// its neighbours; also a cloth folded flat within one row of faces).
  index_t inverted = 0;
  bool any() const { return degenerate > 0 || inverted > 0; }
  /// "3 degenerate faces and 1 inverted face" (only the non-zero counts).
  std::string describe() const;
};

/// The `FaceQuality` of `mesh` at its positions `node_pos`.
FaceQuality face_quality(const Mesh& mesh);

/// Options of `run_to_files`; mirrored by `tear run`'s flags.
struct RunOptions {
  /// `FramePattern` syntax, e.g. "out/cloth.####.obj"; a .usda/.usd path without frame number is
  /// one USD layer for the whole run (`UsdLayer`).
  std::string output_pattern;
  int frames = 0;  ///< frames to run, 1..script.frames; 0: all of the script's
  /// The number of the first frame in outputs (file names, USD time codes, the report,
  /// `FrameResult::output_frame`), >= 0; the script's frame 1 is written as this frame.
  int start_frame = 1;
  /// USD stage metadata (`upAxis`, `metersPerUnit`); other formats have none and ignore these.
  /// `timeCodesPerSecond` is the script's `simulation.fps` (24 without a simulation block).
  UpAxis up_axis = UpAxis::y;
  double meters_per_unit = 1;  ///< finite, > 0
  Device device = Device::cpu;
  /// Called after each frame is on disk, in frame order, on the thread that called `run_to_files`
  /// (may be empty). Frames are written beside the run (`FrameWriter`), so this comes a frame or a
  /// few after the frame was computed.
  FrameWrittenCallback on_frame;
  /// Threads that write the frames beside the run (`FrameWriter`); 0: min(4, hardware threads).
  int writer_threads = 0;
  /// When not empty, a JSON report of the run (docs/cli.md, `--report`) is written there
  /// atomically once the last frame is written.
  std::string report_path;
  /// When not empty, a checkpoint (tear/checkpoint.h) is written there atomically after every
  /// `checkpoint_every`-th frame, after the last one, and when the run is stopped: the cloth as
  /// that frame left it, written once that frame and every frame before it are on disk.
  std::string checkpoint_path;
  int checkpoint_every = 1;
  /// With `checkpoint_path`: when the checkpoint exists, go on after its frame (an input `Error`
  /// when it was made from other inputs, or is damaged); when it does not, start from frame 1.
  bool resume = false;
  /// The options that change results besides the mesh, the script and the device, spelled out
  /// ("name=value;..."), so that a checkpoint made with others is refused.
  std::string result_options;
  /// When true, `check_run_plan` also checks the outputs (`check_output_files`): no output is one
  /// of `input_files`, no two outputs are the same file, and every output folder can be made
  /// (`tear run` and `tear demo` set it).
  bool check_outputs = false;
  /// The files the run reads, for `check_outputs`: {"mesh", "cloth.obj"}, {"script", "shot.json"}.
  std::vector<NamedPath> input_files;
  /// True when the caller has run `check_run_plan` on this mesh and script with these options (as
  /// `tear run` does, before it clears stale temporary files): `run_to_files` does not check again.
  bool plan_checked = false;
  /// Milliseconds the caller spent reading and checking the inputs, for the report's
  /// `totals.input_ms` (0 when not measured).
  double input_ms = 0;
  /// Each frame written is checked for degenerate and inverted faces (`face_quality`, on the
  /// writer's threads): counted in the report (`degenerate_faces`, `inverted_faces`), and when there
  /// are any, said to `on_warning` (may be empty) once the frame is on disk, "frame 12 (out/f.0012.obj):
  /// 3 degenerate faces"; with `strict` the run stops there with a runtime `Error` (exit 3) instead.
  std::function<void(const std::string&)> on_warning;
  bool strict = false;
  /// Checked after each frame is handed to the writer, and before each substep of a simulated
  /// frame: once it is set (by a signal handler), the frame being stepped, if any, is dropped, the
  /// run waits until every frame handed over is on disk, writes its checkpoint (of the last frame
  /// handed over when stopped after it; when stopped inside a frame, the checkpoint stays what the
  /// frames before wrote: with `checkpoint_every` 1, the frame before) and stops with an `Error`
  /// of kind `interrupted`.
  const volatile std::sig_atomic_t* stop = nullptr;
};

/// What a run will write, as `check_run_plan` found it.
struct RunPlan {
  int frame_count = 0;  ///< frames the run computes and writes: `RunOptions::frames`, or all of the script's
  /// Every file the run writes: its frames (a single USD layer with the sample files it streams to),
  /// the report and the checkpoint when there are; for `remove_stale_temporaries`.
  std::vector<std::string> outputs;
};

/// Every check of a run, before anything is read from or written to its outputs, in this order:
/// the pattern's syntax and format; `frames` within 1..script.frames (a usage `Error`, "--frames N
/// is more than the script's M frames" when above); the frame numbers and the pattern against the
/// frame count (`FramePattern::check`: a placeholder for more than one frame); `meters_per_unit`;
/// `check_run_inputs`; with `check_outputs`, the outputs (`check_output_files`); and last the
/// checkpoint options (`resume` needs a `checkpoint_path`; a single USD layer cannot be
/// checkpointed: usage `Error`s). Throws the first `Error` found; creates nothing.
RunPlan check_run_plan(const Mesh& mesh, const std::string& mesh_path, const CutScript& script,
                       const RunOptions& options);

/// What `run_to_files` did, for a summary line.
struct RunSummary {
  int frames = 0;
  index_t faces = 0;  ///< of the last frame
  double wall_ms = 0;
};

/// A whole run: checks everything first (`check_run_plan`, unless `RunOptions::plan_checked`
/// says the caller did), and only then creates
/// the output folders and writes every frame from `cloth.mesh()` to the sink the pattern names:
/// one file per frame (`FrameFiles`: `write_mesh`, atomic), or one USD layer for the run
/// (`UsdLayer`, a .usda/.usd pattern without frame number): positions, faces and the corner UVs
/// and normals the mesh came with, carried through the cuts. A folder that cannot be created, or
/// a file that cannot be written, is a runtime `Error` naming it. The same inputs give
/// byte-identical files.
///
/// This thread runs the frames and downloads each frame's mesh; a `FrameWriter` of
/// `writer_threads` threads computes its normals, encodes and writes it, at most twice as many
/// frames in flight as threads. Files are renamed into place in frame order, and `on_frame`,
/// checkpoints and the stop come after the frame is on disk. The first frame that cannot be
/// written ends the run with its `Error` once the frames before it are on disk; no frame after it
/// is renamed and no temporary file is left. An error of the run itself (a simulation that
/// diverged) leaves the frames before it on disk.
///
/// With a `simulation` block the block and its `nodes` pins are checked with the rest, the cloth
/// moves (`run_cuts`), and a mesh that came with normals is written with
/// `area_weighted_corner_normals` of the moved positions, since the carried normals no longer fit.
RunSummary run_to_files(const Mesh& mesh, const std::string& mesh_path, const CutScript& script,
                        const RunOptions& options);

}  // namespace tear
