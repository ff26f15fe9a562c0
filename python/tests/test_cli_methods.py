"""Bit-equality with `deform move` for the newer options: --steps, --slide, the angle springs,
RBF and linear elasticity (the same SU2 mesh through the tool and through deform())."""

import subprocess

import numpy as np
import pytest

import deform_kernel as dk
from meshes import holed_square, read_su2_points, write_su2
from test_cli_bits import deform_bin

# (method, tool flags, motion, deform() keywords)
CASES = [
    ("spring", ["--rotate", "20", "--steps", "4"], dk.Rotation(20.0), {"steps": 4}),
    ("quaternion", ["--rotate", "25", "--steps", "3"], dk.Rotation(25.0), {"steps": 3}),
    ("spring", ["--translate", "0.2,0.1", "--steps", "2", "--stiffness", "wall-distance"],
     dk.Translation((0.2, 0.1)), {"steps": 2, "stiffness": "wall-distance"}),
    ("angle-direct", ["--rotate", "8"], dk.Rotation(8.0), {}),
    ("angle-cg", ["--rotate", "8", "--solver", "cg"], dk.Rotation(8.0), {"solver": "cg"}),
    ("rbf", ["--rotate", "10"], dk.Rotation(10.0), {}),
    ("rbf", ["--rotate", "10", "--rbf-kernel", "tps"], dk.Rotation(10.0), {"rbf_kernel": "tps"}),
    ("rbf", ["--translate", "0.1,0.05", "--rbf-radius", "1.5", "--rbf-tolerance", "0.01"],
     dk.Translation((0.1, 0.05)), {"rbf_radius": 1.5, "rbf_tolerance": 0.01}),
    ("elasticity", ["--rotate", "7"], dk.Rotation(7.0), {}),
    ("idw", ["--rotate", "9", "--idw-theta", "0.5"], dk.Rotation(9.0), {"idw_theta": 0.5}),
    ("quaternion", ["--rotate", "9", "--reach", "1.0"], dk.Rotation(9.0), {"reach": 1.0}),
    ("spring", ["--rotate", "8", "--amg-strength", "0.25"], dk.Rotation(8.0),
     {"amg_strength": 0.25}),
    ("elasticity", ["--rotate", "7", "--stiffness", "constant", "--poisson", "0.25",
                    "--steps", "2", "--solver", "cg"], dk.Rotation(7.0),
     {"stiffness": "constant", "poisson": 0.25, "steps": 2, "solver": "cg"}),
    ("elasticity", ["--translate", "0.1,0", "--stiffness", "wall-distance"],
     dk.Translation((0.1, 0.0)), {"stiffness": "wall-distance"}),
    ("elasticity", ["--rotate", "7", "--steps", "3", "--poisson", "0.45", "--rigid-layer", "0.3"],
     dk.Rotation(7.0), {"steps": 3, "poisson": 0.45, "rigid_layer": 0.3}),
]


def mesh():
    """The holed square with irregular interior coordinates; its outer edges split into the
    bottom side (y = -2, flat) and the rest."""
    pts, tris, hole, outer, hole_edges, outer_edges = holed_square(n=11, half=2.0, hole=0.6)
    pts = pts + 0.01 * np.sin(7.0 * pts[:, ::-1]) * (np.abs(pts).max(axis=1) < 1.9)[:, None]
    bottom = np.all(pts[outer_edges][:, :, 1] == -2.0, axis=1)
    return pts, tris, hole_edges, outer_edges[bottom], outer_edges[~bottom]


def run_tool(tmp_path, markers, flags, method):
    src, dst = tmp_path / "in.su2", tmp_path / "out.su2"
    pts, tris = markers.pop("_pts"), markers.pop("_tris")
    write_su2(src, pts, tris, markers)
    cmd = [deform_bin(), "move", str(src), "--marker", "body", "--method", method, *flags,
           "--out", str(dst)]
    subprocess.run(cmd, check=True, capture_output=True)
    return read_su2_points(dst)


@pytest.mark.parametrize("method,flags,motion,kw", CASES)
def test_same_bits_as_deform_move(tmp_path, method, flags, motion, kw):
    pts, tris, body, bottom, rest = mesh()
    theirs = run_tool(tmp_path, {"_pts": pts, "_tris": tris, "body": body,
                                 "farfield": np.concatenate([bottom, rest])}, flags, method)
    ours = dk.deform(pts, [("triangle", tris)], np.unique(body), motion,
                     np.unique(np.concatenate([bottom, rest])), method=method, **kw)
    assert np.max(np.abs(ours - pts)) > 1e-3
    assert ours.tobytes() == theirs.tobytes()


