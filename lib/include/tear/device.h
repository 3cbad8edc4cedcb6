// tear: choosing the backend that runs the kernels.
#pragma once

#include <cstddef>
#include <string>
#include <thread>

namespace tear {

/// The two backends every kernel runs on: the GPU through Thrust's CUDA system, or the CPU
/// through Thrust's OpenMP system.
enum class Device { cpu = 0, cuda = 1 };

/// True when this build carries the CUDA backend.
bool cuda_compiled();

/// True when the CUDA backend is compiled in and at least one usable GPU is present.
bool cuda_available();

/// Parses `auto`, `cpu`, `cuda` or `cuda:N` and picks the backend. `auto` is CUDA when a usable
/// GPU is present, else the CPU. `cuda` without a GPU (or in a CPU-only build) throws a usage
/// error. `cuda:N` also makes GPU N the current device.
Device select_device(const std::string& spec);

/// Makes `device` ready for work on a thread of its own while the caller goes on (reading its
/// input, say): on CUDA it creates the current GPU's context, which takes a tenth of a second and
/// more and would otherwise be waited for at the first use of the GPU; that first use now waits
/// only for what is left of it. Nothing on the CPU. The destructor waits for the thread.
class DeviceWarmUp {
 public:
  explicit DeviceWarmUp(Device device);
  ~DeviceWarmUp();
  DeviceWarmUp(const DeviceWarmUp&) = delete;
  DeviceWarmUp& operator=(const DeviceWarmUp&) = delete;

 private:
  std::thread thread_;
};

/// "cpu" or "cuda".
const char* to_string(Device device);

/// The GPU that work on Device::cuda goes to from this thread (CUDA's current device; `--device
/// cuda:N` selects it), or -1 where there is none (a CPU-only build, no usable GPU).
int current_gpu();

/// A human-readable name of the hardware: the GPU's name, or "CPU (N threads)".
std::string device_name(Device device);

/// Waits until the work queued on `device` is done (the CUDA backend queues without waiting).
void synchronize(Device device);

/// Limits the CPU backend's OpenMP teams made from this thread, and the frame writers it starts
/// (tear/frame_writer.h, the USD layer's writer), to `threads` (>= 1); what `--threads N` does.
/// Without it the limit is OpenMP's: `OMP_NUM_THREADS`, else the hardware threads (the `tear`
/// program turns a Slurm job's `SLURM_CPUS_PER_TASK` into `OMP_NUM_THREADS`, docs/cli.md).
void set_cpu_threads(int threads);

/// The limit `set_cpu_threads` set for this thread, else OpenMP's (a thread that starts another,
/// which begins with OpenMP's, hands it on so).
int cpu_threads();

/// Memory held by tear's arrays on a backend now, and the most held since the last
/// `reset_memory_peak`, in bytes: GPU memory for Device::cuda (arrays and cached scratch buffers);
/// host memory of the CPU backend's arrays for Device::cpu (without Thrust's short-lived scratch
/// buffers of scans and sorts, which it allocates for itself there).
std::size_t memory_in_use(Device device);
std::size_t memory_peak(Device device);
/// Starts a new peak from the memory in use now.
void reset_memory_peak(Device device);

}  // namespace tear
