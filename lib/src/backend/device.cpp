#include "tear/device.h"

#include <omp.h>

#include <atomic>
#include <string>
#include <system_error>

#include "backend/device_memory.h"

#include "tear/error.h"

#if TEAR_WITH_CUDA
#include <cuda_runtime_api.h>
#endif

namespace tear {

bool cuda_compiled() { return TEAR_WITH_CUDA != 0; }

bool cuda_available() {
#if TEAR_WITH_CUDA
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess) {
    cudaGetLastError();  // clear the sticky "no driver" error
    return false;
  }
  return count > 0;
#else
  return false;
#endif
}

Device select_device(const std::string& spec) {
  if (spec == "cpu") return Device::cpu;
  if (spec == "auto") return cuda_available() ? Device::cuda : Device::cpu;
  if (spec == "cuda" || spec.rfind("cuda:", 0) == 0) {
    if (!cuda_compiled()) throw Error(ErrorKind::usage, "--device " + spec + ": this build of tear has no CUDA backend");
    if (!cuda_available()) throw Error(ErrorKind::usage, "--device " + spec + ": no usable CUDA GPU was found");
#if TEAR_WITH_CUDA
    if (spec.size() > 5) {
      const std::string number = spec.substr(5);
      int count = 0;
      cudaGetDeviceCount(&count);
      std::size_t used = 0;
      int ordinal = -1;
      try {
        ordinal = std::stoi(number, &used);
      } catch (const std::exception&) {
      }
      if (used != number.size() || ordinal < 0 || ordinal >= count)
        throw Error(ErrorKind::usage, "--device " + spec + ": expected cuda:N with N in 0.." + std::to_string(count - 1));
      if (cudaSetDevice(ordinal) != cudaSuccess) throw runtime_error("--device " + spec + ": cannot select that GPU");
    }
#endif
    return Device::cuda;
  }
  throw Error(ErrorKind::usage, "--device " + spec + ": expected auto, cpu, cuda or cuda:N");
}

DeviceWarmUp::DeviceWarmUp(Device device) {
#if TEAR_WITH_CUDA
  if (device != Device::cuda) return;
  int ordinal = 0;
  if (cudaGetDevice(&ordinal) != cudaSuccess) {
    cudaGetLastError();
    return;
  }
  try {
    // The current device is the calling thread's: the warm-up thread selects the same one.
    thread_ = std::thread([ordinal] {
      if (cudaSetDevice(ordinal) != cudaSuccess || cudaFree(nullptr) != cudaSuccess) cudaGetLastError();
    });
  } catch (const std::system_error&) {
    // No thread to spare: the first use of the GPU creates the context, as it would have.
  }
#else
  static_cast<void>(device);
#endif
}

DeviceWarmUp::~DeviceWarmUp() {
  if (thread_.joinable()) thread_.join();
}

namespace {
struct MemoryAccount {
  std::atomic<std::size_t> in_use{0}, peak{0};
};
MemoryAccount accounts[2];  // by Device
MemoryAccount& account(Device device) { return accounts[device == Device::cuda ? 1 : 0]; }
}  // namespace

namespace backend {
void count_allocation(Device device, std::size_t bytes) {
  MemoryAccount& a = account(device);
  const std::size_t now = a.in_use.fetch_add(bytes) + bytes;
  std::size_t peak = a.peak.load();
  while (now > peak && !a.peak.compare_exchange_weak(peak, now)) {
  }
}
void count_release(Device device, std::size_t bytes) { account(device).in_use.fetch_sub(bytes); }
}  // namespace backend

std::size_t memory_in_use(Device device) { return account(device).in_use.load(); }
std::size_t memory_peak(Device device) { return account(device).peak.load(); }
void reset_memory_peak(Device device) { account(device).peak.store(account(device).in_use.load()); }

void synchronize(Device device) {
#if TEAR_WITH_CUDA
  if (device == Device::cuda) cudaDeviceSynchronize();
#endif
  (void)device;
}

const char* to_string(Device device) { return device == Device::cuda ? "cuda" : "cpu"; }

int current_gpu() {
#if TEAR_WITH_CUDA
  int ordinal = -1;
  if (cudaGetDevice(&ordinal) == cudaSuccess) return ordinal;
  cudaGetLastError();
#endif
  return -1;
}

std::string device_name(Device device) {
#if TEAR_WITH_CUDA
  if (device == Device::cuda) {
    int ordinal = 0;
    cudaDeviceProp prop{};
    if (cudaGetDevice(&ordinal) == cudaSuccess && cudaGetDeviceProperties(&prop, ordinal) == cudaSuccess)
      return prop.name;
    return "CUDA GPU";
  }
#endif
  (void)device;
  return "CPU (" + std::to_string(omp_get_max_threads()) + " threads)";
}

int cpu_threads() { return omp_get_max_threads(); }

void set_cpu_threads(int threads) {
  if (threads < 1) throw Error(ErrorKind::usage, "--threads: expected a number >= 1, got " + std::to_string(threads));
  omp_set_num_threads(threads);
}

}  // namespace tear
