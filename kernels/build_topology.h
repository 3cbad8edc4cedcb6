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

#include "hd.h"
#include "node_edges.h"
#include "sort_runs.h"

namespace tear::kernels {

using index_t = std::int32_t;

// A counting sort of items by key into a CSR (device_topology.h `build_csr_by_counting`): a
// histogram of the keys (`count_keys`), an exclusive scan into offsets, each item's value put in
// its key's run through the key's cursor (`fill_by_key`: the order within a run depends on
// timing), then each run sorted (`sort_runs`), so runs list their values ascending. `Items` gives
// key(i), a node or −1 for an item that has none, and value(i).

/// Histogram of the items' keys (`tally` zeroed first).
template <class Items>
struct count_keys {
  Items items;
  index_t* tally;
  TEAR_HD void operator()(index_t i) const {
    const index_t k = items.key(i);
    if (k >= 0) atomic_fetch_add(&tally[k], 1);
  }
};

/// Puts each item's value in its key's run, at a place taken from the key's cursor (the run's
/// start, copied from the offsets).
template <class Items>
struct fill_by_key {
  Items items;
  index_t* cursor;
  index_t* values;
  TEAR_HD void operator()(index_t i) const {
    const index_t k = items.key(i);
    if (k >= 0) values[atomic_fetch_add(&cursor[k], 1)] = items.value(i);
  }
};

/// The corners of the faces keyed by their node, valued by their face: node→faces.
struct FaceCorners {
  const index_t* face_nodes;
  TEAR_HD index_t key(index_t c) const { return face_nodes[c]; }
  TEAR_HD index_t value(index_t c) const { return c / 3; }
};

// A node of many edges (the first corner of a fanned polygon of 10M corners, a node of 300,000
// copies of one triangle) would cost a pass over its faces per edge: quadratic. A build counts the
// lower half-edges of the nodes whose edges do not fit the one-pass list, and when there are any,
// sorts the half-edges of every node of more than `medium_run` faces as 64-bit keys (higher end,
// face) in a slice of its own, and counts and writes those nodes' edges from the sorted keys.

/// The half-edges of node n's faces whose lower end is n: the number `for_each_lower_half_edge`
/// visits.
TEAR_HD inline index_t count_lower_half_edges(const index_t* face_nodes, const index_t* node_face_offset,
                                              const index_t* node_faces, index_t n) {
  index_t count = 0;
  for_each_lower_half_edge(face_nodes, node_face_offset, node_faces, n, [&](index_t, index_t) {
    ++count;
    return true;
  });
  return count;
}

/// Calls visit(edge) for each edge of `keys` [count], node n's lower half-edges as (higher end << 32
/// | face), sorted: the edges `for_each_node_edge` visits, in its order.
template <class Visit>
TEAR_HD inline void for_each_sorted_edge(const std::uint64_t* keys, index_t count, Visit visit) {
  NodeEdge edge;
  for (index_t i = 0; i < count; ++i) {
    const index_t end = static_cast<index_t>(keys[i] >> 32);
    if (end != edge.end) {
      if (edge.end >= 0) visit(edge);
      edge = NodeEdge{};
      edge.end = end;
    }
    edge.add_face(static_cast<index_t>(keys[i] & 0xffffffffu));
  }
  if (edge.end >= 0) visit(edge);
}

/// Whether node n's edges are taken from sorted keys when a build sorts any.
TEAR_HD inline bool sorts_half_edges(const index_t* node_face_offset, index_t n) {
  return node_face_offset[n + 1] - node_face_offset[n] > medium_run;
}

/// Room for the keys of node n (its lower half-edges when `sorts_half_edges`, else none); run over
/// one index more than the nodes, whose thread writes the 0 the scan turns into the total.
struct count_half_edge_keys {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  index_t node_count;
  index_t* key_count;
  TEAR_HD void operator()(index_t n) const {
    key_count[n] = n < node_count && sorts_half_edges(node_face_offset, n)
                       ? count_lower_half_edges(face_nodes, node_face_offset, node_faces, n)
                       : 0;
  }
};

/// Node n's lower half-edges as keys in its slice [key_offset[n], key_offset[n + 1]), sorted, and its
/// edge count from them. Run over one index more than the nodes: that thread clears the count of
/// half-edges left uncounted (`count_node_edges`).
struct sort_node_half_edges {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  const index_t* key_offset;
  std::uint64_t* keys;
  index_t node_count;
  index_t* node_edge_count;
  TEAR_HD void operator()(index_t n) const {
    if (n == node_count) {
      node_edge_count[n] = 0;
      return;
    }
    const index_t begin = key_offset[n], size = key_offset[n + 1] - begin;
    if (size == 0) return;
    std::uint64_t* key = keys + begin;
    index_t i = 0;
    for_each_lower_half_edge(face_nodes, node_face_offset, node_faces, n, [&](index_t hi, index_t f) {
      key[i++] = (static_cast<std::uint64_t>(hi) << 32) | static_cast<std::uint32_t>(f);
      return true;
    });
    heap_sort(key, size);
    index_t count = 0;
    for_each_sorted_edge(key, size, [&](const NodeEdge&) { ++count; });
    node_edge_count[n] = count;
  }
};

/// Number of edges whose lower node is n: the distinct higher ends of its half-edges. Run over two
/// indices more than the nodes. A node whose edges do not fit the one-pass list counts 0 here and
/// adds its lower half-edges to node_edge_count[node_count], which must be 0 before (so that a
/// build knows to sort them, `sort_node_half_edges`); the last thread writes the 0 after it. An
/// exclusive scan of node_count + 2 counts then ends in the edge count and, one further, the edge
/// count plus those half-edges.
struct count_node_edges {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  index_t* node_edge_count;
  index_t node_count;
  TEAR_HD void operator()(index_t n) const {
    if (n >= node_count) {
      if (n == node_count + 1) node_edge_count[n] = 0;
      return;
    }
    index_t count = 0;
    if (!for_each_node_edge_in_one_pass(face_nodes, node_face_offset, node_faces, n,
                                        [&](const NodeEdge&) { ++count; })) {
      atomic_fetch_add(&node_edge_count[node_count],
                       count_lower_half_edges(face_nodes, node_face_offset, node_faces, n));
      count = 0;
    }
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
  TEAR_HD void write(index_t e, index_t n, const NodeEdge& edge) const {
    edge_nodes[2 * e] = n;
    edge_nodes[2 * e + 1] = edge.end;
    edge_face_count[e] = edge.count;
    edge_faces[2 * e] = edge.face[0];
    edge_faces[2 * e + 1] = edge.face[1];
    edge_boundary[e] = edge.count == 1 ? 1 : 0;
  }

  /// The sorted half-edges of `sort_node_half_edges`, when a build made them (else null).
  const index_t* key_offset = nullptr;
  const std::uint64_t* keys = nullptr;

  TEAR_HD void operator()(index_t n) const {
    index_t e = node_edge_offset[n];
    auto visit = [&](const NodeEdge& edge) { write(e++, n, edge); };
    if (keys && key_offset[n + 1] > key_offset[n])
      for_each_sorted_edge(keys + key_offset[n], key_offset[n + 1] - key_offset[n], visit);
    else
      for_each_node_edge(face_nodes, node_face_offset, node_faces, n, visit);
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


// Patching the topology after a cut (device_topology.h `patch_device_topology`) instead of building
// it again: the same arrays as a build, but each node whose faces the cut left alone keeps its
// node→faces run and its edges, copied with the faces renumbered, and only the others are counted
// and written as a build would. The new faces are numbered through the cut's scan, so an old face
// f that stays one face becomes face face_offset[f] (ascending in f: runs stay sorted).

/// Marks old face f touched when the cut splits it or gives it another node, and marks touched
/// every node of it, old or new (a node's face set changes only through touched faces). Several
/// threads may store the same 1 into a node's flag, nothing else.
struct mark_cut_faces {
  const index_t* old_face_nodes;
  const index_t* face_nodes;
  const index_t* face_offset;  ///< [old face count + 1] first new face of each old face
  std::uint8_t* face_touched;
  std::uint8_t* node_touched;
  TEAR_HD void operator()(index_t f) const {
    const index_t g = face_offset[f], count = face_offset[f + 1] - g;
    bool touched = count != 1;
    for (int k = 0; k < 3 && !touched; ++k) touched = face_nodes[3 * g + k] != old_face_nodes[3 * f + k];
    face_touched[f] = touched ? 1 : 0;
    if (!touched) return;
    for (int k = 0; k < 3; ++k) node_touched[old_face_nodes[3 * f + k]] = 1;
    for (index_t c = 3 * g; c < 3 * (g + count); ++c) node_touched[face_nodes[c]] = 1;
  }
};

/// Node n's flag before the marks: nodes the cut made are touched, old ones not yet.
struct clear_node_marks {
  index_t old_node_count;
  std::uint8_t* node_touched;
  TEAR_HD void operator()(index_t n) const { node_touched[n] = n >= old_node_count ? 1 : 0; }
};

/// The old arrays a patch reads, and the map of old faces to new.
struct OldTopology {
  index_t node_count;
  const index_t* node_face_offset;
  const index_t* node_faces;
  const index_t* node_edge_offset;
  const index_t* edge_nodes;
  const index_t* edge_faces;
  const index_t* edge_face_count;
  const std::uint8_t* edge_boundary;
  const std::uint8_t* node_boundary;
  const index_t* face_offset;  ///< [old face count + 1] first new face of each old face
  const std::uint8_t* face_touched;
  const std::uint8_t* node_touched;
  TEAR_HD bool kept(index_t n) const { return n < node_count && !node_touched[n]; }
  TEAR_HD index_t new_face(index_t f) const { return f < 0 ? f : face_offset[f]; }
};

/// Node n's corner count in the new faces, from its old run: all of it when n is kept, its untouched
/// faces when n is touched (`add_touched_corners` adds the touched faces' new corners). Run over
/// one index more than the nodes, like `count_node_edges`.
struct count_patched_corners {
  OldTopology old;
  index_t node_count;
  index_t* tally;
  TEAR_HD void operator()(index_t n) const {
    index_t count = 0;
    if (n < old.node_count) {
      const index_t begin = old.node_face_offset[n], end = old.node_face_offset[n + 1];
      if (!old.node_touched[n])
        count = end - begin;
      else
        for (index_t i = begin; i < end; ++i) count += old.face_touched[old.node_faces[i]] ? 0 : 1;
    }
    tally[n] = n < node_count ? count : 0;
  }
};

/// Adds the corners of the new faces of touched old face f to their nodes' counts.
struct add_touched_corners {
  const index_t* face_nodes;
  const index_t* face_offset;
  const std::uint8_t* face_touched;
  index_t* tally;
  TEAR_HD void operator()(index_t f) const {
    if (!face_touched[f]) return;
    for (index_t c = 3 * face_offset[f]; c < 3 * face_offset[f + 1]; ++c) atomic_fetch_add(&tally[face_nodes[c]], 1);
  }
};

/// Node n's run: its untouched old faces renumbered, in order; leaves in cursor[n] where the
/// touched faces' corners go (`fill_touched_corners`).
struct fill_patched_runs {
  OldTopology old;
  const index_t* node_face_offset;
  index_t* node_faces;
  index_t* cursor;
  TEAR_HD void operator()(index_t n) const {
    index_t at = node_face_offset[n];
    if (n < old.node_count) {
      const bool kept = !old.node_touched[n];
      for (index_t i = old.node_face_offset[n]; i < old.node_face_offset[n + 1]; ++i) {
        const index_t f = old.node_faces[i];
        if (kept || !old.face_touched[f]) node_faces[at++] = old.face_offset[f];
      }
    }
    cursor[n] = at;
  }
};

/// Puts the new faces of touched old face f into their nodes' runs (order by timing; sorted after).
struct fill_touched_corners {
  const index_t* face_nodes;
  const index_t* face_offset;
  const std::uint8_t* face_touched;
  index_t* cursor;
  index_t* node_faces;
  TEAR_HD void operator()(index_t f) const {
    if (!face_touched[f]) return;
    for (index_t c = 3 * face_offset[f]; c < 3 * face_offset[f + 1]; ++c)
      node_faces[atomic_fetch_add(&cursor[face_nodes[c]], 1)] = c / 3;
  }
};

/// Node n's number of edges: a kept node's old count; a touched node's run sorted (a kept node's is
/// in order already), then its edges counted as a build counts them.
struct count_patched_edges {
  OldTopology old;
  count_node_edges count;
  sort_runs sort;
  TEAR_HD void operator()(index_t n) const {
    if (n < count.node_count && old.kept(n)) {
      count.node_edge_count[n] = old.node_edge_offset[n + 1] - old.node_edge_offset[n];
      return;
    }
    if (n < count.node_count) sort(n);
    count(n);  // the ends, n >= node_count, as a build's
  }
};

/// Node n's edges: a kept node's old ones with their faces renumbered (same ends, counts and
/// flags), a touched node's written as a build writes them.
struct write_patched_edges {
  OldTopology old;
  write_node_edges write;
  TEAR_HD void operator()(index_t n) const {
    if (!old.kept(n)) {
      write(n);
      return;
    }
    // A batch of edges at a time, all its loads issued before its stores (a store may alias a later
    // load, so one edge after the other would wait for each edge's loads in turn): measured 9 to 17 %
    // off the patch at 1M to 4M faces on an H100 (docs/BENCHMARKS.md).
    constexpr int batch = 8;
    const index_t begin = old.node_edge_offset[n], end = old.node_edge_offset[n + 1];
    index_t e = write.node_edge_offset[n];
    for (index_t o = begin; o < end; o += batch, e += batch) {
      const int size = end - o < batch ? static_cast<int>(end - o) : batch;
      index_t ends[2 * batch], faces[2 * batch], counts[batch];
      std::uint8_t boundary[batch];
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
      for (int j = 0; j < batch; ++j)
        if (j < size) {
          ends[2 * j] = old.edge_nodes[2 * (o + j)];
          ends[2 * j + 1] = old.edge_nodes[2 * (o + j) + 1];
          faces[2 * j] = old.edge_faces[2 * (o + j)];
          faces[2 * j + 1] = old.edge_faces[2 * (o + j) + 1];
          counts[j] = old.edge_face_count[o + j];
          boundary[j] = old.edge_boundary[o + j];
        }
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
      for (int j = 0; j < 2 * batch; ++j)
        if (j < 2 * size) faces[j] = old.new_face(faces[j]);
      for (int j = 0; j < size; ++j) {
        write.edge_nodes[2 * (e + j)] = ends[2 * j];
        write.edge_nodes[2 * (e + j) + 1] = ends[2 * j + 1];
        write.edge_faces[2 * (e + j)] = faces[2 * j];
        write.edge_faces[2 * (e + j) + 1] = faces[2 * j + 1];
        write.edge_face_count[e + j] = counts[j];
        write.edge_boundary[e + j] = boundary[j];
      }
    }
  }
};

/// Node n's boundary flag: a kept node's old flag (its edges and their faces are as they were),
/// a touched node's found as a build finds it.
struct flag_patched_boundary {
  OldTopology old;
  flag_boundary_nodes flag;
  TEAR_HD void operator()(index_t n) const {
    if (old.kept(n))
      flag.node_boundary[n] = old.node_boundary[n];
    else
      flag(n);
  }
};

}  // namespace tear::kernels
