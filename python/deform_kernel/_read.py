"""``read``: mesh files through the ``deform`` tool's own readers (SU2, Plot3D), other
formats through meshio."""

import pathlib
from dataclasses import dataclass, field
from typing import Dict, List, Tuple

import numpy as np

from . import _native

PLOT3D_SUFFIXES = (".x", ".xyz", ".p3d", ".g", ".grd", ".xy", ".p2d")


@dataclass
class Mesh:
    """An unstructured mesh: ``points`` ``(N, dim)`` float64, ``cells`` in CSR form
    ``(offsets, nodes, kinds)`` (VTK codes) and ``markers``: name -> boundary elements in the
    same form (pass them as ``moved``/``fixed``/``slide`` to :func:`deform`)."""

    points: np.ndarray
    cells: Tuple[np.ndarray, np.ndarray, np.ndarray]
    markers: Dict[str, Tuple[np.ndarray, np.ndarray, np.ndarray]] = field(default_factory=dict)

    def marker_nodes(self, *names):
        """Sorted distinct nodes of the named markers."""
        missing = [n for n in names if n not in self.markers]
        if missing:
            raise KeyError(f"no marker {missing[0]!r} (markers: {sorted(self.markers)})")
        nodes = [self.markers[n][1] for n in names]
        return np.unique(np.concatenate(nodes)) if nodes else np.zeros(0, dtype=np.uint32)


@dataclass
class Grid:
    """A structured (Plot3D) grid: ``blocks`` of points ``(ni, nj, 2)`` (2D) or
    ``(ni, nj, nk, 3)`` (3D), the layout :func:`smooth_structured` takes."""

    dim: int
    blocks: List[np.ndarray]


def _block(dims, points, dim):
    ni, nj, nk = dims
    if dim == 2:
        return np.ascontiguousarray(points.reshape(nj, ni, 2).transpose(1, 0, 2))
    return np.ascontiguousarray(points.reshape(nk, nj, ni, 3).transpose(2, 1, 0, 3))


def read(path):
    """Reads a mesh file: ``.su2`` (native ASCII SU2, multi-zone files as one mesh) gives a
    :class:`Mesh` with its markers and Plot3D grids (``.x .xyz .p3d .g .grd .xy .p2d``; ASCII
    or binary, detected) a :class:`Grid`, both through the ``deform`` tool's readers, so a
    script sees exactly what ``deform move`` sees. Anything else (VTK ``.vtu``/``.vtk``,
    Gmsh ``.msh``, ...) is read by meshio when it is installed (a :class:`Mesh` of its volume
    cells, markers from Gmsh physical groups: :func:`mesh_from_meshio`). Errors name the file
    and the line."""
    p = pathlib.Path(path)
    suffix = p.suffix.lower()
    if suffix == ".su2":
        dim, points, cells, markers = _native.read_su2(str(p))
        return Mesh(points, cells, dict(markers))
    if suffix in PLOT3D_SUFFIXES:
        dim, blocks = _native.read_plot3d(str(p))
        return Grid(dim, [_block(dims, pts, dim) for dims, pts in blocks])
    try:
        import meshio
    except ImportError as e:
        raise ValueError(f"{p}: not SU2 or Plot3D, and meshio (for other formats) is not "
                         "installed") from e
    from ._meshio import mesh_from_meshio

    return mesh_from_meshio(meshio.read(p))
