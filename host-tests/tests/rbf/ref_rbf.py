"""Independent RBF reference for host-tests/tests/rbf/interpolation.rs.

Input file (whitespace text): a header line `KERNEL RADIUS DIM NC NE` (KERNEL `tps` or
`wendland`; RADIUS ignored for `tps`), then NC lines `x.. d..` (centre and its motion), then
NE lines `x..` (evaluation points). Prints NE lines of the interpolated motion (repr floats).

tps: scipy.interpolate.RBFInterpolator(kernel='thin_plate_spline', degree=1), phi = r^2 log r
with the linear polynomial and its orthogonality conditions.
wendland: phi(r) = (1 - r/R)^4 (4 r/R + 1) for r < R, solved densely with numpy (no
polynomial), evaluated by dense matrix products.
"""
import sys

import numpy as np
from scipy.interpolate import RBFInterpolator


def wendland(r, radius):
    rho = r / radius
    return np.where(rho < 1.0, (1.0 - rho) ** 4 * (4.0 * rho + 1.0), 0.0)


def main(path):
    with open(path) as f:
        kernel, radius, dim, nc, ne = f.readline().split()
        radius, dim, nc, ne = float(radius), int(dim), int(nc), int(ne)
        rows = [[float(v) for v in line.split()] for line in f if line.strip()]
    data = np.array(rows[:nc])
    centres, motion = data[:, :dim], data[:, dim:]
    points = np.array(rows[nc:nc + ne])
    if kernel == "tps":
        rbf = RBFInterpolator(centres, motion, kernel="thin_plate_spline", degree=1)
        out = rbf(points)
    elif kernel == "wendland":
        def dist(a, b):
            return np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(axis=2))
        coeffs = np.linalg.solve(wendland(dist(centres, centres), radius), motion)
        out = wendland(dist(points, centres), radius) @ coeffs
    else:
        raise SystemExit(f"unknown kernel {kernel}")
    for row in out:
        print(" ".join(repr(float(v)) for v in row))


if __name__ == "__main__":
    main(sys.argv[1])
