// The device side of `tear bench`: the copy that measures memory bandwidth.
#include <algorithm>
#include <chrono>

#include <thrust/copy.h>
#include <thrust/fill.h>

#include "backend/backend.h"
#include "bench/bench_device.h"

namespace tear::backend {

template <class System>
double fastest_copy_seconds(std::size_t bytes, int repeats) {
  const auto policy = Traits<System>::policy();
  const std::size_t n = bytes / sizeof(float);
  vector<System, float> from(n), to(n);
  thrust::fill(policy, from.begin(), from.end(), 1.0f);
  Traits<System>::synchronize();
  double best = 0;
  for (int i = 0; i <= repeats; ++i) {  // the first copy warms up
    const auto start = std::chrono::steady_clock::now();
    thrust::copy(policy, from.begin(), from.end(), to.begin());
    Traits<System>::synchronize();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (i > 0 && (best == 0 || seconds < best)) best = seconds;
  }
  return best;
}

#define TEAR_INSTANTIATE(S) template double fastest_copy_seconds<S>(std::size_t, int);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
