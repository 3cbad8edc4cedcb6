// tear: launch mode `two-pass`: the whole substep in one cooperative kernel, each iteration a pass
// over the constraints and one over the nodes.
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include "sim/pd_launch_cooperative.h"

#if TEAR_CUDA_SYSTEM

namespace tear::backend {

/// The whole substep in one cooperative kernel: each pass a loop over its elements calling the
/// same functor as its own launch would, the grid synchronised between passes. The grid is sized
/// for the constraints (the larger pass); the nodes, a third as many or fewer, are dealt to every
/// block in equal runs rather than to the first blocks only, so that the gather's loads, the
/// longest chain of an iteration, are spread over every multiprocessor's caches and load units
/// (H100, 100 iterations: 0.76 → 0.69 ms at 2,822 faces, whose 1,486 nodes the first 6 of 34
/// blocks gathered; 1.15 → 0.88 ms at 38,298 faces). Each node's gather issues 16 slots' loads at
/// a time, where the graph's large meshes take 8 (9,022 faces 0.71 → 0.66 ms; 8 keeps 2M faces at
/// 23.5 ms, which 16 made 25.5).
__global__ void two_pass_substep_kernel(SubstepKernels s) {
  cooperative_groups::grid_group grid = cooperative_groups::this_grid();
  const index_t first = static_cast<index_t>(blockIdx.x * blockDim.x + threadIdx.x);
  const index_t stride = static_cast<index_t>(gridDim.x * blockDim.x);
  const BlockNodes nodes = block_nodes(s.node_count);
  const index_t node_first = nodes.begin + static_cast<index_t>(threadIdx.x);
  const index_t node_stride = static_cast<index_t>(blockDim.x);
  for (index_t n = node_first; n < nodes.end; n += node_stride) s.predict(n);
  grid.sync();
  Iterates it = s.first_iterates();
  for (int k = 0; k < s.iterations; ++k) {
    s.iteration(k, it);
    for (index_t c = first; c < s.constraint_count; c += stride) s.project(c);
    grid.sync();
    for (index_t n = node_first; n < nodes.end; n += node_stride) s.update.update<16>(n);
    grid.sync();
    it.rotate();
  }
  s.finish_from(it);
  for (index_t n = node_first; n < nodes.end; n += node_stride) s.finish(n);
}

}  // namespace tear::backend
#endif
