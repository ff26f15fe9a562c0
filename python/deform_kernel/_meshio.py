"""meshio interop (meshio is optional: imported only when these functions run)."""

import numpy as np

from ._cells import VTK_CODES

_DIM_OF = {"line": 1, "triangle": 2, "quad": 2, "tetra": 3, "hexahedron": 3, "wedge": 3,
           "pyramid": 3}


def from_meshio(mesh, dim=None):
    """``(points, cells)`` of a ``meshio.Mesh`` for :func:`deform_kernel.deform`.

    ``dim`` (2 or 3; default: 2 when every z is 0 and there are no 3D cells, else 3) sets the
    point columns; ``cells`` are the blocks of that dimension as ``[(type, conn), ...]``
    (boundary blocks and unsupported types are left out). Points are a new float64 array.
    """
    pts = np.asarray(mesh.points, dtype=np.float64)
    blocks = [(b.type, np.asarray(b.data)) for b in mesh.cells if b.type in VTK_CODES]
    if dim is None:
        flat = pts.shape[1] == 2 or not np.any(pts[:, 2])
        dim = 2 if flat and not any(_DIM_OF[t] == 3 for t, _ in blocks) else 3
    if dim not in (2, 3):
        raise ValueError(f"dim: {dim}, expected 2 or 3")
    volume = [(t, c) for t, c in blocks if _DIM_OF[t] == dim]
    if not volume:
        raise ValueError(f"mesh: no {dim}D cells")
    return np.ascontiguousarray(pts[:, :dim]), volume


def to_meshio(points, cells):
    """A ``meshio.Mesh`` of ``points`` and meshio-style ``cells`` blocks (needs meshio)."""
    import meshio

    return meshio.Mesh(np.asarray(points), [(t, np.asarray(c)) for t, c in cells])


def boundary_nodes(mesh, cell_type, tag, key):
    """Sorted node indices of the ``cell_type`` cells whose ``mesh.cell_data[key]`` is ``tag``
    (for example the boundary segments of a Gmsh physical group)."""
    nodes = [np.asarray(b.data)[np.asarray(d) == tag].reshape(-1)
             for b, d in zip(mesh.cells, mesh.cell_data[key]) if b.type == cell_type]
    return np.unique(np.concatenate(nodes)) if nodes else np.zeros(0, dtype=np.int64)
