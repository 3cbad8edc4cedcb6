// tear kernels: building edges, edge→faces, face→edges, node→faces and boundary flags by counting
// and scanning, without sorting.
//
// Node→faces is a counting sort of the corners by node (an integer histogram, an exclusive scan,
// a fill through per-node cursors), each node's short run then put in face order. An edge belongs
// to its lower node: each node enumerates the distinct higher ends of its faces' half-edges in
// ascending order, so numbering the edges through a scan of the per-node counts gives them in
// (low, high) order, the order a sort of the edge keys would.
#pragma once

#include <cstdint>

#include "backend.h"

namespace tear::kernels {

using index_t = std::int32_t;

/// Half-edge h = 3 * face + k is local edge k of the face: it joins local nodes k+1 and k+2.
TEAR_HD inline void half_edge_nodes(const index_t* face_nodes, index_t f, int k, index_t& lo, index_t& hi) {
  const index_t p = face_nodes[3 * f + (k + 1) % 3], q = face_nodes[3 * f + (k + 2) % 3];
  lo = p < q ? p : q;
  hi = p < q ? q : p;
}

/// Histogram of corners by node (`node_count_of` zeroed first).
struct count_node_corners {
  const index_t* face_nodes;
  index_t* node_count_of;
  TEAR_HD void operator()(index_t c) const { atomic_fetch_add(&node_count_of[face_nodes[c]], 1); }
};

/// Puts each corner's face in its node's run, at a place taken from the node's cursor (its run's
/// start, copied from the offsets). The order within a run depends on timing; `sort_runs` fixes it.
struct fill_node_faces {
  const index_t* face_nodes;
  index_t* node_cursor;
  index_t* node_faces;
  TEAR_HD void operator()(index_t c) const {
    const index_t at = atomic_fetch_add(&node_cursor[face_nodes[c]], 1);
    node_faces[at] = c / 3;
  }
};

/// Sorts run n of a CSR ascending (insertion sort: runs are a node's valence long). For node→faces,
/// a face that repeats the node appears once per corner, adjacent after the sort.
struct sort_runs {
  const index_t* offset;
  index_t* values;
  TEAR_HD void operator()(index_t n) const {
    const index_t begin = offset[n], end = offset[n + 1];
    for (index_t i = begin + 1; i < end; ++i) {
      const index_t v = values[i];
      index_t j = i;
      for (; j > begin && values[j - 1] > v; --j) values[j] = values[j - 1];
      values[j] = v;
    }
  }
};

/// The smallest higher end greater than `after` of the half-edges, in node n's faces, whose lower
/// end is n; -1 when there is none.
TEAR_HD inline index_t next_edge_end(const index_t* face_nodes, const index_t* node_face_offset,
                                     const index_t* node_faces, index_t n, index_t after) {
  index_t best = -1;
  for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1]; ++i) {
    const index_t f = node_faces[i];
    for (int k = 0; k < 3; ++k) {
      index_t lo, hi;
      half_edge_nodes(face_nodes, f, k, lo, hi);
      if (lo == n && hi > after && (best < 0 || hi < best)) best = hi;
    }
  }
  return best;
}

/// The edges whose lower node is n, gathered in one pass over its faces: higher ends ascending,
/// each with its number of half-edges and its first two faces (faces ascending). Holds up to
/// `capacity` edges; a node with more sets `overflow`, and the caller enumerates them with
/// `next_edge_end` instead (slower: one pass over the faces per edge).
struct NodeEdgeList {
  static constexpr int capacity = 8;
  int size = 0;
  bool overflow = false;
  index_t end[capacity], count[capacity], face[capacity][2];

  TEAR_HD void gather(const index_t* face_nodes, const index_t* node_face_offset, const index_t* node_faces,
                      index_t n) {
    for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1]; ++i) {
      const index_t f = node_faces[i];
      if (i > node_face_offset[n] && node_faces[i - 1] == f) continue;  // a face repeating n, seen
      for (int k = 0; k < 3; ++k) {
        index_t lo, hi;
        half_edge_nodes(face_nodes, f, k, lo, hi);
        if (lo != n) continue;
        int j = 0;
        while (j < size && end[j] < hi) ++j;
        if (j < size && end[j] == hi) {
          if (count[j] < 2) face[j][count[j]] = f;
          ++count[j];
          continue;
        }
        if (size == capacity) {
          overflow = true;
          return;
        }
        for (int m = size; m > j; --m) {
          end[m] = end[m - 1];
          count[m] = count[m - 1];
          face[m][0] = face[m - 1][0];
          face[m][1] = face[m - 1][1];
        }
        end[j] = hi;
        count[j] = 1;
        face[j][0] = f;
        face[j][1] = -1;
        ++size;
      }
    }
  }
};

