"""deform_kernel.deform against the `deform move` tool on a 234k-node mesh (not run in CI;
`cargo xtask bench` runs it as its step 5 and puts its figures in the report).

    python bench/python/deform_vs_cli.py [--deform PATH] [--method spring] [--repeat 3]
                                         [--n 505] [--figures FILE]

Builds a triangulated square with a square hole (505 x 505 grid, 234 k nodes, irregular
interior coordinates) with numpy, writes it as SU2, and runs the same spring move (the body
rotated 5 degrees, far field fixed, AMG-preconditioned CG to 1e-10) three ways:

- the tool, as a process (`deform --json move ...`): its wall time (reading, writing and the
  quality check included) and the time it reports for the move itself;
- deform_kernel.deform on numpy arrays (the same engine, the GIL released);
- the same with out= (the result written into a caller array).

It checks that the points are bit-identical and prints the ratio of the Python call to the
tool's own move time (the issue asks for no more than 10 % over the Rust call). Needs a release
build of both: `cargo build --release -p deform-cli` and `pip install ./python` (maturin
builds release). Timings are medians of --repeat runs after a warm-up call. With --figures,
the figures are also written to FILE as `name value` lines.
"""

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

import deform_kernel as dk

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python" / "tests"))
from meshes import read_su2_points, write_su2  # noqa: E402


def mesh(n=505, half=2.0, hole_steps=72):
    """(points, triangles, body edges, far-field edges), vectorised: an n x n grid on
    [-half, half]^2 with the square hole of half-width hole_steps grid steps (505, 72: 234 k
    nodes)."""
    hole = hole_steps * 2.0 * half / (n - 1)
    xs = np.linspace(-half, half, n)
    x, y = np.meshgrid(xs, xs, indexing="xy")
    pts = np.column_stack([x.ravel(), y.ravel()])
    j, i = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (j * n + i).ravel()
    b, c, d = a + 1, a + n + 1, a + n
    centre = 0.5 * (pts[a] + pts[c])
    keep = ~np.all(np.abs(centre) < hole - 1e-9, axis=1)
    a, b, c, d = a[keep], b[keep], c[keep], d[keep]
    tris = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    used = np.unique(tris)
    renum = np.full(len(pts), -1)
    renum[used] = np.arange(used.size)
    pts, tris = pts[used], renum[tris]
    inner = np.abs(pts).max(axis=1) < half - 1e-9
    on_hole = np.all(np.abs(pts) <= hole + 1e-12, axis=1)
    pts = pts + 0.002 * np.sin(37.0 * pts[:, ::-1]) * (inner & ~on_hole)[:, None]
    return pts, tris, boundary_edges(tris, on_hole), boundary_edges(tris, ~inner)


def boundary_edges(tris, mask):
    """Edges in one triangle only, both ends in mask."""
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    key = np.sort(e, axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True, return_counts=True)
    e = e[first[count == 1]]
    return e[mask[e[:, 0]] & mask[e[:, 1]]]


def median_time(f, repeat):
    f()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--deform", default=str(ROOT / "target" / "release" / "deform"))
    ap.add_argument("--method", default="spring")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--n", type=int, default=505, help="grid points per side (505: 234 k nodes)")
    ap.add_argument("--figures", help="also write the figures here, `name value` a line")
    args = ap.parse_args()
    pts, tris, body, far = mesh(args.n, 2.0, (args.n - 1) // 7)
    print(f"{len(pts)} nodes, {len(tris)} triangles, method {args.method}")
    with tempfile.TemporaryDirectory() as tmp:
        src, dst = pathlib.Path(tmp) / "in.su2", pathlib.Path(tmp) / "out.su2"
        write_su2(src, pts, tris, {"body": body, "farfield": far})
        cmd = [args.deform, "--json", "move", str(src), "--marker", "body", "--method",
               args.method, "--rotate", "5", "--out", str(dst)]
        reported = []

        def tool():
            r = subprocess.run(cmd, check=True, capture_output=True, text=True)
            reported.append(json.loads(r.stdout)["seconds"])

        tool_wall = median_time(tool, args.repeat)
        tool_move = float(np.median(reported[1:]))
        theirs = read_su2_points(dst)
    cells = [("triangle", tris)]
    moved, fixed = np.unique(body), np.unique(far)
    call = lambda **kw: dk.deform(pts, cells, moved, dk.Rotation(5.0), fixed,  # noqa: E731
                                  method=args.method, **kw)
    ours = call()
    out = np.empty_like(pts)
    py = median_time(call, args.repeat)
    py_out = median_time(lambda: call(out=out), args.repeat)
    identical = ours.tobytes() == theirs.tobytes()
    print(f"bit-identical to deform move: {identical}")
    print(f"deform move: {tool_wall:.3f} s wall, {tool_move:.3f} s reported for the move")
    print(f"deform_kernel.deform: {py:.3f} s ({py / tool_move:.3f} x the tool's move), "
          f"with out=: {py_out:.3f} s")
    if args.figures:
        figures = {"nodes": len(pts), "method": args.method, "repeat": args.repeat,
                   "tool_wall_s": tool_wall, "tool_move_s": tool_move, "call_s": py,
                   "call_out_s": py_out, "bit_identical": int(identical)}
        pathlib.Path(args.figures).write_text(
            "".join(f"python_{k} {v}\n" for k, v in figures.items()))
    return 0 if identical else 1


if __name__ == "__main__":
    sys.exit(main())
