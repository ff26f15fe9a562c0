"""The peer of the kernel's RBF row in `cargo xtask bench` (issue 28 items 2 and 4).

Reads what `bench/src/rbf.rs` wrote to DIR (the NACA 2412 mesh's points, its boundary nodes
and their motion, the kernel's displacements), fits scipy's RBFInterpolator with the same
centres (every boundary node), the same kernel (thin-plate spline) and the same linear
polynomial (degree 1), and evaluates it at every node, in blocks of 20,000 points so that the
N x B kernel matrix never sits in memory whole (the kernel evaluates node by node).

Writes DIR/peers_rbf.txt (`name value` lines): fit and evaluation seconds (median of REPS
runs) and the largest difference to the kernel's displacements relative to the largest
displacement.

    python rbf.py DIR [REPS]
"""

import sys
import time
from pathlib import Path

import numpy as np
from scipy.interpolate import RBFInterpolator

BLOCK = 20_000


def run(pts, centres, motion):
    t0 = time.perf_counter()
    rbf = RBFInterpolator(centres, motion, kernel="thin_plate_spline", degree=1)
    t1 = time.perf_counter()
    out = np.empty_like(pts)
    for s in range(0, len(pts), BLOCK):
        out[s:s + BLOCK] = rbf(pts[s:s + BLOCK])
    t2 = time.perf_counter()
    return t1 - t0, t2 - t1, out


def main():
    d = Path(sys.argv[1])
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    pts = np.fromfile(d / "rbf_points.f64", dtype="<f8").reshape(-1, 2)
    boundary = np.fromfile(d / "rbf_boundary.u32", dtype="<u4").astype(np.int64)
    motion = np.fromfile(d / "rbf_motion.f64", dtype="<f8").reshape(-1, 2)
    kernel = np.fromfile(d / "rbf_result.f64", dtype="<f8").reshape(-1, 2)
    runs = [run(pts, pts[boundary], motion) for _ in range(max(reps, 1))]
    fit = sorted(r[0] for r in runs)[len(runs) // 2]
    evaluate = sorted(r[1] for r in runs)[len(runs) // 2]
    out = runs[-1][2]
    scale = max(np.abs(kernel).max(), 1e-300)
    diff = np.abs(out - kernel).max() / scale
    lines = [
        f"rbf_scipy_fit_s {fit}",
        f"rbf_scipy_evaluate_s {evaluate}",
        f"rbf_scipy_s {fit + evaluate}",
        f"rbf_max_relative_difference {diff:e}",
    ]
    (d / "peers_rbf.txt").write_text("\n".join(lines) + "\n")
    print("\n".join("  " + l for l in lines))


if __name__ == "__main__":
    main()
