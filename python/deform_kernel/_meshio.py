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


def mesh_from_meshio(mesh, dim=None, key="gmsh:physical"):
    """A :class:`deform_kernel.Mesh` of a ``meshio.Mesh``: its points and volume cells (as
    :func:`from_meshio`) and its markers, the boundary cells (one dimension lower) grouped by
    ``mesh.cell_data[key]`` (Gmsh physical groups by default), named from ``mesh.field_data``
    (the tag's number when it has no name). Markers go straight into ``deform``."""
    from ._cells import cells_from_blocks
    from ._read import Mesh

    points, volume = from_meshio(mesh, dim)
    n, d = points.shape
    names = {int(v[0]): name for name, v in getattr(mesh, "field_data", {}).items()
             if len(v) >= 2 and int(v[1]) == d - 1}
    groups = {}
    for block, tags in zip(mesh.cells, mesh.cell_data.get(key, [])):
        if block.type not in VTK_CODES or _DIM_OF[block.type] != d - 1:
            continue
        tags, conn = np.asarray(tags).reshape(-1), np.asarray(block.data)
        for tag in np.unique(tags):
            name = names.get(int(tag), str(int(tag)))
            groups.setdefault(name, []).append((block.type, conn[tags == tag]))
    markers = {name: cells_from_blocks(blocks, n) for name, blocks in groups.items()}
    return Mesh(points, cells_from_blocks(volume, n), markers)
