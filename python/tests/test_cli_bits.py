"""Bit-equality with the `deform move` tool of this repository on the same SU2 mesh.

The tool is found through $DEFORM_BIN, else target/{release,debug}/deform of the repository;
`cargo xtask ci --step python` builds it and sets DEFORM_REQUIRE_CLI=1 so that a missing tool
fails instead of skipping.
"""

import os
import pathlib
import subprocess

import numpy as np
import pytest

import deform_kernel as dk
from meshes import hex_box, holed_square, read_su2_points, write_su2

ROOT = pathlib.Path(__file__).resolve().parents[2]


def deform_bin():
    candidates = [os.environ.get("DEFORM_BIN")] + [
        ROOT / "target" / p / "deform" for p in ("release", "debug")
    ]
    for c in candidates:
        if c and pathlib.Path(c).is_file():
            return str(c)
    if os.environ.get("DEFORM_REQUIRE_CLI"):
        pytest.fail("the deform tool was not found (set DEFORM_BIN)")
    pytest.skip("the deform tool is not built (cargo build -p deform-cli)")


CASES = [
    ("quaternion", ["--rotate", "12.5"], dk.Rotation(12.5)),
    ("quaternion", ["--rotate", "-8", "--center", "0.2,0.1"], dk.Rotation(-8.0, (0.2, 0.1))),
    ("spring", ["--rotate", "6"], dk.Rotation(6.0)),
    ("spring", ["--translate", "0.1,-0.05", "--solver", "cg"], dk.Translation((0.1, -0.05))),
    ("idw", ["--rotate", "15"], dk.Rotation(15.0)),
    ("spring", ["--rotate", "6", "--stiffness", "wall-distance"], dk.Rotation(6.0)),
    ("spring", ["--rotate", "6", "--stiffness", "inverse-volume"], dk.Rotation(6.0)),
    ("quaternion", ["--rotate", "9", "--stiffness", "inverse-volume"], dk.Rotation(9.0)),
]


@pytest.mark.parametrize("method,flags,motion", CASES)
def test_same_bits_as_deform_move(tmp_path, method, flags, motion):
    tool = deform_bin()
    pts, tris, hole, outer, hole_edges, outer_edges = holed_square(n=11, half=2.0, hole=0.6)
    # Irregular coordinates, so that every digit matters.
    pts = pts + 0.01 * np.sin(7.0 * pts[:, ::-1]) * (np.abs(pts).max(axis=1) < 1.9)[:, None]
    src, dst = tmp_path / "in.su2", tmp_path / "out.su2"
    write_su2(src, pts, tris, {"body": hole_edges, "farfield": outer_edges})
    option = lambda name, default: flags[flags.index(name) + 1] if name in flags else default  # noqa: E731
    solver, stiffness = option("--solver", "amg"), option("--stiffness", "batina")
    cmd = [tool, "move", str(src), "--marker", "body", "--method", method, *flags,
           "--out", str(dst)]
    subprocess.run(cmd, check=True, capture_output=True)
    ours = dk.deform(pts, [("triangle", tris)], np.unique(hole_edges), motion,
                     np.unique(outer_edges), method=method, solver=solver, stiffness=stiffness)
    theirs = read_su2_points(dst)
    assert np.max(np.abs(ours - pts)) > 1e-3
    assert ours.tobytes() == theirs.tobytes()


@pytest.mark.parametrize("method", ["quaternion", "spring"])
def test_same_bits_as_deform_move_3d(tmp_path, method):
    tool = deform_bin()
    pts, hexes, bottom, others = hex_box(5)
    inner = np.all((pts > 0) & (pts < 1), axis=1)
    pts = pts + 0.02 * np.sin(5.0 * pts[:, [1, 2, 0]]) * inner[:, None]
    src, dst = tmp_path / "in.su2", tmp_path / "out.su2"
    write_su2(src, pts, hexes, {"floor": bottom, "walls": others})
    cmd = [tool, "move", str(src), "--marker", "floor", "--method", method, "--rotate", "3",
           "--axis", "0,1,0.5", "--out", str(dst)]
    subprocess.run(cmd, check=True, capture_output=True)
    fixed = np.setdiff1d(np.unique(others), np.unique(bottom))
    ours = dk.deform(pts, [("hexahedron", hexes)], np.unique(bottom),
                     dk.Rotation(3.0, axis=(0, 1, 0.5)), fixed, method=method)
    assert np.max(np.abs(ours - pts)) > 1e-3
    assert ours.tobytes() == read_su2_points(dst, 3).tobytes()
