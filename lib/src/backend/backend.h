// tear: the one header that owns the differences between the two backends (host side; the device
// side's markers are kernels/hd.h).
//
// Kernels are written once, as TEAR_HD functors over raw pointers, and launched through Thrust
// algorithms with the execution policy of a backend system: Thrust's CUDA system on the GPU,
// its OpenMP system on the CPU. Stage code is templated on the system tag and never tests
// __CUDACC__ itself.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <thrust/copy.h>
#include <thrust/detail/config.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>
#include <thrust/system/omp/execution_policy.h>
#include <thrust/system/omp/vector.h>

#include "backend/device_memory.h"
#include "backend/systems.h"
#include "hd.h"
#include "tear/error.h"

#if TEAR_WITH_CUDA && defined(__CUDACC__)
#include <cub/block/block_load.cuh>
#include <cub/block/block_scan.cuh>
#include <cub/block/block_store.cuh>
#include <thrust/system/cuda/execution_policy.h>
#include <thrust/system/cuda/vector.h>
#define TEAR_CUDA_SYSTEM 1
#else
#define TEAR_CUDA_SYSTEM 0
#endif



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

/// A backend's vector: Thrust's (whose `resize` writes every new element, a launch of its own on
/// CUDA), with `resize_for_overwrite`, which leaves new elements unwritten for arrays that a stage
/// then writes whole. A cloth grows with every tear, and every stage array with it: through
/// Thrust's resize each would cost a launch per tear for values nobody reads.
template <class Base>
class Vector : public Base {
 public:
  using Base::Base;
  using Base::operator=;
  Vector() = default;

  /// Resizes to `n` elements; those past the old size hold whatever the memory held.
  void resize_for_overwrite(std::size_t n) {
    static_assert(std::is_trivially_copyable<typename Base::value_type>::value &&
                      std::is_trivially_destructible<typename Base::value_type>::value,
                  "only for plain values");
    if (n > this->capacity()) this->reserve(n);
    const std::size_t old = this->size();
    this->m_size = static_cast<typename Base::size_type>(n);
#if TEAR_POISON_GROWN
    // Sanitizer builds: what a stage leaves unwritten is garbage the tests see (a NaN, an index out
    // of range), not the zero that fresh memory often holds.
    using T = typename Base::value_type;
    if (n > old) {
      T poison;
      std::memset(&poison, std::is_floating_point<T>::value ? 0xFF : 0xA5, sizeof poison);
      thrust::fill(this->begin() + static_cast<std::ptrdiff_t>(old), this->end(), poison);
    }
#else
    static_cast<void>(old);
#endif
  }
};

template <class System>
struct Traits;

template <>
struct Traits<Omp> {
  template <class T>
  using vector = Vector<thrust::omp::vector<T, CountingAllocator<T, thrust::omp::allocator<T>, Device::cpu>>>;
  static auto policy() { return thrust::omp::par; }
  /// The policy for stages given a temporary allocator: on the CPU, Thrust's own (malloc is cheap,
  /// and the OpenMP algorithms may allocate from several threads at once, which the caching
  /// allocator is not made for).
  template <class Allocator>
  static auto policy(Allocator&) {
    return thrust::omp::par;
  }
  static void synchronize() {}
  static void* allocate_bytes(std::size_t n) {
    void* p = std::malloc(n);
    if (p) count_allocation(Device::cpu, n);
    return p;
  }
  static void free_bytes(void* p, std::size_t n) {
    std::free(p);
    count_release(Device::cpu, n);
  }
  /// Host memory that backend memory is copied into without waiting (`ReadBack`): plain memory,
  /// and the copy is done when it returns.
  static void* allocate_staging(std::size_t n) { return std::malloc(n); }
  static void free_staging(void* p, std::size_t) { std::free(p); }
  static void copy_to_staging(void* host, const void* from, std::size_t n) { std::memcpy(host, from, n); }
  static void copy_from_staging(void* to, const void* host, std::size_t n) { std::memcpy(to, host, n); }
  /// A point in the backend's queue that the host can wait for (`Upload`): on the CPU, passed when
  /// recorded.
  class QueuePoint {
   public:
    void record() {}
    void wait() {}
  };
  /// A copy of backend memory to the host that runs beside the backend's later work (`start`),
  /// waited for by `wait` on any one thread. On the CPU backend memory is host memory: nothing is
  /// copied, and `wait` returns the memory itself, which must stay as it is until then.
  class HostCopy {
   public:
    void start(const void* from, std::size_t) { data_ = from; }
    const void* wait() { return data_; }

