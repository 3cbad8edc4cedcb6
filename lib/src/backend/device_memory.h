// tear: the account of the memory the library's arrays hold on each backend, kept by the backends'
// allocators (tear::memory_in_use).
#pragma once

#include <cstddef>

#include "tear/device.h"

namespace tear::backend {

/// Records an allocation or a release of `bytes` on `device` (thread-safe).
void count_allocation(Device device, std::size_t bytes);
void count_release(Device device, std::size_t bytes);

}  // namespace tear::backend
