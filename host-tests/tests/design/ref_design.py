"""Independent numpy references for the kernel's SU2 design variables (tests/design/).

Usage:
  ref_design.py ffd FILE   FILE: line 1 "D deg0 deg1 [deg2]", line 2 the control points (flat,
                           i slowest), line 3 the parametric coordinates (flat). Prints the
                           evaluated points, one number per line.
  ref_design.py hh FILE    FILE: line 1 "x_max", line 2 the x values. Prints the bumps.

The FFD is the textbook tensor-product Bezier volume sum_ijk P_ijk b_i(u) b_j(v) b_k(w) with
b_i(t) = C(n,i) t^i (1-t)^(n-i), written as an einsum over basis matrices built with
math.comb; the bump is sin(pi x^(ln 0.5 / ln x_max))^3 with x clamped at 0 (SU2's
CSurfaceMovement::SetHicksHenne), written from the formula, not from the kernel.
"""
import math
import sys

import numpy as np


def basis(n, t):
    """(len(t), n+1) matrix of Bernstein polynomials of degree n."""
    t = np.asarray(t, dtype=np.float64)
    i = np.arange(n + 1)
    c = np.array([math.comb(n, k) for k in i], dtype=np.float64)
    return c * t[:, None] ** i * (1.0 - t[:, None]) ** (n - i)


def ffd(lines):
    head = [int(v) for v in lines[0].split()]
    d, deg = head[0], head[1:]
    cp = np.array([float(v) for v in lines[1].split()]).reshape([k + 1 for k in deg] + [d])
    uvw = np.array([float(v) for v in lines[2].split()]).reshape(-1, d)
    bs = [basis(deg[a], uvw[:, a]) for a in range(d)]
    if d == 3:
        out = np.einsum("pi,pj,pk,ijkc->pc", bs[0], bs[1], bs[2], cp)
    else:
        out = np.einsum("pi,pj,ijc->pc", bs[0], bs[1], cp)
    return out.ravel()


def hicks_henne(lines):
    xk = float(lines[0])
    x = np.maximum(0.0, np.array([float(v) for v in lines[1].split()]))
    e = np.log(0.5) / np.log(xk)
    with np.errstate(divide="ignore"):
        f = np.sin(np.pi * x**e) ** 3
    return np.where(x > 1e-15, f, 0.0)


def main():
    mode, path = sys.argv[1], sys.argv[2]
    with open(path) as fh:
        lines = fh.read().splitlines()
    out = ffd(lines) if mode == "ffd" else hicks_henne(lines)
    sys.stdout.write("\n".join(repr(float(v)) for v in out) + "\n")


if __name__ == "__main__":
    main()