   private:
    const void* data_ = nullptr;
  };
  /// A point in the backend's queue of work, to time what lies between two (`elapsed_ms`, once
  /// both are passed). On the CPU the work is done when its call returns: the host's clock.
  class QueueMark {
   public:
    void record() { at_ = std::chrono::steady_clock::now(); }
    static double elapsed_ms(const QueueMark& a, const QueueMark& b) {
      return std::chrono::duration<double, std::milli>(b.at_ - a.at_).count();
    }

   private:
    std::chrono::steady_clock::time_point at_;
  };
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
  void deallocate(char* p, std::size_t) noexcept { PoolAllocator<char>().deallocate(thrust::cuda::pointer<char>(p), 0); }
};

template <>
struct Traits<Cuda> {
  template <class T>
  using vector = Vector<thrust::cuda::vector<T, CountingAllocator<T, PoolAllocator<T>, Device::cuda>>>;
  // Stages queue on the default stream without waiting; reading a result back (a count, a total)
  // is what synchronises, so a cut waits only where it needs a number on the host. Thrust's own
  // temporary storage (reductions, scans) comes from the same pool as the vectors, in stream order:
  // its default, cudaMalloc and cudaFree, would wait for the whole device around every such call.
  static auto policy() {
    static PoolBytes bytes;
    return thrust::cuda::par_nosync(bytes);
  }
  /// Thrust's temporary storage (sort and scan buffers) taken from `alloc`, which keeps its blocks:
  /// cudaMalloc and cudaFree synchronise the device, and a cut would otherwise call them per stage.
  template <class Allocator>
  static auto policy(Allocator& alloc) {
    return thrust::cuda::par_nosync(alloc);
  }
  static void synchronize() { cudaStreamSynchronize(0); }

 private:
  struct StagingPool {
    std::mutex mutex;
    std::multimap<std::size_t, void*> free;  // by size
  };
  static StagingPool& staging_pool() {
    static StagingPool* pool = new StagingPool;  // never destroyed: its blocks outlive every cloth
    return *pool;
  }

 public:
  static void* allocate_bytes(std::size_t n) {
    void* p = nullptr;
    if (cudaMalloc(&p, n) != cudaSuccess) return nullptr;
    count_allocation(Device::cuda, n);
    return p;
  }
  static void free_bytes(void* p, std::size_t n) {
    cudaFree(p);
    count_release(Device::cuda, n);
  }
  /// Page-locked host memory: a copy into it is queued on the default stream behind the stages
  /// and the host goes on (into pageable memory the copy would wait for the device first). Blocks
  /// are kept for the process's lifetime and handed out again: cudaMallocHost takes about a
  /// millisecond, which a cloth made for one cut would otherwise pay at its cut.
  static void* allocate_staging(std::size_t n) {
    StagingPool& pool = staging_pool();
    {
      const std::lock_guard<std::mutex> lock(pool.mutex);
      const auto free = pool.free.lower_bound(n);
      if (free != pool.free.end()) {
        void* p = free->second;
        pool.free.erase(free);
        return p;
      }
    }
    void* p = nullptr;
    if (cudaMallocHost(&p, n) != cudaSuccess) {
      cudaGetLastError();
      return nullptr;
    }
    return p;
  }
  /// `n`: the size `p` was asked for.
  static void free_staging(void* p, std::size_t n) {
    StagingPool& pool = staging_pool();
    const std::lock_guard<std::mutex> lock(pool.mutex);
    pool.free.emplace(n, p);
  }
  static void copy_to_staging(void* host, const void* from, std::size_t n) {
    const cudaError_t status = cudaMemcpyAsync(host, from, n, cudaMemcpyDeviceToHost, 0);
    if (status != cudaSuccess) {
      cudaGetLastError();
      throw std::bad_alloc();
    }
  }
  static void copy_from_staging(void* to, const void* host, std::size_t n) {
    const cudaError_t status = cudaMemcpyAsync(to, host, n, cudaMemcpyHostToDevice, 0);
    if (status != cudaSuccess) {
      cudaGetLastError();
      throw std::bad_alloc();
    }
  }
  /// A CUDA event in the default stream, made on its first record; `record` returns false (and
  /// leaves no error behind) where it cannot be made or recorded.
  class RecordedEvent {
   public:
    explicit RecordedEvent(unsigned flags) : flags_(flags) {}
    RecordedEvent(const RecordedEvent&) = delete;
    RecordedEvent& operator=(const RecordedEvent&) = delete;
    ~RecordedEvent() {
      if (event_) cudaEventDestroy(event_);
    }
    bool record() {
      if (!event_ && cudaEventCreateWithFlags(&event_, flags_) != cudaSuccess) event_ = nullptr;
      const bool recorded = event_ && cudaEventRecord(event_, 0) == cudaSuccess;
      if (!recorded) cudaGetLastError();
      return recorded;
    }
    cudaEvent_t get() const { return event_; }

