// tear: launching a kernel on a backend: `for_each_index` and `exclusive_sum`, on CUDA with
// programmatic dependent launch and a one-block scan for small counts.
#pragma once

#include <string>
#include <type_traits>

#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>

#include "backend/compiled_systems.h"
#include "backend/traits.h"
#include "hd.h"
#include "tear/error.h"

namespace tear::backend {

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

}  // namespace tear::backend
