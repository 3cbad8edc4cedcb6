// tear: loops cut into pieces that OpenMP threads run at once, for the readers and writers of
// meshes. Each piece has an output of its own (or a range of a shared one), and results are joined
// in piece order, so what a loop computes does not depend on the pieces or on the threads.
#pragma once

#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <exception>
#include <utility>
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

/// A team of threads and the pieces each loop it runs is cut into: one piece on one thread, else
/// a few per thread, so that a slow piece does not hold the others up. (The mesh writers encode
/// a frame with one.)
struct PieceTeam {
  int threads = 1;

  std::size_t pieces(std::size_t count) const {
    if (threads == 1) return 1;
    return std::max<std::size_t>(1, std::min(count, 4 * static_cast<std::size_t>(threads)));
  }

  /// Runs `body(k, begin, end)` for the `piece_count` pieces of [0, count) (piece k is
  /// [count * k / piece_count, count * (k + 1) / piece_count)); the same count and piece count
  /// give the same ranges.
  template <typename Body>
  void for_each_range(std::size_t count, std::size_t piece_count, Body body) const {
    for_each_piece(
        piece_count, [&](std::size_t k) { body(k, count * k / piece_count, count * (k + 1) / piece_count); }, threads);
  }
  template <typename Body>
  void for_each_range(std::size_t count, Body body) const {
    for_each_range(count, pieces(count), body);
  }
};

/// Replaces each count by the sum of the counts before it; returns the sum of all.
inline std::size_t exclusive_sums(std::vector<std::size_t>& counts) {
  std::size_t sum = 0;
  for (std::size_t& count : counts) sum += std::exchange(count, sum);
  return sum;
}

}  // namespace tear
