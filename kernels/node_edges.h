// tear kernels: the edges of one node, enumerated from its faces (build_topology.h): an edge belongs
// to its lower node, which visits the distinct higher ends of its faces' half-edges in ascending
// order, from registers, from a one-pass list, or edge by edge.
#pragma once

#include <cstdint>

#include "hd.h"
#include "sort_runs.h"

namespace tear::kernels {

using index_t = std::int32_t;

/// Half-edge h = 3 * face + k is local edge k of the face: it joins local nodes k+1 and k+2.
TEAR_HD inline void half_edge_nodes(const index_t* face_nodes, index_t f, int k, index_t& lo, index_t& hi) {
  const index_t p = face_nodes[3 * f + (k + 1) % 3], q = face_nodes[3 * f + (k + 2) % 3];
  lo = p < q ? p : q;
  hi = p < q ? q : p;
}

/// Calls visit(hi, f) for each half-edge (n, hi) of node n's faces whose lower end is n, faces
/// ascending (a face repeating n visited once), local edges in order; stops when visit returns false.
template <class Visit>
TEAR_HD inline void for_each_lower_half_edge(const index_t* face_nodes, const index_t* node_face_offset,
                                             const index_t* node_faces, index_t n, Visit visit) {
  for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1]; ++i) {
    const index_t f = node_faces[i];
    if (i > node_face_offset[n] && node_faces[i - 1] == f) continue;  // a face repeating n, seen
    for (int k = 0; k < 3; ++k) {
      index_t lo, hi;
      half_edge_nodes(face_nodes, f, k, lo, hi);
      if (lo == n && !visit(hi, f)) return;
    }
  }
}

/// The smallest higher end greater than `after` of node n's edges whose lower end is n; -1 when
/// there is none.
TEAR_HD inline index_t next_edge_end(const index_t* face_nodes, const index_t* node_face_offset,
                                     const index_t* node_faces, index_t n, index_t after) {
  index_t best = -1;
  for_each_lower_half_edge(face_nodes, node_face_offset, node_faces, n, [&](index_t hi, index_t) {
    if (hi > after && (best < 0 || hi < best)) best = hi;
    return true;
  });
  return best;
}

/// An edge of a node: its higher end, its number of half-edges and its first two faces (ascending).
struct NodeEdge {
  index_t end = -1, count = 0, face[2] = {-1, -1};
  TEAR_HD void add_face(index_t f) {
    if (count < 2) face[count] = f;
    ++count;
  }
};

/// The edges whose lower node is n, gathered in one pass over its faces, higher ends ascending.
/// Holds up to `capacity` edges; a node with more sets `overflow`, and the caller enumerates them
/// with `next_edge_end` and `edge_to` instead (slower: one pass over the faces per edge).
struct NodeEdgeList {
  static constexpr int capacity = 16;
  int size = 0;
  bool overflow = false;
  NodeEdge edge[capacity];

  TEAR_HD void gather(const index_t* face_nodes, const index_t* node_face_offset, const index_t* node_faces,
                      index_t n) {
    for_each_lower_half_edge(face_nodes, node_face_offset, node_faces, n, [&](index_t hi, index_t f) {
      int j = 0;
      while (j < size && edge[j].end < hi) ++j;
      if (j == size || edge[j].end != hi) {
        if (size == capacity) {
          overflow = true;
          return false;
        }
        for (int m = size; m > j; --m) edge[m] = edge[m - 1];
        edge[j] = NodeEdge{};
        edge[j].end = hi;
        ++size;
      }
      edge[j].add_face(f);
      return true;
    });
  }
};

/// Edge (n, end) of lower node n, gathered by its own pass over n's faces.
TEAR_HD inline NodeEdge edge_to(const index_t* face_nodes, const index_t* node_face_offset, const index_t* node_faces,
                                index_t n, index_t end) {
  NodeEdge e;
  e.end = end;
  for_each_lower_half_edge(face_nodes, node_face_offset, node_faces, n, [&](index_t hi, index_t f) {
    if (hi == end) e.add_face(f);
    return true;
  });
  return e;
}

