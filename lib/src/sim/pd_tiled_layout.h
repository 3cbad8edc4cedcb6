// tear: the tiled launch's layout of a solver's model (sim/pd_launch_tiled.h): the places (the
// nodes in Morton order of their rest positions), each tile's packed edge records and halo, and
// each place's slots, built on the backend from the model and its node→slot CSR.
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include <thrust/binary_search.h>
#include <thrust/for_each.h>
#include <thrust/functional.h>
#include <thrust/gather.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/transform_iterator.h>
#include <thrust/scan.h>
#include <thrust/scatter.h>
#include <thrust/sequence.h>
#include <thrust/sort.h>
#include <thrust/transform.h>
#include <thrust/transform_reduce.h>
#include <thrust/unique.h>

#include "backend/backend.h"
#include "pd_model.h"
#include "pd_step.h"

namespace tear::backend {

inline constexpr int tiled_block = 256;  ///< nodes per tile: threads per block
/// Blocks of the tiled kernel a multiprocessor should hold (registers: at most 85 a thread).
/// Measured on an H200 (ms per 100 iterations at 2M / 512K / 128K / 64K faces): 256 nodes a tile
/// and 3 blocks 12.31 / 3.78 / 1.07 / 0.84; 4 blocks 12.19 / 3.77 / 1.17 / 0.92; 2 blocks
/// 15.73 / 4.40 / 1.07 / 0.86; 128 nodes and 8 blocks 14.11 / 4.23 / 1.21 / 1.00; 512 nodes and
/// 2 blocks 12.92 / 3.80 / 1.14 / 1.05.
inline constexpr int tiled_blocks_per_sm = 3;
inline constexpr std::uint16_t tiled_no_node = 0xFFFF;  ///< an edge record's node slot left unused
inline constexpr index_t tiled_most_edges = 8192;       ///< edge records a tile may have (13 bits of a slot)

/// What the tiled kernel reads, in the solver's tile order ("places"): tile t holds places
/// [t·tile_nodes, (t + 1)·tile_nodes). Its edge records are an edge's spring and hinge, with the
/// nodes as indices into the tile's copy of the iterate: its own places first, then its halo.
struct TiledModel {
  index_t node_count;
  index_t tile_nodes;              ///< places per tile: the block's threads
  const index_t* edge_offset;      ///< [tiles + 1]: each tile's run of edge records
  const std::uint16_t* edge_node;  ///< [records * 4]: a, b, then the hinge's other two (or none)
  const float* spring;             ///< [records * 2]: weight, rest length (weight 0: no spring)
  const float* hinge_coef;         ///< [records * 4]
  const float* hinge;              ///< [records * 2]: weight, rest value
  const index_t* halo_offset;      ///< [tiles + 1]
  const index_t* halo_place;       ///< the places a tile reads besides its own, ascending
  const index_t* slot_offset;      ///< [node_count + 1], by place
  /// A place's slots in slot order, each (record << 3) | (hinge << 2) | the node's slot in it.
  const std::uint16_t* slot;
};

/// The order of the places: node of place i (`place_node`), place of node n (`node_place`).
struct MortonKey {
  const float* node_rest;
  float lo[3], scale[3];
  TEAR_HD static std::uint64_t spread(std::uint64_t v) {  // 21 bits to every third of 63
    v &= 0x1FFFFF;
    v = (v | v << 32) & 0x1F00000000FFFFULL;
    v = (v | v << 16) & 0x1F0000FF0000FFULL;
    v = (v | v << 8) & 0x100F00F00F00F00FULL;
    v = (v | v << 4) & 0x10C30C30C30C30C3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  }
  TEAR_HD std::uint64_t operator()(index_t n) const {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      float q = (node_rest[3 * n + a] - lo[a]) * scale[a];
      q = q > 0.0f ? (q < 2097151.0f ? q : 2097151.0f) : 0.0f;  // NaN to 0
      key |= spread(static_cast<std::uint64_t>(q)) << a;
    }
    return key;
  }
};

/// The rest shape's box, as a reduction.
struct RestBox {
  float lo[3], hi[3];
};
struct rest_box_of {
  const float* node_rest;
  TEAR_HD RestBox operator()(index_t n) const {
    RestBox b;
    for (int a = 0; a < 3; ++a) b.lo[a] = b.hi[a] = node_rest[3 * n + a];
    return b;
  }
};
struct merge_rest_box {
  TEAR_HD RestBox operator()(const RestBox& x, const RestBox& y) const {
    RestBox b;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = y.lo[a] < x.lo[a] ? y.lo[a] : x.lo[a];
      b.hi[a] = y.hi[a] > x.hi[a] ? y.hi[a] : x.hi[a];
    }
    return b;
  }
};

