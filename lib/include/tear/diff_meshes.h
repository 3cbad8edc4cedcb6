// tear: comparing two meshes the way a golden-file test needs (topology exact, values within a
// tolerance), so that a frame made on the GPU matches one made on the CPU.
//
// Example: a = one face (0 1 2), b = the same face written (1 2 0) with node 2 moved by 3e-5 in y:
//   diff_meshes(a, b) -> equal() false; first = {Position, element 2, component 1,
//   value_a 1, value_b 1.00003, by 3e-5}; max_position 3e-5.
// The rotated face is the same face; flipped, (0 2 1), it would be a Face difference.
#pragma once

#include <string>

#include "tear/mesh.h"

namespace tear {

/// Options of `diff_meshes`; mirrored by `tear diff --tolerance` and `--uv-tolerance`.
struct DiffOptions {
  /// Largest absolute difference, per coordinate, of two positions (mesh units) or velocities (m/s)
  /// that still compare equal. The default is a few float ulps of a metre-sized cloth: enough for a
  /// GPU's fused multiply-adds against a CPU's, far below anything visible.
  double tolerance = 1e-5;
  /// Largest absolute difference, per component, of two corner UVs or corner normals.
  double uv_tolerance = 1e-5;
};

/// What differs first. Stable values, `None = 0` first.
enum class DiffKind {
  None = 0,
  NodeCount,  ///< node counts differ (value_a, value_b: the counts)
  FaceCount,  ///< face counts differ (value_a, value_b: the counts)
  Face,       ///< a face of one mesh has no match in the other (element: the face, in `in_b`'s mesh)
  Position,   ///< a node's coordinate differs by more than `tolerance`
  Velocity,   ///< a node's velocity differs by more than `tolerance` (both meshes carry velocities)
  Uv,         ///< a corner UV differs by more than `uv_tolerance`, or only one mesh has UVs
  Normal,     ///< a corner normal differs by more than `uv_tolerance`, or only one mesh has normals
};

const char* to_string(DiffKind kind);

/// One difference between mesh a and mesh b.
struct Difference {
  DiffKind kind = DiffKind::None;
  /// The node (NodeCount, FaceCount: -1; Position, Velocity: the node; Face: the face in a, or in b
  /// when `in_b`; Uv, Normal: the face of a whose corner differs, -1 when only one mesh has them).
  index_t element = none;
  int corner = -1;                  ///< Uv, Normal: the corner (0..2) of face `element` of a; else -1
  int component = -1;               ///< Position, Velocity, Normal: 0..2 (x, y, z); Uv: 0..1 (u, v); else -1
  bool in_b = false;                ///< Face: the unmatched face is b's (a's faces all matched)
  double value_a = 0, value_b = 0;  ///< both values (counts for NodeCount, FaceCount)
  double by = 0;                    ///< |value_a - value_b| (infinite when one is NaN)
  std::string describe() const;     ///< one line, e.g. "node 12 y position 0.5 vs 0.50002 (by 2e-05)"
};

/// The result of `diff_meshes`.
struct MeshDiff {
  Difference first;  ///< the first difference, in the order of `DiffKind`, then of element index
  /// Largest absolute per-component differences over everything compared (0 when nothing was):
  /// positions and velocities of the nodes both meshes have, UVs and normals of matched corners.
  double max_position = 0, max_velocity = 0, max_uv = 0, max_normal = 0;
  bool equal() const { return first.kind == DiffKind::None; }
};

/// Compares mesh `a` with mesh `b`, node `i` against node `i` (node indices are identity).
///
/// - Counts: node and face counts must be equal.
/// - Faces, exact, as sets: each face is rotated to start at its smallest node (so (1 2 0) is
///   (0 1 2)) and the two sorted lists must be equal; face order does not matter, orientation does
///   ((0 2 1) is another face). Repeated faces are matched in face order.
/// - Positions (and velocities, when both meshes carry them) within `options.tolerance`, per
///   coordinate, over the nodes both have.
/// - Corner UVs and normals within `options.uv_tolerance`, corners matched through the face
///   matching; one mesh with UVs (normals) and the other without is a difference.
/// Every difference is measured (for the maxima); `first` is the first in the order above. NaN
/// equals NaN; NaN against a number differs by infinity. Throws nothing for well-formed meshes
/// (face indices in range, arrays of their documented sizes).
MeshDiff diff_meshes(const Mesh& a, const Mesh& b, const DiffOptions& options = {});

}  // namespace tear
