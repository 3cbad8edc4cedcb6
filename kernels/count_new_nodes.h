// tear kernels: count of new nodes per node, edge and face (paper §2.2): one per sector.
#pragma once

#include "walk_sectors.h"

namespace tear::kernels {

/// A node on cut lines gets one copy per sector. The first copy keeps the node's index (identity:
/// the index is the node's persistent id), so what is counted, scanned and appended are the extra
/// copies: sectors - 1 (0 for a node no cut line splits).
struct count_node_copies {
  SectorMesh mesh;
  index_t* node_extra_count;
  TEAR_HD void operator()(index_t n) const {
    if (node_uncut(mesh, n)) {  // most nodes, away from the cuts: one sector, no walk
      node_extra_count[n] = 0;
      return;
    }
    count_sectors c;
    const bool closed = walk_node(mesh, n, c);
    node_extra_count[n] = c.sectors(closed) - 1;
  }
};

/// An edge with a cut point inside it gets one node per sector of that point; others none.
struct count_edge_copies {
  SectorMesh mesh;
  const std::uint8_t* edge_point;
  index_t* edge_new_count;
  TEAR_HD void operator()(index_t e) const {
    if (edge_point[e] != edge_point_inside) {
      edge_new_count[e] = 0;
      return;
    }
    count_sectors c;
    const bool closed = walk_edge_point(mesh, e, c);
    edge_new_count[e] = c.sectors(closed);
  }
};

/// A face whose lines cross gets one node per sector of its face point; others none.
struct count_face_copies {
  SectorMesh mesh;
  index_t* face_new_count;
  TEAR_HD void operator()(index_t f) const {
    if (!split_case(mesh.table, mesh.face_state[f]).face_point) {
      face_new_count[f] = 0;
      return;
    }
    count_sectors c;
    walk_face_point(mesh, f, c);
    face_new_count[f] = c.sectors(true);
  }
};

/// New triangles per face, from the split table (paper §2.3).
struct count_new_faces {
  const std::uint16_t* face_state;
  const SplitCase* table;
  index_t* face_new_face_count;
  TEAR_HD void operator()(index_t f) const { face_new_face_count[f] = split_case(table, face_state[f]).tri_count; }
};

/// Per face, both counts: its new nodes and its new triangles. Run over one index more than the
/// faces: that thread writes the 0 after each array's counts, which their exclusive scans turn into
/// the totals.
struct count_face_copies_and_triangles {
  count_face_copies copies;
  count_new_faces triangles;
  index_t face_count;
  TEAR_HD void operator()(index_t f) const {
    if (f == face_count) {
      copies.face_new_count[f] = 0;
      triangles.face_new_face_count[f] = 0;
      return;
    }
    copies(f);
    triangles(f);
  }
};

/// The cut's summary: edges with a cut point, edges with a cut line along them, faces with a face
/// point, added into `counts` [3] (zeroed first). Integer sums, so the same in any order.
struct summarize_cut {
  const std::uint8_t* edge_point;
  const std::uint8_t* edge_cut;
  const index_t* face_new_offset;  ///< [face_count + 1]: a face's new nodes are the difference
  index_t edge_count, face_count;
  index_t* counts;
  TEAR_HD void operator()(index_t i) const {
    if (i < edge_count) {
      if (edge_point[i] == edge_point_inside) atomic_fetch_add(&counts[0], 1);
      if (edge_cut[i]) atomic_fetch_add(&counts[1], 1);
    }
    if (i < face_count && face_new_offset[i + 1] != face_new_offset[i]) atomic_fetch_add(&counts[2], 1);
  }
};

}  // namespace tear::kernels
