// tear: launch mode `one-pass`: the whole substep in one cooperative kernel, each iteration one
// pass, a group of lanes per node computing its constraints' forces and summing them.
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include "sim/pd_launch_cooperative.h"

#if TEAR_CUDA_SYSTEM

namespace tear::backend {

/// Slots of a node whose products the lanes of its group hold before the group sums them.
inline constexpr int group_chunk = 32;

/// Adds to g the products that the lanes of a group hold for slots [c·group_chunk,
/// (c + 1)·group_chunk) of a node of `count` slots, in slot order: every lane gets the same sum.
template <int group_lanes>
__device__ void sum_group_products(const kernels::Vec3f (&product)[group_chunk / group_lanes], int c, index_t count,
                                   kernels::Vec3f& g) {
  using kernels::Vec3f;
#pragma unroll
  for (int r = 0; r < group_chunk / group_lanes; ++r)
#pragma unroll
    for (int l = 0; l < group_lanes; ++l) {
      const Vec3f p{__shfl_sync(0xffffffffu, product[r].x, l, group_lanes),
                    __shfl_sync(0xffffffffu, product[r].y, l, group_lanes),
                    __shfl_sync(0xffffffffu, product[r].z, l, group_lanes)};
      if (c * group_chunk + r * group_lanes + l < count) g = g + p;
    }
}

/// One Jacobi-Chebyshev update of node n (`active`) by a group of `group_lanes` lanes: each lane
/// computes the forces of some of the node's constraints itself (`compute_constraint_force`, as
/// the local step would) times their coefficients, and every lane sums the products in slot order
/// through shuffles, so the result is the bits of `jacobi_chebyshev_update` after
/// `project_constraints`, without the forces' trip through memory and the barrier between them.
/// Every lane of the warp calls it the same number of times (inactive groups too).
template <int group_lanes>
__device__ void group_update(const kernels::jacobi_chebyshev_update& u, index_t n, bool active) {
  using kernels::Vec3f;
  constexpr int group_rounds = group_chunk / group_lanes;
  const int lane = static_cast<int>(threadIdx.x) % group_lanes;
  index_t begin = 0, count = 0;
  Vec3f x{0, 0, 0}, s{0, 0, 0}, g{0, 0, 0};
  if (active) {
    x = kernels::load3<float>(u.node_iter, n);
    begin = u.node_slot_offset[n];
    count = u.node_slot_offset[n + 1] - begin;
    s = kernels::load3<float>(u.node_pred, n);
    g = u.inertial_term(n, x, s);
  }
  const int chunks = __reduce_max_sync(0xffffffffu, static_cast<unsigned>((count + group_chunk - 1) / group_chunk));
  for (int c = 0; c < chunks; ++c) {
    Vec3f product[group_rounds];
#pragma unroll
    for (int r = 0; r < group_rounds; ++r) {
      const index_t j = c * group_chunk + r * group_lanes + lane;
      product[r] = Vec3f{0, 0, 0};
      if (j < count) {
        const index_t slot = u.node_slots[begin + j];
        product[r] =
            u.node_slot_coef[begin + j] *
            kernels::compute_constraint_force(u.constraints, u.node_iter, u.constraints.constraint_of_slot(slot));
      }
    }
    sum_group_products<group_lanes>(product, c, count, g);
  }
  if (active && lane == 0) kernels::store3(u.node_iter_next, n, u.next_from_sum(n, x, s, g));
}

/// `group_update` of a node whose group keeps, in registers, all that an iteration reads of it
/// except the iterate's neighbours: its constraints' terms and coefficients (a node of at most
/// `group_chunk` slots), its mass, diagonal, pin and prediction, and its own last two iterates.
/// The model does not change within a substep, so each iteration's chain of dependent loads
/// (offsets → slots → constraints → positions) becomes the positions' loads alone. Same
/// operations on the same values as `group_update`: the same bits.
template <int group_lanes>
struct HeldGroupNode {
  static constexpr int rounds = group_chunk / group_lanes;
  kernels::ConstraintTerms terms[rounds];
  float coef[rounds];
  index_t count = 0;
  bool active = false;
  HeldNodeState node{};

