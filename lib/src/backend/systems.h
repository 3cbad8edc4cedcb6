// tear: tags naming the backend systems, without pulling in Thrust; host code declares the
// per-system entry points with them and dispatches on `Device` (`dispatch`).
#pragma once

#include "tear/device.h"
#include "tear/error.h"

namespace tear::backend {

struct Omp {};   ///< Thrust's OpenMP system: the CPU backend
struct Cuda {};  ///< Thrust's CUDA system: the GPU backend

/// Calls `f(Omp{})` or `f(Cuda{})` for `device`.
template <class F>
decltype(auto) dispatch(Device device, F&& f) {
#if TEAR_WITH_CUDA
  if (device == Device::cuda) return f(Cuda{});
#else
  if (device == Device::cuda) throw Error(ErrorKind::usage, "this build of tear has no CUDA backend");
#endif
  return f(Omp{});
}

}  // namespace tear::backend
