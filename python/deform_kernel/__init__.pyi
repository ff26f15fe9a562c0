import os
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

CsrCells = Tuple[npt.NDArray[np.integer], npt.NDArray[np.integer], npt.NDArray[np.integer]]
BlockCells = Sequence[Union[Tuple[Union[str, int], npt.ArrayLike], Any]]
Cells = Union[CsrCells, BlockCells]
Method = Literal["quaternion", "spring", "idw", "angle-direct", "angle-cg", "rbf", "elasticity"]
Solver = Literal["amg", "cg", "cg-ssor", "gauss-seidel", "jacobi"]
Stiffness = Literal["batina", "wall-distance", "inverse-volume", "constant"]
Renumber = Literal["auto", "off", "rcm", "hilbert"]
Float2 = npt.NDArray[np.float64]
#: Node indices, or boundary elements in either cell form.
Boundary = Union[npt.ArrayLike, Cells]

class KernelError(ValueError):
    """A typed deform-kernel error (or an unconverged solve)."""

    kind: str
    arg: Optional[str]
    position: Optional[int]

class Rotation:
    degrees: float
    center: Optional[Sequence[float]]
    axis: Sequence[float]
    def __init__(
        self,
        degrees: float,
        center: Optional[Sequence[float]] = None,
        axis: Sequence[float] = (0.0, 0.0, 1.0),
    ) -> None: ...

class Translation:
    vector: Sequence[float]
    def __init__(self, vector: Sequence[float]) -> None: ...

class Displacement:
    values: npt.NDArray[np.float64]
    def __init__(self, values: npt.NDArray[np.float64]) -> None: ...

Motion = Union[Rotation, Translation, Displacement]

def deform(
    points: Float2,
    cells: Cells,
    moved: Boundary,
    motion: Motion,
    fixed: Optional[Boundary] = None,
    method: Method = "quaternion",
    solver: Solver = "amg",
    stiffness: Optional[Stiffness] = None,
    tol: float = 1e-10,
    max_iter: int = 10000,
    idw_exponent: float = 2.0,
    allow_unconverged: bool = False,
    return_info: bool = False,
    steps: int = 1,
    slide: Optional[Sequence[Boundary]] = None,
    renumber: Renumber = "auto",
    poisson: float = 0.3,
    reach: Optional[float] = None,
    rbf_kernel: Literal["wendland", "tps"] = "wendland",
    rbf_radius: Optional[float] = None,
    rbf_tolerance: float = 0.0,
    rbf_max_centres: int = 1000,
    rbf_correction: Optional[float] = None,
    idw_theta: Optional[float] = None,
    idw_tolerance: float = 0.1,
    out: Optional[Float2] = None,
    allow_folds: bool = False,
    rigid_layer: Optional[float] = None,
    amg_strength: Optional[float] = None,
) -> Union[Float2, Tuple[Float2, Dict[str, Any]]]:
    """New points (or ``out``); with ``return_info``, also ``{"iterations", "residual",
    "converged", "sliding_nodes", "max_slide_offset", "rbf_centres"}``."""
    ...

class Plan:
    method: str
    dim: int
    node_count: int
    boundary: npt.NDArray[np.uint32]
    steps: int
    def __init__(
        self,
        points: Float2,
        cells: Cells,
        boundary: npt.ArrayLike,
        method: Literal["spring", "quaternion"] = "spring",
        solver: Solver = "amg",
        tol: float = 1e-10,
        max_iter: int = 10000,
        renumber: Literal["off", "rcm", "hilbert"] = "off",
    ) -> None: ...
    def pool_sizes(self) -> Tuple[int, int, int]: ...
    def step(
        self,
        positions: Float2,
        rotations: Optional[Float2] = None,
        origin: Optional[Sequence[float]] = None,
        start: Literal["warm", "cold"] = "warm",
        out: Optional[Float2] = None,
        return_info: bool = False,
    ) -> Union[Float2, Tuple[Float2, Dict[str, Any]]]: ...

CsrArrays = Tuple[npt.NDArray[np.uint32], npt.NDArray[np.uint32], npt.NDArray[np.uint8]]

class Mesh:
    points: Float2
    cells: CsrArrays
    markers: Dict[str, CsrArrays]
    def marker_nodes(self, *names: str) -> npt.NDArray[np.uint32]: ...

class Grid:
    dim: int
    blocks: List[Float2]

def mesh_from_meshio(mesh: Any, dim: Optional[int] = None, key: str = "gmsh:physical") -> Mesh: ...
def read(path: Union[str, "os.PathLike[str]"]) -> Union[Mesh, Grid]: ...
def smooth_graph(
    points: Float2,
    cells: Cells,
    iterations: int = 10,
    lam: float = 0.33,
    mu: float = -0.34,
    weights: Literal["uniform", "inverse-distance"] = "uniform",
    fixed: Optional[npt.ArrayLike] = None,
    return_info: bool = False,
) -> Union[Float2, Tuple[Float2, Dict[str, Any]]]: ...
def quality(points: npt.NDArray[np.float64], cells: Cells) -> Dict[str, npt.NDArray[np.float64]]: ...
def cells_from_blocks(
    blocks: BlockCells, node_count: int
) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.uint32], npt.NDArray[np.uint8]]: ...
def normalise_cells(
    cells: Cells, node_count: int
) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.uint32], npt.NDArray[np.uint8]]: ...
def from_meshio(mesh: Any, dim: Optional[int] = None) -> Tuple[npt.NDArray[np.float64], List[Tuple[str, npt.NDArray[Any]]]]: ...
def to_meshio(points: npt.ArrayLike, cells: BlockCells) -> Any: ...
def boundary_nodes(mesh: Any, cell_type: str, tag: int, key: str) -> npt.NDArray[np.int64]: ...
def smooth_structured(
    points: npt.NDArray[np.float64],
    direction: Literal["i", "j", "k"],
    iterations: int = 30,
    lam: float = 0.33,
    mu: float = -0.334,
    normalised: bool = False,
    fixed: Optional[npt.NDArray[np.bool_]] = None,
    coarse: Optional[int] = None,
    return_info: bool = False,
) -> Union[npt.NDArray[np.float64], Tuple[npt.NDArray[np.float64], Dict[str, Any]]]: ...
