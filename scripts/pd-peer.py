#!/usr/bin/env python3
"""A peer of `tear bench --only pd` in PyTorch: the same Jacobi-Chebyshev projective dynamics
iteration (edge springs and hinge bending, Wang 2015) on a regular sheet of the same size, written
the way a PyTorch user would (gathers, `index_add_` scatters), 100 iterations recorded once as a
CUDA graph and replayed. Prints the time of one step and the node-iterations per second, for
comparison with tear's figures in the same run.

    python3 scripts/pd-peer.py [--faces 2097152,38298] [--iterations 100] [--repeats 5]

Needs PyTorch with CUDA. The sheet is an n x n grid of quads, each cut by a diagonal, with n the
largest where 2 n^2 <= faces (tear's sheet adds a few centre nodes to hit the face count exactly).
"""
import argparse
import math
import time

import torch


def sheet(n, device):
    """Nodes, faces, edges (a, b) with their face counts, hinges (a, b, c, d) of an n x n grid of quads."""
    i = torch.arange(n + 1, device=device)
    y, x = torch.meshgrid(i, i, indexing="ij")
    pos = torch.stack([x.flatten(), y.flatten(), torch.zeros_like(x.flatten())], 1).float() / n
    q = torch.arange(n, device=device)
    qy, qx = torch.meshgrid(q, q, indexing="ij")
    v00 = (qy * (n + 1) + qx).flatten()
    v10, v01, v11 = v00 + 1, v00 + n + 1, v00 + n + 2
    faces = torch.cat([torch.stack([v00, v10, v11], 1), torch.stack([v00, v11, v01], 1)])
    # Each face's three edges, with the opposite node; edges sorted so that twins meet.
    fe = torch.cat([faces[:, [0, 1, 2]], faces[:, [1, 2, 0]], faces[:, [2, 0, 1]]])
    lo, hi = torch.minimum(fe[:, 0], fe[:, 1]), torch.maximum(fe[:, 0], fe[:, 1])
    key = lo * pos.shape[0] + hi
    order = torch.argsort(key)
    key, lo, hi, opp = key[order], lo[order], hi[order], fe[order, 2]
    unique, counts = torch.unique_consecutive(key, return_counts=True)
    first = torch.cumsum(counts, 0) - counts
    edges = torch.stack([lo[first], hi[first]], 1)
    inner = counts == 2
    hinges = torch.stack([lo[first[inner]], hi[first[inner]], opp[first[inner]], opp[first[inner] + 1]], 1)
    return pos, faces, edges, counts, hinges


def hinge_coefficients(x, h):
    x0, x1, x2, x3 = (x[h[:, j]].double() for j in range(4))
    e = x1 - x0
    len2 = (e * e).sum(1)
    a0 = torch.linalg.cross(e, x2 - x0).norm(dim=1)
    a1 = torch.linalg.cross(e, x3 - x0).norm(dim=1)
    cot_a0 = (e * (x2 - x0)).sum(1) / a0
    cot_b0 = ((x0 - x1) * (x2 - x1)).sum(1) / a0
    cot_a1 = (e * (x3 - x0)).sum(1) / a1
    cot_b1 = ((x0 - x1) * (x3 - x1)).sum(1) / a1
    ln = len2.sqrt()
    k = torch.stack([-(cot_b0 + cot_b1), -(cot_a0 + cot_a1), cot_a0 + cot_b0, cot_a1 + cot_b1], 1) / ln[:, None]
    return k, len2, 0.5 * (a0 + a1)


