#!/usr/bin/env bash
# Before and after one change, in one run on the GPU machine: builds the older source tree OLD_SRC
# (e.g. `git archive <commit> | tar -x -C old-src`) beside the current one, runs the paper's scene
# with both on both backends and checks the frames are the same meshes up to node order
# (scripts/compare-sorted.py: exactly for the unsimulated paper scene, within a tolerance for the
# simulated demo), then runs `tear bench` remesh and scene parts of both, alternating
# old and new, so the figures are ratios of one run. Logs go to LOG_DIR.
#   [SKIP_BENCH=1] scripts/gpu-compare.sh OLD_SRC LOG_DIR [NEW_BUILD_DIR]   (after scripts/gpu-suite.sh built NEW_BUILD_DIR)
set -uo pipefail
old_src=$1
log_dir=$2
new_build=${3:-build-gpu}
old_build=build-old
mkdir -p "$log_dir"
arch=${CMAKE_CUDA_ARCHITECTURES:-native}
if [ ! -x "$old_build/tear" ]; then
  cmake -S "$old_src" -B "$old_build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CUDA_ARCHITECTURES="$arch" \
    -DTEAR_BUILD_TESTS=OFF > "$log_dir/old-configure.log" 2>&1 &&
    cmake --build "$old_build" -j"$(nproc)" --target tear_cli > "$log_dir/old-build.log" 2>&1 ||
    { tail -20 "$log_dir/old-build.log"; exit 1; }
fi
status=0
compare() {  # compare NAME OLD_DIR NEW_DIR [--tolerance T]
  local name=$1 a=$2 b=$3
  shift 3
  local line
  line=$(python3 scripts/compare-sorted.py "$a" "$b" "$@" | tail -1) || status=1
  echo "$name: $line" | tee -a "$log_dir/compare.txt"
}
for device in cuda cpu; do
  # The paper's scene as `tear run` (cuts only): the same meshes up to node order, exactly.
  for res in low high; do
    rm -rf "/tmp/cmp-run-old" "/tmp/cmp-run-new"
    "$old_build/tear" run "examples/meshes/sheet_$res.obj" examples/paper_scene.json -o /tmp/cmp-run-old/f.####.obj --device "$device"
    "$new_build/tear" run "examples/meshes/sheet_$res.obj" examples/paper_scene.json -o /tmp/cmp-run-new/f.####.obj --device "$device"
    compare "run paper_scene $res on $device, exact" /tmp/cmp-run-old /tmp/cmp-run-new
    compare "run paper_scene $res on $device, within 1e-6" /tmp/cmp-run-old /tmp/cmp-run-new --tolerance 1e-6
  done
  # The simulated demo: positions depend on the summation order, hence on node order, in the last bits.
  for res in low high; do
    rm -rf "/tmp/cmp-old-$device-$res" "/tmp/cmp-new-$device-$res"
    "$old_build/tear" demo --resolution "$res" --device "$device" -o "/tmp/cmp-old-$device-$res" > /dev/null
    "$new_build/tear" demo --resolution "$res" --device "$device" -o "/tmp/cmp-new-$device-$res" > /dev/null
    compare "demo $res on $device, within 1e-4" "/tmp/cmp-old-$device-$res" "/tmp/cmp-new-$device-$res" --tolerance 1e-4
  done
done
[ -n "${SKIP_BENCH:-}" ] && exit $status
for round in 1 2; do
  for which in old new; do
    build=$old_build
    [ "$which" = new ] && build=$new_build
    "$build/tear" bench --only remesh,scene --no-cpu --repeats "${REPEATS:-5}" --json "$log_dir/bench-$which-$round.json" \
      > "$log_dir/bench-$which-$round.txt" 2>&1 || status=1
  done
done
exit $status
