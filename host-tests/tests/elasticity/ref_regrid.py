"""Re-place the O-grid points of a deform-generated NACA mesh (node i + ni*j) as
meshgen::ogrid_points does, with the blend of the radial-line direction from the wall
normal to the far-field direction w(t) = min(1, K t) instead of w = t; same cells.
python regen.py src dst ni nj first K"""
import sys
import numpy as np
src, dst = sys.argv[1], sys.argv[2]
ni, nj, first, K = int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6])
lines = open(src).read().split("\n")
k = next(i for i, l in enumerate(lines) if l.startswith("NPOIN="))
n = int(lines[k].split("=")[1].split()[0])
pts = np.array([[float(x) for x in lines[k + 1 + m].split()[:2]] for m in range(n)])
surf = pts[:ni]
far = pts[ni * (nj - 1):]


def fractions(n, first):
    lo, hi = 1.0, 2.0
    tot = lambda q: sum(first * q ** k for k in range(n))
    while tot(hi) < 1: hi *= 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if tot(mid) < 1 else (lo, mid)
    q = 0.5 * (lo + hi)
    h = first * q ** np.arange(n)
    out = np.concatenate([[0], np.cumsum(h)])
    return out / out[-1]


def unit(v):
    return v / np.linalg.norm(v)


en = []
for i in range(ni):
    d = surf[(i + 1) % ni] - surf[i]
    en.append(unit(np.array([-d[1], d[0]])))
out = pts.copy()
for i in range(ni):
    s, f = surf[i], far[i]
    nrm = unit(en[i - 1] + en[i])
    dist = np.linalg.norm(f - s)
    u = (f - s) / dist
    fr = fractions(nj - 1, first / dist)
    for j in range(1, nj - 1):
        t = fr[j]
        w = min(1.0, K * t)
        out[i + ni * j] = s + t * dist * ((1 - w) * nrm + w * u)
for m in range(n):
    rest = lines[k + 1 + m].split()[2:]
    lines[k + 1 + m] = " ".join([repr(float(out[m, 0])), repr(float(out[m, 1]))] + rest)
open(dst, "w").write("\n".join(lines))
print("max moved", np.abs(out - pts).max())
