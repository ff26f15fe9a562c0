"""deform_kernel: mesh deformation on numpy arrays (Python bindings of the Rust deform-kernel).

``deform`` moves a mesh whose boundary nodes follow a rigid rotation, a translation or a
prescribed displacement, by the ``deform move`` tool's own engine (Samareh's quaternion method,
Batina's linear springs, quaternion IDW, angle springs, RBF, linear elasticity; steps, sliding
planes), with the same bits as the tool. ``Plan`` prepares a mesh once and steps it with warm
starts; ``quality`` gives signed cell measures and scaled Jacobians; ``smooth_structured`` and
``smooth_graph`` are Taubin filters on structured blocks and on mesh graphs; ``read`` reads
SU2 and Plot3D files with the tool's readers (other formats through meshio). Inputs are checked
before anything runs; the caller's arrays are never modified except an ``out`` array.
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
