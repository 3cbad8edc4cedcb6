#!/usr/bin/env python3
"""Write tearing scenes beyond `tear demo`'s into a folder: a mesh (OBJ) and a script (JSON) each.

    python3 examples/tearing/make_scenes.py out/scenes
    tear run out/scenes/hole_low.obj out/scenes/hole.json -o out/hole_low/f.####.ply --report out/hole_low.json

Each sheet is a grid of jittered nodes whose cells are quads or triangles with either diagonal
(seeded, so the files are the same on every run), written with UVs and a `-0` normal as exporters
write them, at two resolutions: `low` (about 2.5 cm edges) and `high` (about 1.25 cm). The scenes
and what they show are in docs/simulation.md, *Other scenes*. Python's standard library only.
"""

import json
import math
import os
import random
import sys


def sheet(width, height, edge, seed, hole=None, quads=True, rotation=None, offset=(0.0, 0.0, 0.0)):
    """Nodes and faces of a width × height sheet in the xy plane, then turned and moved."""
    rng = random.Random(seed)
    nx, ny = round(width / edge), round(height / edge)
    index, nodes = {}, []
    for j in range(ny + 1):
        for i in range(nx + 1):
            x, y = width * i / nx, height * j / ny
            if 0 < i < nx and 0 < j < ny:
                x += rng.uniform(-0.25, 0.25) * edge
                y += rng.uniform(-0.25, 0.25) * edge
            index[i, j] = len(nodes)
            nodes.append([x, y, 0.0])
    faces = []
    for j in range(ny):
        for i in range(nx):
            q = [index[i, j], index[i + 1, j], index[i + 1, j + 1], index[i, j + 1]]
            cx = sum(nodes[n][0] for n in q) / 4
            cy = sum(nodes[n][1] for n in q) / 4
            if hole and math.hypot(cx - hole[0], cy - hole[1]) < hole[2]:
                continue
            r = rng.random()
            if quads and r < 0.5:
                faces.append(q)
            elif r < 0.75:
                faces += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
            else:
                faces += [[q[0], q[1], q[3]], [q[1], q[2], q[3]]]
    used = sorted({n for f in faces for n in f})
    renumber = {n: k for k, n in enumerate(used)}
    nodes = [nodes[n] for n in used]
    faces = [[renumber[n] for n in f] for f in faces]
    if rotation:
        nodes = [[sum(rotation[r][c] * p[c] for c in range(3)) for r in range(3)] for p in nodes]
    nodes = [[p[k] + offset[k] for k in range(3)] for p in nodes]
    return nodes, faces


def write_obj(path, nodes, faces):
    lo = [min(p[k] for p in nodes) for k in range(3)]
    span = max(max(p[k] for p in nodes) - lo[k] for k in range(3))
    with open(path, "w") as out:
        out.write("o sheet\n")
        for p in nodes:
            out.write("v %.6f %.6f %.6f\n" % tuple(p))
        for p in nodes:
            out.write("vt %.6f %.6f\n" % ((p[0] - lo[0]) / span, (p[1] - lo[1]) / span))
        out.write("vn -0 -0 1\n")
        for f in faces:
            out.write("f " + " ".join("%d/%d/1" % (n + 1, n + 1) for n in f) + "\n")


def keys(offset, frame=48):
    return [{"frame": 0, "offset": [0, 0, 0]}, {"frame": frame, "offset": list(offset)}]


def box(lo, hi, offset=None):
    pin = {"box": {"min": list(lo), "max": list(hi)}}
    if offset is not None:
        pin["keys"] = keys(offset)
    return pin


def script(pins, gravity=(0, 0, 0), tearing=None, cuts=None, **simulation):
    s = {"version": 1, "frames": 48,
         "simulation": dict(gravity=list(gravity), pins=pins, tearing=tearing or {"stretch": 1.3}, **simulation)}
    if cuts:
        s["cuts"] = cuts
    return s


