"""Plan: built once, stepped 20 times with warm starts (a pitching body), against the
stateless deform() of every step; bad steps leave the plan and `out` unchanged."""

import numpy as np
import pytest

import deform_kernel as dk
from meshes import holed_square

STEPS = 20


def case():
    pts, tris, hole, outer, _, _ = holed_square(n=13, half=2.0, hole=0.5)
    boundary = np.concatenate([hole, outer])
    return pts, tris, hole, outer, boundary


def pitch(s):
    """The body's angle at step s (degrees): one period of a 4-degree pitch."""
    return 4.0 * np.sin(2.0 * np.pi * s / STEPS)


def test_spring_plan_twenty_warm_steps_match_stateless_calls():
    pts, tris, hole, outer, boundary = case()
    plan = dk.Plan(pts, [("triangle", tris)], boundary, method="spring")
    cells = [("triangle", tris)]
    warm_iterations, cold_iterations = 0, 0
    out = np.empty_like(pts)
    for s in range(1, STEPS + 1):
        ref, ref_info = dk.deform(pts, cells, hole, dk.Rotation(pitch(s), (0.0, 0.0)), outer,
                                  method="spring", renumber="off", return_info=True)
        positions = ref[boundary]  # exactly p + d on the boundary
        res, info = plan.step(positions, out=out, return_info=True)
        assert res is out and info["step"] == s == plan.steps
        assert info["converged"]
        # Warm from step 2 on, except where the body passes its rest position (there the
        # cold guess, zero, is the better start and the plan takes it).
        if abs(pitch(s)) > 1e-6:
            assert info["warm"] == (s > 1)
        assert np.array_equal(out[boundary], positions)
        scale = np.max(np.abs(ref - pts))
        assert np.max(np.abs(out - ref)) <= 1e-8 * scale
        warm_iterations += info["iterations"]
        cold_iterations += ref_info["iterations"]
    assert warm_iterations < cold_iterations


@pytest.mark.parametrize("solver", ["amg", "cg", "jacobi"])
def test_cold_step_has_the_bits_of_the_stateless_solve(solver):
    pts, tris, hole, outer, boundary = case()
    plan = dk.Plan(pts, [("triangle", tris)], boundary, method="spring", solver=solver,
                   max_iter=100000)
    ref = dk.deform(pts, [("triangle", tris)], hole, dk.Rotation(3.0), outer, method="spring",
                    solver=solver, renumber="off", max_iter=100000)
    plan.step(pts[boundary])  # a first step, so that the cold start below is a choice
    res = plan.step(ref[boundary], start="cold")
    assert res.tobytes() == ref.tobytes()


def rotations(boundary, hole, degrees):
    """Unit quaternions (w, x, y, z): the pitch on the body's nodes, identity elsewhere."""
    half = np.radians(degrees) / 2.0
    q = np.tile([1.0, 0.0, 0.0, 0.0], (boundary.size, 1))
    q[np.isin(boundary, hole)] = [np.cos(half), 0.0, 0.0, np.sin(half)]
    return q


def test_quaternion_plan_steps_track_the_stateless_method():
    pts, tris, hole, outer, boundary = case()
    plan = dk.Plan(pts, [("triangle", tris)], boundary, method="quaternion")
    for s in range(1, STEPS + 1):
        ref = dk.deform(pts, [("triangle", tris)], hole, dk.Rotation(pitch(s), (0.0, 0.0)),
                        outer, method="quaternion", renumber="off")
        res, info = plan.step(ref[boundary], rotations(boundary, hole, pitch(s)),
                              origin=(0.0, 0.0), return_info=True)
        assert info["converged"] and info["step"] == s
        assert np.max(np.abs(res - ref)) <= 1e-7 * max(np.max(np.abs(ref - pts)), 1e-12)


def test_bad_steps_change_nothing():
    pts, tris, hole, outer, boundary = case()
    plan = dk.Plan(pts, [("triangle", tris)], boundary)
    good = pts[boundary].copy()
    plan.step(good)
    out = np.full_like(pts, 7.0)
    bad = good.copy()
    bad[3, 0] = np.nan
    with pytest.raises(ValueError, match="row 3 is not finite"):
        plan.step(bad, out=out)
    with pytest.raises(ValueError, match="shape"):
        plan.step(good[:-1], out=out)
    with pytest.raises(ValueError, match="rotations"):
        plan.step(good, rotations=np.zeros((boundary.size, 4)), out=out)
    with pytest.raises(TypeError, match="out"):
        plan.step(good, out=out.astype(np.float32))
    assert np.all(out == 7.0) and plan.steps == 1
    q = dk.Plan(pts, [("triangle", tris)], boundary, method="quaternion")
    with pytest.raises(dk.KernelError):  # a zero quaternion cannot be normalised
        q.step(good, np.zeros((boundary.size, 4)), out=out)
    assert np.all(out == 7.0) and q.steps == 0


@pytest.mark.parametrize("kw,message", [
    ({"method": "idw"}, "method"), ({"solver": "lu"}, "solver"), ({"tol": 0.0}, "tol"),
    ({"renumber": "auto"}, "renumber"),
])
def test_bad_plans(kw, message):
    pts, tris, _, _, boundary = case()
    with pytest.raises(ValueError, match=message):
        dk.Plan(pts, [("triangle", tris)], boundary, **kw)
    with pytest.raises(ValueError, match="distinct"):
        dk.Plan(pts, [("triangle", tris)], np.append(boundary, boundary[0]))


@pytest.mark.parametrize("renumber", ["rcm", "hilbert"])
def test_renumbered_plan_matches_the_plain_plan(renumber):
    """A plan that renumbers itself, on a randomly numbered mesh, returns its meshes in the
    caller's numbering: the plain plan's to solver tolerance, the boundary exactly (the bits
    against a caller-renumbered mesh are checked in host-tests/tests/plan/order.rs)."""
    pts, tris, _, _, boundary = case()
    shuffle = np.random.default_rng(3).permutation(len(pts))  # new -> old
    where = np.argsort(shuffle)  # old -> new
    pts, tris, boundary = pts[shuffle], where[tris], where[boundary]
    cells = [("triangle", tris)]
    plan = dk.Plan(pts, cells, boundary, method="quaternion", solver="cg", renumber=renumber)
    plain = dk.Plan(pts, cells, boundary, method="quaternion", solver="cg")
    # The same pools but the stored permutation (2 N indices).
    reals, indices, nbytes = plain.pool_sizes()
    assert plan.pool_sizes() == (reals, indices + 2 * len(pts), nbytes)
    for s in (1, 2):
        half = np.radians(pitch(s)) / 2
        q = np.tile([np.cos(half), 0.0, 0.0, np.sin(half)], (boundary.size, 1))
        moved = pts[boundary] + 0.01 * s
        a = plan.step(moved, q)
        b = plain.step(moved, q)
        assert np.max(np.abs(a - b)) < 1e-7
        assert np.array_equal(a[boundary], moved)
