"""Argument checks that run before the kernel sees anything (clear messages, nothing mutated)."""

import numpy as np


def points_array(points, name="points"):
    """``points`` as a C-contiguous ``(N, 2|3)`` float64 array with finite entries (not copied)."""
    if not isinstance(points, np.ndarray):
        raise TypeError(f"{name}: expected a numpy array of shape (N, 2) or (N, 3), dtype float64")
    if points.dtype != np.float64:
        raise TypeError(f"{name}: dtype {points.dtype}, expected float64")
    if points.ndim != 2 or points.shape[1] not in (2, 3) or points.shape[0] == 0:
        raise ValueError(f"{name}: shape {points.shape}, expected (N, 2) or (N, 3) with N > 0")
    if not points.flags.c_contiguous:
        raise ValueError(f"{name}: not C-contiguous (pass np.ascontiguousarray({name}))")
    bad = np.flatnonzero(~np.isfinite(points).all(axis=1))
    if bad.size:
        raise ValueError(f"{name}: row {bad[0]} is not finite")
    return points


def out_array(out, shape):
    """``out`` checked as a writable C-contiguous float64 array of ``shape`` (or ``None``)."""
    if out is None:
        return None
    if not isinstance(out, np.ndarray) or out.dtype != np.float64:
        raise TypeError(f"out: expected a float64 numpy array of shape {shape}")
    if out.shape != shape:
        raise ValueError(f"out: shape {out.shape}, expected {shape}")
    if not out.flags.c_contiguous or not out.flags.writeable:
        raise ValueError("out: must be C-contiguous and writable")
    return out


def index_array(name, values, bound):
    """``values`` as a 1-D uint32 array of indices in ``[0, bound)`` (a new array)."""
    a = np.asarray(values)
    if a.size == 0:
        return np.zeros(0, dtype=np.uint32)
    if not np.issubdtype(a.dtype, np.integer):
        raise TypeError(f"{name}: dtype {a.dtype}, expected integers")
    if a.ndim != 1:
        raise ValueError(f"{name}: shape {a.shape}, expected a 1-D array")
    bad = np.flatnonzero((a < 0) | (a >= bound))
    if bad.size:
        raise ValueError(f"{name}: entry {bad[0]} is {a[bad[0]]}, outside [0, {bound})")
    return a.astype(np.uint32)


def vector(name, values, dim, lengths=None):
    """A finite float tuple of ``dim`` (or any of ``lengths``) entries, padded to 3 with zeros."""
    v = np.asarray(values, dtype=np.float64)
    allowed = lengths or (dim,)
    if v.ndim != 1 or v.size not in allowed:
        raise ValueError(f"{name}: {v.shape}, expected {' or '.join(map(str, allowed))} values")
    if not np.isfinite(v).all():
        raise ValueError(f"{name}: not finite")
    return tuple(float(x) for x in v) + (0.0,) * (3 - v.size)