def main(folder):
    os.makedirs(folder, exist_ok=True)
    scripts = {}

    def write(name, nodes, faces):
        write_obj(os.path.join(folder, name + ".obj"), nodes, faces)

    far = (500.0, 20.0, -300.0)
    a, b = math.radians(35), math.radians(20)
    rx = [[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]]
    ry = [[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]]
    tilt = [[sum(ry[r][k] * rx[k][c] for k in range(3)) for c in range(3)] for r in range(3)]
    along = [tilt[r][0] for r in range(3)]  # the tilted sheet's own x axis
    for resolution, edge in (("low", 0.025), ("high", 0.0125)):
        # A 2 × 0.6 m strip of quads and triangles far from the origin, no notch, pulled at its ends.
        write("strip_" + resolution, *sheet(2.0, 0.6, edge, 7, offset=far))
        # A 1 m sheet with a hole of 16 cm across in its middle, pulled at its sides.
        write("hole_" + resolution, *sheet(1.0, 1.0, 0.8 * edge, 3, hole=(0.5, 0.5, 0.08)))
        # A 1.2 × 0.8 m sheet of triangles turned 35° about x and 20° about y, pulled along its own
        # x axis under gravity by the nodes of its end strips.
        nodes, faces = sheet(1.2, 0.8, 0.8 * edge, 11, quads=False, rotation=tilt)
        write("tilt_" + resolution, nodes, faces)
        local_x = [sum(along[k] * p[k] for k in range(3)) for p in nodes]
        ends = [[n for n, x in enumerate(local_x) if x < 0.03], [n for n, x in enumerate(local_x) if x > 1.17]]
        pins = [{"nodes": ends[0], "keys": keys([-0.3 * c for c in along])},
                {"nodes": ends[1], "keys": keys([0.3 * c for c in along])}]
        scripts["tilt_" + resolution] = script(pins, gravity=(0, -9.81, 0))
        # A 1.5 × 1 m sheet pulled out by its four corners.
        write("corners_" + resolution, *sheet(1.5, 1.0, edge, 21))
        # A 1 × 1.5 m heavy sheet hung from its two top corners.
        write("hang_" + resolution, *sheet(1.0, 1.5, edge, 9))
    # A 30 × 5 cm ribbon pulled at its ends.
    write("ribbon", *sheet(0.3, 0.05, 0.005, 2))

    side = lambda x0, x1, offset: box((x0, -1, -1), (x1, 2, 1), offset)
    scripts["strip"] = script([box((far[0] - 1, far[1] - 1, far[2] - 1), (far[0] + 0.04, far[1] + 2, far[2] + 1), (-0.4, 0, 0)),
                               box((far[0] + 1.96, far[1] - 1, far[2] - 1), (far[0] + 3, far[1] + 2, far[2] + 1), (0.4, 0, 0))])
    scripts["hole"] = script([side(-1, 0.04, (-0.3, 0, 0)), side(0.96, 2, (0.3, 0, 0))])
    scripts["corners"] = script([box((-1, -1, -1), (0.05, 0.05, 1), (-0.25, -0.25, 0)),
                                 box((1.45, -1, -1), (2, 0.05, 1), (0.25, -0.25, 0)),
                                 box((-1, 0.95, -1), (0.05, 2, 1), (-0.25, 0.25, 0)),
                                 box((1.45, 0.95, -1), (2, 2, 1), (0.25, 0.25, 0))])
    scripts["hang"] = script([box((-1, 1.44, -1), (0.06, 2, 1)), box((0.94, 1.44, -1), (2, 2, 1))],
                             gravity=(0, -9.81, 0), tearing={"stretch": 1.15}, density=3.0)
    scripts["ribbon"] = script([box((-1, -1, -1), (0.01, 1, 1), (-0.06, 0, 0)), box((0.29, -1, -1), (1, 1, 1), (0.06, 0, 0))])
    # For examples/meshes/sheet_*.obj: sheared (one strip up, one down), and a notched pull twisted out
    # of its plane.
    notch = [{"frame": 1, "space": "rest-xy", "polyline": [[0.5, -0.1], [0.5, 0.25]]}]
    scripts["shear"] = script([side(-1, 0.04, (-0.1, -0.4, 0)), side(0.96, 2, (0.1, 0.4, 0))])
    scripts["twist"] = script([side(-1, 0.04, (0, 0, -0.4)), side(0.96, 2, (0, 0, 0.4))], cuts=notch)
    # For examples/meshes/tube.gltf: held by its bottom ring, its top ring pulled 0.5 m along its axis.
    scripts["tube"] = script([box((-1, -1, -1), (1, 0.02, 1)), box((-1, 0.98, -1), (1, 2, 1), (0, 0.5, 0))])
    for name, s in scripts.items():
        with open(os.path.join(folder, name + ".json"), "w") as out:
            json.dump(s, out, indent=1)
            out.write("\n")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: make_scenes.py FOLDER")
    main(sys.argv[1])
