// tear: the allocators of the backends' vectors: every allocation counted (`tear::memory_peak`),
// and on CUDA taken from the stream-ordered pool.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>

#include "backend/compiled_systems.h"
#include "backend/device_memory.h"
#include "tear/device.h"

namespace tear::backend {

/// The execution policy of a vector's own work (the fill of a resize, a copy between vectors):
/// by default its pointer's system, Thrust's blocking policy on CUDA.
template <Device device>
struct VectorSystem {};

#if TEAR_CUDA_SYSTEM
/// On CUDA, the non-blocking policy the stages use: a resize that grows a vector fills the new
/// elements with a kernel, and with the blocking policy it would also wait for the device, once
/// per growing array per cut. The fill is queued on the same stream as the stages, so order holds.
template <>
struct VectorSystem<Device::cuda> {
  using system_type = thrust::cuda_cub::par_nosync_t;
  system_type& system() {
    static system_type policy;
    return policy;
  }
};
#endif

/// A Thrust allocator `Base` with every allocation counted against `device` (`tear::memory_peak`).
template <class T, class Base, Device device>
struct CountingAllocator : Base, VectorSystem<device> {
  using value_type = T;
  using pointer = typename Base::pointer;
  using size_type = typename Base::size_type;
  template <class U>
  struct rebind {
    using other = CountingAllocator<U, typename Base::template rebind<U>::other, device>;
  };
  CountingAllocator() = default;
  template <class U, class B>
  CountingAllocator(const CountingAllocator<U, B, device>&) noexcept {}
  pointer allocate(size_type n) {
    pointer p = Base::allocate(n);
    count_allocation(device, n * sizeof(T));
    return p;
  }
  void deallocate(pointer p, size_type n) noexcept {
    Base::deallocate(p, n);
    count_release(device, n * sizeof(T));
  }
  bool operator==(const CountingAllocator&) const { return true; }
  bool operator!=(const CountingAllocator&) const { return false; }
};

#if TEAR_CUDA_SYSTEM
/// Device memory of the vectors, from CUDA's stream-ordered pool on the default stream, where every
/// stage runs: a freed block goes back to the pool in stream order and the next allocation of that
/// size takes it without asking the driver (cudaMalloc and cudaFree synchronise the device, and map
/// and unmap pages in proportion to the size). The pool keeps what is freed for the process's
/// lifetime, so a cloth that grows cut after cut, or one cloth after another in one process, reuses
/// it. Where the device has no memory pools, cudaMalloc and cudaFree.
template <class T>
struct PoolAllocator : thrust::cuda::allocator<T> {
  using Base = thrust::cuda::allocator<T>;
  using value_type = T;
  using pointer = typename Base::pointer;
  using size_type = typename Base::size_type;
  template <class U>
  struct rebind {
    using other = PoolAllocator<U>;
  };
  PoolAllocator() = default;
  template <class U>
  PoolAllocator(const PoolAllocator<U>&) noexcept {}
  pointer allocate(size_type n) {
    void* p = nullptr;
    const cudaError_t status = pools() ? cudaMallocAsync(&p, n * sizeof(T), 0) : cudaMalloc(&p, n * sizeof(T));
    if (status != cudaSuccess) {
      cudaGetLastError();  // not a sticky error: clear it, and report it as the allocation failure it is
      throw std::bad_alloc();
    }
    return pointer(static_cast<T*>(p));
  }
  void deallocate(pointer p, size_type) noexcept {
    if (pools())
      cudaFreeAsync(thrust::raw_pointer_cast(p), 0);
    else
      cudaFree(thrust::raw_pointer_cast(p));
  }
  bool operator==(const PoolAllocator&) const { return true; }
  bool operator!=(const PoolAllocator&) const { return false; }

 private:
  /// Whether the current device has memory pools; the first call also tells its default pool to
  /// keep freed memory.
  static bool pools() {
    static const bool has_pools = [] {
      int device = 0, supported = 0;
      if (cudaGetDevice(&device) != cudaSuccess ||
          cudaDeviceGetAttribute(&supported, cudaDevAttrMemoryPoolsSupported, device) != cudaSuccess || !supported) {
        cudaGetLastError();
        return false;
      }
      cudaMemPool_t pool;
      if (cudaDeviceGetDefaultMemPool(&pool, device) != cudaSuccess) {
        cudaGetLastError();
        return false;
      }
      std::uint64_t keep = ~std::uint64_t(0);
      cudaMemPoolSetAttribute(pool, cudaMemPoolAttrReleaseThreshold, &keep);
      return true;
    }();
    return has_pools;
  }
};

/// Thrust's temporary storage from `PoolAllocator` (an allocator of bytes, as Thrust's execution
/// policies take one).
struct PoolBytes {
  using value_type = char;
  char* allocate(std::ptrdiff_t bytes) {
    return thrust::raw_pointer_cast(PoolAllocator<char>().allocate(static_cast<std::size_t>(bytes)));
  }
  void deallocate(char* p, std::size_t) noexcept {
    PoolAllocator<char>().deallocate(thrust::cuda::pointer<char>(p), 0);
  }
};
#endif

}  // namespace tear::backend
