"""Cells in the kernel's CSR form: ``(offsets, nodes, kinds)`` with VTK kind codes."""

import numpy as np

from ._checks import index_array

#: meshio cell type names and their VTK codes (the kinds the kernel knows).
VTK_CODES = {
    "line": 3,
    "triangle": 5,
    "quad": 9,
    "tetra": 10,
    "hexahedron": 12,
    "wedge": 13,
    "pyramid": 14,
}
#: Nodes per cell of each VTK code.
NODES_PER_KIND = {3: 2, 5: 3, 9: 4, 10: 4, 12: 8, 13: 6, 14: 5}


def _kind_code(kind):
    if isinstance(kind, str):
        if kind not in VTK_CODES:
            raise ValueError(f"cells: cell type {kind!r} is not one of {sorted(VTK_CODES)}")
        return VTK_CODES[kind]
    code = int(kind)
    if code not in NODES_PER_KIND:
        raise ValueError(f"cells: VTK cell type {code} is not one of {sorted(NODES_PER_KIND)}")
    return code


def cells_from_blocks(blocks, node_count):
    """``(offsets, nodes, kinds)`` from ``[(type, connectivity (C, k)), ...]`` blocks.

    ``type`` is a meshio name (``"triangle"``) or a VTK code (5); meshio ``CellBlock`` objects
    (``.type``, ``.data``) are accepted too.
    """
    offsets, nodes, kinds = [np.zeros(1, dtype=np.int64)], [], []
    end = 0
    for i, block in enumerate(blocks):
        kind, data = (block.type, block.data) if hasattr(block, "data") else block
        code = _kind_code(kind)
        conn = np.asarray(data)
        k = NODES_PER_KIND[code]
        if conn.ndim != 2 or conn.shape[1] != k:
            raise ValueError(f"cells: block {i} has shape {conn.shape}, expected (C, {k})")
        flat = index_array(f"cells block {i}", conn.reshape(-1), node_count)
        nodes.append(flat)
        kinds.append(np.full(conn.shape[0], code, dtype=np.uint8))
        offsets.append(end + k * np.arange(1, conn.shape[0] + 1, dtype=np.int64))
        end += flat.size
    return (
        np.concatenate(offsets).astype(np.uint32),
        np.concatenate(nodes) if nodes else np.zeros(0, dtype=np.uint32),
        np.concatenate(kinds) if kinds else np.zeros(0, dtype=np.uint8),
    )


def normalise_cells(cells, node_count):
    """Either cell form as new ``(offsets uint32, nodes uint32, kinds uint8)`` arrays.

    A tuple of three 1-D numpy arrays is the CSR form; anything else is a list of blocks
    (:func:`cells_from_blocks`). Node indices are checked against ``node_count``; the kernel
    checks offsets, kinds and node counts per cell.
    """
    if isinstance(cells, tuple) and len(cells) == 3 and all(
        isinstance(c, np.ndarray) and c.ndim == 1 for c in cells
    ):
        offsets, nodes, kinds = cells
        nodes = index_array("cells nodes", nodes, node_count)
        offsets = index_array("cells offsets", offsets, nodes.size + 1)
        if offsets.size == 0:
            raise ValueError("cells offsets: empty (needs C + 1 entries)")
        steps = np.diff(offsets.astype(np.int64))
        if offsets[0] != 0 or offsets[-1] != nodes.size or (steps < 0).any():
            raise ValueError("cells offsets: must rise from 0 to len(nodes)")
        kinds = np.asarray(kinds)
        if not np.issubdtype(kinds.dtype, np.integer) or (kinds < 0).any() or (kinds > 255).any():
            raise ValueError("cells kinds: expected VTK codes (integers 0..255)")
        return offsets, nodes, kinds.astype(np.uint8)
    return cells_from_blocks(cells, node_count)


#: VTK code of a vertex (a boundary given as bare node indices).
VTK_VERTEX = 1


def _is_cells(value):
    """Whether ``value`` is cells (CSR tuple or blocks) rather than node indices."""
    if isinstance(value, tuple) and len(value) == 3 and all(
            isinstance(c, np.ndarray) and c.ndim == 1 for c in value):
        return True
    if isinstance(value, (list, tuple)) and value:
        first = value[0]
        return hasattr(first, "data") or (isinstance(first, tuple) and len(first) == 2)
    return False


def boundary_cells(name, value, node_count):
    """A boundary (node indices, or elements in either cell form) as CSR cells, and its
    nodes: the entries as given (node indices) or the sorted distinct element nodes."""
    if value is None:
        value = np.zeros(0, dtype=np.uint32)
    if _is_cells(value):
        offsets, nodes, kinds = normalise_cells(value, node_count)
        return (offsets, nodes, kinds), np.unique(nodes).astype(np.uint32)
    nodes = index_array(name, value, node_count)
    offsets = np.arange(nodes.size + 1, dtype=np.uint32)
    kinds = np.full(nodes.size, VTK_VERTEX, dtype=np.uint8)
    return (offsets, nodes, kinds), nodes
