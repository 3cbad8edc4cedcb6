#!/usr/bin/env bash
# On the GPU host: builds tear with the CUDA backend, runs the tearing and crack-growth tests on the
# GPU, the pull and punch scenes at every resolution (frames kept: 12, 24, 48, as PLY), the parity
# test, and `tear bench --only tear`. Logs and frames go to the folder given (default: gpu-tearing).
#   scripts/gpu-tearing.sh [OUT_DIR] [BUILD_DIR]
set -uo pipefail
out=${1:-gpu-tearing}
build=${2:-build-gpu}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$out/machine.txt" 2>&1
start=$(date +%s)
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CUDA_ARCHITECTURES=${CMAKE_CUDA_ARCHITECTURES:-native} \
  > "$out/configure.log" 2>&1 || { tail -30 "$out/configure.log"; exit 1; }
cmake --build "$build" -j"$(nproc)" > "$out/build.log" 2>&1 || { grep -E "error|FAILED" "$out/build.log" | head -40; exit 1; }
echo "build: $(( $(date +%s) - start )) s"
TEAR_TEST_DEVICE=cuda "$build/tests/tear_tests" "[tearing]" > "$out/tearing-cuda.log" 2>&1; tail -2 "$out/tearing-cuda.log"
for scene in pull punch; do
  for r in low medium high; do
    t0=$(date +%s%N)
    "$build/tear" demo --device cuda --scene $scene --resolution $r -o "$out/frames/$scene-$r/f.####.ply" \
      --report "$out/$scene-$r.json" > "$out/$scene-$r.log" 2>&1
    echo "$scene $r: exit $? $(( ($(date +%s%N) - t0) / 1000000 )) ms"
    find "$out/frames/$scene-$r" -name 'f.*.ply' ! -name 'f.0012.ply' ! -name 'f.0024.ply' ! -name 'f.0048.ply' -delete
  done
done
"$build/tear" bench --device cuda --only tear > "$out/bench-tear.txt" 2>&1; tail -8 "$out/bench-tear.txt"