   private:
    unsigned flags_;
    cudaEvent_t event_ = nullptr;
  };
  /// A point in the default stream (an event without timing) that the host can wait for.
  class QueuePoint {
   public:
    void record() { state_ = event_.record() ? State::recorded : State::unrecorded; }
    /// Waits until the device has passed the last point recorded (the whole default stream where it
    /// could not be recorded); returns at once when none was recorded since the last wait.
    void wait() {
      if (state_ == State::recorded)
        cudaEventSynchronize(event_.get());
      else if (state_ == State::unrecorded)
        cudaStreamSynchronize(0);
      state_ = State::none;
    }

   private:
    enum class State { none, recorded, unrecorded };
    RecordedEvent event_{cudaEventDisableTiming};
    State state_ = State::none;
  };
  /// The stream of `HostCopy`: one of its own, that does not wait for the default stream's later
  /// work (non-blocking), so a frame's copy runs while the next frame computes. The default stream
  /// where one cannot be made.
  static cudaStream_t copy_stream() {
    static const cudaStream_t stream = [] {
      cudaStream_t s = nullptr;
      if (cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking) != cudaSuccess) {
        cudaGetLastError();
        s = nullptr;
      }
      return s;
    }();
    return stream;
  }
  /// A copy of device memory to page-locked host memory on `copy_stream`, queued by `start` behind
  /// the default stream's work so far and waited for by `wait` on any one thread; the default
  /// stream goes on meanwhile. The device memory must stay as it is until the copy is waited for
  /// (the destructor waits too). The host memory comes from the staging pool in sizes rounded up
  /// to a power of two, so frames that grow a little at a time reuse blocks.
  class HostCopy {
   public:
    HostCopy() = default;
    HostCopy(const HostCopy&) = delete;
    HostCopy& operator=(const HostCopy&) = delete;
    ~HostCopy() {
      if (done_) {
        cudaEventSynchronize(done_);
        cudaEventDestroy(done_);
        cudaGetLastError();
      }
      if (host_) free_staging(host_, capacity_);
    }
    void start(const void* from, std::size_t n) {
      if (n == 0) return;  // nothing to copy: `wait` returns null
      capacity_ = std::size_t(1) << 16;
      while (capacity_ < n) capacity_ *= 2;
      host_ = allocate_staging(capacity_);
      if (!host_) throw std::bad_alloc();
      const cudaStream_t stream = copy_stream();
      cudaEvent_t queued = nullptr;
      cudaError_t status = cudaEventCreateWithFlags(&queued, cudaEventDisableTiming);
      if (status == cudaSuccess) status = cudaEventRecord(queued, 0);
      if (status == cudaSuccess) status = cudaStreamWaitEvent(stream, queued, 0);
      if (queued) cudaEventDestroy(queued);  // released once the stream has passed it
      if (status == cudaSuccess) status = cudaMemcpyAsync(host_, from, n, cudaMemcpyDeviceToHost, stream);
      if (status == cudaSuccess) status = cudaEventCreateWithFlags(&done_, cudaEventDisableTiming);
      if (status == cudaSuccess) status = cudaEventRecord(done_, stream);
      if (status != cudaSuccess) fail(status);
    }
    const void* wait() {
      if (done_) {
        const cudaError_t status = cudaEventSynchronize(done_);
        if (status != cudaSuccess) fail(status);
      }
      return host_;
    }

   private:
    [[noreturn]] static void fail(cudaError_t status) {
      cudaGetLastError();
      throw runtime_error(std::string("a frame could not be copied from the device: ") + cudaGetErrorString(status));
    }
    void* host_ = nullptr;
    std::size_t capacity_ = 0;
    cudaEvent_t done_ = nullptr;
  };
  /// A point in the default stream (a CUDA event), to time the device's work between two
  /// (`elapsed_ms`, once the device has passed both) without waiting for it in between.
  class QueueMark {
   public:
    void record() { event_.record(); }
    static double elapsed_ms(const QueueMark& a, const QueueMark& b) {
      float ms = 0;
      if (!a.event_.get() || !b.event_.get() || cudaEventElapsedTime(&ms, a.event_.get(), b.event_.get()) != cudaSuccess) {
        cudaGetLastError();
        return 0;
      }
      return ms;
    }

   private:
    RecordedEvent event_{cudaEventDefault};
  };
};
#endif

