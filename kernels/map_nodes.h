// tear kernels: node mapping (paper §2.4): each point walks its new triangles again and writes
// its copies' indices into their corners. Every corner is written by exactly one point.
#pragma once

#include "walk_sectors.h"

namespace tear::kernels {

/// New node indices: node copies first, then edge points' copies, then face points'.
struct map_node_copies {
  SectorMesh mesh;
  const index_t* face_tri_offset;
  const index_t* node_new_offset;
  index_t* new_face_nodes;
  TEAR_HD void operator()(index_t n) const {
    assign_copies a{face_tri_offset, new_face_nodes, node_new_offset[n], (node_new_offset[n + 1] - node_new_offset[n])};
    walk_node(mesh, n, a);
  }
};

struct map_edge_copies {
  SectorMesh mesh;
  const index_t* face_tri_offset;
  const index_t* edge_new_offset;  ///< already past the node copies
  index_t* new_face_nodes;
  TEAR_HD void operator()(index_t e) const {
    if (!(edge_new_offset[e + 1] - edge_new_offset[e])) return;
    assign_copies a{face_tri_offset, new_face_nodes, edge_new_offset[e], (edge_new_offset[e + 1] - edge_new_offset[e])};
    walk_edge_point(mesh, e, a);
  }
};

struct map_face_copies {
  SectorMesh mesh;
  const index_t* face_tri_offset;
  const index_t* face_new_offset;  ///< already past the node and edge copies
  index_t* new_face_nodes;
  TEAR_HD void operator()(index_t f) const {
    if (!(face_new_offset[f + 1] - face_new_offset[f])) return;
    assign_copies a{face_tri_offset, new_face_nodes, face_new_offset[f], (face_new_offset[f + 1] - face_new_offset[f])};
    walk_face_point(mesh, f, a);
  }
};

}  // namespace tear::kernels
