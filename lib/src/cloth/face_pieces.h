// tear: the piece ids of a cloth's faces (docs/identity.md, *Pieces*): the connected piece (faces
// joined through shared nodes) each face belongs to, numbered once and kept through every split.
//
// Example: a sheet of 4 faces, one piece: piece = [0, 0, 0, 0]. A cut splits it into faces {0, 1}
// (rest area 2) and {2, 3} (rest area 1): the larger part keeps id 0, the other takes the next
// unused id, so piece = [0, 0, 1, 1]. Host code: deterministic, the same on every backend.
#pragma once

#include <vector>

#include "tear/mesh.h"

namespace tear {

/// Numbers the pieces of `face_nodes` [face_count * 3] (over `node_count` nodes) afresh, in order
/// of their lowest face: the piece of face 0 is 0, the next piece met is 1, ...; returns the count.
index_t number_pieces(const std::vector<index_t>& face_nodes, index_t node_count, std::vector<index_t>& face_piece);

/// Renumbers `face_piece` (each face's id before the mesh was cut, carried from its parent face)
/// for the pieces of the cut mesh: of the pieces that carry one old id, the one with the largest
/// rest area (from `node_rest` [node_count * 3]; a tie goes to the lowest face) keeps it, and every
/// other piece, over all old ids in order of its lowest face, takes the next unused id (one more
/// than the largest id in use). Returns the largest id in use plus one.
index_t renumber_pieces(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest,
                        std::vector<index_t>& face_piece);

/// The number of distinct ids in `face_piece`.
index_t count_pieces(const std::vector<index_t>& face_piece);

/// Each node's piece [node_count]: the piece of a face that uses it (every face around a node is
/// in one piece), -1 for a node no face uses.
std::vector<index_t> node_pieces(const std::vector<index_t>& face_nodes, const std::vector<index_t>& face_piece,
                                 index_t node_count);

}  // namespace tear
