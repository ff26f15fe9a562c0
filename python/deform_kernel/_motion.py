"""``deform`` and ``quality``: checked arguments in, new arrays out."""

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from . import _native
from ._cells import normalise_cells
from ._checks import index_array, points_array, vector
from ._native import KernelError

METHODS = ("quaternion", "spring", "idw")
SOLVERS = ("amg", "cg", "cg-ssor", "gauss-seidel", "jacobi")
STIFFNESS = ("batina", "wall-distance", "inverse-volume")


@dataclass(frozen=True)
class Rotation:
    """Rigid rotation by ``degrees`` (counter-clockwise, right-hand rule) about ``axis``
    through ``center`` (``None``: the centroid of the moved nodes)."""

    degrees: float
    center: Optional[Sequence[float]] = None
    axis: Sequence[float] = (0.0, 0.0, 1.0)


@dataclass(frozen=True)
class Translation:
    """Rigid translation of the moved nodes by ``vector`` (2 or 3 entries, as the points)."""

    vector: Sequence[float]


@dataclass(frozen=True)
class Displacement:
    """One displacement row per entry of ``moved``: an ``(M, dim)`` float64 array."""

    values: np.ndarray


def _motion_args(motion, dim, moved):
    """``(kind, degrees, axis, center, vector, field)`` for the native call, checked."""
    none3 = (0.0, 0.0, 0.0)
    if isinstance(motion, Rotation):
        deg = float(motion.degrees)
        if not np.isfinite(deg):
            raise ValueError("motion.degrees: not finite")
        axis = vector("motion.axis", motion.axis, 3)
        if axis == none3:
            raise ValueError("motion.axis: zero vector")
        if dim == 2 and (axis[0] != 0.0 or axis[1] != 0.0):
            raise ValueError("motion.axis: a 2D rotation turns about z")
        center = None
        if motion.center is not None:
            center = vector("motion.center", motion.center, dim, (2, 3) if dim == 3 else (2,))
        return "rotate", deg, axis, center, none3, None
    if isinstance(motion, Translation):
        return "translate", 0.0, none3, None, vector("motion.vector", motion.vector, dim), None
    if isinstance(motion, Displacement):
        field = points_array(motion.values) if isinstance(motion.values, np.ndarray) else None
        if field is None:
            raise TypeError("motion.values: expected a float64 numpy array (M, dim)")
        if field.shape != (moved.size, dim):
            raise ValueError(f"motion.values: shape {field.shape}, expected {(moved.size, dim)}")
        if np.unique(moved).size != moved.size:
            raise ValueError("moved: repeated nodes (each needs exactly one displacement row)")
        return "field", 0.0, none3, None, none3, field
    raise TypeError("motion: expected Rotation, Translation or Displacement")


def deform(
    points,
    cells,
    moved,
    motion,
    fixed=None,
    method="quaternion",
    solver="amg",
    stiffness="batina",
    tol=1e-10,
    max_iter=10000,
    idw_exponent=2.0,
    allow_unconverged=False,
    return_info=False,
):
    """Moves the mesh: the ``moved`` nodes follow ``motion``, the ``fixed`` nodes stay, and
    every other node follows by ``method`` ("quaternion": Samareh's quaternion method with
    spring propagation; "spring": Batina's linear springs; "idw": quaternion inverse-distance
    weighting). Returns new ``(N, dim)`` points (and an info dict with ``return_info``).

    ``points``: ``(N, 2|3)`` C-contiguous float64. ``cells``: a tuple of numpy arrays
    ``(offsets, nodes, kinds)`` (VTK codes) or meshio-style blocks ``[("triangle", conn), ...]``.
    ``moved``/``fixed``: node indices. ``solver`` (spring and quaternion): "amg" (default),
    "cg", "cg-ssor", "gauss-seidel", "jacobi". ``stiffness`` (spring and quaternion): "batina"
    (1/L), "wall-distance" (times d̄/d, d the distance to the moved nodes), "inverse-volume"
    (times V̄/V, V the dual volume), as SU2's options. A solve that stops before ``tol`` within
    ``max_iter`` raises ``KernelError`` unless ``allow_unconverged``. The same call on the same
    input gives the same bits as ``deform move`` (one step).
    """
    points = points_array(points)
    n, dim = points.shape
    cells = normalise_cells(cells, n)
    moved = index_array("moved", moved, n)
    if moved.size == 0:
        raise ValueError("moved: no nodes")
    fixed = index_array("fixed", [] if fixed is None else fixed, n)
    if method not in METHODS:
        raise ValueError(f"method: {method!r} is not one of {METHODS}")
    if solver not in SOLVERS:
        raise ValueError(f"solver: {solver!r} is not one of {SOLVERS}")
    if stiffness not in STIFFNESS:
        raise ValueError(f"stiffness: {stiffness!r} is not one of {STIFFNESS}")
    if method != "spring" and isinstance(motion, Displacement):
        raise ValueError(f"method {method!r} needs a Rotation or Translation in this version")
    if not (tol > 0 and np.isfinite(tol)) or int(max_iter) < 1:
        raise ValueError("tol must be positive and finite, max_iter at least 1")
    kind, deg, axis, center, vec, field = _motion_args(motion, dim, moved)
    out, iterations, residual, converged = _native.move_points(
        points, *cells, moved, fixed, kind, deg, axis, center, vec, field,
        method, solver, stiffness, float(tol), int(max_iter), float(idw_exponent),
    )
    if not converged and not allow_unconverged:
        raise KernelError(
            f"{method}: the solve stopped at relative residual {residual:.3e} after "
            f"{iterations} iterations (tol {tol:g}); raise max_iter or pass allow_unconverged"
        )
    if return_info:
        info = {"iterations": iterations, "residual": residual, "converged": converged}
        return out, info
    return out


def quality(points, cells):
    """Signed measure (length, area or volume) and smallest scaled corner Jacobian of every
    cell: a dict of two new ``(C,)`` float64 arrays, ``measure`` and ``scaled_jacobian``."""
    points = points_array(points)
    offsets, nodes, kinds = normalise_cells(cells, points.shape[0])
    measure, jac = _native.cell_quality(points, offsets, nodes, kinds)
    return {"measure": measure, "scaled_jacobian": jac}
