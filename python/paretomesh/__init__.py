"""ParetoMesh: the Pareto front of simplified meshes of a height field.

A surface z = f(x, y) on a W×H grid is simplified by keeping a subset of its grid points (the
four corners always) and Delaunay-triangulating them. Each mesh has two objectives, both
minimised: E_sum, the sum over every grid point of the vertical error |z − z̃|, and T, its
number of triangles. ``simplify`` finds the whole front of (E_sum, T) meshes at once; pick one
with ``Front.knee()``, ``Front.at_most_triangles(n)`` or ``Front.at_most_vertical_error(x)``
and take its ``mesh()``.

    >>> import numpy as np, paretomesh
    >>> z = np.add.outer(np.sin(np.linspace(0, 3, 33)), np.cos(np.linspace(0, 3, 33)))
    >>> front = paretomesh.simplify(z, evals=2000)
    >>> vertices, triangles = front.at_most_triangles(100).mesh()

The same core runs as the ``paretomesh`` command-line tool: a front saved with ``Front.save``
is the front.json that ``paretomesh export`` reads. ``paretomesh.dask.simplify`` spreads a
large grid's tiles over a Dask cluster.
"""

from __future__ import annotations

import os
from typing import Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import Front, Member

__all__ = ["simplify", "read", "load_front", "Front", "Member", "METHODS", "DEFAULT_TILE"]

#: The methods ``simplify`` runs, named as the CLI's ``--algo`` names them.
METHODS: Tuple[str, ...] = tuple(_native.METHODS)
#: The tile side in grid points when ``tile`` is not given.
DEFAULT_TILE: int = _native.DEFAULT_TILE

PathLike = Union[str, "os.PathLike[str]"]
Pair = Union[float, Sequence[float]]


def _heights(z) -> np.ndarray:
    """``z`` as a C-contiguous float64 (rows, columns) array, or a ValueError saying why not."""
    if not isinstance(z, np.ndarray):
        if hasattr(z, "compute") and hasattr(z, "chunks"):
            raise ValueError(
                "z is a dask array: use paretomesh.dask.simplify, or pass z.compute()"
            )
        z = np.asarray(z)
    if z.ndim != 2:
        raise ValueError(
            f"z must be a 2-D array (rows, columns) of heights, got {z.ndim} dimension(s) "
            f"with shape {z.shape}"
        )
    kind, size = z.dtype.kind, z.dtype.itemsize
    if not ((kind == "f" and size in (4, 8)) or kind in "iu"):
        raise ValueError(
            f"z has dtype {z.dtype}; ParetoMesh reads 32/64-bit floats (NaN marks nodata) and "
            "integers"
        )
    return np.ascontiguousarray(z, dtype=np.float64)


def _pair(value: Optional[Pair], name: str) -> Optional[Tuple[float, float]]:
    """A scalar or a 2-sequence as an (x, y) pair of floats."""
    if value is None:
        return None
    if np.ndim(value) == 0:
        return (float(value), float(value))
    values = tuple(float(v) for v in value)  # type: ignore[union-attr]
    if len(values) != 2:
        raise ValueError(f"{name} must be one number or an (x, y) pair, got {value!r}")
    return values  # type: ignore[return-value]


