// tear: a torn sequence as USD: one ASCII layer (USDA) holding every frame as a time sample, or
// one layer per frame.
//
// A two-frame run of the triangle (0,0,0) (1,0,0) (0,1,0), cut through its corner 0 in frame 2
// (node 3 is node 0's copy, nodes 4 and 5 the two sides of the cut's point on edge 1-2), gives
// (abridged; tests/test_usd_layer.cpp checks it):
//
//   #usda 1.0
//   (
//       defaultPrim = "cloth"
//       endTimeCode = 2
//       framesPerSecond = 24
//       ...
//   )
//
//   def Mesh "cloth"
//   {
//       ...
//       int[] faceVertexCounts.timeSamples = {
//           1: [3],
//           2: [3, 3],
//       }
//       int[] faceVertexIndices.timeSamples = {
//           1: [0, 1, 2],
//           2: [4, 2, 3, 0, 1, 5],
//       }
//       point3f[] points.timeSamples = {
//           1: [(0, 0, 0), (1, 0, 0), (0, 1, 0)],
//           2: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 0), (0.5, 0.5, 0), (0.5, 0.5, 0)],
//       }
//       ...
//       int[] primvars:tear_edge.timeSamples = {
//           1: [0, 0, 0],
//           2: [0, 0, 1, 0, 0, 1],
//       }
//   }
//
// The layer is the form a renderer needs to motion-blur a mesh whose topology changes: points and
// topology are sampled every frame, `velocities` give each point's motion within the frame.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tear/frame_path.h"
#include "tear/frame_sink.h"
#include "tear/mesh.h"

namespace tear {

/// The stage's up axis (USD's `upAxis` metadata). It declares how the points are to be read; the
/// points themselves are written as they are.
enum class UpAxis { y, z };

/// "Y" or "Z", as USD spells them.
const char* to_string(UpAxis axis);

/// Parses "Y" or "Z" (either case); anything else is a usage `Error`.
UpAxis parse_up_axis(const std::string& text);

/// The stage metadata of a layer.
struct UsdLayerOptions {
  /// `timeCodesPerSecond` and `framesPerSecond`: one time code per frame, frames per second.
  double frames_per_second = 24;
  UpAxis up_axis = UpAxis::y;  ///< `upAxis`
  double meters_per_unit = 1;  ///< `metersPerUnit`: the length of one unit of the points, metres
};

/// True when `path`'s extension is `.usda` or `.usd` (case-insensitive): a path USD output goes
/// to. Both are written as USDA text (USD reads text from a `.usd` file as well as binary).
bool is_usd_path(const std::string& path);

/// The USD sink. The layer holds one `UsdGeomMesh`, `/cloth`, the layer's default prim, with a
/// time sample per frame (time code = the frame's number) of:
///
/// - `points` [node_count] (node i is point i, so indices persist from sample to sample),
///   `faceVertexCounts` [face_count] (all 3), `faceVertexIndices` [face_count * 3]
///   (counter-clockwise, USD's default `rightHanded` orientation), `extent` (the points' box);
/// - `velocities` [node_count]: `mesh.node_vel`, units per second (0 when the mesh has none);
/// - `normals` and `primvars:st`, `faceVarying` [face_count * 3]: `corner_normal` and `corner_uv`,
///   when the mesh has them;
/// - `primvars:tear_edge`, `faceVarying` int [face_count * 3]: 1 where the edge from the corner to
///   the next corner of its face is in `mesh.torn_edge_nodes` (a border made by a cut or tear of
///   the run), else 0.
///
/// Without a frame number in `pattern` (`shot.usda`) every frame goes to one layer, with
/// `startTimeCode`/`endTimeCode` the first and last frame written. Memory stays bounded: each
/// attribute's samples are streamed to a temporary file beside the layer
/// (`.<name>.<attribute>.tmp.<pid>.<16 hex digits>`, open and so locked until removed) by a writer
/// thread of the layer's own (`write` copies the
/// mesh and returns; at most two frames wait), and `finish` waits for it, assembles the layer in
/// `.<name>.tmp.<pid>.<16 hex digits>` and renames it, so the layer appears whole or not at all. A failure of the
/// writer is thrown by the next `write` or by `finish`. With a frame number (`shot.####.usda`)
/// each frame is a layer of its own holding that frame's sample, written atomically by `write`.
///
/// Floats are written as the shortest text that reads back to the same float, so the same frames
/// give the same bytes. A file that cannot be written is a runtime `Error` naming the layer
/// ("<path>: cannot write: <reason>"); temporaries are removed on failure, and by the destructor
/// of a layer that was never finished.
class UsdLayer final : public FrameSink {
 public:
  /// `pattern`'s extension must be .usda or .usd (a usage `Error` otherwise). Nothing is created
  /// before the first `write`.
  explicit UsdLayer(FramePattern pattern, UsdLayerOptions options = {});
  ~UsdLayer() override;
  UsdLayer(const UsdLayer&) = delete;
  UsdLayer& operator=(const UsdLayer&) = delete;

  /// Frames must come in increasing order of `frame`; every frame must have the UVs and normals
  /// the first one had (a runtime `Error` otherwise).
  void write(int frame, const Mesh& mesh) override;
  void finish() override;
  std::string path_of(int frame) const override { return pattern_.path(frame); }
  /// True for a layer per frame (`shot.####.usda`): each frame's layer is staged on its own. A
  /// layer for the run takes its frames in order through `write`.
  bool stages_files() const override { return pattern_.has_frame_number(); }
  TemporaryFile stage(int frame, const Mesh& mesh, std::string& bytes) const override;

 private:
  struct Sequence;
  FramePattern pattern_;
  UsdLayerOptions options_;
  std::unique_ptr<Sequence> sequence_;
};

/// The paths whose temporary files (`.<name>.tmp.<pid>.<16 hex digits>`, as `create_temporary_file` spells them)
/// a single layer at `path` streams its samples to: `<path>.<attribute>` for every attribute a
/// layer can hold. A run passes them to `remove_stale_temporaries` with its outputs, so that what
/// a killed run left beside the layer goes.
std::vector<std::string> usd_layer_sample_paths(const std::string& path);

/// The text of a layer holding `mesh` as the single time sample `frame` (what `UsdLayer` writes for
/// one frame).
std::string usda_layer_text(const Mesh& mesh, int frame, const UsdLayerOptions& options = {});

}  // namespace tear
