# %% [markdown]
# # Pitching an airfoil with deform_kernel
#
# A notebook-style script (cells marked `# %%`, so Jupyter, VS Code and `jupytext` open it as
# a notebook; `python pitch_airfoil.py [plot.png]` runs it whole). It builds an O-mesh around
# a NACA 0012 airfoil with numpy, pitches the airfoil 10° about its quarter chord with
# Samareh's quaternion method, checks the cells, compares the methods, steps an oscillating
# pitch with a `Plan` (warm starts) and plots the mesh with matplotlib.

# %%
import sys

import numpy as np

import deform_kernel as dk


def naca0012(n):
    """n points around a NACA 0012 (closed trailing edge), counter-clockwise from the
    trailing edge, cosine-clustered at both edges."""
    beta = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    x = 0.5 * (1.0 + np.cos(beta))
    t = 0.6 * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3
               - 0.1036 * x**4)
    return np.column_stack([x, np.where(beta <= np.pi, t, -t)])


def o_mesh(ni=96, nj=40, radius=15.0, growth=1.16):
    """Quads between the airfoil (ring j = 0) and a circle (ring nj - 1), rings stretched
    geometrically: (points, quads, airfoil nodes, far-field nodes)."""
    wall = naca0012(ni)
    centre = np.array([0.5, 0.0])
    far = centre + radius * np.column_stack([np.cos(np.linspace(0, 2 * np.pi, ni, endpoint=False)),
                                             np.sin(np.linspace(0, 2 * np.pi, ni, endpoint=False))])
    s = np.cumsum(growth ** np.arange(nj - 1))
    s = np.concatenate([[0.0], s / s[-1]])
    pts = (wall[None, :, :] * (1 - s)[:, None, None] + far[None, :, :] * s[:, None, None])
    pts = np.ascontiguousarray(pts.reshape(-1, 2))
    node = lambda j, i: j * ni + i % ni  # noqa: E731
    quads = np.array([[node(j, i), node(j + 1, i), node(j + 1, i + 1), node(j, i + 1)]
                      for j in range(nj - 1) for i in range(ni)])
    return pts, quads, np.arange(ni), np.arange((nj - 1) * ni, nj * ni)


points, quads, airfoil, farfield = o_mesh()
cells = [("quad", quads)]
print(f"{len(points)} nodes, {len(quads)} quads; smallest scaled Jacobian "
      f"{dk.quality(points, cells)['scaled_jacobian'].min():.3f}")

# %% [markdown]
# ## Pitch 10° nose-up about the quarter chord
# Nose-up is clockwise here (x downstream, y up): a rotation by -10°. The airfoil nodes
# follow the rigid rotation exactly, the far field stays, every other node follows by the
# quaternion method (rotations and translations propagated by linear springs).

# %%
ANGLE = -10.0
pitched, info = dk.deform(points, cells, airfoil, dk.Rotation(ANGLE, center=(0.25, 0.0)),
                          fixed=farfield, method="quaternion", return_info=True)
q = dk.quality(pitched, cells)
print(f"solve: {info['iterations']} iterations, residual {info['residual']:.1e}; "
      f"smallest scaled Jacobian {q['scaled_jacobian'].min():.3f}")
assert q["measure"].min() > 0, "a cell inverted"
c, s = np.cos(np.radians(ANGLE)), np.sin(np.radians(ANGLE))
rigid = (points[airfoil] - [0.25, 0.0]) @ np.array([[c, s], [-s, c]]) + [0.25, 0.0]
print(f"airfoil nodes vs. a rigid rotation: {np.abs(pitched[airfoil] - rigid).max():.1e}")

# %% [markdown]
# ## The other methods on the same pitch
# Smallest scaled Jacobian (1 is a perfect cell, below 0 a folded one). Like the `deform move`
# tool, `deform` refuses a result that folds cells the input did not have (`KernelError`);
# `allow_folds=True` returns it anyway, to look at. Plain springs fold the cells at the sharp
# trailing edge; the rotation-aware methods keep them.

# %%
for method in ("quaternion", "spring", "idw", "rbf", "elasticity"):
    moved = dk.deform(points, cells, airfoil, dk.Rotation(ANGLE, center=(0.25, 0.0)),
                      fixed=farfield, method=method, allow_folds=True)
    jac = dk.quality(moved, cells)["scaled_jacobian"]
    print(f"{method:>10}: smallest scaled Jacobian {jac.min():+.3f}, "
          f"{np.count_nonzero(jac <= 0)} folded cells")

# %% [markdown]
# ## An oscillating pitch, time-stepped with a Plan
# The plan validates the mesh and builds stiffness and multigrid once; each step passes the
# new boundary positions and starts from the previous solutions.

# %%
boundary = np.concatenate([airfoil, farfield])
plan = dk.Plan(points, cells, boundary, method="spring")
frames = []
for step in range(1, 13):
    angle = 10.0 * np.sin(2.0 * np.pi * step / 12)
    c, s = np.cos(np.radians(angle)), np.sin(np.radians(angle))
    wall = (points[airfoil] - [0.25, 0.0]) @ np.array([[c, s], [-s, c]]) + [0.25, 0.0]
    positions = np.ascontiguousarray(np.concatenate([wall, points[farfield]]))
    frame, step_info = plan.step(positions, return_info=True)
    frames.append(frame)
    print(f"step {step:2d}: pitch {angle:+6.2f}°, {step_info['iterations']:2d} iterations "
          f"({'warm' if step_info['warm'] else 'cold'} start)")

# %% [markdown]
# ## Plot (matplotlib)

# %%
if len(sys.argv) > 1:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    titles = ("undeformed", "pitched 10° nose-up (quaternion method)")
    for ax, p, title in zip(axes, (points, pitched), titles):
        ax.add_collection(PolyCollection(p[quads], facecolor="none", edgecolor="k", lw=0.3))
        ax.fill(*p[airfoil].T, color="tab:blue")
        ax.set_xlim(-0.4, 1.4)
        ax.set_ylim(-0.6, 0.6)
        ax.set_aspect("equal")
        ax.set_title(title)
    fig.savefig(sys.argv[1], dpi=130)
    print(f"wrote {sys.argv[1]}")
