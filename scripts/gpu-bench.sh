#!/usr/bin/env bash
# Runs `tear bench` on a machine with a GPU, after scripts/gpu-suite.sh built BUILD_DIR: every part
# on the default sizes with the CPU backend alongside (the solver's substeps as persistent
# kernels, the default), then the solver and the scene again with TEAR_CUDA_LAUNCH=one-pass, =shared,
# =two-pass, =tiled, =graph and =plain, for the ratios. Output and JSON go to LOG_DIR, with the scaling plot of the first run
# (scaling.svg: time against faces, GPU and CPU, drawn by scripts/plot-bench.py).
#   [REPEATS=K] scripts/gpu-bench.sh [LOG_DIR] [BUILD_DIR] [extra tear bench options...]
# REPEATS (default 5) is --repeats; the extra options must not repeat --repeats, --only or --json.
set -uo pipefail
log_dir=${1:-gpu-logs}
build_dir=${2:-build-gpu}
shift 2 || true
mkdir -p "$log_dir"
tear="$build_dir/tear"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv > "$log_dir/machine.txt" 2>&1
git rev-parse --short HEAD >> "$log_dir/machine.txt" 2>/dev/null
date -u >> "$log_dir/machine.txt"
"$tear" bench --repeats "${REPEATS:-5}" --json "$log_dir/bench.json" "$@" 2>&1 | tee "$log_dir/bench.txt"
python3 "$(dirname "$0")/plot-bench.py" "$log_dir/bench.json" -o "$log_dir/scaling.svg" \
  --title "tear bench, $(head -2 "$log_dir/machine.txt" | tail -1 | cut -d, -f1)"
for mode in one-pass shared two-pass tiled graph plain; do
  TEAR_CUDA_LAUNCH=$mode "$tear" bench --repeats "${REPEATS:-5}" --only pd,scene --no-cpu --json "$log_dir/bench-$mode.json" "$@" 2>&1 |
    tee "$log_dir/bench-$mode.txt"
done
