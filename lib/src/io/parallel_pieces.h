// tear: loops cut into pieces that OpenMP threads run at once, for the readers and writers of
// meshes. Each piece has an output of its own (or a range of a shared one), and results are joined
// in piece order, so what a loop computes does not depend on the pieces or on the threads.
#pragma once

#include <omp.h>

#include <cstddef>
#include <exception>
#include <vector>

namespace tear {

/// Runs `body(k)` for k in [0, count) on `threads` OpenMP threads (0: `omp_get_max_threads()`),
/// the pieces handed out one at a time; the first exception (by k) is rethrown here, after every
/// piece has run. With one thread or one piece the loop runs on the calling thread, starting no
/// team.
template <typename Body>
void for_each_piece(std::size_t count, Body body, int threads = 0) {
  if (threads <= 0) threads = omp_get_max_threads();
  if (threads == 1 || count <= 1) {
    for (std::size_t k = 0; k < count; ++k) body(k);
    return;
  }
  std::vector<std::exception_ptr> errors(count);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t k = 0; k < count; ++k) {
    try {
      body(k);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  }
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

}  // namespace tear
