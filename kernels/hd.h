// tear kernels: what device code needs from the backend, and nothing of the library: the TEAR_HD
// marker for functions callable on both systems, the index type, and the few primitives whose
// spelling differs between a CUDA and a host compiler. The host side (Thrust systems, vectors,
// allocators) is lib/src/backend/backend.h.
#pragma once

#include <cstdint>

namespace tear {
/// The one index type of the project (tear/mesh.h declares the same); -1 means "none".
using index_t = std::int32_t;
}  // namespace tear

// Functions callable from kernels on both systems. A host compiler (the CPU-only build, or host
// code including these headers) sees plain functions; __host__/__device__ are never redefined.
#if defined(__CUDACC__)
#define TEAR_HD __host__ __device__
#else
#define TEAR_HD
#endif
// Unrolls the next loop in device code (host compilers do not know the pragma).
#if defined(__CUDA_ARCH__)
#define TEAR_UNROLL _Pragma("unroll")
#else
#define TEAR_UNROLL
#endif

namespace tear::kernels {
/// True for a finite float, on host and device alike (x - x is NaN for NaN and infinities).
TEAR_HD inline bool is_finite(float x) { return x - x == 0.0f; }

/// Adds `v` to `*p` atomically and returns the old value. Integer only: the sums it makes are exact
/// whatever the order, so results stay deterministic (positions it hands out are put in order
/// afterwards by whoever uses them).
TEAR_HD inline int atomic_fetch_add(int* p, int v) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(p, v);
#else
  return __atomic_fetch_add(p, v, __ATOMIC_RELAXED);
#endif
}

/// Per-element passes over consecutive index ranges in one launch: [0, a) runs first(i),
/// [a, a + b) second(i - a), the rest third(i - a - b). A stage's passes over nodes, edges and faces
/// that read nothing the others write launch once instead of three times, and each thread still
/// does one element.
template <class First, class Second, class Third>
struct over_three_ranges {
  First first;
  Second second;
  Third third;
  index_t a, b;
  TEAR_HD void operator()(index_t i) const {
    if (i < a)
      first(i);
    else if (i < a + b)
      second(i - a);
    else
      third(i - a - b);
  }
};

/// A pass that does nothing: `over_three_ranges` with two ranges.
struct no_pass {
  TEAR_HD void operator()(index_t) const {}
};

template <class First, class Second, class Third>
over_three_ranges<First, Second, Third> make_over_three_ranges(First first, Second second, Third third, index_t a,
                                                               index_t b) {
  return {first, second, third, a, b};
}

}  // namespace tear::kernels
