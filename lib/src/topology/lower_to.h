// tear: an atomic minimum on the host, for passes on the OpenMP threads that keep the lowest
// index met (shared by the piece numbering and the writers' corner numbering).
#pragma once

#include "tear/mesh.h"

namespace tear {

/// Lowers `slot` to `value` when that is smaller; other threads may lower it at the same time.
/// The result is the smallest value any thread gave, whatever their order.
inline void lower_to(index_t& slot, index_t value) {
  index_t seen = __atomic_load_n(&slot, __ATOMIC_RELAXED);
  while (value < seen && !__atomic_compare_exchange_n(&slot, &seen, value, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
}

}  // namespace tear
