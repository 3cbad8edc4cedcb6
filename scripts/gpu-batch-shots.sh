#!/usr/bin/env bash
# Many shots in one process against one process per shot, on the GPU: a 1M-face sheet (708 x 708
# nodes, UVs) as GLB, cut once by each shot and written as GLB; PROCESSES runs of `tear run` (default
# 10), then `tear batch` of 100 such shots, in the same run; prints the wall time per shot of each
# and checks that the batch's outputs are the processes' bytes. Needs python3. DEVICE (default
# cuda) and SHOTS (default 100) change the backend and the batch's length, for a quick try.
#   scripts/gpu-batch-shots.sh [BUILD_DIR] [WORK_DIR] [PROCESSES]
set -uo pipefail
tear=$(realpath "${1:-build-gpu}")/tear
work=${2:-/tmp/tear-batch-shots}
processes=${3:-10}
device=${DEVICE:-cuda}
shots=${SHOTS:-100}
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
[ "$device" = cpu ] || nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
python3 - <<'PY'
n = 708
with open("sheet.obj", "w") as out:
    out.write("".join("v %.6f %.6f 0\n" % (i / (n - 1), j / (n - 1)) for j in range(n) for i in range(n)))
    out.write("".join("vt %.6f %.6f\n" % (i / (n - 1), j / (n - 1)) for j in range(n) for i in range(n)))
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i + 1
            faces.append("f %d/%d %d/%d %d/%d\nf %d/%d %d/%d %d/%d\n" % (a, a, a + 1, a + 1, a + n + 1, a + n + 1,
                                                                      a, a, a + n + 1, a + n + 1, a + n, a + n))
    out.write("".join(faces))
PY
echo '{"version": 1, "frames": 1, "cuts": []}' > none.json
"$tear" run --device "$device" sheet.obj none.json -o conv/sheet.####.glb > conv.log 2>&1 || { tail -3 conv.log; exit 1; }
mv conv/sheet.0001.glb sheet.glb
"$tear" info sheet.glb | head -2
echo '{"version": 1, "frames": 1, "cuts": [{"frame": 1, "space": "rest-xy", "polyline": [[0.2, 0.5], [0.8, 0.5]]}]}' > cut.json
t0=$(date +%s%N)
for i in $(seq 1 "$processes"); do
  "$tear" run --device "$device" sheet.glb cut.json -o "p/$i/f.####.glb" > /dev/null 2>&1 || echo "process $i failed"
done
t1=$(date +%s%N)
echo "$processes processes: $(( (t1 - t0) / 1000000 )) ms, $(( (t1 - t0) / 1000000 / processes )) ms a shot"
python3 -c "import json, sys; json.dump([{'mesh': 'sheet.glb', 'script': 'cut.json', 'output': 'b/%d/f.####.glb' % i}
                                         for i in range(1, int(sys.argv[1]) + 1)], open('shots.json', 'w'))" "$shots"
t0=$(date +%s%N)
"$tear" batch shots.json --device "$device" > batch.log 2>&1
status=$?
t1=$(date +%s%N)
echo "tear batch of $shots shots: exit $status, $(( (t1 - t0) / 1000000 )) ms, $(( (t1 - t0) / 1000000 / shots )) ms a shot"
same=0
for i in $(seq 1 "$(( processes < shots ? processes : shots ))"); do cmp -s "p/$i/f.0001.glb" "b/$i/f.0001.glb" && same=$((same + 1)); done
echo "batch outputs the same bytes as the processes': $same of $(( processes < shots ? processes : shots ))"
