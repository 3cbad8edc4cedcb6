#!/usr/bin/env bash
# The floor under every tear command that uses the GPU: the wall time of a process that does nothing
# but start CUDA as tear does (count the devices, create the context, take one 64 MiB page-locked
# block as a frame's download does, give it back) and exit. Prints each run's wall time in ms and
# the steps' times inside the process. Needs nvcc and a GPU.
#   scripts/cuda-floor.sh [RUNS]   (default 5)
set -euo pipefail
runs=${1:-5}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat > "$dir/floor.cu" <<'EOF'
#include <chrono>
#include <cstdio>
#include <cuda_runtime.h>
int main() {
  using clock = std::chrono::steady_clock;
  const auto ms = [](clock::time_point a, clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  const auto t0 = clock::now();
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0) return 1;
  const auto t1 = clock::now();
  if (cudaFree(nullptr) != cudaSuccess) return 1;
  const auto t2 = clock::now();
  void* block = nullptr;
  if (cudaMallocHost(&block, std::size_t(64) << 20) != cudaSuccess) return 1;
  cudaFreeHost(block);
  const auto t3 = clock::now();
  std::printf("driver %.1f ms, context %.1f ms, 64 MiB page-locked %.1f ms\n", ms(t0, t1), ms(t1, t2), ms(t2, t3));
  return 0;
}
EOF
nvcc -O2 -o "$dir/floor" "$dir/floor.cu"
for ((i = 1; i <= runs; ++i)); do
  start=$(date +%s%N)
  inside=$("$dir/floor") || { echo "cuda-floor: CUDA did not start (no device?)" >&2; exit 1; }
  echo "run $i: process $(( ($(date +%s%N) - start) / 1000000 )) ms ($inside)"
done