template <class System, class T>
using vector = typename Traits<System>::template vector<T>;

#if TEAR_CUDA_SYSTEM
namespace detail {
/// Programmatic dependent launch (compute capability 9.0 and up). A stage's kernel is queued with
/// leave to start before the kernel ahead of it in the stream has finished: its blocks are placed
/// on the multiprocessors while the kernel ahead runs, then wait at `wait_for_kernel_ahead` until
/// that kernel has finished and its writes are visible. What a launch costs the device between
/// two dependent kernels (a microsecond or two) is then paid beside the kernel ahead, not after
/// it. Every kernel queued this way waits before it touches memory, so each still sees all the
/// work queued before it: the kernel ahead had waited for its own predecessor before finishing.
__device__ inline void wait_for_kernel_ahead() {
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ >= 900
  asm volatile("griddepcontrol.wait;" ::: "memory");
#endif
}
/// Lets the next kernel queued with leave to start early place its blocks; called once this
/// kernel has waited, so at most one kernel waits ahead of its turn.
__device__ inline void let_next_kernel_start() {
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ >= 900
  asm volatile("griddepcontrol.launch_dependents;");
#endif
}

/// The largest grid queued with leave to start early: 0 where the device does not take
/// programmatic dependent launches, else four blocks per multiprocessor (asked once). A larger
/// grid runs long enough that a launch's gap is lost in it, and was measured slower with the leave
/// (on an H100, a cut of a million faces by 6 %, of four million by 13 %).
inline unsigned dependent_launch_max_blocks() {
  static const unsigned blocks = [] {
    int device = 0, major = 0, sms = 0;
    if (cudaGetDevice(&device) != cudaSuccess ||
        cudaDeviceGetAttribute(&major, cudaDevAttrComputeCapabilityMajor, device) != cudaSuccess ||
        cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device) != cudaSuccess) {
      cudaGetLastError();
      return 0u;
    }
    return major >= 9 && sms > 0 ? 4u * static_cast<unsigned>(sms) : 0u;
  }();
  return blocks;
}

/// Whether a grid of `grid` blocks is queued with leave to start early.
inline bool launch_early(unsigned grid) { return grid <= dependent_launch_max_blocks(); }

