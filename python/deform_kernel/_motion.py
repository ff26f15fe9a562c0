"""``deform`` and ``quality``: checked arguments in, new arrays out."""

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from . import _native
from ._cells import boundary_cells, normalise_cells
from ._checks import out_array, points_array, vector

METHODS = ("quaternion", "spring", "idw", "angle-direct", "angle-cg", "rbf", "elasticity")
SOLVERS = ("amg", "cg", "cg-ssor", "gauss-seidel", "jacobi")
STIFFNESS = ("batina", "wall-distance", "inverse-volume", "constant")
RENUMBER = ("auto", "off", "rcm", "hilbert")
RBF_KERNELS = ("wendland", "tps")


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


def _motion_args(motion, dim, field_nodes):
    """The motion as the native call's dict, checked."""
    none3 = (0.0, 0.0, 0.0)
    args = {"kind": "", "degrees": 0.0, "axis": none3, "center": None, "vector": none3,
            "field": None}
    if isinstance(motion, Rotation):
        deg = float(motion.degrees)
        if not np.isfinite(deg):
            raise ValueError("motion.degrees: not finite")
        axis = vector("motion.axis", motion.axis, 3)
        if axis == none3:
            raise ValueError("motion.axis: zero vector")
        if dim == 2 and (axis[0] != 0.0 or axis[1] != 0.0):
            raise ValueError("motion.axis: a 2D rotation turns about z")
        if motion.center is not None:
            lengths = (2, 3) if dim == 3 else (2,)
            args["center"] = vector("motion.center", motion.center, dim, lengths)
        return {**args, "kind": "rotate", "degrees": deg, "axis": axis}
    if isinstance(motion, Translation):
        return {**args, "kind": "translate",
                "vector": vector("motion.vector", motion.vector, dim)}
    if isinstance(motion, Displacement):
        if not isinstance(motion.values, np.ndarray):
            raise TypeError("motion.values: expected a float64 numpy array (M, dim)")
        field = points_array(motion.values, "motion.values")
        if field.shape != (field_nodes.size, dim):
            raise ValueError(
                f"motion.values: shape {field.shape}, expected {(field_nodes.size, dim)} "
                "(one row per moved node)")
        if np.unique(field_nodes).size != field_nodes.size:
            raise ValueError("moved: repeated nodes (each needs exactly one displacement row)")
        return {**args, "kind": "field", "field": field}
    raise TypeError("motion: expected Rotation, Translation or Displacement")


def _check_choices(method, solver, stiffness, renumber):
    """The method's names checked; the stiffness default (inverse-volume for elasticity)."""
    for name, value, allowed in (("method", method, METHODS), ("solver", solver, SOLVERS),
                                 ("renumber", renumber, RENUMBER)):
        if value not in allowed:
            raise ValueError(f"{name}: {value!r} is not one of {allowed}")
    if stiffness is None:
        stiffness = "inverse-volume" if method == "elasticity" else "batina"
    if stiffness not in STIFFNESS:
        raise ValueError(f"stiffness: {stiffness!r} is not one of {STIFFNESS}")
    if method == "elasticity":
        if stiffness == "batina":
            raise ValueError("stiffness: 'batina' is a spring stiffness; elasticity takes "
                             "'inverse-volume', 'wall-distance' or 'constant'")
        if solver not in ("amg", "cg"):
            raise ValueError("solver: elasticity takes 'amg' or 'cg'")
    elif stiffness == "constant":
        raise ValueError("stiffness: 'constant' applies to method='elasticity'")
    return stiffness


def _positive(name, value):
    if value is not None and not (np.isfinite(value) and value > 0):
        raise ValueError(f"{name}: must be a positive distance")
    return None if value is None else float(value)