/// Node j of edge e's constraints: the hinge's nodes where it has one, else the spring's two.
TEAR_HD inline index_t tiled_edge_node(const kernels::PdConstraints& c, index_t e, int j) {
  const index_t h = c.hinge_nodes[4 * e + j];
  if (h >= 0 || j >= 2) return h;
  return c.spring_nodes[2 * e + j];
}

/// The distinct tiles whose nodes edge e's constraints act on (at most four), in the order of its
/// nodes.
TEAR_HD inline int tiled_edge_tiles_of(const kernels::PdConstraints& c, const index_t* node_place, index_t tile_nodes,
                                       index_t e, index_t (&tile)[4]) {
  int count = 0;
  for (int j = 0; j < 4; ++j) {
    const index_t n = tiled_edge_node(c, e, j);
    if (n < 0) continue;
    const index_t t = node_place[n] / tile_nodes;
    bool seen = false;
    for (int i = 0; i < count; ++i) seen = seen || tile[i] == t;
    if (!seen) tile[count++] = t;
  }
  return count;
}
struct tiled_count_edge_tiles {
  kernels::PdConstraints c;
  const index_t* node_place;
  index_t tile_nodes;
  index_t* count;  // [edges + 1]
  TEAR_HD void operator()(index_t e) const {
    index_t tile[4];
    count[e] = tiled_edge_tiles_of(c, node_place, tile_nodes, e, tile);
  }
};
/// (tile, edge) for each tile edge e's constraints act on, at its offset.
struct tiled_edge_tiles {
  kernels::PdConstraints c;
  const index_t* node_place;
  index_t tile_nodes;
  const index_t* offset;
  std::uint64_t* key;
  TEAR_HD void operator()(index_t e) const {
    index_t tile[4];
    const int count = tiled_edge_tiles_of(c, node_place, tile_nodes, e, tile);
    for (int i = 0; i < count; ++i) key[offset[e] + i] = (std::uint64_t(tile[i]) << 32) | static_cast<std::uint32_t>(e);
  }
};

/// (tile, place) for each node of record r that lies outside the record's tile, written from
/// offset[r]; with no `key`, their number counted into offset[r].
struct tiled_halo_places {
  kernels::PdConstraints c;
  const index_t* node_place;
  index_t tile_nodes;
  const std::uint64_t* record;  // (tile, edge)
  index_t* offset;              // [records + 1]
  std::uint64_t* key;
  TEAR_HD void operator()(index_t r) const {
    const index_t tile = static_cast<index_t>(record[r] >> 32), e = static_cast<index_t>(record[r] & 0xFFFFFFFFu);
    index_t count = 0;
    for (int j = 0; j < 4; ++j) {
      const index_t n = tiled_edge_node(c, e, j);
      const index_t p = n < 0 ? -1 : node_place[n];
      if (p < 0 || p / tile_nodes == tile) continue;
      if (key) key[offset[r] + count] = (std::uint64_t(tile) << 32) | static_cast<std::uint32_t>(p);
      ++count;
    }
    if (!key) offset[r] = count;
  }
};

/// Record r's packed copy of its edge's constraints, its nodes as indices into its tile's copy.
struct tiled_write_records {
  kernels::PdConstraints c;
  const index_t* node_place;
  index_t tile_nodes;
  const std::uint64_t* record;
  const index_t* halo_offset;
  const index_t* halo_place;
  std::uint16_t* edge_node;
  float* spring;
  float* hinge_coef;
  float* hinge;
  TEAR_HD void operator()(index_t r) const {
    const index_t tile = static_cast<index_t>(record[r] >> 32), e = static_cast<index_t>(record[r] & 0xFFFFFFFFu);
    const index_t* halo_begin = halo_place + halo_offset[tile];
    const index_t* halo_end = halo_place + halo_offset[tile + 1];
    for (int j = 0; j < 4; ++j) {
      const index_t n = tiled_edge_node(c, e, j);
      std::uint16_t local = tiled_no_node;
      if (n >= 0) {
        const index_t p = node_place[n];
        if (p / tile_nodes == tile) {
          local = static_cast<std::uint16_t>(p - tile * tile_nodes);
        } else {
          const index_t* lo = halo_begin;  // the place's index in the tile's halo
          index_t count = static_cast<index_t>(halo_end - halo_begin);
          while (count > 0) {
            const index_t step = count / 2;
            if (lo[step] < p) {
              lo += step + 1;
              count -= step + 1;
            } else {
              count = step;
            }
          }
          local = static_cast<std::uint16_t>(tile_nodes + (lo - halo_begin));
        }
      }
      edge_node[4 * r + j] = local;
      hinge_coef[4 * r + j] = c.hinge_coef[4 * e + j];
    }
    spring[2 * r] = c.spring_weight[e];
    spring[2 * r + 1] = c.spring_rest[e];
    hinge[2 * r] = c.hinge_weight[e];
    hinge[2 * r + 1] = c.hinge_rest[e];
  }
};

