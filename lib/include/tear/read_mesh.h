// tear: importing a cloth mesh through assimp, welded into one topology.
#pragma once

#include <string>

#include "tear/mesh.h"

namespace tear {

/// Options of `read_mesh`; mirrored by the CLI flags `--mesh-name` and `--weld-tolerance`.
struct ReadOptions {
  /// Import only the meshes whose assimp aiMesh name, or the name of the aiNode that places them,
  /// equals this; empty: merge every mesh of the file.
  std::string mesh_name;
  /// Nodes whose coordinates each differ by at most this much (metres) are welded into one; 0
  /// welds only identical positions. See `weld_nodes`.
  double weld_tolerance = 0.0;
};

/// Reads OBJ, glTF, GLB, PLY or anything else assimp reads.
///
/// - Polygons are triangulated; points and lines are dropped.
/// - Every mesh of the file (or those `options.mesh_name` selects) is merged, each placed by the
///   product of its node transforms down from the root: a mesh placed by two nodes appears twice.
///   Normals go through the inverse transpose of that transform and are renormalised (unless it is
///   the identity); a mirroring transform also swaps two corners of each face so faces stay
///   counter-clockwise.
/// - UVs (assimp channel 0) and normals become `corner_uv` / `corner_normal`. When some merged
///   meshes have them and others do not, the corners of the others get UV (0, 0) and normal
///   (0, 0, 0); when none has them, the arrays stay empty.
/// - Importers split nodes at UV seams and normal creases; `weld_nodes(mesh,
///   options.weld_tolerance)` restores the topology.
///
/// Throws an input `Error` ("<path>: ...", one line) when the file is missing or unreadable,
/// assimp cannot import it (with assimp's message), no mesh has the requested name (listing the
/// names there are), or it holds no (non-degenerate) triangle. Throws a usage `Error` for a
/// negative or non-finite weld tolerance.
Mesh read_mesh(const std::string& path, const ReadOptions& options = {});

/// Welds nodes of `mesh` that lie at the same place, so faces split by an importer share nodes again.
///
/// - `tolerance == 0`: nodes whose three coordinates compare equal weld (so -0 and +0 weld).
/// - `tolerance > 0`: two nodes are linked when each coordinate differs by at most `tolerance`;
///   groups are the connected components of that relation, so a chain of close nodes welds into
///   one group even when its ends are farther apart.
/// - Only nodes some face uses take part; a node with a non-finite coordinate welds with nothing.
/// - A group takes the position of its lowest-index node. Nodes keep their relative order (the
///   order of each group's lowest original index); nodes no face uses are dropped.
/// - Faces left with a repeated node (collapsed by welding) are dropped with their corner UVs and
///   normals; other corner attributes are untouched.
///
/// Deterministic: the result depends on positions and indices only. Throws an input `Error` when a
/// face uses a node out of range or the corner arrays have the wrong size, and a usage `Error` when
/// `tolerance` is negative or not finite.
void weld_nodes(Mesh& mesh, double tolerance);

}  // namespace tear
