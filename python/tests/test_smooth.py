"""smooth_structured(): properties of the filter and bit-equality with `deform smooth`."""

import subprocess

import numpy as np
import pytest

import deform_kernel as dk
from test_cli_bits import deform_bin


def wavy_block(ni=6, nj=9, nk=3):
    """A 3D block with uneven spacing along j: points[i, j, k]."""
    i, j, k = np.meshgrid(np.arange(ni), np.arange(nj), np.arange(nk), indexing="ij")
    s = (j / (nj - 1)) ** 1.7 + 0.03 * np.sin(3.0 * j) * (0 < j) * (j < nj - 1)
    return np.stack([i * 0.2, s * (1.0 + 0.1 * i), k * 0.3 + 0.01 * np.cos(i + j)], axis=-1)


def test_uniform_lines_stay_and_ends_never_move():
    x, y = np.meshgrid(np.linspace(0, 1, 7), np.linspace(0, 2, 11), indexing="ij")
    grid = np.stack([x, y], axis=-1)
    out = dk.smooth_structured(grid, "j", iterations=20)
    assert np.max(np.abs(out - grid)) < 1e-14
    wavy = wavy_block()
    before = wavy.copy()
    out, info = dk.smooth_structured(wavy, "j", iterations=40, return_info=True)
    assert np.array_equal(wavy, before)  # the input is untouched
    assert np.array_equal(out[:, [0, -1]], wavy[:, [0, -1]])  # line ends stay
    assert info["max_point_move"] > 1e-3
    assert info["stretching_after"] < info["stretching_before"]


def test_fixed_points_stay():
    wavy = wavy_block()
    fixed = np.zeros(wavy.shape[:-1], dtype=bool)
    fixed[2, 4, 1] = True
    out = dk.smooth_structured(wavy, "j", iterations=10, fixed=fixed)
    free = dk.smooth_structured(wavy, "j", iterations=10)
    assert np.array_equal(out[2, 4, 1], wavy[2, 4, 1]) and not np.array_equal(free, out)


def test_bad_blocks():
    with pytest.raises(ValueError, match="shape"):
        dk.smooth_structured(np.zeros((4, 4, 3)), "i")
    with pytest.raises(ValueError, match="direction"):
        dk.smooth_structured(np.zeros((4, 4, 2)), "k")
    with pytest.raises(TypeError, match="float64"):
        dk.smooth_structured(np.zeros((4, 4, 2), dtype=np.float32), "i")


def write_plot3d_ascii(path, grid):
    """One 3D block, i fastest, coordinates in repr (exact)."""
    ni, nj, nk, _ = grid.shape
    values = [repr(float(v)) for c in range(3) for v in grid[..., c].transpose(2, 1, 0).ravel()]
    path.write_text(f"1\n{ni} {nj} {nk}\n" + "\n".join(values) + "\n")


def read_plot3d_ascii(path, shape):
    tokens = path.read_text().split()
    ni, nj, nk = shape
    assert [int(t) for t in tokens[1:4]] == [ni, nj, nk]
    v = np.array([float(t) for t in tokens[4:]]).reshape(3, nk, nj, ni)
    return np.ascontiguousarray(v.transpose(3, 2, 1, 0))


@pytest.mark.parametrize("flags,kw", [
    (["--iterations", "25"], {"iterations": 25}),
    (["--iterations", "12", "--normalized", "--coarse", "2"],
     {"iterations": 12, "normalised": True, "coarse": 2}),
])
def test_same_bits_as_deform_smooth(tmp_path, flags, kw):
    tool = deform_bin()
    grid = wavy_block()
    src, dst = tmp_path / "in.x", tmp_path / "out.x"
    write_plot3d_ascii(src, grid)
    cmd = [tool, "smooth", str(src), "--direction", "j", *flags, "--out", str(dst)]
    subprocess.run(cmd, check=True, capture_output=True)
    theirs = read_plot3d_ascii(dst, grid.shape[:-1])
    ours = dk.smooth_structured(grid, "j", **kw)
    assert np.max(np.abs(ours - grid)) > 1e-3
    assert ours.tobytes() == theirs.tobytes()