/// Queues `kernel<<<grid, block>>>(args...)` on the default stream, with leave to start before the
/// kernel ahead of it finishes where `early` (`launch_early(grid)`). The kernel must then begin
/// with `wait_for_kernel_ahead()`.
template <class... Params, class... Args>
void launch_dependent(void (*kernel)(Params...), unsigned grid, unsigned block, bool early, Args... args) {
  cudaLaunchConfig_t config{};
  config.gridDim = dim3(grid);
  config.blockDim = dim3(block);
  cudaLaunchAttribute leave[1];
  leave[0].id = cudaLaunchAttributeProgrammaticStreamSerialization;
  leave[0].val.programmaticStreamSerializationAllowed = 1;
  config.attrs = leave;
  config.numAttrs = early ? 1 : 0;
  const cudaError_t status = cudaLaunchKernelEx(&config, kernel, args...);
  if (status != cudaSuccess) {
    cudaGetLastError();
    throw runtime_error(std::string("a kernel could not be launched: ") + cudaGetErrorString(status));
  }
}

/// `early`: queued with leave to start early (a small grid). A large grid skips the two grid
/// controls: in every block they made large kernels slower even queued without the leave (on an
/// H100 the node mapping of a million-face cut went from 56 to 63 µs).
template <class F>
__global__ void for_each_index_kernel(F f, index_t count, bool early) {
  if (early) {
    wait_for_kernel_ahead();
    let_next_kernel_start();
  }
  const index_t i = static_cast<index_t>(blockIdx.x * blockDim.x + threadIdx.x);
  if (i < count) f(i);
}
}  // namespace detail
#endif

/// Runs f(i) for every i in [0, count) on `System`'s backend, queued behind the work before it.
/// On CUDA one element per thread in blocks of 128: Thrust's for_each gives each thread two
/// elements one after the other, which doubles a pass whose elements each wait on a chain of
/// loads (the per-node passes of a cut, the topology and the solver's model), and on a mesh of a
/// few thousand nodes leaves most of the device's multiprocessors idle.
template <class System, class F>
void for_each_index(index_t count, const F& f) {
  if (count <= 0) return;
#if TEAR_CUDA_SYSTEM
  if constexpr (std::is_same<System, Cuda>::value) {
    constexpr int block = 128;
    const auto grid = static_cast<unsigned>((count + block - 1) / block);
    const bool early = detail::launch_early(grid);
    detail::launch_dependent(detail::for_each_index_kernel<F>, grid, block, early, f, count, early);
    return;
  }
#endif
  thrust::for_each(Traits<System>::policy(), thrust::counting_iterator<index_t>(0),
                   thrust::counting_iterator<index_t>(count), f);
}

#if TEAR_CUDA_SYSTEM
namespace detail {
/// An exclusive sum of `count` integers by one block, tile after tile, each tile's sum carried into
/// the next (`in` and `out` may be the same: a tile is read whole before it is written). A tile is
/// loaded and stored warp by warp in consecutive addresses and turned to one run per thread in
/// shared memory: every load of a tile is issued before any is used.
template <int Threads, int Items>
__global__ void __launch_bounds__(Threads) one_block_exclusive_sum(const index_t* in, index_t* out, index_t count) {
  using Load = cub::BlockLoad<index_t, Threads, Items, cub::BLOCK_LOAD_TRANSPOSE>;
  using Store = cub::BlockStore<index_t, Threads, Items, cub::BLOCK_STORE_TRANSPOSE>;
  using Scan = cub::BlockScan<index_t, Threads>;
  __shared__ union {
    typename Load::TempStorage load;
    typename Store::TempStorage store;
    typename Scan::TempStorage scan;
  } temp;
  __shared__ index_t carry;
  wait_for_kernel_ahead();
  let_next_kernel_start();
  if (threadIdx.x == 0) carry = 0;
  __syncthreads();
  for (index_t base = 0; base < count; base += Threads * Items) {
    const int valid = static_cast<int>(count - base < Threads * Items ? count - base : Threads * Items);
    index_t v[Items];
    Load(temp.load).Load(in + base, v, valid, index_t(0));
    __syncthreads();  // `temp` is the scan's next
    index_t tile_sum;
    Scan(temp.scan).ExclusiveSum(v, v, tile_sum);
    const index_t before = carry;
    for (int j = 0; j < Items; ++j) v[j] += before;
    __syncthreads();  // every thread has read `carry` and is done with `temp`
    if (threadIdx.x == 0) carry = before + tile_sum;
    Store(temp.store).Store(out + base, v, valid);
    __syncthreads();  // `temp` is the next tile's load; `carry` is written
  }
}
}  // namespace detail
#endif

