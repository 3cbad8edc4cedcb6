// tear: reading a cloth mesh file into one welded topology that keeps the file's node order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tear/mesh.h"

namespace tear {

/// The default of `ReadOptions::max_faces` (`--max-faces`).
constexpr std::uint64_t default_max_faces = 50'000'000;

/// Options of `read_mesh`; mirrored by the CLI flags `--mesh-name`, `--weld-tolerance` and
/// `--no-weld`.
struct ReadOptions {
  /// Read only the meshes of this name: OBJ, the name of the `o` or `g` line the faces follow;
  /// glTF, the mesh's name or that of the scene node that places it; other formats, assimp's mesh
  /// or node name. Empty: merge every mesh of the file.
  std::string mesh_name;
  /// Nodes whose coordinates each differ by at most this much (metres) are welded into one; 0
  /// welds only identical positions. See `weld_nodes`. Not used for files that carry node ids.
  double weld_tolerance = 0.0;
  /// Weld the file's vertices into nodes: by id when the file carries ids (tear's own PLY and
  /// glTF/GLB), else by position. false: every vertex a face uses is a node of its own.
  bool weld = true;
  /// The most triangles the mesh may have, counted after triangulating and placing every glTF
  /// instance (a glTF file stops being read as soon as its placed triangles pass it); more is an
  /// input `Error`. Mirrors `--max-faces`.
  std::uint64_t max_faces = default_max_faces;
  /// Nodes as the file writes them, for comparing files (`tear diff`): vertex i is node i. Where the
  /// file carries ids (tear's PLY and glTF/GLB), the copies written after the nodes (at UV seams)
  /// rejoin their node; nothing is welded by position (a torn OBJ frame stays torn), and nodes no
  /// face uses, and faces that repeat a node, are kept. `weld` and `weld_tolerance` are not used.
  bool as_written = false;
};

/// What welding did to data the file kept apart (docs/robustness.md, *What reading and running did
/// to the data*): faces of three different vertices of the file left with a repeated node, so
/// dropped, and the nodes lost by joining two corners of one face. Apart means at different
/// positions (joined by a weld tolerance longer than an edge, or by one node id), or at one
/// float32 position where float32 keeps fewer than 1024 steps along the mesh's median edge at its
/// largest coordinate: positions that differ in the file but read as one float32, far from the
/// origin. Two corners at one position of a finely resolved mesh were one point in the file too
/// (a face degenerate there), and are not counted.
struct WeldReport {
  std::int64_t collapsed_faces = 0;  ///< faces dropped whose corners were three different vertices
  std::int64_t joined_nodes = 0;     ///< vertices of such faces joined into another vertex of theirs
  /// The largest coordinate of the vertices read, in absolute value (for the message: float32 holds
  /// coordinates about 1.2e-7 of it apart).
  double largest_coordinate = 0;

  bool any() const { return collapsed_faces > 0 || joined_nodes > 0; }
  /// "180 faces lost in reading: welding joined corners of theirs, different vertices in the file,
  /// into one node (99 nodes lost so); coordinates reach 1e+07, where float32 has steps of 1": what
  /// the warning says after the file's name.
  std::string describe() const;
};

/// Reads OBJ, PLY, glTF/GLB (tear's own readers) or anything else assimp reads (docs/io.md).
///
/// - Node order: the file's vertex order (OBJ `v` lines, PLY vertices, glTF primitives' vertices
///   in scene order) after welding, which keeps the lowest index of each group in ascending order
///   (by id: ascending id, so node i is id i when the ids are 0..N-1). Vertices no face uses are
///   dropped; the others keep their order.
/// - Polygons are triangulated in place (`triangulate_polygon`); points and lines are dropped.
/// - Every mesh of the file (or those `options.mesh_name` selects) is merged, each placed by the
///   product of its node transforms down from the root: a mesh placed by two nodes appears twice.
///   Normals go through the inverse transpose of that transform and are renormalised (unless it is
///   the identity); a mirroring transform also swaps two corners of each face so faces stay
///   counter-clockwise.
/// - UVs and normals become `corner_uv` / `corner_normal`. When some merged meshes have them and
///   others do not, the corners of the others get UV (0, 0) and normal (0, 0, 0); when none has
///   them, the arrays stay empty.
/// - Identity: PLY vertex properties `id`, `vx vy vz`, `origin_face`, `origin_u origin_v` and
///   an `edge` element (`vertex1 vertex2`), glTF attributes `_ID` and `_VELOCITY`, fill the
///   node ids (welding), `node_vel`, `node_origin_face`/`node_origin_bary` and `torn_edge_nodes`.
///
/// Throws an input `Error` ("<path>: ...", one line) when the file is missing, unreadable or
/// malformed (truncated data, counts larger than the file, an index out of range, a non-finite
/// PLY value), no mesh has the requested name (listing the names there are), or it holds no
/// (non-degenerate) triangle. Throws a usage `Error` for a negative or non-finite weld tolerance.
Mesh read_mesh(const std::string& path, const ReadOptions& options = {});
/// The same, and what welding did to data the file kept apart, in `report` (the CLI warns, or with
/// `--strict` fails).
Mesh read_mesh(const std::string& path, const ReadOptions& options, WeldReport& report);

/// Welds nodes of `mesh` that lie at the same place, so faces split by an importer share nodes again.
///
/// - `tolerance == 0`: nodes whose three coordinates compare equal weld (so -0 and +0 weld).
/// - `tolerance > 0`: two nodes are linked when each coordinate differs by at most `tolerance`;
///   groups are the connected components of that relation, so a chain of close nodes welds into
///   one group even when its ends are farther apart.
/// - Only nodes some face uses take part; a node with a non-finite coordinate welds with nothing.
/// - A group takes the position (and velocity, origin) of its lowest-index node. Nodes keep their
///   relative order (the order of each group's lowest original index); nodes no face uses are
///   dropped.
/// - Faces left with a repeated node (collapsed by welding) are dropped with their corner UVs and
///   normals; other corner attributes are untouched. Torn edges follow their nodes and are kept
///   while they are an edge of exactly one face. `report` (when given) counts the dropped faces
///   whose corners were three different nodes, and the nodes joined to a corner of their own face.
///
/// Deterministic: the result depends on positions and indices only. Throws an input `Error` when a
/// face uses a node out of range or an array has the wrong size, and a usage `Error` when
/// `tolerance` is negative or not finite.
void weld_nodes(Mesh& mesh, double tolerance, WeldReport* report = nullptr);

/// Welds nodes of `mesh` that have the same id, whatever their positions: the rule for files that
/// carry node ids, so that a torn frame reads back torn.
///
/// - `node_id`: [node_count] the id of each node, >= 0 for every node a face uses.
/// - Nodes with one id become one node, which takes the values of the lowest-index one. The nodes
///   are ordered by ascending id: ids 0..N-1 give node i = id i. Nodes no face uses are dropped
///   (the ids after them move down); faces and torn edges as for `weld_nodes`.
///
/// Throws an input `Error` when the sizes do not match, a face uses a node out of range or a used
/// node has a negative id.
void weld_nodes_by_id(Mesh& mesh, const std::vector<index_t>& node_id, WeldReport* report = nullptr);

/// What `read_mesh` does with `weld = false`: drops the nodes no face uses and the faces that
/// repeat a node, keeping the order of the rest, and welds nothing.
void drop_unused_nodes(Mesh& mesh);

}  // namespace tear
