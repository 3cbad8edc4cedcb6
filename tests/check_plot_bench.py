#!/usr/bin/env python3
"""scripts/plot-bench.py draws what `tear bench --json` measured: one line per part and backend,
a point per size, x growing with faces; a JSON with nothing to plot is exit 2 and no SVG.

Usage: check_plot_bench.py TEAR_BINARY SOURCE_DIR
"""
import json
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

tear, source = sys.argv[1], sys.argv[2]
script = os.path.join(source, "scripts", "plot-bench.py")
with tempfile.TemporaryDirectory() as tmp:
    bench = os.path.join(tmp, "bench.json")
    subprocess.run([tear, "bench", "--device", "cpu", "--only", "remesh,pd", "--faces", "8,32,128",
                    "--repeats", "1", "--warmup", "0", "--iterations", "2", "--json", bench],
                   check=True, stdout=subprocess.DEVNULL)
    doc = json.load(open(bench))
    svg = os.path.join(tmp, "plot.svg")
    subprocess.run([sys.executable, script, bench, "-o", svg, "--title", "a <test> & more"], check=True)
    root = ET.parse(svg).getroot()  # well-formed, the title escaped
    ns = "{http://www.w3.org/2000/svg}"
    lines = root.findall(f"{ns}polyline")
    expected = {(part, row["device"]) for part in ("remesh", "pd") for row in doc[part]}
    assert len(lines) == len(expected), (len(lines), expected)
    for line in lines:
        xs = [float(p.split(",")[0]) for p in line.get("points").split()]
        assert len(xs) == 3 and xs == sorted(xs) and len(set(xs)) == 3, xs
    assert "a &lt;test&gt; &amp; more" in open(svg).read()

    empty = os.path.join(tmp, "empty.json")
    json.dump({"remesh": []}, open(empty, "w"))
    out = os.path.join(tmp, "none.svg")
    r = subprocess.run([sys.executable, script, empty, "-o", out], capture_output=True, text=True)
    assert r.returncode == 2 and "empty.json" in r.stderr and not os.path.exists(out), (r.returncode, r.stderr)
    r = subprocess.run([sys.executable, script, os.path.join(tmp, "missing.json"), "-o", out],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "missing.json" in r.stderr, (r.returncode, r.stderr)
print("ok")
