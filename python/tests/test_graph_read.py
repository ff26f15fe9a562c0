"""smooth_graph against a numpy Taubin filter; read() against the files the tests write."""

import numpy as np
import pytest

import deform_kernel as dk
from meshes import holed_square, write_su2


def taubin_reference(pts, tris, iterations, lam, mu, fixed, inverse_distance):
    """Taubin's λ|μ filter written out: Jacobi passes of weighted neighbour averages."""
    n = len(pts)
    w = np.zeros((n, n))
    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            d = np.linalg.norm(pts[a] - pts[b])
            w[a, b] = w[b, a] = 1.0 / d if inverse_distance else 1.0
    x = pts.copy()
    free = ~np.isin(np.arange(n), fixed)
    for _ in range(iterations):
        for f in (lam, mu):
            avg = (w @ x) / w.sum(axis=1)[:, None]
            x = x + f * (avg - x) * free[:, None]
    return x


@pytest.mark.parametrize("weights", ["uniform", "inverse-distance"])
def test_graph_taubin_matches_numpy(weights):
    pts, tris, hole, outer, _, _ = holed_square(n=9, half=2.0, hole=0.5)
    rng = np.random.default_rng(3)
    noisy = pts + 0.05 * rng.standard_normal(pts.shape) * (np.abs(pts).max(axis=1) < 1.9)[:, None]
    fixed = np.concatenate([hole, outer])
    before = noisy.copy()
    ours, info = dk.smooth_graph(noisy, [("triangle", tris)], 7, 0.33, -0.34, weights, fixed,
                                 return_info=True)
    ref = taubin_reference(noisy, tris, 7, 0.33, -0.34, fixed,
                           weights == "inverse-distance")
    assert np.array_equal(noisy, before)
    assert np.max(np.abs(ours - ref)) < 1e-13
    assert np.array_equal(ours[fixed], noisy[fixed]) and info["last_change"] > 0
    assert np.max(np.abs(ours - pts)) < np.max(np.abs(noisy - pts))  # the noise shrinks


def test_graph_taubin_bad_input():
    pts, tris, _, _, _, _ = holed_square(n=5, half=1.0, hole=0.5)
    with pytest.raises(ValueError, match="weights"):
        dk.smooth_graph(pts, [("triangle", tris)], weights="cotangent")
    with pytest.raises(ValueError, match="fixed: entry"):
        dk.smooth_graph(pts, [("triangle", tris)], fixed=[len(pts)])
    with pytest.raises(dk.KernelError, match="lambda|mu|InvalidParameter|parameter"):
        dk.smooth_graph(pts, [("triangle", tris)], lam=-0.5)


def assert_markers_drive_deform(mesh, pts, tris, body_edges, far_edges):
    """The markers "body" and "farfield" of a read mesh go straight into deform(): the same
    bits as the node indices of the edges that made them."""
    a = dk.deform(mesh.points, mesh.cells, mesh.markers["body"], dk.Rotation(5.0),
                  mesh.markers["farfield"], method="spring")
    b = dk.deform(pts, [("triangle", tris)], np.unique(body_edges), dk.Rotation(5.0),
                  np.unique(far_edges), method="spring")
    assert np.max(np.abs(a - pts)) > 1e-3 and a.tobytes() == b.tobytes()


def test_read_su2_gives_the_written_mesh(tmp_path):
    pts, tris, hole, outer, hole_edges, outer_edges = holed_square(n=9, half=2.0, hole=0.5)
    assert hole_edges.size and outer_edges.size
    pts = pts + 1e-3 * np.sin(pts)  # digits that must survive
    path = tmp_path / "m.su2"
    write_su2(path, pts, tris, {"body": hole_edges, "farfield": outer_edges})
    mesh = dk.read(path)
    assert mesh.points.tobytes() == pts.tobytes()
    offsets, nodes, kinds = mesh.cells
    assert np.array_equal(nodes.reshape(-1, 3), tris) and np.all(kinds == 5)
    assert np.array_equal(offsets, 3 * np.arange(len(tris) + 1))
    assert sorted(mesh.markers) == ["body", "farfield"]
    assert np.array_equal(mesh.markers["body"][1].reshape(-1, 2), hole_edges)
    assert np.array_equal(mesh.marker_nodes("body"), np.unique(hole_edges))
    assert_markers_drive_deform(mesh, pts, tris, hole_edges, outer_edges)


def test_read_plot3d_ascii_block(tmp_path):
    ni, nj = 4, 3
    x, y = np.meshgrid(np.linspace(0, 1, ni) ** 1.5, np.linspace(0, 2, nj), indexing="ij")
    path = tmp_path / "g.xy"
    # Single-block 2D ASCII Plot3D: dims, then all x (i fastest), then all y.
    flat = lambda a: " ".join(repr(float(v)) for v in a.T.reshape(-1))  # noqa: E731
    path.write_text(f"{ni} {nj}\n{flat(x)}\n{flat(y)}\n")
    grid = dk.read(path)
    assert grid.dim == 2 and len(grid.blocks) == 1
    block = grid.blocks[0]
    assert block.shape == (ni, nj, 2)
    assert np.array_equal(block[..., 0], x) and np.array_equal(block[..., 1], y)


def test_read_vtk_through_meshio_and_errors(tmp_path):
    meshio = pytest.importorskip("meshio")
    pts, tris, _, _, _, _ = holed_square(n=5, half=1.0, hole=0.5)
    path = tmp_path / "m.vtu"
    meshio.write(path, meshio.Mesh(np.column_stack([pts, np.zeros(len(pts))]),
                                   [("triangle", tris)]))
    mesh = dk.read(path)
    assert np.array_equal(mesh.points, pts) and mesh.markers == {}
    assert np.array_equal(mesh.cells[1].reshape(-1, 3), tris)
    bad = tmp_path / "bad.su2"
    bad.write_text("NDIME= 4\n")
    with pytest.raises(ValueError, match="bad.su2.*NDIME"):
        dk.read(bad)
    with pytest.raises(ValueError, match="missing.su2"):
        dk.read(tmp_path / "missing.su2")


def test_meshio_markers_from_physical_groups(tmp_path):
    meshio = pytest.importorskip("meshio")
    pts, tris, hole, outer, hole_edges, outer_edges = holed_square(n=9, half=2.0, hole=0.5)
    lines = np.concatenate([hole_edges, outer_edges])
    tags = np.array([7] * len(hole_edges) + [8] * len(outer_edges))
    m = meshio.Mesh(np.column_stack([pts, np.zeros(len(pts))]),
                    [("line", lines), ("triangle", tris)],
                    cell_data={"gmsh:physical": [tags, np.full(len(tris), 1)],
                               "gmsh:geometrical": [tags, np.full(len(tris), 1)]},
                    field_data={"body": np.array([7, 1]), "farfield": np.array([8, 1]),
                                "fluid": np.array([1, 2])})
    mesh = dk.mesh_from_meshio(m)
    assert sorted(mesh.markers) == ["body", "farfield"]
    assert np.array_equal(mesh.markers["body"][1].reshape(-1, 2), hole_edges)
    assert np.array_equal(mesh.marker_nodes("farfield"), np.unique(outer_edges))
    path = tmp_path / "m.msh"
    meshio.write(path, m, file_format="gmsh22", binary=False)
    again = dk.read(path)
    assert np.array_equal(again.points, pts)
    assert np.array_equal(again.marker_nodes("body"), np.unique(hole_edges))
    assert_markers_drive_deform(again, pts, tris, hole_edges, outer_edges)
