#!/usr/bin/env bash
# Fuzzes tear with libFuzzer for MINUTES minutes (default 10): mesh reading (OBJ, PLY, glTF, GLB),
# cut script parsing and cutting, with a validity oracle (tests/fuzz/fuzz_tear.cpp says what
# counts as a failure). Builds the fuzz target with clang, ASan and UBSan in BUILD_DIR (default
# build-fuzz), starting from tests/fuzz/seeds and tests/fuzz/corpus; the inputs it finds grow
# BUILD_DIR/fuzz-corpus, failures land in BUILD_DIR/fuzz-artifacts. Copy each failing input into
# tests/fuzz/corpus (a short name saying what it does): ctest then replays it as a regression test.
#   scripts/fuzz.sh [MINUTES] [BUILD_DIR]
# JOBS (default 1) runs that many fuzzing processes side by side; extra libFuzzer options go in
# FUZZ_OPTIONS. The run goes on after a failure (libFuzzer's fork mode), so one run finds several.
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=${1:-10}
build_dir=${2:-build-fuzz}
jobs=${JOBS:-1}
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DTEAR_CUDA=OFF -DTEAR_FUZZ=ON -DTEAR_BUILD_TESTS=ON > "$build_dir.configure.log" 2>&1 ||
  { tail -30 "$build_dir.configure.log"; exit 1; }
cmake --build "$build_dir" -j"${BUILD_JOBS:-2}" --target tear_fuzz
corpus="$build_dir/fuzz-corpus"
artifacts="$build_dir/fuzz-artifacts"
mkdir -p "$corpus" "$artifacts"
# One OpenMP thread: a fuzzing process is one core's worth of work, and libFuzzer's coverage and
# timing stay per input.
export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive
# Every sanitizer report is a failure, but for the suppressed idioms of third-party code.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1:abort_on_error=1:suppressions=$PWD/tests/sanitizers/ubsan.supp}
seconds=$((minutes * 60))
options=(-max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1
  -artifact_prefix="$artifacts/" -fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
start=$(date +%s)
status=0
# shellcheck disable=SC2086
inputs=("$corpus")
for folder in tests/fuzz/seeds tests/fuzz/corpus; do [ -d "$folder" ] && inputs+=("$folder"); done
"$build_dir/tests/fuzz/tear_fuzz" "${options[@]}" ${FUZZ_OPTIONS:-} "${inputs[@]}" || status=$?
echo "fuzz: $(( ($(date +%s) - start) / 60 )) min, $(find "$corpus" -type f | wc -l) inputs in $corpus," \
  "$(find "$artifacts" -type f | wc -l) failing inputs in $artifacts"
exit $status
