// tear: launch mode `persistent` (the default): which cooperative kernel (`one-pass`, `shared` or
// `two-pass`) runs a substep on this mesh and device, or none (then as `graph`), and its launch.
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include <algorithm>
#include <cstddef>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "sim/pd_launch_one_pass.h"
#include "sim/pd_launch_shared.h"
#include "sim/pd_launch_two_pass.h"
#include "sim/pd_solver_on.h"
#include "tear/error.h"

namespace tear::backend {

template <class System>
typename PdSolverOn<System>::PersistentLaunch PdSolverOn<System>::persistent_launch() const {
  return {};
}

#if TEAR_CUDA_SYSTEM
namespace {
/// The blocks of each cooperative substep kernel the device holds at once, asked once per device
/// (a solver is rebuilt after every tear); 0 where cooperative launches are not available.
struct ResidentBlocks {
  long long two_pass = 0, one_pass_16 = 0, one_pass_8 = 0;
  int sms = 0;
  std::size_t shared_bytes = 0;  // the most a block of the shared-memory kernel may take; 0: none
};

ResidentBlocks resident_blocks() {
  static std::mutex mutex;
  static std::map<int, ResidentBlocks> known;
  int device = 0;
  if (cudaGetDevice(&device) != cudaSuccess) {
    cudaGetLastError();
    return {};
  }
  const std::lock_guard<std::mutex> lock(mutex);
  auto found = known.find(device);
  if (found != known.end()) return found->second;
  ResidentBlocks resident;
  int cooperative = 0, sms = 0, two_pass = 0, one_pass_16 = 0, one_pass_8 = 0;
  if (cudaDeviceGetAttribute(&cooperative, cudaDevAttrCooperativeLaunch, device) == cudaSuccess && cooperative &&
      cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device) == cudaSuccess &&
      cudaOccupancyMaxActiveBlocksPerMultiprocessor(&two_pass, two_pass_substep_kernel, persistent_block, 0) ==
          cudaSuccess &&
      cudaOccupancyMaxActiveBlocksPerMultiprocessor(&one_pass_16, one_pass_substep_kernel<16>, persistent_block, 0) ==
          cudaSuccess &&
      cudaOccupancyMaxActiveBlocksPerMultiprocessor(&one_pass_8, one_pass_substep_kernel<8>, persistent_block, 0) ==
          cudaSuccess)
    resident = {static_cast<long long>(sms) * two_pass, static_cast<long long>(sms) * one_pass_16,
                static_cast<long long>(sms) * one_pass_8, sms};
  int optin = 0;
  if (resident.sms > 0 &&
      cudaDeviceGetAttribute(&optin, cudaDevAttrMaxSharedMemoryPerBlockOptin, device) == cudaSuccess &&
      cudaFuncSetAttribute(shared_substep_kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, optin) == cudaSuccess)
    resident.shared_bytes = static_cast<std::size_t>(optin);
  cudaGetLastError();  // clear the error of a refused query
  known.emplace(device, resident);
  return resident;
}
}  // namespace

