// tear: what the mesh writers number: the vertices of PLY and glTF frames, which split a node
// where its corners disagree on UV or normal, and OBJ's `vt` and `vn` lists, values in order of
// first use. Both are computed in pieces on a team of threads; the numbers never depend on them.
#pragma once

#include <vector>

#include "io/mesh/parallel_pieces.h"
#include "tear/mesh.h"

namespace tear {

/// Vertices for formats without per-corner indices (PLY, glTF). Vertex `i` is node `i` for every
/// `i < node_count`, with the UV and normal of the node's first corner; a corner whose UV or
/// normal differs (as numbers: -0 and +0 are one value, NaN is one value) from those of every
/// vertex of its node so far gets a vertex of its own, numbered after all the nodes in the order
/// of the corners. So a reader that keeps vertex order sees node `i` at vertex `i`, and identical
/// attributes never split a node.
struct SplitNodes {
  std::vector<index_t> vertex_node;    ///< [vertex_count] node of each vertex
  std::vector<index_t> vertex_corner;  ///< [vertex_count] first corner using it (its UV and normal), -1 if none
  std::vector<index_t> corner_vertex;  ///< [face_count * 3] vertex of each corner
};

/// The vertices of `mesh`, whose faces use nodes in range (`encode_mesh` checks).
SplitNodes split_nodes(const Mesh& mesh, const PieceTeam& team);

/// Distinct values of `width` floats per corner (compared bit for bit), numbered in order of
/// first use, as OBJ's `vt`/`vn` lists.
struct ValueNumbers {
  std::vector<index_t> corner_value;  ///< [corner_count] the number of each corner's value
  std::vector<index_t> first_corner;  ///< [value_count] the corner that first uses each value
};

/// The values of `corner_values`, `width` (2 or 3) floats a corner.
ValueNumbers number_by_value(const std::vector<float>& corner_values, int width, const PieceTeam& team);

}  // namespace tear