/// The number of slots of the node at place p (from the model's node→slot CSR).
struct tiled_place_slot_count {
  const index_t* place_node;
  const index_t* node_slot_offset;
  TEAR_HD index_t operator()(index_t p) const {
    const index_t n = place_node[p];
    return node_slot_offset[n + 1] - node_slot_offset[n];
  }
};
/// Place p's slots, from its node's run of the CSR (in slot order), each as
/// (record in the tile << 3) | (hinge << 2) | the node's slot in the constraint.
struct tiled_write_slots {
  index_t edge_count;
  index_t tile_nodes;
  const index_t* place_node;
  const index_t* node_slot_offset;
  const index_t* node_slots;
  const std::uint64_t* record;  // sorted (tile, edge)
  const index_t* edge_offset;
  const index_t* slot_offset;
  std::uint16_t* slot;
  TEAR_HD void operator()(index_t p) const {
    const index_t n = place_node[p], tile = p / tile_nodes;
    const index_t first = edge_offset[tile], last = edge_offset[tile + 1];
    index_t out = slot_offset[p];
    for (index_t i = node_slot_offset[n]; i < node_slot_offset[n + 1]; ++i) {
      const index_t s = node_slots[i], spring_slots = 2 * edge_count;
      const bool is_hinge = s >= spring_slots;
      const index_t e = is_hinge ? (s - spring_slots) / 4 : s / 2;
      const index_t j = is_hinge ? (s - spring_slots) % 4 : s % 2;
      const std::uint64_t want = (std::uint64_t(tile) << 32) | static_cast<std::uint32_t>(e);
      index_t lo = first, count = last - first;  // the edge's record in the tile
      while (count > 0) {
        const index_t step = count / 2;
        if (record[lo + step] < want) {
          lo += step + 1;
          count -= step + 1;
        } else {
          count = step;
        }
      }
      slot[out++] = static_cast<std::uint16_t>(((lo - first) << 3) | (index_t(is_hinge) << 2) | j);
    }
  }
};
/// The first key at or after (i << shift), for a vector of lower bounds.
struct tiled_key_of {
  int shift;
  TEAR_HD std::uint64_t operator()(index_t i) const { return std::uint64_t(i) << shift; }
};
struct tiled_run_length {
  const index_t* offset;
  TEAR_HD index_t operator()(index_t t) const { return offset[t + 1] - offset[t]; }
};

/// The tiled layout of a solver's model on `System`: built from the model's constraints
/// (`build`), held beside them. On the CPU it is never built.
template <class System>
struct TiledLayout {
  template <class T>
  using vec = vector<System, T>;
  index_t node_count = 0, tile_nodes = tiled_block, tiles = 0, records = 0, halo = 0, slots = 0;
  index_t most_records = 0, most_halo = 0;  // in one tile
  vec<index_t> place_node, node_place;
  vec<float> mass, diag;
  vec<std::uint8_t> pinned;
  vec<index_t> edge_offset, halo_offset, halo_place, slot_offset;
  vec<std::uint16_t> edge_node, slot;
  vec<float> spring, hinge_coef, hinge;
  vec<std::uint64_t> record_key;  // (tile, edge) of each record, sorted: from `plan` to `write_slots`

  /// Shared memory a block takes: each record's hinge coefficients and two forces, and the copy of
  /// the iterate.
  std::size_t shared_bytes() const {
    return static_cast<std::size_t>(most_records) * (4 * sizeof(float) + 2 * sizeof(kernels::Vec3f)) +
           static_cast<std::size_t>(tile_nodes + most_halo) * sizeof(kernels::Vec3f);
  }

  /// Reads of an iteration, bytes: each tile's copy of the iterate and halo list, its records, each
  /// place's slots and offset, and its prediction, previous iterate, mass, diagonal and pin, and
  /// the next iterate written.
  std::size_t bytes_per_iteration() const {
    const std::size_t n = static_cast<std::size_t>(node_count), h = static_cast<std::size_t>(halo),
                      r = static_cast<std::size_t>(records), s = static_cast<std::size_t>(slots);
    return (n + h) * 3 * sizeof(float) + h * sizeof(index_t) + r * (4 * sizeof(std::uint16_t) + 8 * sizeof(float)) +
           s * sizeof(std::uint16_t) + n * (sizeof(index_t) + 3 * 3 * sizeof(float) + 2 * sizeof(float) + 1);
  }