/// Number of edges whose lower node is n: the distinct higher ends of its half-edges.
struct count_node_edges {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  index_t* node_edge_count;
  TEAR_HD void operator()(index_t n) const {
    NodeEdgeList list;
    list.gather(face_nodes, node_face_offset, node_faces, n);
    if (!list.overflow) {
      node_edge_count[n] = list.size;
      return;
    }
    index_t count = 0;
    for (index_t end = next_edge_end(face_nodes, node_face_offset, node_faces, n, -1); end >= 0;
         end = next_edge_end(face_nodes, node_face_offset, node_faces, n, end))
      ++count;
    node_edge_count[n] = count;
  }
};

/// Writes the edges of lower node n from edge node_edge_offset[n] on, higher ends ascending: their
/// nodes, their faces (the faces of n holding the half-edge, ascending; the first two kept, all
/// counted) and boundary flags (one face).
struct write_node_edges {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  const index_t* node_edge_offset;
  index_t* edge_nodes;
  index_t* edge_faces;
  index_t* edge_face_count;
  std::uint8_t* edge_boundary;
  TEAR_HD void write(index_t e, index_t n, index_t end, index_t count, index_t face0, index_t face1) const {
    edge_nodes[2 * e] = n;
    edge_nodes[2 * e + 1] = end;
    edge_face_count[e] = count;
    edge_faces[2 * e] = face0;
    edge_faces[2 * e + 1] = face1;
    edge_boundary[e] = count == 1 ? 1 : 0;
  }

  TEAR_HD void operator()(index_t n) const {
    index_t e = node_edge_offset[n];
    NodeEdgeList list;
    list.gather(face_nodes, node_face_offset, node_faces, n);
    if (!list.overflow) {
      for (int j = 0; j < list.size; ++j) write(e + j, n, list.end[j], list.count[j], list.face[j][0], list.face[j][1]);
      return;
    }
    for (index_t end = next_edge_end(face_nodes, node_face_offset, node_faces, n, -1); end >= 0;
         end = next_edge_end(face_nodes, node_face_offset, node_faces, n, end), ++e) {
      index_t count = 0, faces[2] = {-1, -1};
      for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1]; ++i) {
        const index_t f = node_faces[i];
        if (i > node_face_offset[n] && node_faces[i - 1] == f) continue;  // a face repeating n, seen
        for (int k = 0; k < 3; ++k) {
          index_t lo, hi;
          half_edge_nodes(face_nodes, f, k, lo, hi);
          if (lo != n || hi != end) continue;
          if (count < 2) faces[count] = f;
          ++count;
        }
      }
      write(e, n, end, count, faces[0], faces[1]);
    }
  }
};

/// face_edges[h]: the edge of half-edge h, found among its lower node's edges (higher ends sorted)
/// by binary search.
struct write_face_edges {
  const index_t* face_nodes;
  const index_t* node_edge_offset;
  const index_t* edge_nodes;
  index_t* face_edges;
  TEAR_HD void operator()(index_t h) const {
    index_t lo, hi;
    half_edge_nodes(face_nodes, h / 3, h % 3, lo, hi);
    index_t first = node_edge_offset[lo], last = node_edge_offset[lo + 1];  // [first, last)
    while (first < last) {
      const index_t mid = first + (last - first) / 2;
      if (edge_nodes[2 * mid + 1] < hi)
        first = mid + 1;
      else
        last = mid;
    }
    face_edges[h] = first;
  }
};

/// A node is on the boundary when one of the edges it shares with its faces is a boundary edge
/// (a gather over its faces, so no two threads write the same flag).
struct flag_boundary_nodes {
  const index_t* face_nodes;
  const index_t* face_edges;
  const index_t* node_face_offset;
  const index_t* node_faces;
  const std::uint8_t* edge_boundary;
  std::uint8_t* node_boundary;
  TEAR_HD void operator()(index_t n) const {
    std::uint8_t flag = 0;
    for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1] && !flag; ++i) {
      const index_t f = node_faces[i];
      for (int k = 0; k < 3; ++k)
        if (face_nodes[3 * f + k] != n && edge_boundary[face_edges[3 * f + k]]) flag = 1;
    }
    node_boundary[n] = flag;
  }
};

}  // namespace tear::kernels