@pytest.mark.parametrize("method", ["spring", "quaternion", "angle-cg", "elasticity"])
def test_sliding_plane_same_bits(tmp_path, method):
    pts, tris, body, bottom, rest = mesh()
    flags = ["--translate", "0.3,0.2", "--slide", "symm"]
    theirs = run_tool(tmp_path, {"_pts": pts, "_tris": tris, "body": body, "symm": bottom,
                                 "farfield": rest}, flags, method)
    # Boundary elements (not only nodes) for the moved marker: the same as the tool's.
    ours, info = dk.deform(pts, [("triangle", tris)], [("line", body)],
                           dk.Translation((0.3, 0.2)), np.unique(rest), method=method,
                           slide=[[("line", bottom)]], return_info=True)
    assert ours.tobytes() == theirs.tobytes()
    on_symm = np.setdiff1d(np.unique(bottom), np.unique(rest))
    assert info["sliding_nodes"] == on_symm.size > 0
    assert np.all(ours[on_symm, 1] == -2.0)  # they stay on their line ...
    assert np.max(np.abs(ours[on_symm, 0] - pts[on_symm, 0])) > 1e-3  # ... and slide along it


def test_steps_end_on_the_exact_motion():
    pts, tris, body, bottom, rest = mesh()
    fixed = np.unique(np.concatenate([bottom, rest]))
    one = dk.deform(pts, [("triangle", tris)], np.unique(body), dk.Rotation(30.0), fixed,
                    method="spring")
    four = dk.deform(pts, [("triangle", tris)], np.unique(body), dk.Rotation(30.0), fixed,
                     method="spring", steps=4)
    b = np.unique(body)
    assert four[b].tobytes() == one[b].tobytes()
    assert np.max(np.abs(four - one)) > 1e-6  # the interior differs: stiffness re-derived


@pytest.mark.parametrize("method,steps", [("spring", 1), ("quaternion", 1), ("rbf", 1),
                                          ("elasticity", 2), ("spring", 3)])
def test_displacement_field_same_bits(tmp_path, method, steps):
    """A bending displacement of the body's nodes (`--displacements FILE`); the quaternion
    method takes its rotations from the moved elements' shape."""
    pts, tris, body, bottom, rest = mesh()
    nodes = np.unique(body)
    x, y = pts[nodes, 0], pts[nodes, 1]
    disp = np.ascontiguousarray(np.column_stack([-0.02 * y * x, 0.04 * x * x + 0.01]))
    table = tmp_path / "d.txt"
    table.write_text("".join(f"{n} {float(a)!r} {float(b)!r}\n" for n, (a, b) in zip(nodes, disp)))
    flags = ["--displacements", str(table), "--steps", str(steps)]
    theirs = run_tool(tmp_path, {"_pts": pts, "_tris": tris, "body": body,
                                 "farfield": np.concatenate([bottom, rest])}, flags, method)
    # Elements as moved and fixed (rows per sorted distinct node; every boundary node needs
    # an element for the shape's rotations), shuffled nodes for spring (rows follow them).
    farfield = np.concatenate([bottom, rest])
    if method == "spring":
        order = np.random.default_rng(1).permutation(nodes.size)
        moved, values, fixed = nodes[order], np.ascontiguousarray(disp[order]), np.unique(farfield)
    else:
        moved, values, fixed = [("line", body)], disp, [("line", farfield)]
    ours = dk.deform(pts, [("triangle", tris)], moved, dk.Displacement(values), fixed,
                     method=method, steps=steps)
    assert np.max(np.abs(ours - pts)) > 1e-3
    assert ours.tobytes() == theirs.tobytes()


def test_folds_are_refused_as_the_tool_refuses_them(tmp_path):
    """Plain springs fold cells around a hole turned by 60 degrees: `deform move` refuses
    the result (exit 1, nothing written) and so does deform(); with --allow-folds /
    allow_folds=True both return the same bits."""
    pts, tris, body, bottom, rest = mesh()
    far = np.concatenate([bottom, rest])
    src, dst = tmp_path / "in.su2", tmp_path / "out.su2"
    write_su2(src, pts, tris, {"body": body, "farfield": far})
    cmd = [deform_bin(), "move", str(src), "--marker", "body", "--method", "spring",
           "--rotate", "60", "--out", str(dst)]
    refused = subprocess.run(cmd, capture_output=True, text=True)
    assert refused.returncode != 0 and not dst.exists(), refused.stderr
    out = np.zeros_like(pts)
    args = (pts, [("triangle", tris)], np.unique(body), dk.Rotation(60.0), np.unique(far))
    with pytest.raises(dk.KernelError, match="inverted or folded"):
        dk.deform(*args, method="spring", out=out)
    assert not out.any()
    subprocess.run(cmd + ["--allow-folds"], check=True, capture_output=True)
    ours = dk.deform(*args, method="spring", allow_folds=True)
    assert ours.tobytes() == read_su2_points(dst).tobytes()
    q = dk.quality(ours, [("triangle", tris)])
    assert (q["measure"] <= 0).any()
