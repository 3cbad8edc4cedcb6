#!/usr/bin/env python3
"""Plots how `tear bench` scales: time against faces, log-log, one line per part and backend.

Reads the JSON that `tear bench --json FILE` writes and draws its `remesh` rows (ms per cut) and
`pd` rows (ms per solver step) as an SVG, with nothing but the standard library:

    tear bench --only remesh,pd --json bench.json
    scripts/plot-bench.py bench.json -o docs/scaling.svg [--title "H100, 2026-11-24"]

Exit codes: 0 ok, 1 usage error, 2 the JSON is missing, unreadable or has no rows to plot.
"""
import argparse
import json
import math
import sys

WIDTH, HEIGHT = 720, 460
LEFT, RIGHT, TOP, BOTTOM = 70, 200, 40, 50
COLOURS = {("remesh", "cuda"): "#1f77b4", ("remesh", "cpu"): "#9ecae1",
           ("pd", "cuda"): "#d62728", ("pd", "cpu"): "#f4a6a6"}
LABELS = {"remesh": "one cut", "pd": "solver step"}
TIME_KEYS = {"remesh": "remesh_ms", "pd": "step_ms"}


def series(doc):
    """{(part, device): [(faces, ms), ...]} of the rows with a positive time, faces ascending."""
    out = {}
    for part, key in TIME_KEYS.items():
        for row in doc.get(part, []):
            faces, ms = row.get("faces"), row.get(key)
            if not isinstance(faces, (int, float)) or not isinstance(ms, (int, float)):
                continue
            if faces > 0 and ms > 0:
                out.setdefault((part, row.get("device", "?")), []).append((faces, ms))
    for points in out.values():
        points.sort()
    return out


def decades(lo, hi):
    return range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1)


def svg(lines, title):
    xs = [f for pts in lines.values() for f, _ in pts]
    ys = [ms for pts in lines.values() for _, ms in pts]
    x_dec, y_dec = decades(min(xs), max(xs)), decades(min(ys), max(ys))
    x0, x1 = x_dec[0], max(x_dec[-1], x_dec[0] + 1)
    y0, y1 = y_dec[0], max(y_dec[-1], y_dec[0] + 1)
    plot_w, plot_h = WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM

    def px(f):
        return LEFT + (math.log10(f) - x0) / (x1 - x0) * plot_w

    def py(ms):
        return TOP + plot_h - (math.log10(ms) - y0) / (y1 - y0) * plot_h

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" '
           f'font-family="sans-serif" font-size="12">',
           f'<rect width="{WIDTH}" height="{HEIGHT}" fill="white"/>',
           f'<text x="{LEFT}" y="22" font-size="14">{escape(title)}</text>']
    for d in range(x0, x1 + 1):
        x = px(10 ** d)
        out.append(f'<line x1="{x:.1f}" y1="{TOP}" x2="{x:.1f}" y2="{TOP + plot_h}" stroke="#ddd"/>')
        out.append(f'<text x="{x:.1f}" y="{TOP + plot_h + 18}" text-anchor="middle">1e{d}</text>')
    for d in range(y0, y1 + 1):
        y = py(10 ** d)
        out.append(f'<line x1="{LEFT}" y1="{y:.1f}" x2="{LEFT + plot_w}" y2="{y:.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{LEFT - 6}" y="{y + 4:.1f}" text-anchor="end">{10.0 ** d:g}</text>')
    out.append(f'<text x="{LEFT + plot_w / 2:.1f}" y="{HEIGHT - 10}" text-anchor="middle">faces</text>')
    out.append(f'<text x="16" y="{TOP + plot_h / 2:.1f}" transform="rotate(-90 16 {TOP + plot_h / 2:.1f})" '
               f'text-anchor="middle">ms</text>')
    for i, ((part, device), pts) in enumerate(sorted(lines.items())):
        colour = COLOURS.get((part, device), "#555")
        path = " ".join(f"{px(f):.1f},{py(ms):.1f}" for f, ms in pts)
        out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for f, ms in pts:
            out.append(f'<circle cx="{px(f):.1f}" cy="{py(ms):.1f}" r="3" fill="{colour}"/>')
        ly = TOP + 10 + 20 * i
        out.append(f'<line x1="{LEFT + plot_w + 15}" y1="{ly}" x2="{LEFT + plot_w + 40}" y2="{ly}" '
                   f'stroke="{colour}" stroke-width="2"/>')
        out.append(f'<text x="{LEFT + plot_w + 46}" y="{ly + 4}">{escape(LABELS.get(part, part))}, {escape(device)}</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def escape(text):
    return str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("json", help="the file `tear bench --json` wrote")
    parser.add_argument("-o", "--output", required=True, help="the SVG to write")
    parser.add_argument("--title", default="tear bench: time against faces", help="the plot's title")
    args = parser.parse_args()
    try:
        with open(args.json, encoding="utf-8") as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        print(f"{args.json}: cannot read: {e}", file=sys.stderr)
        return 2
    lines = series(doc) if isinstance(doc, dict) else {}
    if not lines:
        print(f"{args.json}: no remesh or pd rows with a time to plot", file=sys.stderr)
        return 2
    text = svg(lines, args.title)
    try:
        with open(args.output, "w", encoding="utf-8") as f:
            f.write(text)
    except OSError as e:
        print(f"{args.output}: cannot write: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
