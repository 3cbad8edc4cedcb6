// tear kernels: what a frame says about where its nodes and edges came from, derived from the
// carried attributes `face_origin` (the input face a face lies in) and `corner_origin` (each
// corner's barycentric weights in that input face, [corner * 3]).
//
// Example: an input sheet of two faces, cut once across face 0: a node made on the cut inside
// face 0's edge 2 has origin face 0 and weights (w0, w1, 0); the edge of the new triangle along the
// cut lies inside face 0 (no weight of its two corners is zero on both), so it is torn; an edge
// whose two corners both have weight 0 for corner c lies on input edge c, torn only where that
// input edge was not already on the border.
#pragma once

#include <cstdint>

#include "hd.h"

namespace tear::kernels {

/// A node's origin: the input face and weights of its lowest-numbered face's corner at the node
/// (the node's faces are listed in ascending order). A node of no face gets -1 and (0, 0).
struct gather_node_origins {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  const index_t* face_origin;
  const float* corner_origin;   ///< [corner * 3]
  index_t* node_origin_face;    ///< [node_count]
  float* node_origin_bary;      ///< [node_count * 2]: the weights of the 2nd and 3rd corner
  TEAR_HD void operator()(index_t n) const {
    if (node_face_offset[n + 1] == node_face_offset[n]) {
      node_origin_face[n] = -1;
      node_origin_bary[2 * n] = node_origin_bary[2 * n + 1] = 0.f;
      return;
    }
    const index_t f = node_faces[node_face_offset[n]];
    const index_t c = 3 * f + (face_nodes[3 * f] == n ? 0 : face_nodes[3 * f + 1] == n ? 1 : 2);
    node_origin_face[n] = face_origin[f];
    node_origin_bary[2 * n] = corner_origin[3 * c + 1];
    node_origin_bary[2 * n + 1] = corner_origin[3 * c + 2];
  }
};

/// Marks corner c = 3f + k when the edge from it to the next corner of its face is a border edge
/// made by a cut or tear: a border edge that lies inside an input face, or on an input edge that
/// was not on the input's border. Zero weights stay exactly zero through interpolation, so "on
/// input edge j" is an exact test.
struct mark_torn_corners {
  const index_t* face_edges;
  const index_t* edge_faces;
  const index_t* face_origin;
  const float* corner_origin;             ///< [corner * 3]
  const std::uint8_t* input_face_border;  ///< [input_face_count]: bit j = input edge j is a border edge
  std::uint8_t* corner_torn;              ///< [face_count * 3]
  TEAR_HD void operator()(index_t c) const {
    const index_t f = c / 3;
    const int k = static_cast<int>(c - 3 * f);
    const index_t e = face_edges[3 * f + (k + 2) % 3];  // edge j joins corners j+1 and j+2
    if (edge_faces[2 * e + 1] >= 0) {
      corner_torn[c] = 0;
      return;
    }
    const index_t next = 3 * f + (k + 1) % 3;
    for (int j = 0; j < 3; ++j)
      if (corner_origin[3 * c + j] == 0.f && corner_origin[3 * next + j] == 0.f) {
        corner_torn[c] = ((input_face_border[face_origin[f]] >> j) & 1u) ? 0 : 1;
        return;
      }
    corner_torn[c] = 1;
  }
};

}  // namespace tear::kernels