/// Calls visit(edge) for each edge whose lower node is n, higher ends ascending, when n has at
/// most `Faces` faces and none of them repeats a node (returns false, visiting nothing, when not).
/// Each face holds n once, so it gives the two half-edges from n to its other nodes: at most
/// 2 * Faces keys (higher end, face), all loaded before any is used and sorted by a network in
/// registers. Equal ends are then one edge, its faces ascending: what `NodeEdgeList` gathers by
/// insertion.
template <int Faces, class Visit>
TEAR_HD inline bool for_each_node_edge_in_registers(const index_t* face_nodes, const index_t* node_faces,
                                                    index_t begin, index_t size, index_t n, Visit& visit) {
  constexpr std::uint64_t none = ~std::uint64_t(0);
  std::uint64_t key[2 * Faces];
  bool simple = true;
  TEAR_UNROLL
  for (int i = 0; i < Faces; ++i) {
    key[2 * i] = key[2 * i + 1] = none;
    if (i < size) {
      const index_t f = node_faces[begin + i];
      const index_t a = face_nodes[3 * f], b = face_nodes[3 * f + 1], c = face_nodes[3 * f + 2];
      simple = simple && a != b && b != c && a != c;
      const index_t u = a == n ? b : a, v = a == n ? c : b == n ? c : b;  // the other two nodes
      const std::uint64_t face = static_cast<std::uint32_t>(f);
      if (u > n) key[2 * i] = (static_cast<std::uint64_t>(u) << 32) | face;
      if (v > n) key[2 * i + 1] = (static_cast<std::uint64_t>(v) << 32) | face;
    }
  }
  if (!simple) return false;
  sort_network<2 * Faces>(key);
  NodeEdge edge;
  TEAR_UNROLL
  for (int j = 0; j < 2 * Faces; ++j) {
    if (key[j] == none) continue;
    const index_t end = static_cast<index_t>(key[j] >> 32);
    if (end != edge.end) {
      if (edge.end >= 0) visit(edge);
      edge = NodeEdge{};
      edge.end = end;
    }
    edge.add_face(static_cast<index_t>(key[j] & 0xffffffffu));
  }
  if (edge.end >= 0) visit(edge);
  return true;
}

/// The above for a node of up to `medium_run` faces; false when n has more or one repeats a node.
template <class Visit>
TEAR_HD inline bool for_each_small_node_edge(const index_t* face_nodes, const index_t* node_face_offset,
                                             const index_t* node_faces, index_t n, Visit visit) {
  const index_t begin = node_face_offset[n], size = node_face_offset[n + 1] - begin;
  if (size <= small_run) return for_each_node_edge_in_registers<small_run>(face_nodes, node_faces, begin, size, n, visit);
  if (size <= medium_run)
    return for_each_node_edge_in_registers<medium_run>(face_nodes, node_faces, begin, size, n, visit);
  return false;
}

/// Calls visit(edge) for each edge whose lower node is n, higher ends ascending, from registers
/// (above) or from the one-pass list; false, visiting nothing, when the node has more edges than
/// the list holds.
template <class Visit>
TEAR_HD inline bool for_each_node_edge_in_one_pass(const index_t* face_nodes, const index_t* node_face_offset,
                                                   const index_t* node_faces, index_t n, Visit visit) {
  if (for_each_small_node_edge(face_nodes, node_face_offset, node_faces, n, visit)) return true;
  NodeEdgeList list;
  list.gather(face_nodes, node_face_offset, node_faces, n);
  if (list.overflow) return false;
  for (int j = 0; j < list.size; ++j) visit(list.edge[j]);
  return true;
}

/// Calls visit(edge) for each edge whose lower node is n, higher ends ascending: in one pass
/// (above), or edge by edge when the node has more edges than the list holds (a pass over its
/// faces per edge: a build sorts such a node's half-edges instead, `sort_node_half_edges`).
template <class Visit>
TEAR_HD inline void for_each_node_edge(const index_t* face_nodes, const index_t* node_face_offset,
                                       const index_t* node_faces, index_t n, Visit visit) {
  if (for_each_node_edge_in_one_pass(face_nodes, node_face_offset, node_faces, n, visit)) return;
  for (index_t end = next_edge_end(face_nodes, node_face_offset, node_faces, n, -1); end >= 0;
       end = next_edge_end(face_nodes, node_face_offset, node_faces, n, end))
    visit(edge_to(face_nodes, node_face_offset, node_faces, n, end));
}

}  // namespace tear::kernels