/// out[i] = in[0] + ... + in[i - 1] for i in [0, count), on `System`'s backend; `in` and `out`
/// may be the same. On CUDA, up to `one_block_limit` values are summed by one block in one launch:
/// a device-wide scan costs two launches and its dispatch on the host, which a cut of a small mesh
/// pays at every scan.
template <class System, class Policy>
void exclusive_sum(const Policy& policy, const index_t* in, index_t* out, index_t count) {
  if (count <= 0) return;
#if TEAR_CUDA_SYSTEM
  if constexpr (std::is_same<System, Cuda>::value) {
    constexpr int threads = 1024, items = 8;
    constexpr index_t one_block_limit = 4 * threads * items;
    if (count <= one_block_limit) {
      detail::launch_dependent(detail::one_block_exclusive_sum<threads, items>, 1, threads, detail::launch_early(1), in,
                               out, count);
      return;
    }
  }
#endif
  thrust::exclusive_scan(policy, in, in + count, out);
}

/// Resizes `v` to `n` elements for its stage to write them all: new elements are left unwritten
/// (`Vector::resize_for_overwrite`). When an allocated vector must grow, its capacity becomes n
/// plus an eighth (Thrust's own resize would double it): a cloth grows a little with every cut, and
/// its arrays should neither be reallocated every cut nor hold twice what they need. An empty one
/// gets exactly n.
template <class V>
void resize_for_overwrite(V& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(v.capacity() > 0 ? n + n / 8 : n);
  v.resize_for_overwrite(n);
}

/// Copies between the host and a backend's vectors. Thrust's copy of an empty range still forms a
/// reference to the first element of its destination, which an empty vector does not have (a
/// null reference: undefined behaviour, reported by UBSan for every mesh without UVs and every
/// simulation without colliders); these helpers copy nothing then.
///
/// `v` [n] in `System`'s memory → a host vector of n `T`s.
template <class T, class Vector>
std::vector<T> to_host(const Vector& v) {
  std::vector<T> out(v.size());
  if (!out.empty()) thrust::copy(v.begin(), v.end(), out.begin());
  return out;
}

/// `v` becomes a copy of the host range `host` (any container with begin, end and empty).
template <class Vector, class HostRange>
void assign_from_host(Vector& v, const HostRange& host) {
  if (host.empty())
    v.clear();
  else
    v.assign(host.begin(), host.end());
}

/// Small values read back from the backend together: each `queue` copies values from backend
/// memory behind the stages queued so far, without waiting, and one `wait` then makes them all
/// readable. A cut reads its totals this way, one wait instead of one per value. Offsets, not
/// pointers, name what was queued: the staging memory may move when it grows.
template <class System>
class ReadBack {
 public:
  ReadBack() = default;
  ReadBack(const ReadBack&) = delete;
  ReadBack& operator=(const ReadBack&) = delete;
  ~ReadBack() {
    if (data_) Traits<System>::free_staging(data_, capacity_);
  }

  /// Starts a new batch (what was queued before is forgotten).
  void clear() {
    wait();  // a copy still under way must not land in memory the new batch reuses
    used_ = 0;
  }

  /// Queues a copy of `count` values at backend address `from`; returns the offset `at` takes.
  template <class T>
  std::size_t queue(const T* from, std::size_t count) {
    const std::size_t offset = (used_ + alignof(std::max_align_t) - 1) / alignof(std::max_align_t) * alignof(std::max_align_t);
    const std::size_t bytes = count * sizeof(T);
    if (offset + bytes > capacity_) grow(offset + bytes);
    if (bytes > 0) {
      Traits<System>::copy_to_staging(data_ + offset, from, bytes);
      pending_ = true;
    }
    used_ = offset + bytes;
    return offset;
  }

