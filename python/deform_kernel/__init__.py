"""deform_kernel: mesh deformation on numpy arrays (Python bindings of the Rust deform-kernel).

``deform`` moves a mesh whose boundary nodes follow a rigid rotation, a translation or a
prescribed displacement (Samareh's quaternion method, Batina's linear springs, or quaternion
inverse-distance weighting); ``quality`` gives signed cell measures and scaled Jacobians; ``smooth_structured`` runs
Alter's arclength Taubin filter on a structured block.
Inputs are checked before anything runs, the caller's arrays are never modified, and results
are new arrays, bit-identical to the ``deform move`` tool on the same input.
"""

from ._cells import cells_from_blocks, normalise_cells
from ._motion import Displacement, Rotation, Translation, deform, quality
from ._native import KernelError
from ._plan import Plan
from ._read import Grid, Mesh, read
from ._smooth import smooth_graph, smooth_structured
from ._meshio import boundary_nodes, from_meshio, mesh_from_meshio, to_meshio

__all__ = [
    "Displacement",
    "Grid",
    "KernelError",
    "Mesh",
    "Plan",
    "Rotation",
    "Translation",
    "boundary_nodes",
    "cells_from_blocks",
    "deform",
    "from_meshio",
    "mesh_from_meshio",
    "normalise_cells",
    "quality",
    "read",
    "smooth_graph",
    "smooth_structured",
    "to_meshio",
]