  TiledModel model() const {
    return {node_count,
            tile_nodes,
            raw<index_t>(edge_offset),
            raw<std::uint16_t>(edge_node),
            raw<float>(spring),
            raw<float>(hinge_coef),
            raw<float>(hinge),
            raw<index_t>(halo_offset),
            raw<index_t>(halo_place),
            raw<index_t>(slot_offset),
            raw<std::uint16_t>(slot)};
  }

  /// The layout is built in three calls, so that the solver can free what each no longer needs
  /// between them (its slot coefficients after `plan`, its per-edge records after
  /// `write_records`, its node→slot CSR after `write_slots`) and the layout's build never holds
  /// more than the graph's model did.
  ///
  /// First the places, the records' tiles and the halos of a model of `nodes` nodes; false where a
  /// tile would need more records or halo than the packed indices hold (then the solver runs
  /// another way and nothing of the model has been freed).
  bool plan(const kernels::PdConstraints& c, index_t nodes, const float* node_rest) {
    const auto policy = Traits<System>::policy();
    const thrust::counting_iterator<index_t> zero(0);
    node_count = nodes;
    tiles = (nodes + tile_nodes - 1) / tile_nodes;
    const index_t edges = c.edge_count;
    if (nodes <= 0 || edges <= 0) return false;

    // Places: the nodes sorted by the Morton code of their rest position (ties by index).
    RestBox empty;
    for (int a = 0; a < 3; ++a) {
      empty.lo[a] = std::numeric_limits<float>::max();
      empty.hi[a] = -std::numeric_limits<float>::max();
    }
    const RestBox box =
        thrust::transform_reduce(policy, zero, zero + nodes, rest_box_of{node_rest}, empty, merge_rest_box{});
    MortonKey morton{node_rest, {}, {}};
    float extent = 0.0f;
    for (int a = 0; a < 3; ++a) extent = box.hi[a] - box.lo[a] > extent ? box.hi[a] - box.lo[a] : extent;
    for (int a = 0; a < 3; ++a) {
      morton.lo[a] = box.lo[a];
      morton.scale[a] = extent > 0.0f ? 2097151.0f / extent : 0.0f;  // one scale: cells stay square
    }
    resize_for_overwrite(place_node, static_cast<std::size_t>(nodes));
    {
      vec<std::uint64_t> code(static_cast<std::size_t>(nodes));
      thrust::transform(policy, zero, zero + nodes, code.begin(), morton);
      thrust::sequence(policy, place_node.begin(), place_node.end());
      thrust::stable_sort_by_key(policy, code.begin(), code.end(), place_node.begin());
    }
    resize_for_overwrite(node_place, static_cast<std::size_t>(nodes));
    thrust::scatter(policy, zero, zero + nodes, place_node.begin(), node_place.begin());
    const index_t* place_of = raw<index_t>(node_place);

    // Records: (tile, edge) for every tile an edge's constraints act on, sorted.
    {
      vec<index_t> offset(static_cast<std::size_t>(edges) + 1);
      thrust::for_each(policy, zero, zero + edges,
                       tiled_count_edge_tiles{c, place_of, tile_nodes, raw<index_t>(offset)});
      thrust::exclusive_scan(policy, offset.begin(), offset.end(), offset.begin());
      records = offset[edges];
      resize_for_overwrite(record_key, static_cast<std::size_t>(records));
      thrust::for_each(policy, zero, zero + edges,
                       tiled_edge_tiles{c, place_of, tile_nodes, raw<index_t>(offset), raw<std::uint64_t>(record_key)});
    }
    thrust::sort(policy, record_key.begin(), record_key.end());
    resize_for_overwrite(edge_offset, static_cast<std::size_t>(tiles) + 1);
    thrust::lower_bound(policy, record_key.begin(), record_key.end(),
                        thrust::make_transform_iterator(zero, tiled_key_of{32}),
                        thrust::make_transform_iterator(zero + tiles + 1, tiled_key_of{32}), edge_offset.begin());
    most_records = thrust::transform_reduce(policy, zero, zero + tiles, tiled_run_length{raw<index_t>(edge_offset)},
                                            index_t(0), thrust::maximum<index_t>());
    if (most_records > tiled_most_edges) return false;

    // Halos: the places outside a tile that its records read.
    {
      vec<std::uint64_t> key;
      {
        vec<index_t> offset(static_cast<std::size_t>(records) + 1);
        tiled_halo_places places{c,      place_of, tile_nodes, raw<std::uint64_t>(record_key), raw<index_t>(offset),
                                 nullptr};
        thrust::for_each(policy, zero, zero + records, places);
        thrust::exclusive_scan(policy, offset.begin(), offset.end(), offset.begin());
        key.resize(static_cast<std::size_t>(offset[records]));
        places.key = raw<std::uint64_t>(key);
        thrust::for_each(policy, zero, zero + records, places);
      }
      thrust::sort(policy, key.begin(), key.end());
      halo = static_cast<index_t>(thrust::unique(policy, key.begin(), key.end()) - key.begin());
      resize_for_overwrite(halo_offset, static_cast<std::size_t>(tiles) + 1);
      thrust::lower_bound(policy, key.begin(), key.begin() + halo,
                          thrust::make_transform_iterator(zero, tiled_key_of{32}),
                          thrust::make_transform_iterator(zero + tiles + 1, tiled_key_of{32}), halo_offset.begin());
      resize_for_overwrite(halo_place, static_cast<std::size_t>(halo));
      thrust::transform(policy, key.begin(), key.begin() + halo, halo_place.begin(), low_place{});
    }
    most_halo = thrust::transform_reduce(policy, zero, zero + tiles, tiled_run_length{raw<index_t>(halo_offset)},
                                         index_t(0), thrust::maximum<index_t>());
    return tile_nodes + most_halo < tiled_no_node;
  }

