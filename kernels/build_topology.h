// tear kernels: building edges, edge→faces, face→edges, node→faces and boundary flags.
#pragma once

#include <cstdint>

#include "backend.h"

namespace tear::kernels {

using index_t = std::int32_t;

/// The key of the undirected edge (a, b): low node in the high 32 bits, so keys sort by
/// (low, high).
TEAR_HD inline std::uint64_t edge_key(index_t a, index_t b) {
  const index_t lo = a < b ? a : b, hi = a < b ? b : a;
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(lo)) << 32) | static_cast<std::uint32_t>(hi);
}
TEAR_HD inline index_t edge_key_low(std::uint64_t key) { return static_cast<index_t>(key >> 32); }
TEAR_HD inline index_t edge_key_high(std::uint64_t key) { return static_cast<index_t>(key & 0xffffffffu); }

/// Half-edge h = 3 * face + k is local edge k of the face: it joins local nodes k+1 and k+2.
struct make_half_edge_keys {
  const index_t* face_nodes;
  std::uint64_t* half_key;
  index_t* half_id;
  TEAR_HD void operator()(index_t h) const {
    const index_t f = h / 3, k = h % 3;
    half_key[h] = edge_key(face_nodes[3 * f + (k + 1) % 3], face_nodes[3 * f + (k + 2) % 3]);
    half_id[h] = h;
  }
};

/// 1 where a sorted key starts a new edge.
struct flag_edge_heads {
  const std::uint64_t* sorted_key;
  index_t* head;
  TEAR_HD void operator()(index_t i) const { head[i] = (i == 0 || sorted_key[i] != sorted_key[i - 1]) ? 1 : 0; }
};

/// For each sorted half-edge: its edge is (inclusive scan of heads) - 1. Scatters face_edges and,
/// at each edge's first half-edge, the edge's nodes.
struct write_face_edges {
  const std::uint64_t* sorted_key;
  const index_t* sorted_half;
  const index_t* head;
  const index_t* edge_of_sorted;  // inclusive scan of head
  index_t* face_edges;
  index_t* edge_nodes;
  index_t* edge_first_half;  // index into the sorted arrays of the edge's first half-edge
  TEAR_HD void operator()(index_t i) const {
    const index_t e = edge_of_sorted[i] - 1;
    face_edges[sorted_half[i]] = e;
    if (head[i]) {
      edge_nodes[2 * e] = edge_key_low(sorted_key[i]);
      edge_nodes[2 * e + 1] = edge_key_high(sorted_key[i]);
      edge_first_half[e] = i;
    }
  }
};

/// Edge→faces from the sorted half-edges (faces ascending, since the sort is stable).
struct write_edge_faces {
  const index_t* edge_first_half;
  const index_t* sorted_half;
  index_t half_count;
  index_t edge_count;
  index_t* edge_faces;
  index_t* edge_face_count;
  std::uint8_t* edge_boundary;
  TEAR_HD void operator()(index_t e) const {
    const index_t begin = edge_first_half[e];
    const index_t end = e + 1 < edge_count ? edge_first_half[e + 1] : half_count;
    const index_t count = end - begin;
    edge_face_count[e] = count;
    edge_faces[2 * e] = sorted_half[begin] / 3;
    edge_faces[2 * e + 1] = count >= 2 ? sorted_half[begin + 1] / 3 : -1;
    edge_boundary[e] = count == 1 ? 1 : 0;
  }
};

/// Corner c = 3 * face + k: key its node, value its face.
struct make_corner_keys {
  const index_t* face_nodes;
  index_t* corner_node;
  index_t* corner_face;
  TEAR_HD void operator()(index_t c) const {
    corner_node[c] = face_nodes[c];
    corner_face[c] = c / 3;
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
