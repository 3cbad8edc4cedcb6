// tear: importing a cloth mesh through assimp, welded into one topology.
#pragma once

#include <string>

#include "tear/mesh.h"

namespace tear {

/// Options of `read_mesh`; mirrored by the CLI flags `--mesh-name` and `--weld-tolerance`.
struct ReadOptions {
  /// Import only the meshes of this name (assimp's aiMesh name or its node's name); empty: merge
  /// every mesh of the file, each placed by its node's transform.
  std::string mesh_name;
  /// Nodes closer than this distance (metres, per coordinate) are welded into one; 0 welds only
  /// identical positions.
  double weld_tolerance = 0.0;
};

/// Reads OBJ, glTF, GLB, PLY or anything else assimp reads. Polygons are triangulated, points
/// and lines dropped, nodes welded by position (so UV seams and normal creases do not split the
/// topology) while UVs and normals stay per face corner. Throws `Error` (input) naming the file
/// when it cannot be read or holds no triangles.
Mesh read_mesh(const std::string& path, const ReadOptions& options = {});

/// Welds nodes of `mesh` whose positions agree within `tolerance` (0: identical), keeping for each
/// group its lowest-index node's position; drops nodes no face uses. Deterministic.
void weld_nodes(Mesh& mesh, double tolerance);

}  // namespace tear