def run(faces_wanted, iterations, repeats, device):
    n = int(math.isqrt(faces_wanted // 2))
    pos, faces, edges, edge_faces, hinges = sheet(n, device)
    nodes = pos.shape[0]
    h = 1.0 / 24.0  # tear bench: 24 frames a second, one substep
    density, stretch, bend = 0.2, 1000.0, 1e-4  # tear's defaults (SimulationOptions)
    area = 0.5 / (n * n)
    mass = torch.zeros(nodes, device=device).index_add_(0, faces.flatten(), torch.full((faces.numel(),), density * area / 3, device=device))
    ea, eb = edges[:, 0], edges[:, 1]
    rest = (pos[ea] - pos[eb]).norm(dim=1)
    # Springs: weight stiffness x a third of the edge's faces' area / L^2 (two faces inside, one on the border).
    w_s = stretch * (edge_faces.float() * area) / 3 / rest**2
    k, len2, _ = hinge_coefficients(pos, hinges)
    w_h = (bend * 3 * len2 / (2 * area)).float()
    k = k.float()
    inv_h2 = 1.0 / (h * h)
    diag = mass * inv_h2
    diag = diag.index_add(0, ea, w_s).index_add(0, eb, w_s)
    ksum = k.abs().sum(1, keepdim=True)
    beta = torch.maximum(k.abs(), 0.5 * ksum)
    for j in range(4):
        diag = diag.index_add(0, hinges[:, j], w_h * k[:, j].abs() * beta[:, j])
    pinned = pos[:, 1] > 1 - 1e-6
    gravity = torch.tensor([0.0, -9.81, 0.0], device=device)
    x0 = pos.clone()
    v = torch.zeros_like(pos)
    s = x0 + h * v + h * h * gravity
    s[pinned] = x0[pinned]
    rho, gamma, delay = 0.995, 0.9, 10
    omegas, omega = [], 1.0
    for it in range(iterations):
        omega = 1.0 if it < delay else 2.0 / (2.0 - rho * rho) if it == delay else 4.0 / (4.0 - rho * rho * omega)
        omegas.append(omega)
    xs = [s.clone(), s.clone(), s.clone()]
    free = (~pinned).float()[:, None]
    inv_diag = (1.0 / diag)[:, None]

    # Every slot's node, springs' then hinges', for one scatter of all products an iteration.
    slot_node = torch.cat([ea, eb, hinges.t().flatten()])
    hinge_k = k.t().flatten()[:, None]
    mass_h2 = (mass * inv_h2)[:, None]

    def iteration(x, x_prev, out, om):
        d = x[ea] - x[eb]
        ln = d.norm(dim=1, keepdim=True).clamp_min(1e-30)
        f = w_s[:, None] * (d * (rest[:, None] / ln) - d)
        dh = (k[:, :, None] * x[hinges]).sum(1)
        fh = -w_h[:, None] * dh  # flat rest: the projection of a fold is no fold
        products = torch.cat([f, -f, hinge_k * fh.repeat(4, 1)])
        g = (mass_h2 * (s - x)).index_add_(0, slot_node, products)
        x_hat = x + g * inv_diag
        out.copy_(free * (om * (gamma * (x_hat - x) + x - x_prev) + x_prev) + (1 - free) * x)

    def step():
        cur, prev, nxt = xs
        for it in range(iterations):
            iteration(cur, prev, nxt, omegas[it])
            cur, prev, nxt = nxt, cur, prev

    stream = torch.cuda.Stream()
    stream.wait_stream(torch.cuda.current_stream())
    with torch.cuda.stream(stream):
        step()  # warm-up outside the capture
    torch.cuda.current_stream().wait_stream(stream)
    graph = torch.cuda.CUDAGraph()
    with torch.cuda.graph(graph):
        step()
    times = []
    for r in range(repeats + 1):
        torch.cuda.synchronize()
        t = time.perf_counter()
        graph.replay()
        torch.cuda.synchronize()
        if r > 0:
            times.append(time.perf_counter() - t)
    times.sort()
    ms = 1e3 * times[len(times) // 2]
    rate = nodes * iterations / (ms * 1e-3)
    print(f"peer  faces {2 * n * n:>9}  nodes {nodes:>9}  step {ms:9.3f} ms  {ms * 1e3 / iterations:8.2f} us/iteration  {rate / 1e9:6.2f} G node-it/s")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--faces", default="2097152,38298")
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    device = torch.device("cuda")
    print(f"peer  device {torch.cuda.get_device_name(device)}, torch {torch.__version__}")
    for faces in (int(f) for f in args.faces.split(",")):
        run(faces, args.iterations, args.repeats, device)


if __name__ == "__main__":
    main()
