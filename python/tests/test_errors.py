"""Bad input: a clear exception before anything runs, and the caller's arrays untouched."""

import numpy as np
import pytest

import deform_kernel as dk
from meshes import holed_square


def case():
    pts, tris, hole, outer, _, _ = holed_square(n=5, half=1.0, hole=0.5)
    return pts, tris, hole, outer


def call(pts, tris, hole, outer, **kw):
    motion = kw.pop("motion", dk.Rotation(5.0))
    return dk.deform(pts, [("triangle", tris)], hole, motion, outer, **kw)


def mutate_pts(f):
    def run(pts, tris, hole, outer):
        return f(pts), tris, hole, outer
    return run


BAD = {
    "int points": (lambda p, t, h, o: (p.astype(np.int64), t, h, o), TypeError, "dtype"),
    "float32 points": (lambda p, t, h, o: (p.astype(np.float32), t, h, o), TypeError, "float64"),
    "not contiguous": (lambda p, t, h, o: (np.asfortranarray(p), t, h, o), ValueError,
                       "C-contiguous"),
    "1 column": (lambda p, t, h, o: (np.ascontiguousarray(p[:, :1]), t, h, o), ValueError,
                 "shape"),
    "list points": (lambda p, t, h, o: (p.tolist(), t, h, o), TypeError, "numpy array"),
    "nan point": (lambda p, t, h, o: (np.where(np.arange(len(p))[:, None] == 3, np.nan, p),
                                      t, h, o), ValueError, "row 3 is not finite"),
    "moved out of range": (lambda p, t, h, o: (p, t, np.append(h, len(p)), o), ValueError,
                           "moved: entry"),
    "negative fixed": (lambda p, t, h, o: (p, t, h, np.append(o, -1)), ValueError,
                       "fixed: entry"),
    "cell out of range": (lambda p, t, h, o: (p, np.where(t == 0, len(p), t), h, o),
                          ValueError, "outside"),
    "float moved": (lambda p, t, h, o: (p, t, h.astype(float), o), TypeError, "integers"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input_raises_and_touches_nothing(name):
    pts, tris, hole, outer = case()
    change, exc, message = BAD[name]
    args = change(pts, tris, hole, outer)
    before = [np.array(a, copy=True) for a in args]
    with pytest.raises(exc, match=message):
        call(*args)
    for a, b in zip(args, before):
        assert np.array_equal(np.asarray(a), b, equal_nan=True)


@pytest.mark.parametrize("kw,message", [
    ({"method": "magic"}, "method"),
    ({"solver": "lu"}, "solver"),
    ({"stiffness": "soft"}, "stiffness"),
    ({"tol": -1.0}, "tol"),
    ({"motion": dk.Rotation(5.0, axis=(1, 0, 0))}, "about z"),
    ({"motion": dk.Rotation(float("nan"))}, "degrees"),
    ({"motion": dk.Translation((1.0, 2.0, 3.0))}, "motion.vector"),
    ({"motion": dk.Displacement(np.zeros((2, 2)))}, "needs a Rotation"),
    ({"motion": "up"}, "motion"),
])
def test_bad_options(kw, message):
    pts, tris, hole, outer = case()
    with pytest.raises((TypeError, ValueError), match=message):
        call(pts, tris, hole, outer, **kw)


def test_kernel_errors_carry_kind_arg_and_position():
    pts, tris, hole, outer = case()
    kinds = np.full(len(tris), 5)
    kinds[4] = 7  # not a VTK kind the kernel knows
    csr = (np.arange(0, 3 * len(tris) + 1, 3), tris.reshape(-1), kinds)
    with pytest.raises(dk.KernelError) as e:
        dk.deform(pts, csr, hole, dk.Rotation(5.0), outer)
    assert isinstance(e.value, ValueError)
    assert (e.value.kind, e.value.arg, e.value.position) == ("Cell", "cells", 4)
    bad = (np.array([0, 3, 5]), np.array([0, 1, 2, 3, 4]), np.array([5, 5]))
    with pytest.raises(dk.KernelError) as e:  # 2 nodes for a triangle
        dk.quality(pts, bad)
    assert e.value.position == 1


def test_success_leaves_inputs_untouched():
    pts, tris, hole, outer = case()
    before = [a.copy() for a in (pts, tris, hole, outer)]
    out = call(pts, tris, hole, outer)
    assert out is not pts and not np.shares_memory(out, pts)
    for a, b in zip((pts, tris, hole, outer), before):
        assert np.array_equal(a, b)
