// tear: what the cooperative substep kernels (launch modes `two-pass`, `one-pass` and `shared`)
// share: how a block takes its run of nodes, and a node's state held across iterations.
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include <cstdint>

#include "backend/backend.h"
#include "pd_step.h"
#include "sim/pd_substep.h"

#if TEAR_CUDA_SYSTEM
#include <cooperative_groups.h>

namespace tear::backend {

inline constexpr int persistent_block = 256;  ///< threads per block of the persistent kernel

/// The nodes block `block` of `blocks` takes in a cooperative substep kernel: an equal run each,
/// [begin, end). The host sizes the shared-memory kernel's blocks with the same split.
struct BlockNodes {
  index_t run, begin, end;
};
TEAR_HD inline BlockNodes block_nodes_of(index_t node_count, index_t blocks, index_t block) {
  const index_t run = (node_count + blocks - 1) / blocks;
  const index_t begin = block * run;
  return {run, begin, begin + run < node_count ? begin + run : node_count};
}
__device__ inline BlockNodes block_nodes(index_t node_count) {
  return block_nodes_of(node_count, static_cast<index_t>(gridDim.x), static_cast<index_t>(blockIdx.x));
}

/// A node's values that do not change within a substep (prediction, mass, diagonal, pin) and its
/// last two iterates, as a kernel holds them instead of reading them each iteration: in registers
/// (`HeldGroupNode`) or in shared memory (`SharedNode`).
struct HeldNodeState {
  kernels::Vec3f s, x, x_prev;
  float mass, diag;
  std::int32_t pinned;

  /// Node n before the first iteration: `u` set for it.
  __device__ static HeldNodeState load(const kernels::jacobi_chebyshev_update& u, index_t n) {
    return {kernels::load3<float>(u.node_pred, n),
            kernels::load3<float>(u.node_iter, n),
            kernels::load3<float>(u.node_iter_prev, n),
            u.node_mass[n],
            u.node_diag[n],
            u.node_pinned[n]};
  }
  /// The update's sum's first term, m/h² (s − x).
  __device__ kernels::Vec3f inertial_term(const kernels::jacobi_chebyshev_update& u) const {
    return u.inertial_term_of(mass, x, s);
  }
  /// x⁽ᵏ⁺¹⁾ from the summed g, which becomes the held iterate; returns it.
  __device__ kernels::Vec3f advance(const kernels::jacobi_chebyshev_update& u, const kernels::Vec3f& g) {
    const kernels::Vec3f next = u.next_from_held(pinned != 0, diag, x, x_prev, s, g);
    x_prev = x;
    x = next;
    return next;
  }
};

}  // namespace tear::backend
#endif
