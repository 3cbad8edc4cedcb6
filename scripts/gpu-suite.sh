#!/usr/bin/env bash
# Builds tear with the CUDA backend on a machine with a GPU and runs the whole test suite on the
# GPU (TEAR_TEST_DEVICE=cuda), then on the CPU backend of the same binary, and the benchmarks
# when they exist. Logs go to the folder given as the first argument (default: gpu-logs).
#   scripts/gpu-suite.sh [LOG_DIR] [BUILD_DIR]
set -uo pipefail
log_dir=${1:-gpu-logs}
build_dir=${2:-build-gpu}
mkdir -p "$log_dir"
arch=${CMAKE_CUDA_ARCHITECTURES:-native}
{
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv
  nproc
} > "$log_dir/machine.txt" 2>&1
start=$(date +%s)
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CUDA_ARCHITECTURES="$arch" > "$log_dir/configure.log" 2>&1 || { tail -30 "$log_dir/configure.log"; exit 1; }
cmake --build "$build_dir" -j"$(nproc)" > "$log_dir/build.log" 2>&1 || { grep -E "error|FAILED" "$log_dir/build.log" | head -40; exit 1; }
echo "build: $(( $(date +%s) - start )) s"
status=0
TEAR_TEST_DEVICE=cuda ctest --test-dir "$build_dir" -j8 --output-on-failure > "$log_dir/ctest-cuda.log" 2>&1 || status=1
tail -5 "$log_dir/ctest-cuda.log"
ctest --test-dir "$build_dir" -j8 --output-on-failure > "$log_dir/ctest-cpu.log" 2>&1 || status=1
tail -3 "$log_dir/ctest-cpu.log"
TEAR_TEST_DEVICE=cuda "$build_dir/tests/tear_tests" "[parity]" > "$log_dir/parity.log" 2>&1 || status=1
tail -3 "$log_dir/parity.log"
exit $status
