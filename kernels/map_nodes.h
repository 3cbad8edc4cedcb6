// tear kernels: node mapping (paper §2.4): each point walks its new triangles again and writes
// its copies' indices into their corners. Every corner is written by exactly one point.
#pragma once

#include "walk_sectors.h"

namespace tear::kernels {

/// New node indices. Node n keeps index n for its first copy; everything a cut makes is appended
/// after the old nodes (`old_node_count` + offset): the nodes' extra copies, then the edge points'
/// copies, then the face points'. Example: 4 nodes, node 2 split in two, one edge point with two
/// copies: new nodes 0 1 2 3 | 4 (node 2's second copy) | 5 6 (the edge point's).
struct map_node_copies {
  SectorMesh mesh;
  const index_t* face_tri_offset;
  const index_t* node_extra_offset;  ///< scanned extra copies, [node_count + 1]
  index_t old_node_count;
  index_t* new_face_nodes;
  TEAR_HD void operator()(index_t n) const {
    const index_t extra = node_extra_offset[n + 1] - node_extra_offset[n];
    assign_copies a{face_tri_offset, new_face_nodes, n, old_node_count + node_extra_offset[n], extra + 1};
    if (extra == 0) {
      // One sector: every corner gets copy 0, whatever the order, so the faces are visited as
      // listed instead of walked in turn (the walk's loads wait on each other).
      for (index_t i = mesh.node_face_offset[n]; i < mesh.node_face_offset[n + 1]; ++i) {
        const index_t f = mesh.node_faces[i];
        walk_face_fan(mesh, f, corner_of(mesh.face_nodes, f, n), a);
      }
      return;
    }
    walk_node(mesh, n, a);
  }
};

struct map_edge_copies {
  SectorMesh mesh;
  const index_t* face_tri_offset;
  const index_t* edge_new_offset;  ///< already past the node copies
  index_t old_node_count;
  index_t* new_face_nodes;
  TEAR_HD void operator()(index_t e) const {
    const index_t count = edge_new_offset[e + 1] - edge_new_offset[e];
    if (!count) return;
    const index_t first = old_node_count + edge_new_offset[e];
    assign_copies a{face_tri_offset, new_face_nodes, first, first + 1, count};
    walk_edge_point(mesh, e, a);
  }
};

struct map_face_copies {
  SectorMesh mesh;
  const index_t* face_tri_offset;
  const index_t* face_new_offset;  ///< already past the node and edge copies
  index_t old_node_count;
  index_t* new_face_nodes;
  TEAR_HD void operator()(index_t f) const {
    const index_t count = face_new_offset[f + 1] - face_new_offset[f];
    if (!count) return;
    const index_t first = old_node_count + face_new_offset[f];
    assign_copies a{face_tri_offset, new_face_nodes, first, first + 1, count};
    walk_face_point(mesh, f, a);
  }
};

}  // namespace tear::kernels
