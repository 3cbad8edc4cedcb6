#!/usr/bin/env python3
"""`tear batch` with one bad shot among good ones.

    check_batch.py TEAR_BINARY SOURCE_DIR

- three shots, the second with a missing mesh: the batch exits 2 (the bad shot's code), the first
  and third write exactly the files `tear run` writes alone for them (and their reports), the
  second writes nothing; standard error holds the second shot's own message, as `tear run` gives
  it, and a last line naming the failed shot;
- a shot whose key is unknown fails alone with exit 1; a shot interrupted is not tested here;
- a list that is not JSON, or not a list, exits 2 and runs nothing;
- every shot ok: exit 0, nothing on standard error;
- 100 shots, one of them bad (a missing mesh): the other 99 write exactly what `tear run` writes
  alone for each, the bad one is reported with its message and code, and the batch exits 2;
- a shot whose mesh is the frame the shot before it writes (over an older file there) reads the
  new frame; a shot's warning about its mesh, read while the shot before failed, comes after that
  shot's message.
"""

import json
import os
import subprocess
import sys
import tempfile

TEAR, SOURCE = sys.argv[1], sys.argv[2]
MESH = os.path.join(SOURCE, "examples", "meshes", "sheet_low.obj")
CUTS = os.path.join(SOURCE, "examples", "scripts", "crossing_cuts.json")
SLIT = os.path.join(SOURCE, "examples", "scripts", "rest_xy_slit.json")

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL: " + what, file=sys.stderr)


def tear(*args):
    return subprocess.run([TEAR] + list(args), capture_output=True, text=True)


def files(folder):
    out = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                out[os.path.relpath(path, folder)] = f.read()
    return out