def _count(value, name: str, least: int) -> Optional[int]:
    """A whole number of at least ``least``, or None."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be a whole number, got {value!r}")
    if value < least:
        raise ValueError(f"{name} must be at least {least}, got {value}")
    return int(value)


def simplify(
    z,
    *,
    method: str = "memetic",
    seed: int = 1,
    evals: Optional[int] = None,
    threads: Optional[int] = None,
    tile: Optional[int] = None,
    spacing: Optional[Pair] = None,
    origin: Optional[Pair] = None,
    error: str = "sum",
) -> Front:
    """Find the Pareto front of simplified meshes of the height field ``z``.

    Parameters
    ----------
    z : 2-D array, shape (rows, columns)
        Heights; row index = grid y, column index = grid x. float32, float64 or integers.
        NaN (and ±inf) marks nodata: each such cell takes the height of its nearest valid
        cell, as the GeoTIFF reader fills nodata.
    method : str
        ``"memetic"`` (default, the project's own method), ``"nsga2"`` (the paper's NSGA-II
        with orthogonal-array crossover), ``"weighted"``, ``"greedy"`` or ``"decimation"``:
        the CLI's ``--algo``, with the CLI's defaults.
    seed : int
        Seed of the random generator: the same seed gives the same front, bit for bit, as
        ``paretomesh run --seed`` on the same grid.
    evals : int, optional
        Stop after about this many evaluations (default: the method's own budget).
    threads : int, optional
        Threads for a tiled run (default: every core); the front is the same for any number.
    tile : int, optional
        Tile side in grid points (default ``DEFAULT_TILE``, 1025). A grid larger than a tile
        is cut into tiles that share their border rows and columns, each tile is optimised
        on its own, and the whole-grid front is assembled from the tiles' fronts; a grid of
        one tile runs whole, as the CLI does.
    spacing : float or (dx, dy), optional
        Map units between grid columns and rows (default 1).
    origin : (x0, y0), optional
        Map coordinates of grid point (column 0, row 0) (default (0, 0)).
    error : str
        The error the front minimises beside T, the CLI's ``--error``: ``"sum"`` (default,
        the paper's E_sum), ``"rms"`` or ``"max"`` (the vertical error bound). ``nsga2`` and
        ``weighted`` take ``"sum"`` only.

    Returns
    -------
    Front
        The members by increasing triangle count; each has ``E_sum``, ``E_max`` (in the
        heights' units), ``T``, ``kept`` and ``mesh()``.

    Raises
    ------
    ValueError
        For an array that is not 2-D, a side under 2, no finite height, an unsupported
        dtype, or a bad option; the message is the CLI's.
    """
    heights = _heights(z)
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"unknown method {method!r}; the methods are {', '.join(METHODS)}")
    seed = _count(seed, "seed", 0)
    evals = _count(evals, "evals", 1)
    threads = _count(threads, "threads", 1)
    tile = _count(tile, "tile", 2)
    return _native.simplify(
        heights, method, seed, evals, threads, tile,
        _pair(spacing, "spacing"), _pair(origin, "origin"), error,
    )


def read(path: PathLike) -> Tuple[np.ndarray, dict]:
    """Read a grid file as the CLI reads it: raw .f32 (with its .json sidecar), PNG, GeoTIFF,
    PLY, OBJ or STL.

    Returns ``(z, georeferencing)``: ``z`` float64 (rows, columns), nodata already filled;
    ``georeferencing`` a dict with ``spacing`` (dx, dy), ``origin`` (x0, y0) (map
    coordinates of sample centre (0, 0)), ``source`` (a note on how the grid was made),
    ``filled`` (nodata cells filled), ``placement`` (how a mesh was unwrapped) and ``geotiff``
    (the GeoTIFF tags, or None). A georeferenced GeoTIFF's rows are turned over so that row 0
    is the southern one: ``simplify(z, spacing=g["spacing"], origin=g["origin"])`` gives
    meshes in the map's coordinates.

    Raises OSError when the file cannot be read and ValueError when it is not a grid
    ParetoMesh reads, with the CLI's messages.
    """
    return _native.read(os.fspath(path))


def load_front(path: PathLike, grid=None, *, spacing: Optional[Pair] = None,
               origin: Optional[Pair] = None) -> Front:
    """Read a front.json written by ``Front.save``, ``paretomesh run`` or the app.

    ``grid`` is the grid it was made on, a file path or a 2-D array (with ``spacing`` and
    ``origin``); without it the members' numbers and kept points are there but ``mesh()``
    raises ValueError.
    """
    path = os.fspath(path)
    if grid is None:
        return _native.load_front(path)
    if isinstance(grid, (str, os.PathLike)):
        return _native.load_front(path, grid_path=os.fspath(grid))
    return _native.load_front(
        path, z=_heights(grid), spacing=_pair(spacing, "spacing"), origin=_pair(origin, "origin")
    )