def _check_numbers(o):
    """The numeric options of ``deform`` checked (``o``: the options dict)."""
    if not (o["tol"] > 0 and np.isfinite(o["tol"])) or o["max_iter"] < 1:
        raise ValueError("tol must be positive and finite, max_iter at least 1")
    if not 1 <= o["steps"] <= 10000:
        raise ValueError(f"steps: {o['steps']}, expected 1 to 10000")
    if not (np.isfinite(o["poisson"]) and o["poisson"] > -1.0 and o["poisson"] != 0.5):
        raise ValueError("poisson: must be finite, above -1 and not 0.5 ((-1, 0.5) is the "
                         "stable range; above 0.5 is SU2's DEFORM_COEFF convention)")
    if not (np.isfinite(o["idw_exponent"]) and o["idw_exponent"] > 0):
        raise ValueError("idw_exponent: must be positive")
    if o["idw_theta"] is not None:
        if o["method"] != "idw" or not 0.0 <= o["idw_theta"] < 1.0:
            raise ValueError("idw_theta: applies to method='idw', in [0, 1)")
        if np.isnan(o["idw_tolerance"]) or o["idw_tolerance"] < 0:
            raise ValueError("idw_tolerance: must be >= 0 (inf: theta alone)")
    if o["amg_strength"] is not None:
        multigrid = o["method"] in ("spring", "quaternion", "angle-cg") and o["solver"] == "amg"
        if not multigrid or not 0.0 <= o["amg_strength"] < 1.0:
            raise ValueError("amg_strength: applies to solver='amg' with method='spring', "
                             "'quaternion' or 'angle-cg', in [0, 1)")
    if o["rigid_layer"] is not None and (o["method"] != "elasticity" or not (
            np.isfinite(o["rigid_layer"]) and o["rigid_layer"] >= 0)):
        raise ValueError("rigid_layer: a finite distance >= 0, for method='elasticity'")
    if o["reach"] is not None and o["method"] not in ("quaternion", "idw"):
        raise ValueError(f"reach: applies to the quaternion and idw methods, not {o['method']!r}")
    rbf_given = (o["rbf_radius"], o["rbf_correction"]) != (None, None) or (
        o["rbf_tolerance"], o["rbf_max_centres"], o["rbf_kernel"]) != (0.0, 1000, "wendland")
    if rbf_given and o["method"] != "rbf":
        raise ValueError("rbf_*: these options apply to method='rbf'")
    if o["rbf_kernel"] not in RBF_KERNELS:
        raise ValueError(f"rbf_kernel: {o['rbf_kernel']!r} is not one of {RBF_KERNELS}")
    if o["rbf_radius"] is not None and o["rbf_kernel"] == "tps":
        raise ValueError("rbf_radius: the Wendland support; thin-plate splines have none")
    if not (np.isfinite(o["rbf_tolerance"]) and o["rbf_tolerance"] >= 0):
        raise ValueError("rbf_tolerance: must be >= 0")
    if o["rbf_max_centres"] < 1:
        raise ValueError("rbf_max_centres: at least 1")


