// tear kernels: rotational walks around the points a cut touches (paper §2.2 and §2.4).
//
// Every point (an original node, an edge's cut point, a face's cut point) walks the new
// triangles around it counter-clockwise, through the split of each of its original faces
// (split_table.h) and across the original edges between them, and reports each triangle corner
// and each cut line it crosses. Counting the crossings gives the point's number of sectors,
// hence its number of copies; handing out copies along the same walk is the node mapping.
#pragma once

#include <cstdint>

#include "hd.h"
#include "cut_info.h"
#include "split_table.h"

namespace tear::kernels {

/// What a walk reads: the old mesh's topology, the face cut states and the edge cut info.
struct SectorMesh {
  const index_t* face_nodes;
  const index_t* face_edges;
  const index_t* edge_nodes;
  const index_t* edge_faces;
  const index_t* node_face_offset;
  const index_t* node_faces;
  const std::uint16_t* face_state;  ///< split codes: cut state and split variant (split_table.h)
  const std::uint8_t* edge_cut;
  const SplitCase* table;
};

TEAR_HD inline int corner_of(const index_t* face_nodes, index_t f, index_t n) {
  return face_nodes[3 * f] == n ? 0 : face_nodes[3 * f + 1] == n ? 1 : 2;
}

/// True when the half of edge e at node n carries a cut line along the edge.
TEAR_HD inline bool edge_half_cut(const SectorMesh& m, index_t e, index_t n) {
  return (m.edge_cut[e] >> (n == m.edge_nodes[2 * e] ? 0 : 1)) & 1u;
}

/// Visits the fan of point `slot` inside face f.
template <class Visitor>
TEAR_HD inline void walk_face_fan(const SectorMesh& m, index_t f, int slot, Visitor& visit) {
  const SplitCase& c = split_case(m.table, m.face_state[f]);
  const int count = c.fan_count[slot];
  for (int i = 0; i < count; ++i) {
    visit.corner(f, c.fan[slot][i]);
    if (i + 1 < count && ((c.fan_cut[slot] >> i) & 1u)) visit.cut();
  }
}

/// True when no cut line meets node n: no split of its faces has a cut in the node's fan, and no
/// edge at it carries a cut line along its half at n. Its walk would cross no cut (one sector);
/// finding so takes loads that do not wait on each other, where the walk is a chain of them.
/// The faces are taken `chunk` at a time, each level of loads issued for the whole chunk before
/// any is used.
TEAR_HD inline bool node_uncut(const SectorMesh& m, index_t n) {
  constexpr int chunk = 8;
  const index_t begin = m.node_face_offset[n], end = m.node_face_offset[n + 1];
  for (index_t base = begin; base < end; base += chunk) {
    const index_t left = end - base;
    index_t f[chunk];
    TEAR_UNROLL
    for (int j = 0; j < chunk; ++j) f[j] = j < left ? m.node_faces[base + j] : -1;
    int corner[chunk];
    std::uint16_t state[chunk];
    index_t edge[chunk][2];
    TEAR_UNROLL
    for (int j = 0; j < chunk; ++j) {
      corner[j] = 0;
      state[j] = 0;
      edge[j][0] = edge[j][1] = -1;
      if (f[j] < 0) continue;
      const int k = corner_of(m.face_nodes, f[j], n);
      corner[j] = k;
      state[j] = m.face_state[f[j]];
      edge[j][0] = m.face_edges[3 * f[j] + (k + 1) % 3];
      edge[j][1] = m.face_edges[3 * f[j] + (k + 2) % 3];
    }
    bool cut = false;
    TEAR_UNROLL
    for (int j = 0; j < chunk; ++j) {
      if (f[j] < 0) continue;
      // `|`, not `||`: every load of the chunk is issued, none waits on another's result.
      cut = cut | (split_case(m.table, state[j]).fan_cut[corner[j]] != 0) | edge_half_cut(m, edge[j][0], n) |
            edge_half_cut(m, edge[j][1], n);
    }
    if (cut) return false;
  }
  return true;
}

/// Walks around node n. Returns true when the walk is closed (an interior node).
template <class Visitor>
TEAR_HD inline bool walk_node(const SectorMesh& m, index_t n, Visitor& visit) {
  const index_t begin = m.node_face_offset[n], valence = m.node_face_offset[n + 1] - begin;
  if (valence == 0) return false;
  // A boundary node starts at the face whose incoming side (edge k+2, towards N_{k+1}) is a border.
  index_t start = m.node_faces[begin];
  for (index_t i = 0; i < valence; ++i) {
    const index_t f = m.node_faces[begin + i];
    const int k = corner_of(m.face_nodes, f, n);
    if (m.edge_faces[2 * m.face_edges[3 * f + (k + 2) % 3] + 1] < 0) {
      start = f;
      break;
    }
  }
  index_t f = start;
  for (index_t step = 0; step < valence; ++step) {
    const int k = corner_of(m.face_nodes, f, n);
    walk_face_fan(m, f, k, visit);
    const index_t e = m.face_edges[3 * f + (k + 1) % 3];
    const index_t g = m.edge_faces[2 * e] == f ? m.edge_faces[2 * e + 1] : m.edge_faces[2 * e];
    if (g < 0) return false;
    if (edge_half_cut(m, e, n)) visit.cut();
    if (g == start) return true;
    f = g;
  }
  return true;
}

/// Walks around the cut point of edge e (which has one). Returns true when closed (two faces).
template <class Visitor>
TEAR_HD inline bool walk_edge_point(const SectorMesh& m, index_t e, Visitor& visit) {
  const index_t f0 = m.edge_faces[2 * e], f1 = m.edge_faces[2 * e + 1];
  const int k0 = local_edge_of(m.face_edges, f0, e);
  walk_face_fan(m, f0, 3 + k0, visit);
  if (f1 < 0) return false;
  // f0's fan ends at the side towards its N_{k0+1}; f1's fan starts there and ends at its N_{k1+1}.
  if (edge_half_cut(m, e, m.face_nodes[3 * f0 + (k0 + 1) % 3])) visit.cut();
  const int k1 = local_edge_of(m.face_edges, f1, e);
  walk_face_fan(m, f1, 3 + k1, visit);
  if (edge_half_cut(m, e, m.face_nodes[3 * f1 + (k1 + 1) % 3])) visit.cut();
  return true;
}

/// Walks around the cut point of face f (which has one): always closed.
template <class Visitor>
TEAR_HD inline bool walk_face_point(const SectorMesh& m, index_t f, Visitor& visit) {
  const SplitCase& c = split_case(m.table, m.face_state[f]);
  const int count = c.fan_count[6];
  for (int i = 0; i < count; ++i) {
    visit.corner(f, c.fan[6][i]);
    if ((c.fan_cut[6] >> i) & 1u) visit.cut();
  }
  return true;
}

/// Sectors of a walk: a closed walk with c cut crossings has max(c, 1), an open one c + 1
/// (a cut tip inside the cloth does not split its point; one reaching the border does).
struct count_sectors {
  index_t cuts = 0;
  TEAR_HD void corner(index_t, std::uint8_t) {}
  TEAR_HD void cut() { ++cuts; }
  TEAR_HD index_t sectors(bool closed) const { return closed ? (cuts > 0 ? cuts : 1) : cuts + 1; }
};

/// Hands out the point's copies along the walk: copy (cuts crossed so far) mod sectors, so the
/// corners before the first cut of a closed walk share the last sector's copy. Copy 0, the sector
/// holding the walk's first face, is `first_copy`; copies 1.. are `extra_first` onwards. For a
/// node, copy 0 keeps the node's own index: the sector of its lowest-numbered face, or, on the
/// border, of its lowest-numbered face whose incoming side (counter-clockwise) is a border edge.
struct assign_copies {
  const index_t* face_tri_offset;
  index_t* new_face_nodes;
  index_t first_copy;
  index_t extra_first;
  index_t sectors;
  index_t cuts = 0;
  TEAR_HD void corner(index_t f, std::uint8_t entry) {
    const index_t tri = face_tri_offset[f] + fan_entry_tri(entry);
    const index_t copy = cuts % sectors;
    new_face_nodes[3 * tri + fan_entry_corner(entry)] = copy == 0 ? first_copy : extra_first + copy - 1;
  }
  TEAR_HD void cut() { ++cuts; }
};

}  // namespace tear::kernels
