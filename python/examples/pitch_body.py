"""Pitch a square body 20 degrees inside a triangulated box and check the cells.

Run: python python/examples/pitch_body.py [plot.png]   (the plot needs matplotlib)
"""

import sys

import numpy as np

import deform_kernel as dk


def box_with_hole(n=21, half=2.0, hole=0.5):
    """Triangles filling [-half, half]^2 minus the square [-hole, hole]^2."""
    xs = np.linspace(-half, half, n)
    x, y = np.meshgrid(xs, xs)
    pts = np.column_stack([x.ravel(), y.ravel()])
    tris = []
    for j in range(n - 1):
        for i in range(n - 1):
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i
            if np.all(np.abs(pts[[a, b, c, d]].mean(axis=0)) < hole - 1e-9):
                continue
            tris += [[a, b, c], [a, c, d]]
    used = np.unique(tris)
    renumber = np.zeros(len(pts), dtype=np.int64)
    renumber[used] = np.arange(used.size)
    pts, tris = pts[used], renumber[np.array(tris)]
    body = np.flatnonzero(np.all(np.abs(pts) <= hole + 1e-12, axis=1))
    far = np.flatnonzero(np.any(np.abs(pts) >= half - 1e-12, axis=1))
    return pts, tris, body, far


def main():
    pts, tris, body, far = box_with_hole()
    cells = [("triangle", tris)]
    moved, info = dk.deform(pts, cells, body, dk.Rotation(20.0, center=(0.0, 0.0)),
                            fixed=far, method="quaternion", return_info=True)
    q = dk.quality(moved, cells)
    print(f"{len(pts)} nodes, {len(tris)} triangles; solve: {info['iterations']} iterations, "
          f"residual {info['residual']:.1e}")
    print(f"smallest area {q['measure'].min():.4f}, "
          f"smallest scaled Jacobian {q['scaled_jacobian'].min():.3f}")
    assert q["measure"].min() > 0, "a cell inverted"
    if len(sys.argv) > 1:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2, figsize=(10, 5))
        for ax, p, title in zip(axes, (pts, moved), ("undeformed", "body pitched 20°")):
            ax.triplot(p[:, 0], p[:, 1], tris, lw=0.5)
            ax.set_aspect("equal")
            ax.set_title(title)
        fig.savefig(sys.argv[1], dpi=120)
        print(f"wrote {sys.argv[1]}")


if __name__ == "__main__":
    main()
