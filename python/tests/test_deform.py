"""deform(): against dense numpy references, exact rigid motions, and input checks."""

import numpy as np
import pytest

import deform_kernel as dk
from meshes import HEX_EDGES, batina_dense_solve, hex_box, holed_square


@pytest.fixture()
def mesh():
    pts, tris, hole, outer, _, _ = holed_square()
    return pts, tris, hole, outer


def rotate(p, degrees, c):
    t = np.radians(degrees)
    r = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
    return (p - c) @ r.T + c


def test_spring_matches_dense_solve(mesh):
    pts, tris, hole, outer = mesh
    out = dk.deform(pts, [("triangle", tris)], hole, dk.Rotation(7.0, center=(0.1, -0.2)),
                    fixed=outer, method="spring", tol=1e-14)
    disp = np.zeros_like(pts)
    disp[hole] = rotate(pts[hole], 7.0, np.array([0.1, -0.2])) - pts[hole]
    ref = pts + batina_dense_solve(pts, tris, np.concatenate([hole, outer]), disp)
    assert np.max(np.abs(out - ref)) < 1e-12
    assert np.max(np.abs(out - pts)) > 1e-2  # the interior did move


@pytest.mark.parametrize("solver", ["cg", "cg-ssor", "gauss-seidel"])
def test_spring_solvers_agree(mesh, solver):
    pts, tris, hole, outer = mesh
    motion = dk.Translation((0.05, 0.1))
    a = dk.deform(pts, [("triangle", tris)], hole, motion, outer, "spring", tol=1e-13)
    b = dk.deform(pts, [("triangle", tris)], hole, motion, outer, "spring", solver, tol=1e-13)
    assert np.max(np.abs(a - b)) < 1e-10


@pytest.mark.parametrize("method", ["quaternion", "idw"])
def test_rigid_rotation_is_exact(mesh, method):
    """Every boundary node turns the same way: the whole mesh turns rigidly."""
    pts, tris, hole, outer = mesh
    c = np.array([0.3, -0.1])
    out = dk.deform(pts, [("triangle", tris)], np.concatenate([hole, outer]),
                    dk.Rotation(30.0, center=c), method=method)
    assert np.max(np.abs(out - rotate(pts, 30.0, c))) < 1e-14


def test_translation_is_exact_for_every_method(mesh):
    pts, tris, hole, outer = mesh
    everything = np.concatenate([hole, outer])
    # Exact for the quaternion methods; springs: up to the iterative solve's tolerance.
    for method, tol, err in [("quaternion", 1e-10, 1e-15), ("idw", 1e-10, 1e-15),
                             ("spring", 1e-14, 1e-13)]:
        out = dk.deform(pts, [("triangle", tris)], everything, dk.Translation((0.25, -0.5)),
                        method=method, tol=tol)
        assert np.max(np.abs(out - (pts + [0.25, -0.5]))) < err, method


def test_quaternion_keeps_boundary_and_returns_info(mesh):
    pts, tris, hole, outer = mesh
    out, info = dk.deform(pts, [("triangle", tris)], hole, dk.Rotation(20.0), outer,
                          return_info=True)
    assert info["converged"] and info["iterations"] > 0
    c = pts[np.unique(hole)].mean(axis=0)
    assert np.max(np.abs(out[hole] - rotate(pts[hole], 20.0, c))) < 1e-14
    assert np.array_equal(out[outer], pts[outer])
    assert dk.quality(out, [("triangle", tris)])["measure"].min() > 0


def test_displacement_field_with_springs(mesh):
    pts, tris, hole, outer = mesh
    d = np.column_stack([0.01 * np.arange(hole.size), np.zeros(hole.size)])
    out = dk.deform(pts, [("triangle", tris)], hole, dk.Displacement(d), outer, "spring",
                    tol=1e-14)
    disp = np.zeros_like(pts)
    disp[hole] = d
    ref = pts + batina_dense_solve(pts, tris, np.concatenate([hole, outer]), disp)
    assert np.max(np.abs(out - ref)) < 1e-12


def test_csr_cells_equal_blocks(mesh):
    pts, tris, hole, outer = mesh
    csr = (np.arange(0, 3 * len(tris) + 1, 3), tris.reshape(-1), np.full(len(tris), 5))
    a = dk.deform(pts, csr, hole, dk.Rotation(5.0), outer)
    b = dk.deform(pts, [(5, tris)], hole, dk.Rotation(5.0), outer)
    assert a.tobytes() == b.tobytes()


def test_unconverged_solve_raises(mesh):
    pts, tris, hole, outer = mesh
    args = (pts, [("triangle", tris)], hole, dk.Rotation(5.0), outer, "spring", "jacobi")
    with pytest.raises(dk.KernelError, match="stopped"):
        dk.deform(*args, max_iter=2)
    out, info = dk.deform(*args, max_iter=2, allow_unconverged=True, return_info=True)
    assert not info["converged"] and info["iterations"] == 2


def rotation_matrix(axis, degrees):
    """Rodrigues' rotation matrix (independent of the kernel's quaternions)."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    t = np.radians(degrees)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(t) * kx + (1 - np.cos(t)) * kx @ kx


def test_3d_rigid_rotation_about_any_axis_is_exact():
    pts, hexes, bottom, others = hex_box()
    everything = np.unique(np.concatenate([bottom.ravel(), others.ravel()]))
    c = np.array([0.2, 0.4, 0.1])
    ref = (pts - c) @ rotation_matrix((1.0, 2.0, 3.0), 40.0).T + c
    for method in ("quaternion", "idw"):
        out = dk.deform(pts, [("hexahedron", hexes)], everything,
                        dk.Rotation(40.0, center=c, axis=(1.0, 2.0, 3.0)), method=method)
        assert np.max(np.abs(out - ref)) < 1e-14, method


def test_3d_springs_match_dense_solve():
    pts, hexes, bottom, others = hex_box(5)
    moved, fixed = np.unique(bottom), np.unique(others)
    fixed = np.setdiff1d(fixed, moved)
    r = rotation_matrix((0.0, 1.0, 0.0), 4.0)
    out = dk.deform(pts, [(12, hexes)], moved, dk.Rotation(4.0, (0.5, 0.5, 0.0), (0, 1, 0)),
                    fixed, method="spring", tol=1e-14)
    disp = np.zeros_like(pts)
    c = np.array([0.5, 0.5, 0.0])
    disp[moved] = (pts[moved] - c) @ r.T + c - pts[moved]
    ref = pts + batina_dense_solve(pts, hexes, np.concatenate([moved, fixed]), disp, HEX_EDGES)
    assert np.max(np.abs(out - ref)) < 1e-12
    assert np.max(np.abs(out - pts)[np.setdiff1d(np.arange(len(pts)), np.concatenate(
        [moved, fixed]))]) > 1e-4
