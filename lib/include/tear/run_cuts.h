// tear: the frame loop of a run: a script's cuts applied frame by frame, each frame written out.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/device.h"
#include "tear/mesh.h"

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
  int frame = 0;      ///< 1..frame_count
  int cut_count = 0;  ///< cuts of the script at this frame (0: the frame repeats the previous mesh)
  CutStats stats;     ///< of the frame's `Cloth::cut`; counts only (before = after) when it had no cut
  std::string path;   ///< the file written, by `run_to_files`; empty in `run_cuts`
  bool simulated = false;    ///< the script has a `simulation` block: the frame was stepped after its cuts
  double remesh_ms = 0;      ///< wall time of the frame's cuts (0 without cuts)
  double simulation_ms = 0;  ///< wall time of the frame's step, solver rebuild (after a cut) included
};

/// Called after each frame, with the cloth as the frame left it.
using FrameCallback = std::function<void(const FrameResult&, const Cloth&)>;

/// The frame loop: for frame 1..`frame_count`, applies that frame's cuts of `script` together
/// (`Cloth::cut` with `script.snap`), then calls `on_frame`. Frames without cuts leave the cloth
/// as it is and still call `on_frame`. `frame_count` must be in 1..script.frames (usage `Error`).
///
/// When the script has a `simulation` block (its node pins are resolved before the first frame, so
/// their errors come before any callback), every frame then advances the cloth by one frame (1/fps s)
/// with a `PdSolver`, rebuilt from the cloth's faces and rest positions on the first frame and
/// whenever the frame's cuts changed the node or face count. Box pins are resolved again on the new
/// rest positions; `nodes` pins name nodes of `cloth` as given and are carried through the cuts by
/// `Cloth::provenance`: a new node whose only source (weight 1) was pinned stays pinned, so both
/// copies of a pinned node that a cut separates stay pinned, and a node made on a cut edge or inside
/// a face is free. The state goes to the host and back every frame (`Cloth::set_node_state`).
void run_cuts(Cloth& cloth, const CutScript& script, int frame_count, const FrameCallback& on_frame);

/// Per-corner normals [face_count * 9] of `mesh` at its current positions: at each corner, the
/// area-weighted average of the normals of the faces around the corner's node, normalised. A torn
/// edge has a node on each side, so nothing is smoothed across a tear. A node whose faces have no
/// area keeps the corner's face normal, and a corner of a face of no area keeps (0, 0, 0).
std::vector<float> area_weighted_corner_normals(const Mesh& mesh);

/// The smallest angle, degrees, of the faces of `face_nodes` [face_count * 3] on the positions
/// `node_pos` [node_count * 3]; faces of no area are skipped; NaN when none is left.
double min_face_angle_deg(const std::vector<index_t>& face_nodes, const std::vector<float>& node_pos);

/// Options of `run_to_files`; mirrored by `tear run`'s flags.
struct RunOptions {
  std::string output_pattern;  ///< `FramePattern` syntax, e.g. "out/cloth.####.obj"
  int frames = 0;              ///< frames to run, 1..script.frames; 0: all of the script's
  Device device = Device::cpu;
  /// Called after each frame is written (may be empty).
  FrameCallback on_frame;
  /// When not empty, a JSON report of the run (docs/cli.md, `--report`) is written there
  /// atomically once the last frame is written.
  std::string report_path;
};

/// What `run_to_files` did, for a summary line.
struct RunSummary {
  int frames = 0;
  index_t faces = 0;  ///< of the last frame
  double wall_ms = 0;
};

/// A whole run: checks everything first (pattern and output format, script against mesh,
/// cuttability, frame count; usage and input `Error`s), and only then creates the output folders
/// and writes one file per frame (`write_mesh`, atomic) from `cloth.mesh()`: positions, faces and
/// the corner UVs and normals the mesh came with, carried through the cuts. A folder that cannot
/// be created is a runtime `Error` naming it. The same inputs give byte-identical files.
///
/// With a `simulation` block the block and its `nodes` pins are checked with the rest, the cloth
/// moves (`run_cuts`), and a mesh that came with normals is written with
/// `area_weighted_corner_normals` of the moved positions, since the carried normals no longer fit.
RunSummary run_to_files(const Mesh& mesh, const std::string& mesh_path, const CutScript& script,
                        const RunOptions& options);

}  // namespace tear