def deform(points, cells, moved, motion, fixed=None, method="quaternion", solver="amg",
           stiffness=None, tol=1e-10, max_iter=10000, idw_exponent=2.0,
           allow_unconverged=False, return_info=False, steps=1, slide=None, renumber="auto",
           poisson=0.3, reach=None, rbf_kernel="wendland", rbf_radius=None,
           rbf_tolerance=0.0, rbf_max_centres=1000, rbf_correction=None, idw_theta=None,
           idw_tolerance=0.1, out=None, allow_folds=False, rigid_layer=None,
           amg_strength=None):
    """Moves the mesh: the ``moved`` nodes follow ``motion``, the ``fixed`` nodes stay, the
    ``slide`` markers' nodes slide on their planes, and every other node follows by
    ``method``. Returns the deformed ``(N, dim)`` points (``out`` when given; and an info dict
    with ``return_info``). Same bits as ``deform move`` with the same options.

    Methods: "quaternion" (Samareh's quaternion method, spring propagation), "spring"
    (Batina's linear springs), "idw" (quaternion inverse-distance weighting), "angle-direct"
    and "angle-cg" (Yang & Özgen angle-inclusion springs), "rbf" (radial basis functions:
    ``rbf_kernel`` "wendland"/"tps", ``rbf_radius``, ``rbf_tolerance``, ``rbf_max_centres``,
    ``rbf_correction``), "elasticity" (SU2's linear elasticity, ``poisson`` ratio;
    ``rigid_layer``: the nodes within this distance of the moved nodes move rigidly with
    them, ``deform move --rigid-layer``, rigid motions only).

    ``points``: ``(N, 2|3)`` C-contiguous float64 (3D points are handed to the engine in
    place, not copied). ``cells``: ``(offsets, nodes, kinds)`` numpy arrays (VTK codes) or
    meshio-style blocks ``[("triangle", conn), ...]``. ``moved``/``fixed``: node indices, or
    boundary elements in either cell form (the quaternion method with a ``Displacement`` takes
    the rotations from the boundary's shape: give moved and fixed as elements). ``slide``: a
    list of such markers, each flat (a plane, a line in 2D). ``steps``: the motion in equal
    increments (stiffness re-derived each step). ``solver``: "amg" (default), "cg",
    "cg-ssor", "gauss-seidel", "jacobi". ``stiffness``: "batina" (1/L, the default),
    "wall-distance", "inverse-volume" (elasticity's default), "constant" (elasticity only).
    ``renumber``: "auto" (as the tool: RCM on large scattered meshes), "off", "rcm",
    "hilbert" (the result is in the input's numbering either way). ``reach``: no motion beyond
    this distance (quaternion, idw). ``idw_theta``: the fast tree-based IDW with this opening
    angle and ``idw_tolerance`` (``deform move --idw-theta``). ``amg_strength``: the
    multigrid's strength threshold θ (``deform move --amg-strength``; 0.25 by default, which
    coarsens along stretched boundary layers; 0 makes every spring strong). A solve that stops before
    ``tol`` within ``max_iter`` raises ``KernelError`` unless ``allow_unconverged``; so does
    a result with cells inverted or folded that were valid in the input (as ``deform move``
    refuses it), unless ``allow_folds``. ``out``:
    a writable C-contiguous float64 ``(N, dim)`` array for the result (may be ``points``);
    it is written only on success. The GIL is released during the work.
    """
    points = points_array(points)
    n, dim = points.shape
    out = out_array(out, points.shape)
    if out is not None and np.shares_memory(out, points):
        points = points.copy()
    stiffness = _check_choices(method, solver, stiffness, renumber)
    options = {"method": method, "solver": solver, "stiffness": stiffness, "tol": float(tol),
               "max_iter": int(max_iter), "idw_exponent": float(idw_exponent),
               "steps": int(steps), "renumber": renumber, "poisson": float(poisson),
               "rigid_layer": None if rigid_layer is None else float(rigid_layer),
               "reach": _positive("reach", reach), "rbf_kernel": rbf_kernel,
               "rbf_radius": _positive("rbf_radius", rbf_radius),
               "rbf_tolerance": float(rbf_tolerance), "rbf_max_centres": int(rbf_max_centres),
               "rbf_correction": _positive("rbf_correction", rbf_correction),
               "allow_unconverged": bool(allow_unconverged),
               "allow_folds": bool(allow_folds),
               "idw_theta": None if idw_theta is None else float(idw_theta),
               "idw_tolerance": float(idw_tolerance),
               "amg_strength": None if amg_strength is None else float(amg_strength)}
    _check_numbers(options)
    cells = normalise_cells(cells, n)
    moved_cells, field_nodes = boundary_cells("moved", moved, n)
    if field_nodes.size == 0:
        raise ValueError("moved: no nodes")
    slide = [] if slide is None else list(slide)
    roles = {"moved": moved_cells, "fixed": boundary_cells("fixed", fixed, n)[0],
             "slide": [boundary_cells(f"slide[{k}]", s, n)[0] for k, s in enumerate(slide)],
             "field_nodes": field_nodes}
    if (isinstance(motion, Displacement) and method in ("quaternion", "idw")
            and moved_cells[2].size and (moved_cells[2] == 1).all()):
        raise ValueError(f"method {method!r} needs a Rotation or Translation, or a "
                         "Displacement with the moved boundary elements (moved as cells)")
    args = _motion_args(motion, dim, field_nodes)
    res, iterations, residual, converged, (sliding, offset, centres) = _native.move_points(
        points, cells, roles, args, options, out)
    res = out if res is None else res
    if return_info:
        return res, {"iterations": iterations, "residual": residual, "converged": converged,
                     "sliding_nodes": sliding, "max_slide_offset": offset,
                     "rbf_centres": centres}
    return res


def quality(points, cells):
    """Signed measure (length, area or volume) and smallest scaled corner Jacobian of every
    cell: a dict of two new ``(C,)`` float64 arrays, ``measure`` and ``scaled_jacobian``."""
    points = points_array(points)
    offsets, nodes, kinds = normalise_cells(cells, points.shape[0])
    measure, jac = _native.cell_quality(points, (offsets, nodes, kinds))
    return {"measure": measure, "scaled_jacobian": jac}
