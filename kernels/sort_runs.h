// tear kernels: sorting the runs of a CSR in place, one thread per run (build_topology.h): a
// network in registers for short runs, the thread's own memory for longer ones, a heapsort for the
// longest (a node of a fan or of repeated faces).
#pragma once

#include <cstdint>

#include "hd.h"

namespace tear::kernels {

using index_t = std::int32_t;

/// Sorts a[i] and a[j] into order.
template <class T>
TEAR_HD inline void compare_exchange(T& a, T& b) {
  const T lo = a < b ? a : b;
  b = a < b ? b : a;
  a = lo;
}

// Batcher's odd-even merge sort as a network over a fixed number of values: every index is a
// constant once the templates are expanded, so on the GPU the values stay in registers and no
// thread waits on its own memory. 19 comparators for 8 values, 63 for 16, 191 for 32.

/// Merges the sorted halves of v[Lo, Lo + N), taking every R-th value (N a power of two).
template <int Lo, int N, int R, class T>
TEAR_HD inline void odd_even_merge(T* v) {
  constexpr int step = 2 * R;
  if constexpr (step < N) {
    odd_even_merge<Lo, N, step>(v);
    odd_even_merge<Lo + R, N, step>(v);
    TEAR_UNROLL
    for (int i = Lo + R; i + R < Lo + N; i += step) compare_exchange(v[i], v[i + R]);
  } else {
    compare_exchange(v[Lo], v[Lo + R]);
  }
}

/// Sorts v[Lo, Lo + N) ascending (N a power of two).
template <int Lo, int N, class T>
TEAR_HD inline void odd_even_merge_sort(T* v) {
  if constexpr (N > 1) {
    odd_even_merge_sort<Lo, N / 2>(v);
    odd_even_merge_sort<Lo + N / 2, N / 2>(v);
    odd_even_merge<Lo, N, 1>(v);
  }
}

/// Sorts v[0, N) ascending by the network (N a power of two).
template <int N, class T>
TEAR_HD inline void sort_network(T* v) {
  static_assert(N > 0 && (N & (N - 1)) == 0, "a power of two");
  odd_even_merge_sort<0, N>(v);
}

/// The runs of faces held in registers: most nodes of a cloth have at most 8 faces (the nodes a
/// cut makes about half as many), and a split gives a corner node one or two more.
inline constexpr int small_run = 8, medium_run = 16;

/// Sorts a[0, size) ascending by heapsort: O(size log size) whatever the order (an insertion sort
/// of the long run of a node in 300,000 faces took minutes), in place, without recursion.
template <class T>
TEAR_HD inline void heap_sort(T* a, index_t size) {
  auto sift_down = [a](index_t root, index_t end) {
    const T v = a[root];
    for (index_t child = 2 * root + 1; child < end; child = 2 * root + 1) {
      if (child + 1 < end && a[child] < a[child + 1]) ++child;
      if (!(v < a[child])) break;
      a[root] = a[child];
      root = child;
    }
    a[root] = v;
  };
  for (index_t i = size / 2; i-- > 0;) sift_down(i, size);
  for (index_t end = size - 1; end > 0; --end) {
    const T top = a[0];
    a[0] = a[end];
    a[end] = top;
    sift_down(0, end);
  }
}

/// Sorts run n of a CSR ascending. For node→faces, a face that repeats the node appears once per
/// corner, adjacent after the sort. A run of up to `medium_run` values is sorted by a network in
/// registers; a longer one of up to `local_capacity` is loaded at once (independent loads), sorted
/// in the thread's own memory and stored: sorting in place, each step would wait for a load of what
/// the step before stored. A longer run still (a node of a fan or of repeated faces) is heapsorted
/// in place.
struct sort_runs {
  static constexpr int local_capacity = 32;
  const index_t* offset;
  index_t* values;
  TEAR_HD static void insertion_sort(index_t* a, index_t size) {
    for (index_t i = 1; i < size; ++i) {
      const index_t v = a[i];
      index_t j = i;
      for (; j > 0 && a[j - 1] > v; --j) a[j] = a[j - 1];
      a[j] = v;
    }
  }
  template <int N>
  TEAR_HD void sort_in_registers(index_t begin, index_t size) const {
    index_t run[N];
    TEAR_UNROLL
    for (int i = 0; i < N; ++i) run[i] = i < size ? values[begin + i] : INT32_MAX;
    sort_network<N>(run);
    TEAR_UNROLL
    for (int i = 0; i < N; ++i)
      if (i < size) values[begin + i] = run[i];
  }
  TEAR_HD void operator()(index_t n) const {
    const index_t begin = offset[n], size = offset[n + 1] - begin;
    if (size <= small_run) return sort_in_registers<small_run>(begin, size);
    if (size <= medium_run) return sort_in_registers<medium_run>(begin, size);
    if (size > local_capacity) {
      heap_sort(values + begin, size);
      return;
    }
    index_t run[local_capacity];
    for (index_t i = 0; i < size; ++i) run[i] = values[begin + i];
    insertion_sort(run, size);
    for (index_t i = 0; i < size; ++i) values[begin + i] = run[i];
  }
};

}  // namespace tear::kernels
