"""``smooth_structured``: Alter's arclength Taubin filter on a structured block."""

import numpy as np

from . import _native
from ._cells import normalise_cells
from ._checks import index_array, points_array


def _checked_block(points):
    """``points`` checked: float64 ``(ni, nj, 2)`` or ``(ni, nj, nk, 3)``, finite."""
    if not isinstance(points, np.ndarray) or points.dtype != np.float64:
        raise TypeError("points: expected a float64 numpy array (ni, nj, 2) or (ni, nj, nk, 3)")
    if not ((points.ndim == 3 and points.shape[2] == 2) or
            (points.ndim == 4 and points.shape[3] == 3)):
        raise ValueError(f"points: shape {points.shape}, expected (ni, nj, 2) or (ni, nj, nk, 3)")
    if not np.isfinite(points).all():
        raise ValueError("points: not finite")
    return points


def smooth_structured(points, direction, iterations=30, lam=0.33, mu=-0.334,
                      normalised=False, fixed=None, coarse=None, return_info=False):
    """Smooths the arclength along the ``direction`` ("i", "j" or "k") grid lines of a
    structured block (Alter's Taubin filter, as ``deform smooth``): ``points[i, j]`` (2D,
    shape ``(ni, nj, 2)``) or ``points[i, j, k]`` (3D, ``(ni, nj, nk, 3)``), float64. Line ends
    stay; ``fixed`` (a boolean array of shape ``points.shape[:-1]``) pins more points;
    ``normalised`` filters S/S_line (reduces stretching) instead of S; ``coarse=M`` adds
    Alter's coarse pass. Returns new points of the same shape (and an info dict with
    ``return_info``: iterations, largest stretching ratio before and after, largest move)."""
    points = _checked_block(points)
    dim = points.shape[-1]
    order = (1, 0, 2) if dim == 2 else (2, 1, 0, 3)
    dims = list(points.shape[:-1]) + [1] * (4 - points.ndim)
    flat = np.ascontiguousarray(points.transpose(order)).reshape(-1, dim)
    mask = None
    if fixed is not None:
        fixed = np.asarray(fixed)
        if fixed.dtype != np.bool_ or fixed.shape != points.shape[:-1]:
            raise ValueError(f"fixed: expected a bool array of shape {points.shape[:-1]}")
        mask = np.ascontiguousarray(fixed.transpose(order[:-1])).reshape(-1).astype(np.uint8)
    if direction not in ("i", "j", "k") or (dim == 2 and direction == "k"):
        raise ValueError(f"direction: {direction!r} is not a direction of a {dim}D block")
    if int(iterations) < 0 or not (np.isfinite(lam) and np.isfinite(mu)):
        raise ValueError("iterations must be >= 0, lam and mu finite")
    out, it, before, after, moved = _native.smooth_block(
        flat, dims, direction, int(iterations), float(lam), float(mu), bool(normalised), mask,
        None if coarse is None else int(coarse))
    back = np.ascontiguousarray(out.reshape(points.shape[:-1][::-1] + (dim,)).transpose(order))
    if return_info:
        info = {"iterations": it, "stretching_before": before, "stretching_after": after,
                "max_point_move": moved}
        return back, info
    return back


def smooth_graph(points, cells, iterations=10, lam=0.33, mu=-0.34, weights="uniform",
                 fixed=None, return_info=False):
    """Taubin λ|μ fairing of unstructured mesh points on the edge graph of ``cells`` (each
    iteration ``x += λ (avg(x) − x)`` then ``x += μ (avg(x) − x)`` over the neighbours):
    ``weights`` "uniform" or "inverse-distance" (1/|x_i − x_j|, Fujiwara); ``fixed`` node
    indices keep their places (for instance the boundary). Returns new ``(N, dim)`` points
    (and ``{"last_change"}`` with ``return_info``)."""
    points = points_array(points)
    n = points.shape[0]
    cells = normalise_cells(cells, n)
    if weights not in ("uniform", "inverse-distance"):
        raise ValueError(f"weights: {weights!r} is not 'uniform' or 'inverse-distance'")
    if int(iterations) < 0 or not (np.isfinite(lam) and np.isfinite(mu)):
        raise ValueError("iterations must be >= 0, lam and mu finite")
    mask = None
    if fixed is not None:
        mask = np.zeros(n, dtype=np.uint8)
        mask[index_array("fixed", fixed, n)] = 1
    out, change = _native.smooth_mesh_graph(points, cells, int(iterations), float(lam),
                                            float(mu), weights == "inverse-distance", mask)
    return (out, {"last_change": change}) if return_info else out
