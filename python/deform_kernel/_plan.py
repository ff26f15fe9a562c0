"""``Plan``: a deformation prepared once and stepped many times (warm starts)."""

import numpy as np

from . import _native
from ._cells import normalise_cells
from ._checks import index_array, out_array, points_array
from ._motion import SOLVERS

PLAN_METHODS = ("spring", "quaternion")
PLAN_RENUMBER = ("off", "rcm", "hilbert")


class Plan:
    """A prepared deformation of one mesh (the kernel's ``Plan``, its pools owned by this
    object): the mesh graph, Batina stiffness (1/L) and the solver (multigrid hierarchy) are
    validated and built once; every :meth:`step` takes new absolute positions of the
    ``boundary`` nodes and deforms the *reference* mesh, starting the solve from the previous
    steps' solutions (warm start). ``method``: "spring" (linear springs on the displacements)
    or "quaternion" (Samareh's quaternion method, spring propagation; each step then needs
    one rotation quaternion per boundary node). A cold step gives the bits of the stateless
    ``deform(method="spring", renumber="off")`` with the same solver (tested).
    ``renumber``: "off" (default), "rcm" or "hilbert": the plan solves on the mesh renumbered
    for memory locality and returns every mesh in the caller's numbering, bit for bit what an
    unrenumbered plan gives on the renumbered mesh, put back (worth it on meshes numbered as a
    generator writes them; leave it off for a mesh that is already ordered).
    """

    def __init__(self, points, cells, boundary, method="spring", solver="amg", tol=1e-10,
                 max_iter=10000, renumber="off"):
        points = points_array(points)
        n, self.dim = points.shape
        if method not in PLAN_METHODS:
            raise ValueError(f"method: {method!r} is not one of {PLAN_METHODS}")
        if solver not in SOLVERS:
            raise ValueError(f"solver: {solver!r} is not one of {SOLVERS}")
        if renumber not in PLAN_RENUMBER:
            raise ValueError(f"renumber: {renumber!r} is not one of {PLAN_RENUMBER}")
        if not (tol > 0 and np.isfinite(tol)) or int(max_iter) < 1:
            raise ValueError("tol must be positive and finite, max_iter at least 1")
        boundary = index_array("boundary", boundary, n)
        if boundary.size == 0 or np.unique(boundary).size != boundary.size:
            raise ValueError("boundary: needs distinct node indices (at least one)")
        cells = normalise_cells(cells, n)
        self.method, self.node_count = method, n
        self.boundary = boundary
        self.boundary.flags.writeable = False
        self.steps = 0
        self._native = _native.NativePlan(points, cells, boundary, method, solver, float(tol),
                                          int(max_iter), renumber)

    def pool_sizes(self):
        """``(reals, indices, bytes)``: the lengths of the three pools the plan owns."""
        return self._native.pool_sizes()

    def _rotations(self, rotations):
        b = self.boundary.size
        if self.method == "spring":
            if rotations is not None:
                raise ValueError("rotations: only for method='quaternion'")
            return None
        if rotations is None:
            raise ValueError("rotations: method='quaternion' needs one (w, x, y, z) per "
                             "boundary node")
        r = np.asarray(rotations)
        if r.dtype != np.float64 or r.shape != (b, 4) or not r.flags.c_contiguous:
            raise ValueError(f"rotations: expected C-contiguous float64 of shape {(b, 4)}")
        if not np.isfinite(r).all():
            raise ValueError("rotations: not finite")
        return r

    def step(self, positions, rotations=None, origin=None, start="warm", out=None,
             return_info=False):
        """Deforms the reference mesh so that boundary node ``boundary[k]`` lands on
        ``positions[k]`` (``(B, dim)`` float64): new ``(N, dim)`` points (``out`` when
        given). ``start``: "warm" (from the previous solutions, the default) or "cold".
        ``origin``: the rotation origin (quaternion; default the moving points' centroid).
        With ``return_info``, also ``{"iterations", "residual", "converged", "warm",
        "extrapolated", "step"}``. On error nothing is written and the plan is unchanged."""
        positions = points_array(positions, "positions")
        if positions.shape != (self.boundary.size, self.dim):
            raise ValueError(f"positions: shape {positions.shape}, expected "
                             f"{(self.boundary.size, self.dim)}")
        if start not in ("warm", "cold"):
            raise ValueError(f"start: {start!r} is not 'warm' or 'cold'")
        if origin is not None:
            origin = np.asarray(origin, dtype=np.float64)
            if origin.shape != (self.dim,) or not np.isfinite(origin).all():
                raise ValueError(f"origin: expected {self.dim} finite values")
            origin = tuple(float(x) for x in origin) + (0.0,) * (3 - self.dim)
        out = out_array(out, (self.node_count, self.dim))
        res, it, residual, converged, warm, extrapolated, step = self._native.step(
            positions, self._rotations(rotations), origin, start == "cold", out)
        self.steps = step
        res = out if res is None else res
        if return_info:
            return res, {"iterations": it, "residual": residual, "converged": converged,
                         "warm": warm, "extrapolated": extrapolated, "step": step}
        return res
