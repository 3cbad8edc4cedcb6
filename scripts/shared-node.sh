#!/usr/bin/env bash
# How tear's CPU runs share a node: the time of one run alone, then of three runs started at once.
#
#   scripts/shared-node.sh [TEAR_BINARY] [-- EXTRA TEAR ARGUMENTS]
#
# Each run is `tear demo --scene pull --frames 8 --device cpu` (into a folder of its own under a
# temporary folder); extra arguments (`--threads 1`) go to every run. Prints the wall time of the
# run alone and of each of the three together, and the three's total against three runs one after
# the other. With passive OpenMP waits (tear's default) three runs on a node of few cores take
# about the time of running them in turn, not more: no run burns a core spinning while it waits.
set -euo pipefail

tear=${1:-build-cpu/tear}
shift || true
[[ "${1:-}" == "--" ]] && shift
extra=("$@")
if [[ ! -x "$tear" ]]; then
  echo "shared-node.sh: no tear binary at '$tear' (build it, or give its path)" >&2
  exit 1
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Wall seconds of one run into folder $1, written to $work/$1.time.
run() {
  local start end
  start=$(date +%s.%N)
  "$tear" demo --scene pull --frames 8 --device cpu --progress none -o "$work/$1" "${extra[@]}" >/dev/null
  end=$(date +%s.%N)
  echo "$end - $start" | bc >"$work/$1.time"
}

echo "cores: $(nproc), load before: $(cut -d' ' -f1-3 /proc/loadavg)"
run alone
alone=$(cat "$work/alone.time")
printf 'one run alone:          %6.2f s\n' "$alone"

start=$(date +%s.%N)
run a & pa=$!
run b & pb=$!
run c & pc=$!
wait "$pa" "$pb" "$pc"
end=$(date +%s.%N)
for r in a b c; do printf 'run %s of three at once: %6.2f s\n' "$r" "$(cat "$work/$r.time")"; done
together=$(echo "$end - $start" | bc)
printf 'three at once, in all:  %6.2f s (three alone in turn: %.2f s, ratio %.2f)\n' "$together" \
  "$(echo "3 * $alone" | bc)" "$(echo "$together / (3 * $alone)" | bc -l)"
