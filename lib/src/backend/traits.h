// tear: `Traits<System>`, what differs between the two backends on the host: vectors, execution
// policies, synchronisation, staging memory, copies to the host and points in the backend's queue.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <new>
#include <string>

#include <thrust/system/omp/execution_policy.h>
#include <thrust/system/omp/vector.h>

#include "backend/allocators.h"
#include "backend/compiled_systems.h"
#include "backend/device_memory.h"
#include "backend/systems.h"
#include "backend/vector.h"
#include "tear/error.h"

namespace tear::backend {

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
  /// Bytes from memory the backend can read into its own (`Cloth::copy_node_pos_from`).
  static void copy_in(void* to, const void* from, std::size_t n) {
    if (n > 0) std::memcpy(to, from, n);
  }
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
  /// Bytes from GPU or host memory (unified addressing tells which) into the GPU's.
  static void copy_in(void* to, const void* from, std::size_t n) {
    if (n == 0) return;
    const cudaError_t status = cudaMemcpyAsync(to, from, n, cudaMemcpyDefault, 0);
    if (status != cudaSuccess) {
      cudaGetLastError();
      throw Error(ErrorKind::runtime, std::string("cannot copy the positions in: ") + cudaGetErrorString(status));
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
      if (!a.event_.get() || !b.event_.get() ||
          cudaEventElapsedTime(&ms, a.event_.get(), b.event_.get()) != cudaSuccess) {
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

}  // namespace tear::backend
