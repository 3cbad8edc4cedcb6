// tear: launch mode `shared`: the whole substep in one cooperative kernel, a block per
// multiprocessor holding its run of nodes and their constraints in shared memory.
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include <cstddef>

#include "sim/pd_launch_cooperative.h"

#if TEAR_CUDA_SYSTEM

namespace tear::backend {

/// Threads per block of the shared-memory substep kernel: one block per multiprocessor.
inline constexpr int shared_block = 1024;

/// A slot as a block of the shared-memory kernel holds it: its constraint's terms and its
/// coefficient.
struct SharedSlot {
  kernels::ConstraintTerms terms;
  float coef;
};
/// A node as that block holds it: its held state and its slots' range in the block's slots.
struct SharedNode {
  HeldNodeState state;
  index_t slot_begin, slot_end;
};

/// Shared memory a block of the shared-memory kernel needs for `slots` slots and `nodes` nodes.
inline std::size_t shared_bytes(long long slots, long long nodes) {
  return static_cast<std::size_t>(slots) * (sizeof(SharedSlot) + sizeof(kernels::Vec3f)) +
         static_cast<std::size_t>(nodes) * sizeof(SharedNode);
}

/// The whole substep in one cooperative kernel, each block holding its run of nodes and their
/// slots in shared memory for the substep (the model does not change within one): a block's nodes
/// are consecutive, so their slots are one run of the CSR. Each iteration computes the products
/// coefficient × force of the block's slots (`constraint_force`, as the local step would), synchronises
/// the block, sums each node's products in slot order into its update (the bits of
/// `jacobi_chebyshev_update`) and synchronises the grid: the only loads from memory an iteration
/// makes are its slots' nodes' positions.
__global__ void __launch_bounds__(shared_block, 1) shared_substep_kernel(SubstepKernels s) {
  using kernels::Vec3f;
  cooperative_groups::grid_group grid = cooperative_groups::this_grid();
  extern __shared__ __align__(16) unsigned char shared_held[];
  const BlockNodes nodes = block_nodes(s.node_count);
  const index_t first = static_cast<index_t>(threadIdx.x), stride = static_cast<index_t>(blockDim.x);
  for (index_t n = nodes.begin + first; n < nodes.end; n += stride) s.predict(n);
  grid.sync();
  Iterates it = s.first_iterates();
  s.iteration(0, it);
  const index_t node_count = nodes.end > nodes.begin ? nodes.end - nodes.begin : 0;
  const index_t slot_base = node_count > 0 ? s.update.node_slot_offset[nodes.begin] : 0;
  const index_t slot_count = node_count > 0 ? s.update.node_slot_offset[nodes.end] - slot_base : 0;
  SharedSlot* slots = reinterpret_cast<SharedSlot*>(shared_held);
  Vec3f* products = reinterpret_cast<Vec3f*>(slots + slot_count);
  SharedNode* held = reinterpret_cast<SharedNode*>(products + slot_count);
  {
    const kernels::jacobi_chebyshev_update& u = s.update;
    for (index_t i = first; i < slot_count; i += stride)
      slots[i] = {
          kernels::constraint_terms(u.constraints, u.constraints.constraint_of_slot(u.node_slots[slot_base + i])),
          u.node_slot_coef[slot_base + i]};
    for (index_t j = first; j < node_count; j += stride) {
      const index_t n = nodes.begin + j;
      held[j] = {HeldNodeState::load(u, n), u.node_slot_offset[n] - slot_base, u.node_slot_offset[n + 1] - slot_base};
    }
  }
  __syncthreads();
  for (int k = 0; k < s.iterations; ++k) {
    s.iteration(k, it);
    const kernels::jacobi_chebyshev_update& u = s.update;
    for (index_t i = first; i < slot_count; i += stride) {
      // A node's two slots in a membrane are neighbours in its run (column 0, then 1): column 0's
      // thread computes both from one projection.
      const int column = kernels::membrane_column(slots[i].terms);
      if (column == 1) continue;
      if (column == 0) {
        Vec3f f0, f1;
        kernels::membrane_forces_at(
            slots[i].terms, [&u](index_t n) { return kernels::load3<float>(u.node_iter, n); }, f0, f1);
        products[i] = slots[i].coef * f0;
        products[i + 1] = slots[i + 1].coef * f1;
        continue;
      }
      products[i] = slots[i].coef * kernels::constraint_force(slots[i].terms, u.node_iter);
    }
    __syncthreads();
    for (index_t j = first; j < node_count; j += stride) {
      SharedNode& v = held[j];
      Vec3f g = v.state.inertial_term(u);
      for (index_t i = v.slot_begin; i < v.slot_end; ++i) g = g + products[i];
      kernels::store3(u.node_iter_next, nodes.begin + j, v.state.advance(u, g));
    }
    grid.sync();
    it.rotate();
  }
  s.finish_from(it);
  for (index_t n = nodes.begin + first; n < nodes.end; n += stride) s.finish(n);
}

}  // namespace tear::backend
#endif
