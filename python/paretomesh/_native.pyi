"""Type stubs of the compiled module (``paretomesh._native``)."""

from typing import Iterator, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

METHODS: list[str]
DEFAULT_TILE: int

class Member:
    """One member of a front: a kept set of grid points and its scores."""

    @property
    def E_sum(self) -> float:
        """Σ |z − z̃| over every grid point, in height units."""
    @property
    def E_max(self) -> float:
        """The largest vertical error |z − z̃| over the grid, in height units."""
    @property
    def T(self) -> int:
        """The number of triangles."""
    @property
    def kept(self) -> npt.NDArray[np.uint32]:
        """Kept grid points as increasing flat indices y·W + x, corners included."""
    @property
    def index(self) -> int:
        """This member's position in its front."""
    def mesh(self) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.uint32]]:
        """``(vertices (n, 3) float64 in map coordinates, triangles (m, 3) uint32)``."""

class Front(Sequence[Member]):
    """A run's Pareto front, members by increasing T (so decreasing error)."""

    def __len__(self) -> int: ...
    def __getitem__(self, index: int) -> Member: ...  # type: ignore[override]
    def __iter__(self) -> Iterator[Member]: ...
    @property
    def method(self) -> str: ...
    @property
    def seed(self) -> int: ...
    @property
    def evaluations(self) -> int: ...
    @property
    def millis(self) -> int: ...
    @property
    def shape(self) -> Tuple[int, int]:
        """The grid's (width, height)."""
    @property
    def source(self) -> str: ...
    @property
    def tile(self) -> Optional[int]:
        """The tile side of a tiled run, None for an untiled one."""
    def knee(self) -> Member:
        """The paper's trade-off pick, its weights drawn with the run's seed."""
    def at_most_triangles(self, n: int) -> Member:
        """The member of least E_sum with at most ``n`` triangles."""
    def at_most_vertical_error(self, x: float) -> Member:
        """The member of fewest triangles with E_max at most ``x``."""
    def save(self, path: str) -> None:
        """Write the front as front.json."""

def simplify(
    z: npt.NDArray[np.float64],
    method: str,
    seed: int,
    evals: Optional[int] = ...,
    threads: Optional[int] = ...,
    tile: Optional[int] = ...,
    spacing: Optional[Tuple[float, float]] = ...,
    origin: Optional[Tuple[float, float]] = ...,
    error: Optional[str] = ...,
) -> Front: ...
def read(path: str) -> Tuple[npt.NDArray[np.float64], dict]: ...
def load_front(
    path: str,
    grid_path: Optional[str] = ...,
    z: Optional[npt.NDArray[np.float64]] = ...,
    spacing: Optional[Tuple[float, float]] = ...,
    origin: Optional[Tuple[float, float]] = ...,
) -> Front: ...
def method_params(
    method: str, evals: Optional[int] = ..., error: Optional[str] = ...
) -> str: ...
def tile_plan(
    width: int, height: int, tile: Optional[int] = ...
) -> Tuple[int, List[Tuple[int, int, int, int, int]]]: ...
def run_tile(
    z: npt.NDArray[np.float64], width: int, height: int, tile: int, index: int,
    method: str, params: str, seed: int,
) -> bytes: ...
def run_whole(z: npt.NDArray[np.float64], method: str, params: str, seed: int) -> bytes: ...
def assemble_front(
    width: int, height: int, tile: int, parts: List[bytes], method: str, params: str,
    seed: int, millis: int, source: str, z: Optional[npt.NDArray[np.float64]] = ...,
    grid_path: Optional[str] = ..., spacing: Optional[Tuple[float, float]] = ...,
    origin: Optional[Tuple[float, float]] = ...,
) -> Front: ...
def fill_nodata(z: npt.NDArray[np.float64]) -> Tuple[npt.NDArray[np.float64], int]: ...
def grid_size(path: str) -> Tuple[int, int]: ...
def read_window(path: str, x0: int, y0: int, w: int, h: int) -> npt.NDArray[np.float64]: ...
