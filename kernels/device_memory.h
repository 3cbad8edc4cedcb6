// tear: the account of the GPU memory the library holds, kept by the CUDA backend's allocators.
#pragma once

#include <cstddef>

namespace tear::backend {

/// Records an allocation or a release of `bytes` of GPU memory (thread-safe).
void count_device_allocation(std::size_t bytes);
void count_device_release(std::size_t bytes);

}  // namespace tear::backend
