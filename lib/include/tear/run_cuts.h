// tear: the frame loop of a run: a script's cuts applied frame by frame, each frame written out.
#pragma once

#include <functional>
#include <string>

#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/device.h"
#include "tear/mesh.h"

namespace tear {

/// Throws an input `Error` "<mesh_path>: cannot be cut: <what is wrong>" unless `mesh` passes every
/// check of `validate_mesh` (indices in range, finite coordinates, no degenerate face, no
/// non-manifold edge, no bow-tie node, consistent orientation): the remesher needs an oriented
/// manifold.
void check_cuttable(const Mesh& mesh, const std::string& mesh_path, Device device);

/// Every check of a run that needs no output: `check_script_against_mesh`, then `check_cuttable`.
void check_run_inputs(const CutScript& script, const Mesh& mesh, const std::string& mesh_path, Device device);

/// What one frame of a run did.
struct FrameResult {
  int frame = 0;      ///< 1..frame_count
  int cut_count = 0;  ///< cuts of the script at this frame (0: the frame repeats the previous mesh)
  CutStats stats;     ///< of the frame's `Cloth::cut`; counts only (before = after) when it had no cut
  std::string path;   ///< the file written, by `run_to_files`; empty in `run_cuts`
};

/// Called after each frame, with the cloth as the frame left it.
using FrameCallback = std::function<void(const FrameResult&, const Cloth&)>;

/// The frame loop: for frame 1..`frame_count`, applies that frame's cuts of `script` together
/// (`Cloth::cut` with `script.snap`), then calls `on_frame`. Frames without cuts leave the cloth
/// as it is and still call `on_frame`. `frame_count` must be in 1..script.frames (usage `Error`).
void run_cuts(Cloth& cloth, const CutScript& script, int frame_count, const FrameCallback& on_frame);

/// Options of `run_to_files`; mirrored by `tear run`'s flags.
struct RunOptions {
  std::string output_pattern;  ///< `FramePattern` syntax, e.g. "out/cloth.####.obj"
  int frames = 0;              ///< frames to run, 1..script.frames; 0: all of the script's
  Device device = Device::cpu;
  /// Called after each frame is written (may be empty).
  FrameCallback on_frame;
};

/// A whole run: checks everything first (pattern and output format, script against mesh,
/// cuttability, frame count; usage and input `Error`s), and only then creates the output folders
/// and writes one file per frame (`write_mesh`, atomic) from `cloth.mesh()`: positions, faces and
/// the corner UVs and normals the mesh came with, carried through the cuts. A folder that cannot
/// be created is a runtime `Error` naming it. The same inputs give byte-identical files.
void run_to_files(const Mesh& mesh, const std::string& mesh_path, const CutScript& script, const RunOptions& options);

}  // namespace tear
