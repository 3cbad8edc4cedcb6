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

/// What a cut did, for its statistics: edges with a cut point, edges with a cut line along them,
/// faces with a face point. One reduction, so one read-back.
struct CutSummary {
  index_t edge_points = 0, cut_edges = 0, face_points = 0;
  TEAR_HD CutSummary operator+(const CutSummary& o) const {
    return {edge_points + o.edge_points, cut_edges + o.cut_edges, face_points + o.face_points};
  }
};

struct summarize_cut {
  const std::uint8_t* edge_point;
  const std::uint8_t* edge_cut;
  const index_t* face_new_offset;  ///< [face_count + 1]: a face's new nodes are the difference
  index_t edge_count, face_count;
  TEAR_HD CutSummary operator()(index_t i) const {
    CutSummary s;
    if (i < edge_count) {
      s.edge_points = edge_point[i] == edge_point_inside ? 1 : 0;
      s.cut_edges = edge_cut[i] ? 1 : 0;
    }
    if (i < face_count) s.face_points = face_new_offset[i + 1] != face_new_offset[i] ? 1 : 0;
    return s;
  }
};

}  // namespace tear::kernels
