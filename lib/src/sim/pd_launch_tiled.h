// tear: launch mode `tiled`: each iteration one launch in which a block updates a tile of nodes
// from a copy of their neighbourhood in shared memory, for meshes too large for the cooperative
// kernels. Part of the solver's device code, included by sim/pd_solver.inl alone.
//
// The solver's other large-mesh path (`graph`) runs an iteration as two launches: one writes every
// constraint's force to memory, the next reads them back through the node→slot CSR. Here a block
// computes, in shared memory, the forces of every constraint that acts on its tile's nodes (those
// on the tile's border twice, once in each tile they reach) and sums them into its nodes at once:
// no force goes through memory, and the records a block reads are its own, packed, with 16-bit
// node indices into the block's copy of the iterate. Each node still sums its constraints'
// products in slot order with the same arithmetic (`constraint_force_at`, `next_from_held`), so
// the bits are those of every other launch mode.
//
// Tiles are runs of the nodes in the order of a Morton code of their rest positions, kept apart
// from the cloth's own node order: the solver's iterates and its nodes' values are held in that
// order, and a substep's prediction and end map to and from the cloth's.
#pragma once

#include <cstdint>

#include "backend/backend.h"
#include "pd_model.h"
#include "pd_step.h"
#include "sim/pd_tiled_layout.h"