  /// Then each record's packed copy of its edge's constraints (after `plan`).
  void write_records(const kernels::PdConstraints& c) {
    const thrust::counting_iterator<index_t> zero(0);
    resize_for_overwrite(edge_node, 4 * static_cast<std::size_t>(records));
    resize_for_overwrite(hinge_coef, 4 * static_cast<std::size_t>(records));
    resize_for_overwrite(spring, 2 * static_cast<std::size_t>(records));
    resize_for_overwrite(hinge, 2 * static_cast<std::size_t>(records));
    thrust::for_each(
        Traits<System>::policy(), zero, zero + records,
        tiled_write_records{c, raw<index_t>(node_place), tile_nodes, raw<std::uint64_t>(record_key),
                            raw<index_t>(halo_offset), raw<index_t>(halo_place), raw<std::uint16_t>(edge_node),
                            raw<float>(spring), raw<float>(hinge_coef), raw<float>(hinge)});
  }

  /// Last each place's slots, in slot order, from the model's node→slot CSR (of a model with
  /// `edge_count` edges), and its node's mass, diagonal and pin (after `write_records`).
  void write_slots(index_t edge_count, const index_t* node_slot_offset, const index_t* node_slots,
                   const float* node_mass, const float* node_diag, const std::uint8_t* node_pinned) {
    const auto policy = Traits<System>::policy();
    const thrust::counting_iterator<index_t> zero(0);
    const index_t nodes = node_count;
    resize_for_overwrite(slot_offset, static_cast<std::size_t>(nodes) + 1);
    thrust::transform(policy, zero, zero + nodes, slot_offset.begin(),
                      tiled_place_slot_count{raw<index_t>(place_node), node_slot_offset});
    thrust::exclusive_scan(policy, slot_offset.begin(), slot_offset.end(), slot_offset.begin());
    slots = slot_offset[nodes];
    resize_for_overwrite(slot, static_cast<std::size_t>(slots));
    thrust::for_each(policy, zero, zero + nodes,
                     tiled_write_slots{edge_count, tile_nodes, raw<index_t>(place_node), node_slot_offset, node_slots,
                                       raw<std::uint64_t>(record_key), raw<index_t>(edge_offset),
                                       raw<index_t>(slot_offset), raw<std::uint16_t>(slot)});
    vec<std::uint64_t>().swap(record_key);
    for (auto* v : {&mass, &diag}) resize_for_overwrite(*v, static_cast<std::size_t>(nodes));
    resize_for_overwrite(pinned, static_cast<std::size_t>(nodes));
    thrust::gather(policy, place_node.begin(), place_node.end(), node_mass, mass.begin());
    thrust::gather(policy, place_node.begin(), place_node.end(), node_diag, diag.begin());
    thrust::gather(policy, place_node.begin(), place_node.end(), node_pinned, pinned.begin());
  }

  struct low_place {
    TEAR_HD index_t operator()(std::uint64_t key) const { return static_cast<index_t>(key & 0xFFFFFFFFu); }
  };
};

}  // namespace tear::backend
