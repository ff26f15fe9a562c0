"""Independent numpy implementation of Alter's arclength smoothing with a free outer end.

S. J. Alter, "Rapid Structured Volume Grid Smoothing and Adaption Technique", section III.B:
K-direction arclength functions S(i, j, k) from the wall, Taubin lambda|mu iterations with
the paper's stencils (eqs. 2-6: 6 neighbours inside, 4 in-plane on a face, 2 along an edge,
corners unchanged), then every point placed on its original K line at its filtered
arclength, the outer point extrapolated along the line's last segment when its arclength
grew. Written from the paper, not from the kernel.

usage: ref_alter.py IN OUT ITERATIONS [LAMBDA MU]
IN: little-endian uint64 ni, nj, nk, then ni*nj*nk*3 float64 (x, y, z; i fastest).
OUT: the smoothed points in the same layout without the header. Exit status 3 and a line on
stdout when a line's filtered arclength stops increasing.
"""
import sys

import numpy as np


def read(path):
    raw = np.fromfile(path, dtype="<u8", count=3)
    ni, nj, nk = (int(v) for v in raw)
    pts = np.fromfile(path, dtype="<f8", offset=24).reshape(nk, nj, ni, 3)
    return pts


def arclength(pts):
    """S[k, j, i] = sum of segment lengths along k from the wall."""
    seg = np.sqrt(((pts[1:] - pts[:-1]) ** 2).sum(axis=-1))
    s = np.zeros(pts.shape[:-1])
    for k in range(1, pts.shape[0]):
        s[k] = s[k - 1] + seg[k - 1]
    return s


def average(f):
    """The paper's average: per axis, both neighbours where the point is inside that axis;
    axes where the point is on the boundary are dropped; None (count 0) at corners."""
    total = np.zeros_like(f)
    count = np.zeros(f.shape)
    for axis in range(3):
        n = f.shape[axis]
        if n < 3:
            continue
        inner = [slice(None)] * 3
        lower = [slice(None)] * 3
        upper = [slice(None)] * 3
        inner[axis] = slice(1, n - 1)
        lower[axis] = slice(0, n - 2)
        upper[axis] = slice(2, n)
        total[tuple(inner)] += f[tuple(lower)] + f[tuple(upper)]
        count[tuple(inner)] += 2
    avg = np.where(count > 0, total / np.maximum(count, 1), f)
    return avg


def taubin(s, iterations, lam, mu):
    for it in range(1, iterations + 1):
        s = s + lam * (average(s) - s)
        s = s + mu * (average(s) - s)
        if not (np.diff(s, axis=0) > 0).all():
            k, j, i = np.argwhere(~(np.diff(s, axis=0) > 0))[0]
            print(f"folded line i={i} j={j} at iteration {it}")
            sys.exit(3)
    return s


def place(line, s_orig, targets):
    """Points at arclength `targets` on the polyline `line` (arclength `s_orig`); the first
    point stays; beyond the end, along the last segment."""
    out = line.copy()
    n = len(s_orig)
    for t in range(1, n):
        target = targets[t]
        if target > s_orig[-1]:
            a, b = s_orig[-2], s_orig[-1]
            out[t] = line[-1] + (target - b) / (b - a) * (line[-1] - line[-2])
            continue
        m = min(np.searchsorted(s_orig, target, side="right") - 1, n - 1)
        if m == n - 1:
            out[t] = line[-1]
            continue
        a, b = s_orig[m], s_orig[m + 1]
        out[t] = line[m] + (target - a) / (b - a) * (line[m + 1] - line[m])
    return out


def main():
    src, dst, iterations = sys.argv[1], sys.argv[2], int(sys.argv[3])
    lam = float(sys.argv[4]) if len(sys.argv) > 4 else 0.330
    mu = float(sys.argv[5]) if len(sys.argv) > 5 else -0.334
    pts = read(src)
    s0 = arclength(pts)
    s = taubin(s0.copy(), iterations, lam, mu)
    new = pts.copy()
    nk, nj, ni, _ = pts.shape
    for j in range(nj):
        for i in range(ni):
            new[:, j, i] = place(pts[:, j, i], s0[:, j, i], s[:, j, i])
    new.astype("<f8").tofile(dst)


if __name__ == "__main__":
    main()
