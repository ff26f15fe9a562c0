"""out=: results written into the caller's array (or in place), only on success; bad
arrays for the newer arguments refused before anything runs."""

import numpy as np
import pytest

import deform_kernel as dk
from meshes import hex_box, holed_square


def case():
    pts, tris, hole, outer, _, _ = holed_square(n=7, half=1.5, hole=0.5)
    return pts, [("triangle", tris)], hole, outer


@pytest.mark.parametrize("method", ["spring", "quaternion", "rbf", "elasticity"])
def test_out_gets_the_same_bits(method):
    pts, cells, hole, outer = case()
    new = dk.deform(pts, cells, hole, dk.Rotation(6.0), outer, method=method)
    out = np.zeros_like(pts)
    res = dk.deform(pts, cells, hole, dk.Rotation(6.0), outer, method=method, out=out)
    assert res is out and out.tobytes() == new.tobytes()
    inplace = pts.copy()
    res = dk.deform(inplace, cells, hole, dk.Rotation(6.0), outer, method=method, out=inplace)
    assert res is inplace and inplace.tobytes() == new.tobytes()


def test_3d_in_and_out():
    pts, hexes, bottom, others = hex_box(4)
    fixed = np.setdiff1d(np.unique(others), np.unique(bottom))
    before = pts.copy()
    new = dk.deform(pts, [("hexahedron", hexes)], np.unique(bottom),
                    dk.Translation((0.0, 0.0, 0.05)), fixed, method="spring")
    assert new.flags.c_contiguous and new.flags.writeable and new.dtype == np.float64
    assert new.shape == pts.shape and not np.shares_memory(new, pts)
    assert np.array_equal(pts, before)
    out = np.empty_like(pts)
    dk.deform(pts, [("hexahedron", hexes)], np.unique(bottom),
              dk.Translation((0.0, 0.0, 0.05)), fixed, method="spring", out=out)
    assert out.tobytes() == new.tobytes()


BAD_OUT = {
    "float32": (lambda p: np.zeros(p.shape, np.float32), TypeError, "out"),
    "shape": (lambda p: np.zeros((len(p) + 1, 2)), ValueError, "out: shape"),
    "fortran": (lambda p: np.asfortranarray(np.zeros(p.shape)), ValueError, "C-contiguous"),
    "read-only": (lambda p: np.lib.stride_tricks.as_strided(np.zeros(p.shape)), None, None),
}


@pytest.mark.parametrize("name", sorted(BAD_OUT))
def test_bad_out_refused_and_untouched(name):
    pts, cells, hole, outer = case()
    make, exc, message = BAD_OUT[name]
    out = make(pts)
    if name == "read-only":
        out = np.full(pts.shape, 3.0)
        out.flags.writeable = False
        exc, message = ValueError, "writable"
    before = out.copy()
    with pytest.raises(exc, match=message):
        dk.deform(pts, cells, hole, dk.Rotation(6.0), outer, out=out)
    assert np.array_equal(out, before)


def test_unconverged_leaves_out_untouched():
    pts, cells, hole, outer = case()
    out = np.full_like(pts, 5.0)
    with pytest.raises(dk.KernelError, match="nothing was written"):
        dk.deform(pts, cells, hole, dk.Rotation(6.0), outer, method="spring",
                  solver="jacobi", max_iter=2, out=out)
    assert np.all(out == 5.0)


BAD = [
    ({"slide": [[len(case()[0])]]}, ValueError, r"slide\[0\]: entry"),
    ({"slide": [[("line", np.array([[0, 1], [1, -1]]))]]}, ValueError, "outside"),
    ({"steps": 0}, ValueError, "steps"),
    ({"method": "elasticity", "stiffness": "batina"}, ValueError, "spring stiffness"),
    ({"method": "elasticity", "solver": "jacobi"}, ValueError, "elasticity takes"),
    ({"method": "spring", "stiffness": "constant"}, ValueError, "constant"),
    ({"method": "elasticity", "poisson": 0.5}, ValueError, "poisson"),
    ({"method": "spring", "rigid_layer": 0.1}, ValueError, "rigid_layer"),
    ({"method": "elasticity", "rigid_layer": -0.1}, ValueError, "rigid_layer"),
    ({"method": "rbf", "rbf_kernel": "gauss"}, ValueError, "rbf_kernel"),
    ({"method": "rbf", "rbf_kernel": "tps", "rbf_radius": 1.0}, ValueError, "Wendland"),
    ({"method": "rbf", "rbf_radius": -1.0}, ValueError, "positive"),
    ({"renumber": "random"}, ValueError, "renumber"),
    ({"reach": float("nan")}, ValueError, "reach"),
    ({"method": "spring", "reach": 1.0}, ValueError, "reach: applies"),
    ({"method": "spring", "rbf_tolerance": 0.1}, ValueError, "rbf_"),
    ({"method": "quaternion", "idw_theta": 0.5}, ValueError, "idw_theta"),
    ({"method": "idw", "amg_strength": 0.1}, ValueError, "amg_strength"),
    ({"method": "spring", "amg_strength": 1.0}, ValueError, "amg_strength"),
    ({"method": "idw", "idw_exponent": 0.0}, ValueError, "idw_exponent"),
]


@pytest.mark.parametrize("kw,exc,message", BAD)
def test_bad_new_arguments(kw, exc, message):
    pts, cells, hole, outer = case()
    before = pts.copy()
    with pytest.raises(exc, match=message):
        dk.deform(pts, cells, hole, dk.Rotation(6.0), outer, **kw)
    assert np.array_equal(pts, before)


def test_bad_displacements_and_curved_slide():
    pts, cells, hole, outer = case()
    with pytest.raises(ValueError, match="motion.values: row 1 is not finite"):
        vals = np.zeros((hole.size, 2))
        vals[1, 0] = np.nan
        dk.deform(pts, cells, hole, dk.Displacement(vals), outer, method="spring")
    with pytest.raises(ValueError, match="C-contiguous"):
        vals = np.asfortranarray(np.zeros((hole.size, 2)))
        dk.deform(pts, cells, hole, dk.Displacement(vals), outer, method="spring")
    # The hole's edges are not on one line: they cannot slide.
    _, tris, hole2, outer2, hole_edges, _ = holed_square(n=7, half=1.5, hole=0.5)
    with pytest.raises(ValueError, match="not straight"):
        dk.deform(pts, cells, outer2[:3], dk.Translation((0.1, 0.0)), None,
                  method="spring", slide=[[("line", hole_edges)]])
