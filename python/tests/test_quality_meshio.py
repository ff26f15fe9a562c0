"""quality() against numpy geometry; the meshio helpers."""

import numpy as np
import pytest

import deform_kernel as dk
from meshes import holed_square


def test_triangle_areas_match_numpy():
    pts, tris, *_ = holed_square()
    rng = np.random.default_rng(1)
    pts = pts + 0.05 * rng.standard_normal(pts.shape)
    q = dk.quality(pts, [("triangle", tris)])
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    ref = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    assert np.allclose(q["measure"], ref, rtol=1e-13, atol=0)
    flipped = dk.quality(pts, [("triangle", tris[:, ::-1])])
    assert np.allclose(flipped["measure"], -q["measure"], rtol=1e-13, atol=0)
    assert np.all(flipped["scaled_jacobian"] < 0) and np.all(q["scaled_jacobian"] > 0)


def test_unit_square_and_cube():
    sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    q = dk.quality(sq, [("quad", np.array([[0, 1, 2, 3]]))])
    assert q["measure"][0] == 1.0 and q["scaled_jacobian"][0] == 1.0
    cube = np.array([[x, y, z] for z in (0.0, 2.0) for y in (0.0, 2.0) for x in (0.0, 2.0)])
    hexa = np.array([[0, 1, 3, 2, 4, 5, 7, 6]])
    q = dk.quality(cube, [("hexahedron", hexa)])
    assert q["measure"][0] == pytest.approx(8.0, rel=1e-15)
    assert q["scaled_jacobian"][0] == pytest.approx(1.0, rel=1e-15)


def test_meshio_round_trip():
    meshio = pytest.importorskip("meshio")
    pts, tris, hole, outer, _, _ = holed_square()
    mesh = meshio.Mesh(np.column_stack([pts, np.zeros(len(pts))]),
                       [("triangle", tris), ("line", np.array([[0, 1]]))])
    p2, cells = dk.from_meshio(mesh)
    assert p2.shape == pts.shape and np.array_equal(p2, pts)
    assert [t for t, _ in cells] == ["triangle"]
    out = dk.deform(p2, cells, hole, dk.Rotation(3.0), outer)
    back = dk.to_meshio(out, cells)
    assert isinstance(back, meshio.Mesh) and np.array_equal(back.points, out)