  /// Waits for the copies queued (and everything queued on the backend before them); waits for
  /// nothing when none was queued since the last wait.
  void wait() {
    if (!pending_) return;
    Traits<System>::synchronize();
    pending_ = false;
  }

  /// The values queued at `offset`, after `wait`.
  template <class T>
  const T* at(std::size_t offset) const {
    return reinterpret_cast<const T*>(data_ + offset);
  }

 private:
  void grow(std::size_t bytes) {
    const std::size_t capacity = std::max<std::size_t>(2 * capacity_, std::max<std::size_t>(bytes, 4096));
    char* next = static_cast<char*>(Traits<System>::allocate_staging(capacity));
    if (!next) throw std::bad_alloc();
    if (data_) {
      wait();  // the copies already queued land in the old memory
      std::memcpy(next, data_, used_);
      Traits<System>::free_staging(data_, capacity_);
    }
    data_ = next;
    capacity_ = capacity;
  }

  char* data_ = nullptr;
  std::size_t capacity_ = 0, used_ = 0;
  bool pending_ = false;  // copies queued since the last wait
};

/// Small host arrays sent to the backend together, without waiting: each `send` copies the values
/// into page-locked staging and queues their copy to the backend before the stages queued after it.
/// A batch reuses the staging once the backend has read the batch before (`begin` waits for that
/// point, long passed by then). A cut sends its paths this way: no wait, where a copy from
/// pageable memory waits for the device.
template <class System>
class Upload {
 public:
  Upload() = default;
  Upload(const Upload&) = delete;
  Upload& operator=(const Upload&) = delete;
  ~Upload() {
    sent_.wait();
    if (data_) Traits<System>::free_staging(data_, capacity_);
  }

  /// Starts a batch of `bytes` at most (the sum of the batch's sends, each aligned).
  void begin(std::size_t bytes) {
    sent_.wait();
    used_ = 0;
    if (bytes <= capacity_) return;
    if (data_) Traits<System>::free_staging(data_, capacity_);
    data_ = nullptr;
    capacity_ = 0;
    const std::size_t capacity = std::max<std::size_t>(bytes, 4096);
    data_ = static_cast<char*>(Traits<System>::allocate_staging(capacity));
    if (!data_) throw std::bad_alloc();
    capacity_ = capacity;
  }

  /// The staging a send of `count` values of T takes in a batch.
  template <class T>
  static std::size_t bytes_for(std::size_t count) {
    return (count * sizeof(T) + alignof(std::max_align_t) - 1) / alignof(std::max_align_t) * alignof(std::max_align_t);
  }

  /// `to` resized to `from`'s values, copied there behind the stages queued so far.
  template <class Vector, class T>
  void send(Vector& to, const std::vector<T>& from) {
    resize_for_overwrite(to, from.size());
    const std::size_t bytes = from.size() * sizeof(T);
    if (bytes == 0) return;
    if (used_ + bytes_for<T>(from.size()) > capacity_) throw std::logic_error("Upload: a send beyond its batch");
    std::memcpy(data_ + used_, from.data(), bytes);
    Traits<System>::copy_from_staging(thrust::raw_pointer_cast(to.data()), data_ + used_, bytes);
    used_ += bytes_for<T>(from.size());
    sent_.record();
  }

 private:
  char* data_ = nullptr;
  std::size_t capacity_ = 0, used_ = 0;
  typename Traits<System>::QueuePoint sent_;  // after the last copy sent
};

template <class T, class Vector>
T* raw(Vector& v) {
  return thrust::raw_pointer_cast(v.data());
}
template <class T, class Vector>
const T* raw(const Vector& v) {
  return thrust::raw_pointer_cast(v.data());
}

}  // namespace tear::backend

/// Instantiates `MACRO(System)` for every system this translation unit can run: the OpenMP
/// system always, the CUDA system in a CUDA build.
#if TEAR_CUDA_SYSTEM
#define TEAR_FOR_EACH_SYSTEM(MACRO) \
  MACRO(::tear::backend::Omp)       \
  MACRO(::tear::backend::Cuda)
#else
#define TEAR_FOR_EACH_SYSTEM(MACRO) MACRO(::tear::backend::Omp)
#endif