with tempfile.TemporaryDirectory(prefix="tear-batch-") as work:
    alone, batch = os.path.join(work, "alone"), os.path.join(work, "batch")
    missing = os.path.join(work, "missing.obj")
    # Alone: the two good shots, and the bad one's message.
    r1 = tear("run", MESH, CUTS, "-o", os.path.join(alone, "a", "f.####.ply"), "--device", "cpu")
    r3 = tear("run", MESH, SLIT, "-o", os.path.join(alone, "c", "f.####.obj"), "--device", "cpu", "--start-frame", "7")
    r2 = tear("run", missing, CUTS, "-o", os.path.join(alone, "b", "f.####.ply"), "--device", "cpu")
    check(r1.returncode == 0 and r3.returncode == 0, "the good shots run alone: %s %s" % (r1.stderr, r3.stderr))
    check(r2.returncode == 2, "the bad shot alone exits 2, got %d" % r2.returncode)

    shots = [
        {"mesh": MESH, "script": CUTS, "output": os.path.join(batch, "a", "f.####.ply"),
         "report": os.path.join(work, "report_a.json")},
        {"mesh": missing, "script": CUTS, "output": os.path.join(batch, "b", "f.####.ply")},
        {"mesh": MESH, "script": SLIT, "output": os.path.join(batch, "c", "f.####.obj"), "start_frame": 7},
    ]
    shots_path = os.path.join(work, "shots.json")
    with open(shots_path, "w") as f:
        json.dump(shots, f)
    r = tear("batch", shots_path, "--device", "cpu")
    check(r.returncode == 2, "the batch exits 2 (its bad shot's code), got %d: %s" % (r.returncode, r.stderr))
    lines = r.stderr.splitlines()
    check(len(lines) == 2, "two lines on standard error, got %r" % lines)
    check(lines and lines[0] == r2.stderr.strip(), "the bad shot's message is tear run's: %r vs %r" %
          (lines[:1], r2.stderr.strip()))
    check(len(lines) > 1 and lines[1] == "tear: %s: 1 of 3 shots failed: [1] (exit 2)" % shots_path,
          "the summary line: %r" % lines[1:])
    check(r.stdout == "", "nothing on standard output without -v")
    got = files(batch)
    check(files(os.path.join(alone, "a")) == files(os.path.join(batch, "a")), "shot 1's frames are tear run's")
    check(files(os.path.join(alone, "c")) == files(os.path.join(batch, "c")), "shot 3's frames are tear run's")
    check("c/f.0007.obj" in got, "shot 3 numbers its frames from its start_frame")
    check(not os.path.exists(os.path.join(batch, "b")), "the bad shot writes nothing")
    with open(os.path.join(work, "report_a.json")) as f:
        check(len(json.load(f)["frames"]) == 3, "shot 1's report has its 3 frames")

    # An unknown key fails its shot alone, as a usage error.
    shots[1] = {"mesh": MESH, "script": CUTS, "output": os.path.join(work, "d", "f.####.ply"), "fps": 24}
    with open(shots_path, "w") as f:
        json.dump(shots, f)
    r = tear("batch", shots_path, "--device", "cpu", "-v")
    check(r.returncode == 1, "an unknown key: exit 1, got %d" % r.returncode)
    check(r.stderr.startswith("tear: %s: [1].fps: unknown key" % shots_path), "the unknown key named: %r" % r.stderr)
    check("shot 1/3: ok" in r.stdout and "shot 2/3: failed, exit 1" in r.stdout and "shot 3/3: ok" in r.stdout,
          "-v prints a line per shot: %r" % r.stdout)
    check(not os.path.exists(os.path.join(work, "d")), "the shot with an unknown key writes nothing")

    # A list that cannot be used runs nothing.
    for text, what in (("[{", "not JSON"), ('{"mesh": 1}', "not a list"), ("[]", "empty")):
        with open(shots_path, "w") as f:
            f.write(text)
        r = tear("batch", shots_path, "--device", "cpu")
        check(r.returncode == 2 and r.stderr.startswith("tear: " + shots_path + ": "),
              "a list %s exits 2 naming it: %d %r" % (what, r.returncode, r.stderr))

    # Every shot ok.
    with open(shots_path, "w") as f:
        json.dump([shots[0], shots[2]], f)
    r = tear("batch", shots_path, "--device", "cpu")
    check(r.returncode == 0 and r.stderr == "", "every shot ok: exit 0, silent: %d %r" % (r.returncode, r.stderr))

    # 100 shots, one bad: the 99 others' files against 99 runs of tear run alone.
    bad = 57
    shots = []
    for i in range(100):
        script = CUTS if i % 2 == 0 else SLIT
        mesh = missing if i == bad else MESH
        shots.append({"mesh": mesh, "script": script, "output": os.path.join(work, "b100", str(i), "f.####.ply")})
    with open(shots_path, "w") as f:
        json.dump(shots, f)
    r = tear("batch", shots_path, "--device", "cpu")
    check(r.returncode == 2, "100 shots, one bad: exit 2, got %d" % r.returncode)
    lines = r.stderr.splitlines()
    check(len(lines) == 2 and lines[0] == r2.stderr.strip(), "the bad shot's own message, alone: %r" % lines)
    check(lines[-1:] == ["tear: %s: 1 of 100 shots failed: [%d] (exit 2)" % (shots_path, bad)],
          "the summary names the bad shot: %r" % lines[-1:])
    same = 0
    for i, shot in enumerate(shots):
        if i == bad:
            check(not os.path.exists(os.path.join(work, "b100", str(i))), "the bad shot of 100 writes nothing")
            continue
        alone_dir = os.path.join(work, "a100", str(i))
        ra = tear("run", shot["mesh"], shot["script"], "-o", os.path.join(alone_dir, "f.####.ply"), "--device", "cpu")
        written = files(os.path.join(work, "b100", str(i)))
        if ra.returncode == 0 and written and files(alone_dir) == written:
            same += 1
        else:
            check(False, "shot %d of 100: its files are not tear run's (%d, %r)" % (i, ra.returncode, ra.stderr))
    check(same == 99, "99 of the 100 shots write what tear run writes alone, got %d" % same)

    # A shot that reads a file the shot before it writes reads it once written: the batch reads a
    # shot's mesh beside the shot before only when it lies apart from what that shot writes.
    chain, after = os.path.join(work, "chain"), os.path.join(work, "after")
    uncut = os.path.join(work, "uncut.json")
    with open(uncut, "w") as f:
        json.dump({"version": 1, "frames": 1, "cuts": []}, f)
    cut_a, cut_b = os.path.join(work, "cut_a.json"), os.path.join(work, "cut_b.json")
    for path, line in ((cut_a, [[0.2, 0.5], [0.8, 0.5]]), (cut_b, [[0.5, 0.2], [0.5, 0.8]])):
        with open(path, "w") as f:
            json.dump({"version": 1, "frames": 1, "cuts": [{"frame": 1, "space": "rest-xy", "polyline": line}]}, f)
    stale = tear("run", MESH, uncut, "-o", os.path.join(chain, "f.####.ply"), "--device", "cpu")
    check(stale.returncode == 0, "an earlier run's frame in the chain's folder: %r" % stale.stderr)
    chained = [{"mesh": MESH, "script": cut_a, "output": os.path.join(chain, "f.####.ply")},
               {"mesh": os.path.join(chain, "f.0001.ply"), "script": cut_b, "output": os.path.join(after, "f.####.ply")}]
    with open(shots_path, "w") as f:
        json.dump(chained, f)
    r = tear("batch", shots_path, "--device", "cpu")
    check(r.returncode == 0, "a chain of two shots runs: %d %r" % (r.returncode, r.stderr))
    ra = tear("run", os.path.join(chain, "f.0001.ply"), cut_b, "-o", os.path.join(work, "after_alone", "f.####.ply"),
              "--device", "cpu")
    check(ra.returncode == 0 and files(after) == files(os.path.join(work, "after_alone")),
          "the second shot of a chain reads the first shot's frame, not the file there before it")

    # Messages keep the shots' order when a shot's mesh is read ahead: the first shot's failure,
    # then the second's warning about its mesh (read while the first ran).
    welded = {"mesh": MESH, "script": SLIT, "output": os.path.join(work, "welded", "f.####.ply"),
              "weld_tolerance": 0.02}
    with open(shots_path, "w") as f:
        json.dump([{"mesh": MESH, "script": os.path.join(work, "no_script.json"),
                    "output": os.path.join(work, "none", "f.####.ply")}, welded], f)
    r = tear("batch", shots_path, "--device", "cpu")
    lines = r.stderr.splitlines()
    # (The welded mesh's frames have inverted faces too: warned as they are written, after.)
    check(r.returncode == 2 and len(lines) >= 3, "a failed shot, then a warned one: %d %r" % (r.returncode, lines))
    check(len(lines) >= 3 and "no_script.json" in lines[0] and lines[1].startswith("tear: warning: " + MESH) and
          lines[-1].startswith("tear: " + shots_path + ": 1 of 2 shots failed: [0]"),
          "the failure, the warning and the summary in the shots' order: %r" % lines)

if failures:
    print("%d check(s) failed" % len(failures), file=sys.stderr)
    sys.exit(1)
print("batch: every check holds")
