// tear: a fixed sequence of kernel launches recorded once and replayed: on the GPU a CUDA graph
// (one launch for the whole sequence instead of one per kernel), on the CPU a plain call.
#pragma once

#include <string>

#include "backend/backend.h"
#include "tear/error.h"

namespace tear::backend {

/// `run(enqueue, times)` calls `enqueue(policy)` to queue the sequence `times` times. The
/// sequence must be the same every time (same kernels, same arguments): the GPU version records
/// it on its first run and replays the recording.
template <class System>
class ReplayGraph {
 public:
  template <class Enqueue>
  void run(const Enqueue& enqueue, int times) {
    for (int i = 0; i < times; ++i) enqueue(Traits<System>::policy());
  }
};

#if TEAR_CUDA_SYSTEM
template <>
class ReplayGraph<Cuda> {
 public:
  ReplayGraph() = default;
  ReplayGraph(const ReplayGraph&) = delete;
  ReplayGraph& operator=(const ReplayGraph&) = delete;
  ~ReplayGraph() {
    if (exec_) cudaGraphExecDestroy(exec_);
    if (stream_) cudaStreamDestroy(stream_);
  }

  template <class Enqueue>
  void run(const Enqueue& enqueue, int times) {
    if (!exec_ && !unavailable_) record(enqueue);
    for (int i = 0; i < times; ++i) {
      if (unavailable_) {
        enqueue(Traits<Cuda>::policy());
        continue;
      }
      const cudaError_t status = cudaGraphLaunch(exec_, 0);
      if (status != cudaSuccess)
        throw runtime_error(std::string("CUDA graph launch failed: ") + cudaGetErrorString(status));
    }
  }

 private:
  // Records the sequence on a stream of its own (the legacy default stream cannot be captured).
  // Where recording is refused the sequence is launched kernel by kernel instead.
  template <class Enqueue>
  void record(const Enqueue& enqueue) {
    cudaGraph_t graph = nullptr;
    bool ok = cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking) == cudaSuccess &&
              cudaStreamBeginCapture(stream_, cudaStreamCaptureModeThreadLocal) == cudaSuccess;
    if (ok) {
      enqueue(thrust::cuda::par_nosync.on(stream_));
      ok = cudaStreamEndCapture(stream_, &graph) == cudaSuccess && graph;
    }
    ok = ok && cudaGraphInstantiate(&exec_, graph, 0) == cudaSuccess;
    if (graph) cudaGraphDestroy(graph);
    if (!ok) {
      cudaGetLastError();  // clear the error of the refused recording
      exec_ = nullptr;
      unavailable_ = true;
    }
  }

  cudaStream_t stream_ = nullptr;
  cudaGraphExec_t exec_ = nullptr;
  bool unavailable_ = false;
};
#endif

}  // namespace tear::backend
