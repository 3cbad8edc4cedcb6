// tear: how a solver substep is launched (the launch modes) and the kernels of one substep with
// their arguments, shared by every launch mode.
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include <cstdlib>
#include <string>

#include "backend/backend.h"
#include "pd_step.h"
#include "tear/error.h"

namespace tear::backend {

/// How the CUDA backend launches a substep, from TEAR_CUDA_LAUNCH: `persistent` (the default: one
/// cooperative kernel runs the whole substep, as `one-pass` on a mesh of a few thousand nodes, as
/// `shared` on one whose blocks' shares fit in shared memory, else as `tiled`), `one-pass` (one
/// cooperative kernel, each iteration one pass and one grid barrier: a group of lanes per node
/// computes its constraints' forces and sums them), `shared` (one cooperative kernel, a block per
/// multiprocessor holding its run of nodes and their constraints in shared memory; as `two-pass`
/// where they do not fit), `two-pass` (one cooperative kernel, each iteration a pass over the
/// constraints and one over the nodes, the grid synchronising between them), `tiled` (each
/// iteration one launch, a block per tile of nodes computing the forces on them in shared memory:
/// sim/pd_launch_tiled.h), `graph` (the substep's launches recorded once as a CUDA graph and
/// replayed) or `plain` (every kernel launched on its own). Where the device has no cooperative
/// launch the first four run as `tiled`. `tiled` runs as `graph` on the CPU and where a tile would
/// need more records or halo than its packed indices hold (`persistent` then takes `two-pass` on a
/// mesh the resident threads cover in a few rounds). All of them compute the same operations in the
/// same order: the same bits.
enum class LaunchMode { persistent, one_pass, shared, two_pass, tiled, graph, plain };

inline LaunchMode launch_mode() {
  const char* setting = std::getenv("TEAR_CUDA_LAUNCH");
  if (!setting || !*setting) return LaunchMode::persistent;
  const std::string mode = setting;
  if (mode == "persistent") return LaunchMode::persistent;
  if (mode == "one-pass") return LaunchMode::one_pass;
  if (mode == "shared") return LaunchMode::shared;
  if (mode == "two-pass") return LaunchMode::two_pass;
  if (mode == "tiled") return LaunchMode::tiled;
  if (mode == "graph") return LaunchMode::graph;
  if (mode == "plain") return LaunchMode::plain;
  throw runtime_error("TEAR_CUDA_LAUNCH=" + mode +
                      ": expected persistent, one-pass, shared, two-pass, tiled, graph or plain");
}

/// The three iterate buffers of a substep's iterations: the one an iteration reads (`cur`), the one
/// before it (`prev`) and the one it writes (`next`). Held as pointers, not as indices into
/// `SubstepKernels::iter`: a kernel indexing that array by a variable would keep the whole
/// `SubstepKernels` in local memory and read every argument from there, inside each iteration.
struct Iterates {
  float* cur;
  float* prev;
  float* next;
  /// After an iteration: the next becomes current, the current previous, the previous free.
  TEAR_HD void rotate() {
    float* const old_prev = prev;
    prev = cur;
    cur = next;
    next = old_prev;
  }
};

/// The kernels of one substep with their arguments, built in one place for every way of launching
/// them. The iterate pointers and ω are set per iteration (`iteration`), the last iterate for the
/// velocity update (`finish_from`).
struct SubstepKernels {
  kernels::predict_positions predict;
  kernels::project_constraints project;
  kernels::jacobi_chebyshev_update update;
  kernels::finish_step finish;
  index_t node_count, constraint_count;
  int iterations;
  const float* omega;  // [iterations], ω of each iteration (on the backend for the persistent kernel)
  float* iter[3];

  /// The iterates of the first iteration: prediction's two copies, then the free buffer.
  TEAR_HD Iterates first_iterates() const { return {iter[0], iter[1], iter[2]}; }
  /// Iteration k reads iterates `it.cur` and `it.prev` and writes `it.next`.
  TEAR_HD void iteration(int k, const Iterates& it) {
    project.node_iter = it.cur;
    update.node_iter = it.cur;
    update.node_iter_prev = it.prev;
    update.node_iter_next = it.next;
    update.omega = omega[k];
  }
  TEAR_HD void finish_from(const Iterates& it) { finish.node_iter = it.cur; }
};

}  // namespace tear::backend