namespace tear::backend {

/// Prediction of place i (node `place_node[i]`), stored by place.
struct tiled_predict {
  kernels::predict_positions predict;
  const index_t* place_node;
  TEAR_HD void operator()(index_t i) const { predict.store(i, predict.predicted(place_node[i])); }
};
/// End of step of node n from its place's last iterate.
struct tiled_finish {
  kernels::finish_step finish;
  const index_t* node_place;
  TEAR_HD void operator()(index_t n) const { finish.finish(n, node_place[n]); }
};

#if TEAR_CUDA_SYSTEM
/// Records a thread of the tiled kernel loads before it computes any of them.
inline constexpr int tiled_batch = 4;
/// Slots a place loads before it sums any of them.
inline constexpr int tiled_batch_slots = 8;

/// A block's shared memory: each record's hinge coefficients, spring force and hinge force, then
/// the copy of the iterate (the tile's places, then its halo from `tile_nodes` on).
struct TiledShared {
  float4* hinge_coef;
  kernels::Vec3f *spring_force, *hinge_force, *pos;
  __device__ TiledShared(unsigned char* bytes, index_t records)
      : hinge_coef(reinterpret_cast<float4*>(bytes)),
        spring_force(reinterpret_cast<kernels::Vec3f*>(hinge_coef + records)),
        hinge_force(spring_force + records),
        pos(hinge_force + records) {}
};

/// The spring and hinge forces of records [first, records) of the tile's run from `record_begin`,
/// every `stride`-th, `tiled_batch` records' loads issued before any is computed
/// (`constraint_force_at` on the block's copy of the iterate, as every launch mode computes them).
__device__ inline void tiled_record_forces(const TiledModel& m, index_t record_begin, index_t records, index_t first,
                                           index_t stride, const TiledShared& sh) {
  const kernels::Vec3f* pos = sh.pos;
  const auto at = [pos](index_t i) { return pos[i]; };
  for (index_t r0 = first; r0 < records; r0 += tiled_batch * stride) {
    ushort4 nodes[tiled_batch];
    float2 spring[tiled_batch], hinge[tiled_batch];
    float4 k[tiled_batch];
#pragma unroll
    for (int b = 0; b < tiled_batch; ++b) {
      const index_t r = r0 + b * stride;
      if (r >= records) continue;
      const index_t g = record_begin + r;
      nodes[b] = reinterpret_cast<const ushort4*>(m.edge_node)[g];
      spring[b] = reinterpret_cast<const float2*>(m.spring)[g];
      k[b] = reinterpret_cast<const float4*>(m.hinge_coef)[g];
      hinge[b] = reinterpret_cast<const float2*>(m.hinge)[g];
    }
#pragma unroll
    for (int b = 0; b < tiled_batch; ++b) {
      const index_t r = r0 + b * stride;
      if (r >= records) continue;
      kernels::ConstraintTerms t;  // the spring, as `constraint_terms` gives it
      t.node[0] = nodes[b].x;
      t.node[1] = nodes[b].y;
      t.node[2] = t.node[3] = -1;
      t.k[0] = 1.0f;
      t.k[1] = -1.0f;
      t.k[2] = t.k[3] = 0.0f;
      t.weight = spring[b].x;
      t.rest = spring[b].y;
      sh.spring_force[r] = kernels::constraint_force_at(t, at);
      if (nodes[b].z == tiled_no_node) continue;
      t.node[2] = nodes[b].z;  // the hinge
      t.node[3] = nodes[b].w;
      t.k[0] = k[b].x;
      t.k[1] = k[b].y;
      t.k[2] = k[b].z;
      t.k[3] = k[b].w;
      t.weight = hinge[b].x;
      t.rest = hinge[b].y;
      sh.hinge_force[r] = kernels::constraint_force_at(t, at);
      sh.hinge_coef[r] = k[b];
    }
  }
}

/// g plus the products of slots [begin, end) of `slot`, in order, `tiled_batch_slots` slots'
/// loads issued before any is summed.
__device__ inline kernels::Vec3f tiled_sum_slots(const std::uint16_t* slot, index_t begin, index_t end,
                                                 const TiledShared& sh, kernels::Vec3f g) {
  using kernels::Vec3f;
  for (index_t i0 = begin; i0 < end; i0 += tiled_batch_slots) {
    unsigned v[tiled_batch_slots];
#pragma unroll
    for (int b = 0; b < tiled_batch_slots; ++b) v[b] = i0 + b < end ? slot[i0 + b] : 0u;
#pragma unroll
    for (int b = 0; b < tiled_batch_slots; ++b) {
      if (i0 + b >= end) break;
      const index_t r = static_cast<index_t>(v[b] >> 3);
      const int j = static_cast<int>(v[b] & 3u);
      float coef;
      Vec3f f;
      if (v[b] & 4u) {
        const float4 k = sh.hinge_coef[r];
        coef = j == 0 ? k.x : j == 1 ? k.y : j == 2 ? k.z : k.w;
        f = sh.hinge_force[r];
      } else {
        coef = j ? -1.0f : 1.0f;
        f = sh.spring_force[r];
      }
      const Vec3f product = coef * f;
      g = g + product;
    }
  }
  return g;
}

/// One iteration over one tile per block. Each thread first loads what its place holds through
/// the iteration (prediction, previous iterate, mass, diagonal, pin, slots' range); the block
/// copies its places' and its halo's iterate into shared memory, computes every record's forces
/// (`tiled_record_forces`), and each place sums its slots' products in slot order into its update
/// (`tiled_sum_slots`, `next_from_held`). `u` reads its nodes' values by place.
__global__ void __launch_bounds__(tiled_block, tiled_blocks_per_sm)
    tiled_iteration_kernel(TiledModel m, kernels::jacobi_chebyshev_update u) {
  using kernels::Vec3f;
  extern __shared__ __align__(16) unsigned char tiled_shared[];
  const index_t tile = static_cast<index_t>(blockIdx.x), first = static_cast<index_t>(threadIdx.x);
  const index_t stride = m.tile_nodes, begin = tile * stride;
  const index_t own = m.node_count - begin < stride ? m.node_count - begin : stride;
  const index_t halo_begin = m.halo_offset[tile], halo = m.halo_offset[tile + 1] - halo_begin;
  const index_t record_begin = m.edge_offset[tile], records = m.edge_offset[tile + 1] - record_begin;
  const bool mine = first < own;
  const index_t p = begin + first;
  Vec3f s{0, 0, 0}, x_prev{0, 0, 0};
  float mass = 0.0f, diag = 0.0f;
  bool pinned = false;
  index_t slot_begin = 0, slot_end = 0;
  if (mine) {
    s = kernels::load3<float>(u.node_pred, p);
    x_prev = kernels::load3<float>(u.node_iter_prev, p);
    mass = u.node_mass[p];
    diag = u.node_diag[p];
    pinned = u.node_pinned[p] != 0;
    slot_begin = m.slot_offset[p];
    slot_end = m.slot_offset[p + 1];
  }
  const TiledShared sh(tiled_shared, records);
  if (mine) sh.pos[first] = kernels::load3<float>(u.node_iter, p);
  for (index_t i = first; i < halo; i += stride)
    sh.pos[stride + i] = kernels::load3<float>(u.node_iter, m.halo_place[halo_begin + i]);
  __syncthreads();
  tiled_record_forces(m, record_begin, records, first, stride, sh);
  __syncthreads();
  if (!mine) return;
  const Vec3f x = sh.pos[first];
  const Vec3f g = tiled_sum_slots(m.slot, slot_begin, slot_end, sh, u.inertial_term_of(mass, x, s));
  kernels::store3(u.node_iter_next, p, u.next_from_held(pinned, diag, x, x_prev, s, g));
}
#endif

}  // namespace tear::backend
