from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

CsrCells = Tuple[npt.NDArray[np.integer], npt.NDArray[np.integer], npt.NDArray[np.integer]]
BlockCells = Sequence[Union[Tuple[Union[str, int], npt.ArrayLike], Any]]
Cells = Union[CsrCells, BlockCells]
Method = Literal["quaternion", "spring", "idw"]
Solver = Literal["amg", "cg", "cg-ssor", "gauss-seidel", "jacobi"]
Stiffness = Literal["batina", "wall-distance", "inverse-volume"]

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
    points: npt.NDArray[np.float64],
    cells: Cells,
    moved: npt.ArrayLike,
    motion: Motion,
    fixed: Optional[npt.ArrayLike] = None,
    method: Method = "quaternion",
    solver: Solver = "amg",
    stiffness: Stiffness = "batina",
    tol: float = 1e-10,
    max_iter: int = 10000,
    idw_exponent: float = 2.0,
    allow_unconverged: bool = False,
    return_info: bool = False,
) -> Union[npt.NDArray[np.float64], Tuple[npt.NDArray[np.float64], Dict[str, Any]]]:
    """New points; with ``return_info``, ``(points, {"iterations", "residual", "converged"})``."""
    ...

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
