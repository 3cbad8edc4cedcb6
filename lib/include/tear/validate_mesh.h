// tear: the checks a mesh must pass before it can be cut, shared by the CLI and the tests.
#pragma once

#include <cstdint>
#include <string>

#include "tear/device.h"
#include "tear/mesh.h"
#include "tear/topology.h"

namespace tear {

/// Counts of everything wrong with a mesh. All zero: the mesh is a valid, oriented 2-manifold
/// (with boundary) that the remesher can cut.
struct MeshReport {
  std::int64_t indices_out_of_range = 0;  ///< faces with a node index outside [0, node_count)
  std::int64_t non_finite_nodes = 0;      ///< nodes with a NaN or infinite coordinate
  std::int64_t degenerate_faces = 0;      ///< faces with a repeated node or (numerically) zero area
  std::int64_t non_manifold_edges = 0;    ///< edges with more than two faces
  std::int64_t non_manifold_nodes = 0;    ///< nodes whose faces form more than one fan (bow-ties)
  std::int64_t inconsistent_edges = 0;    ///< two-face edges whose faces disagree on orientation
  /// Faces on the same three (distinct) nodes as another face, in any order: two oppositely
  /// oriented ones pass the other checks but close a surface of no volume, which no cut can split
  /// into a manifold (its ends stay joined: bow-ties).
  std::int64_t duplicate_faces = 0;
  /// Faces that are not degenerate but too thin to cut: twice the area at most `thin_area_ratio`
  /// times the square of the longest edge (a height under 1e-7 of the longest edge). Node
  /// positions are single precision, 24 significant bits: a cut point placed on such a face can
  /// round onto its long edge, and the cut leaves a degenerate face.
  std::int64_t thin_faces = 0;
  /// Faces that are neither degenerate nor thin but whose height is at most `imprecise_steps`
  /// single-precision steps at their largest coordinate: float32 cannot hold the face's width
  /// beside its distance from the origin (features of 0.25 m beside a node 3.3e6 m away, where
  /// float32 has steps of 0.25 m), so a point a cut places on the face is off by a good part of its
  /// height, and its cuts leave faces thinner still, too thin to cut. A mesh with any is not cut
  /// (`cuttable`); a cut's result is not held to it (`ok`): the faces a cut makes of a face near
  /// that limit may be under it.
  std::int64_t imprecise_faces = 0;

  /// No index out of range and no non-finite coordinate: topology and statistics can be computed.
  bool readable() const { return indices_out_of_range == 0 && non_finite_nodes == 0; }
  /// Nothing wrong at all.
  bool ok() const {
    return readable() && degenerate_faces == 0 && non_manifold_edges == 0 && non_manifold_nodes == 0 &&
           inconsistent_edges == 0 && duplicate_faces == 0 && thin_faces == 0;
  }
  /// Nothing wrong, and no imprecise face: what a mesh must be to be cut (`tear run`, `tear info`'s
  /// `cuttable`, `check_cuttable`).
  bool cuttable() const { return ok() && imprecise_faces == 0; }
  /// One line naming every non-zero count, e.g. "3 non-manifold edges, 1 bow-tie node".
  std::string describe() const;
};

/// A face is degenerate when it repeats a node or when twice its area is at most this fraction
/// of the square of its longest edge.
inline constexpr double degenerate_area_ratio = 1e-12;

/// A face that is not degenerate is too thin to cut when twice its area is at most this fraction
/// of the square of its longest edge: its height is within two single-precision ulps (2^-24) of
/// its longest edge. In angles, about 6e-6 degrees; a 0.0004 degree sliver can still be cut (and
/// is warned about: `sliver_angle_deg`).
inline constexpr double thin_area_ratio = 1e-7;

/// A face is imprecise when its height is at most this many single-precision steps at its largest
/// coordinate M (|x|, |y| or |z| of its nodes; a step there is at most M 2^-23): twice its area at
/// most `imprecise_steps` M 2^-23 times its longest edge. The two cuts that thinned a face of 3.2
/// steps under the thin limit took it to 0.32 of a step; 8 steps leave a margin for such cuts.
inline constexpr double imprecise_steps = 8;

/// Checks indices and coordinates only; cheap, and enough to know whether topology can be built.
MeshReport check_indices(const Mesh& mesh, Device device);

/// All checks. `topology` must be `build_topology(mesh)`; requires `check_indices(mesh).readable()`
/// for the topological counts (they stay 0 otherwise).
MeshReport validate_mesh(const Mesh& mesh, const Topology& topology, Device device);

/// Convenience: indices first, then topology and the rest when the indices allow it.
MeshReport validate_mesh(const Mesh& mesh, Device device);

}  // namespace tear
