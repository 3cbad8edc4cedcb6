// tear: the statistics `tear info` prints about a mesh: counts, boundary, components, defects.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "tear/mesh.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"

namespace tear {

/// A face that is not degenerate but has an angle under this many degrees is a sliver: its height
/// is under 1/57 of its longest edge. It can be cut, but a cut near it makes thinner slivers still
/// (the snap rules keep what the remesher makes above 5 degrees only where the input was) and the
/// solver's bending weights grow with one over its height. Triangulated n-gons (Blender's fill)
/// make them; `tear info` and `tear validate` warn about them.
inline constexpr double sliver_angle_deg = 1.0;

/// Counts and measures of one mesh. Every count is a plain number of elements; nothing is -1.
struct MeshInfo {
  std::int64_t nodes = 0;           ///< node_count, including nodes no face uses
  std::int64_t faces = 0;           ///< face_count
  std::int64_t edges = 0;           ///< unique unordered node pairs of the faces
  std::int64_t boundary_edges = 0;  ///< edges with exactly one face
  /// Connected components of the graph formed by the boundary edges (over the nodes they join).
  /// On a manifold mesh each is one closed loop; where bow-tie nodes join two loops at a node,
  /// they count as one.
  std::int64_t boundary_loops = 0;
  /// Groups of faces connected through shared nodes (so two faces meeting only at a bow-tie node
  /// are one component). Nodes no face uses belong to no component.
  std::int64_t components = 0;
  /// Connected pieces: the distinct ids of `Mesh::face_piece` when the mesh carries them, else
  /// `components` (a frame tear wrote has as many pieces as components).
  std::int64_t pieces = 0;
  std::int64_t euler_characteristic = 0;  ///< nodes - edges + faces
  std::int64_t non_manifold_edges = 0;    ///< edges with more than two faces (from MeshReport)
  std::int64_t non_manifold_nodes = 0;    ///< bow-tie nodes: more than one fan of faces (from MeshReport)
  std::int64_t degenerate_faces = 0;      ///< repeated node or (numerically) zero area (from MeshReport)
  std::int64_t inconsistent_edges = 0;    ///< two-face edges with opposite orientations (from MeshReport)
  std::int64_t duplicate_faces = 0;       ///< faces on the same three nodes as another face (from MeshReport)
  std::int64_t thin_faces = 0;            ///< faces too thin to cut, not degenerate (from MeshReport)
  std::int64_t imprecise_faces = 0;       ///< faces too thin for float32 at their coordinates (from MeshReport)
  double area = 0.0;                      ///< sum of the triangle areas, square metres (double sums)
  bool has_uv = false;
  bool has_normals = false;
  /// Smallest interior angle, degrees, over the faces that are not degenerate (same criterion as
  /// `validate_mesh`); NaN when there is no such face.
  double min_angle_deg = 0.0;
  /// Faces that are not degenerate with an angle under `sliver_angle_deg` (a warning, not a defect).
  std::int64_t sliver_faces = 0;
  /// Axis-aligned bounding box of all nodes, metres; NaN when the mesh has no node.
  std::array<double, 3> bbox_min{};
  std::array<double, 3> bbox_max{};
};

/// Computes the statistics of `mesh` on the host. `topology` must be `build_topology(mesh)` and
/// `report` its `validate_mesh(mesh, topology)`; the defect counts are copied from the report.
/// Requires `report.readable()` (indices in range); coordinates may be non-finite, which makes
/// area, angles and box non-finite too.
MeshInfo compute_mesh_info(const Mesh& mesh, const Topology& topology, const MeshReport& report);

/// One JSON object, on one line, with the keys `nodes`, `faces`, `edges`, `boundary_edges`, `boundary_loops`, `components`,
/// `euler_characteristic`, `non_manifold_edges`, `non_manifold_nodes`, `degenerate_faces`,
/// `inconsistent_edges`, `duplicate_faces`, `thin_faces`, `imprecise_faces`, `sliver_faces`, `area`, `has_uv`, `has_normals`, `min_angle_deg` (null when NaN),
/// `bbox_min`, `bbox_max` ([x, y, z], null when the mesh has no node).
/// Keys in alphabetical order.
std::string to_json(const MeshInfo& info);

}  // namespace tear