  /// Reads node n (`active`) before the first iteration: `u` set for it.
  __device__ void load(const kernels::jacobi_chebyshev_update& u, index_t n, bool is_active) {
    active = is_active;
    if (!active) return;
    const int lane = static_cast<int>(threadIdx.x) % group_lanes;
    const index_t begin = u.node_slot_offset[n];
    count = u.node_slot_offset[n + 1] - begin;
#pragma unroll
    for (int r = 0; r < rounds; ++r) {
      const index_t j = r * group_lanes + lane;
      if (j < count) {
        terms[r] = kernels::constraint_terms(u.constraints, u.constraints.constraint_of_slot(u.node_slots[begin + j]));
        coef[r] = u.node_slot_coef[begin + j];
      }
    }
    node = HeldNodeState::load(u, n);
  }

  /// One iteration: `u` set for it (the iterates it reads and writes, ω).
  __device__ void update(const kernels::jacobi_chebyshev_update& u, index_t n) {
    using kernels::Vec3f;
    const int lane = static_cast<int>(threadIdx.x) % group_lanes;
    Vec3f g{0, 0, 0};
    if (active) g = node.inertial_term(u);
    Vec3f product[rounds];
#pragma unroll
    for (int r = 0; r < rounds; ++r) {
      product[r] = Vec3f{0, 0, 0};
      if (r * group_lanes + lane < count) product[r] = coef[r] * kernels::constraint_force(terms[r], u.node_iter);
    }
    sum_group_products<group_lanes>(product, 0, count, g);
    if (!active) return;
    const Vec3f next = node.advance(u, g);
    if (lane == 0) kernels::store3(u.node_iter_next, n, next);
  }
};

/// The whole substep in one cooperative kernel with one pass and one grid barrier per iteration:
/// each node updated by a group of `group_lanes` lanes (`group_update`). The nodes are dealt to the
/// blocks in equal runs, as in `two_pass_substep_kernel`. Where each group has one node (the grid
/// as `persistent_launch` sizes it) and none of a warp's nodes has more than `group_chunk` slots,
/// the groups hold their nodes (`HeldGroupNode`).
template <int group_lanes>
__global__ void one_pass_substep_kernel(SubstepKernels s) {
  cooperative_groups::grid_group grid = cooperative_groups::this_grid();
  const BlockNodes nodes = block_nodes(s.node_count);
  const index_t node_first = nodes.begin + static_cast<index_t>(threadIdx.x);
  const index_t node_stride = static_cast<index_t>(blockDim.x);
  for (index_t n = node_first; n < nodes.end; n += node_stride) s.predict(n);
  grid.sync();
  const index_t groups = static_cast<index_t>(blockDim.x) / group_lanes;
  const index_t rounds = (nodes.run + groups - 1) / groups;  // the same in every block: warps stay whole
  const index_t group = static_cast<index_t>(threadIdx.x) / group_lanes;
  Iterates it = s.first_iterates();
  HeldGroupNode<group_lanes> held;
  const index_t held_node = nodes.begin + group;
  bool holding = false;
  if (rounds == 1) {
    s.iteration(0, it);
    held.load(s.update, held_node, held_node < nodes.end);
    holding = __all_sync(0xffffffffu, held.count <= group_chunk);
  }
  for (int k = 0; k < s.iterations; ++k) {
    s.iteration(k, it);
    if (holding) {
      held.update(s.update, held_node);
    } else {
      for (index_t r = 0; r < rounds; ++r) {
        const index_t n = nodes.begin + r * groups + group;
        group_update<group_lanes>(s.update, n, n < nodes.end);
      }
    }
    grid.sync();
    it.rotate();
  }
  s.finish_from(it);
  for (index_t n = node_first; n < nodes.end; n += node_stride) s.finish(n);
}

}  // namespace tear::backend
#endif
