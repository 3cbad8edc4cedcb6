#!/usr/bin/env python3
"""Compares OBJ frames up to node and face order: each face becomes its corners' (position, UV,
normal) rotated to start at the smallest, and the sorted face lists must be equal, as must the
sorted node positions. Used to check that a change renumbered nodes without changing any mesh.
  scripts/compare-sorted.py A.obj B.obj      or      scripts/compare-sorted.py DIR_A DIR_B
With --tolerance T (for simulated runs, whose positions depend on summation order, hence on node
order, in the last bits): the node and face counts must be equal and every node of each frame must
lie within T (each coordinate) of a node of the other.
Exits 0 when every pair is the same mesh, 1 otherwise (one line per differing pair)."""
import os
import sys


def canonical(path):
    v, vt, vn, faces = [], [], [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == 'v':
                v.append(tuple(t[1:4]))
            elif t[0] == 'vt':
                vt.append(tuple(t[1:3]))
            elif t[0] == 'vn':
                vn.append(tuple(t[1:4]))
            elif t[0] == 'f':
                corners = []
                for c in t[1:]:
                    p = c.split('/')
                    uv = vt[int(p[1]) - 1] if len(p) > 1 and p[1] else None
                    n = vn[int(p[2]) - 1] if len(p) > 2 and p[2] else None
                    corners.append((v[int(p[0]) - 1], uv, n))
                i = corners.index(min(corners))
                faces.append(tuple(corners[i:] + corners[:i]))
    return sorted(v), sorted(faces)


def within(x, y, tol):
    """Counts equal and every node of each within tol of a node of the other (a grid of cells tol)."""
    (vx, fx), (vy, fy) = x, y
    if len(vx) != len(vy) or len(fx) != len(fy):
        return False
    def pts(v):
        return [tuple(float(c) for c in p) for p in v]
    px, py = pts(vx), pts(vy)
    def covered(a, b):
        grid = {}
        for p in b:
            grid.setdefault(tuple(int(c // tol) for c in p), []).append(p)
        for p in a:
            cell = tuple(int(c // tol) for c in p)
            found = False
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    for dz in (-1, 0, 1):
                        for q in grid.get((cell[0] + dx, cell[1] + dy, cell[2] + dz), ()):
                            if all(abs(p[i] - q[i]) <= tol for i in range(3)):
                                found = True
                                break
                        if found:
                            break
                    if found:
                        break
                if found:
                    break
            if not found:
                return False
        return True
    return covered(px, py) and covered(py, px)


def main():
    args = sys.argv[1:]
    tol = None
    if '--tolerance' in args:
        i = args.index('--tolerance')
        tol = float(args[i + 1])
        del args[i:i + 2]
    a, b = args[0], args[1]
    pairs = [(a, b)]
    if os.path.isdir(a):
        names = sorted(n for n in os.listdir(a) if n.endswith('.obj'))
        pairs = [(os.path.join(a, n), os.path.join(b, n)) for n in names]
    bad = 0
    for x, y in pairs:
        if not os.path.exists(y):
            print(f'{y}: missing')
            bad += 1
            continue
        cx, cy = canonical(x), canonical(y)
        if (cx != cy) if tol is None else not within(cx, cy, tol):
            print(f'{x} {y}: different meshes')
            bad += 1
    print(f'{len(pairs) - bad} of {len(pairs)} frames the same up to node order')
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