template <>
typename PdSolverOn<Cuda>::PersistentLaunch PdSolverOn<Cuda>::persistent_launch() const {
  using Kind = PersistentLaunch::Kind;
  const ResidentBlocks resident = resident_blocks();
  const auto blocks_for = [](long long threads, long long most) {
    const long long wanted = threads > 0 ? (threads + persistent_block - 1) / persistent_block : 1;
    return static_cast<int>(wanted < most ? wanted : most);
  };
  // One pass: a group of lanes per node, each group computing the node's constraints' forces
  // itself, three times the local step's arithmetic for one barrier an iteration instead of two
  // and no forces through memory. It wins while the device waits on latency, up to about 256
  // lanes per multiprocessor: 16 lanes a node where they fit, else 8, else shared memory. Measured
  // on an H100 (132 multiprocessors), ms per 100 iterations, 16 lanes / 8 lanes / two passes,
  // before the groups held their nodes in registers: 1,486 nodes 0.47 / 0.59 / 0.65; 4,646 nodes
  // 0.87 / 0.65 / 0.66; 10,201 nodes 1.19 / 0.80 / 0.72; 19,426 nodes 1.84 / 1.29 / 0.89. Holding
  // them, 1,486 nodes take 0.29, and 0.27 once the kernel's arguments left local memory.
  // With the membrane model a group computes a polar decomposition for each of its node's membrane
  // slots, and shared memory wins where it fits: the 1,486-node tearing pull (H200, 2026-11-28) took
  // 1.50 ms a frame in the solver with shared memory, 2.35 with one pass.
  const long long lane_budget = 256LL * resident.sms;
  const long long nodes = node_count_;
  const bool one_pass_fits =
      resident.one_pass_16 > 0 && resident.one_pass_8 > 0 &&
      (launch_mode_ == LaunchMode::one_pass || (launch_mode_ == LaunchMode::persistent && 8 * nodes <= lane_budget));
  const auto one_pass = [&]() -> PersistentLaunch {
    if (16 * nodes <= lane_budget) return {Kind::one_pass, blocks_for(16 * nodes, resident.one_pass_16), 16};
    return {Kind::one_pass, blocks_for(8 * nodes, resident.one_pass_8), 8};
  };
  if (one_pass_fits && (membrane_face_count_ == 0 || launch_mode_ == LaunchMode::one_pass)) return one_pass();
  // Shared memory: each block holds its nodes and their slots (`shared_substep_kernel`), one block
  // per multiprocessor, where every block's fit (up to about 27,000 nodes of a sheet on an H100's
  // 227 KiB a block). Measured on an H100, ms per 100 iterations, shared memory against two passes
  // (before either stopped reading its arguments from local memory): 4,646 nodes 0.43 / 0.66;
  // 10,201 nodes 0.51 / 0.72; 19,426 nodes 0.64 / 0.89 (after: 0.28 and 0.49 at 4,646 and 19,426).
  // At 1,486 nodes one pass in registers takes 0.29 against its 0.39.
  if ((launch_mode_ == LaunchMode::shared || launch_mode_ == LaunchMode::persistent) && resident.shared_bytes > 0 &&
      nodes > 0) {
    const long long slots = used_slot_count();
    if (shared_bytes(slots, nodes) <= resident.shared_bytes * static_cast<std::size_t>(resident.sms)) {
      const index_t blocks = static_cast<index_t>(nodes < resident.sms ? nodes : resident.sms);
      const std::vector<index_t> offset = to_host<index_t>(node_slot_offset_);
      std::size_t most = 0;
      for (index_t block = 0; block < blocks; ++block) {
        const BlockNodes run = block_nodes_of(node_count_, blocks, block);
        if (run.end > run.begin)
          most = std::max(most, shared_bytes(offset[run.end] - offset[run.begin], run.end - run.begin));
      }
      int per_sm = 0;
      if (most <= resident.shared_bytes &&
          cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, shared_substep_kernel, shared_block, most) ==
              cudaSuccess &&
          per_sm > 0)
        return {Kind::shared, static_cast<int>(blocks), 0, most};
      cudaGetLastError();
    }
  }
  if (one_pass_fits) return one_pass();  // a membrane that shared memory does not hold
  if (resident.two_pass == 0) return {};
  // Two passes: only while each thread has at most a few elements per pass; on larger meshes
  // separate launches, replayed as a graph, measured faster. H100 (two blocks of the two-pass
  // kernel per multiprocessor), ms per 100 iterations, two passes against the graph: 49,595 nodes
  // (4.4 elements a thread) 1.23 against 1.38; 66,049 nodes (5.8) 1.42 against 1.46; 98,931 nodes
  // (8.8) 2.98 against 2.81.
  const long long work = node_count_ > constraint_count_ ? node_count_ : constraint_count_;
  if (launch_mode_ == LaunchMode::persistent && work > 7 * resident.two_pass * persistent_block) return {};
  return {Kind::two_pass, blocks_for(work, resident.two_pass), 0};
}
#endif

template <class System>
bool PdSolverOn<System>::step_persistent(int count) {
  if (persistent_.kind == PersistentLaunch::Kind::none) return false;
#if TEAR_CUDA_SYSTEM
  SubstepKernels s = substep_kernels(raw<float>(omega_));
  void* args[] = {&s};
  using Kind = typename PersistentLaunch::Kind;
  const void* kernel = persistent_.kind == Kind::two_pass ? reinterpret_cast<const void*>(two_pass_substep_kernel)
                       : persistent_.kind == Kind::shared ? reinterpret_cast<const void*>(shared_substep_kernel)
                       : persistent_.lanes == 16          ? reinterpret_cast<const void*>(one_pass_substep_kernel<16>)
                                                          : reinterpret_cast<const void*>(one_pass_substep_kernel<8>);
  const int block = persistent_.kind == Kind::shared ? shared_block : persistent_block;
  for (int i = 0; i < count; ++i) {
    const cudaError_t status =
        cudaLaunchCooperativeKernel(kernel, dim3(persistent_.blocks), dim3(block), args, persistent_.bytes, 0);
    if (status != cudaSuccess)
      throw runtime_error(std::string("the solver's kernel could not be launched: ") + cudaGetErrorString(status));
  }
  return true;
#else
  static_cast<void>(count);
  return false;
#endif
}

}  // namespace tear::backend
