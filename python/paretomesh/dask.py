"""ParetoMesh on a Dask cluster: a large grid's tiles run as Dask tasks on any number of
machines, and their fronts are assembled into the whole-grid front on the client.

    >>> from dask.distributed import Client
    >>> client = Client("tcp://scheduler:8786")
    >>> front = paretomesh.dask.simplify("dem.tif", tile=1025, seed=1)

The front is the same, bit for bit, as ``paretomesh.simplify(z, tile=..., seed=...)`` on one
machine: each tile is a pure function of its heights, the plan and the seed, so it does not
matter where or how often (a retry after a lost worker) it runs.
"""

from __future__ import annotations

import os
import time
from typing import Optional

import numpy as np

from . import _heights, _count, _pair, METHODS, Front, _native

__all__ = ["simplify"]


def _tile_from_array(z: np.ndarray, width, height, tile, index, method, params, seed) -> bytes:
    """One tile's front from its heights (a task)."""
    z = np.ascontiguousarray(z, dtype=np.float64)
    if not np.isfinite(z).all():
        raise ValueError(
            f"tile {index} has nodata cells (NaN or infinite): a dask array must be filled "
            "first (a nodata cell takes its nearest valid cell's height, which may lie in "
            "another tile); pass a numpy array or a file instead"
        )
    return _native.run_tile(z, width, height, tile, index, method, params, seed)


def _tile_from_file(path, x0, y0, w, h, width, height, tile, index, method, params, seed) -> bytes:
    """One tile's front from its window of a grid file (a task, run where the file is)."""
    z = _native.read_window(path, x0, y0, w, h)
    return _native.run_tile(z, width, height, tile, index, method, params, seed)


def _whole_from_array(z: np.ndarray, method, params, seed) -> bytes:
    """A one-tile grid's untiled front.json (a task)."""
    return _native.run_whole(np.ascontiguousarray(z, dtype=np.float64), method, params, seed)


def _whole_from_file(path, width, height, method, params, seed) -> bytes:
    """A one-tile grid file's untiled front.json (a task)."""
    z = _native.read_window(path, 0, 0, width, height)
    return _native.run_whole(z, method, params, seed)


def simplify(
    z_or_path,
    client=None,
    tile: Optional[int] = None,
    seed: int = 1,
    *,
    method: str = "memetic",
    evals: Optional[int] = None,
    spacing=None,
    origin=None,
    retries: int = 2,
    error: str = "sum",
) -> Front:
    """Find the whole-grid Pareto front with the grid's tiles spread over a Dask cluster.

    Parameters
    ----------
    z_or_path : numpy array, dask array, or path
        The heights (rows, columns), or a grid file (GeoTIFF, or any format the CLI reads).
        A GeoTIFF is read by windows on the workers: each task decodes only the strips or
        tiles its window meets (the whole file once per worker process when a window holds
        nodata cells, whose fill depends on the rest of the grid, or for other formats). A
        numpy array's nodata (NaN) is filled first, as ``paretomesh.simplify`` fills it; a
        dask array must hold no nodata.
    client : dask.distributed.Client, optional
        The cluster; None uses the current default client.
    tile : int, optional
        Tile side in grid points (default ``paretomesh.DEFAULT_TILE``).
    seed, method, evals, error
        As ``paretomesh.simplify``; ``evals`` is each tile's budget.
    spacing, origin
        As ``paretomesh.simplify``, for arrays (a file carries its own).
    retries : int
        Extra attempts for a task that raised (a task on a worker that died is re-run by
        Dask anyway).

    Returns
    -------
    Front
        Equal, bit for bit, to ``paretomesh.simplify(z, tile=tile, seed=seed, ...)``.
    """
    from dask.distributed import default_client

    client = client if client is not None else default_client()
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"unknown method {method!r}; the methods are {', '.join(METHODS)}")
    seed = _count(seed, "seed", 0)
    tile = _count(tile, "tile", 2)
    params = _native.method_params(method, _count(evals, "evals", 1), error)

    path = None
    darr = None
    if isinstance(z_or_path, (str, os.PathLike)):
        path = os.path.abspath(os.fspath(z_or_path))
        width, height = _native.grid_size(path)
        source = f"grid file {path}"
    elif hasattr(z_or_path, "chunks") and hasattr(z_or_path, "compute"):
        darr = z_or_path
        if darr.ndim != 2:
            raise ValueError(
                f"z must be a 2-D array (rows, columns) of heights, got {darr.ndim} dimension(s)"
            )
        _heights(np.zeros((2, 2), dtype=darr.dtype))  # the dtype check alone
        height, width = darr.shape
        source = f"dask array ({width}×{height})"
    else:
        z, filled = _native.fill_nodata(_heights(z_or_path))
        height, width = z.shape
        source = f"numpy array ({width}×{height}" + (
            f"; {filled} cells that were not finite numbers filled from their nearest valid cell)"
            if filled else ")"
        )

    side, tiles = _native.tile_plan(width, height, tile)
    started = time.perf_counter()
    if not tiles:
        if path is not None:
            tasks = [client.submit(_whole_from_file, path, width, height, method, params, seed,
                                   retries=retries, pure=False)]
        else:
            whole = darr if darr is not None else z
            tasks = [client.submit(_whole_from_array, whole, method, params, seed,
                                   retries=retries, pure=False)]
    elif path is not None:
        tasks = [
            client.submit(_tile_from_file, path, x0, y0, w, h, width, height, side, index,
                          method, params, seed, retries=retries, pure=False)
            for index, x0, y0, w, h in tiles
        ]
    elif darr is not None:
        import dask

        parts = [
            dask.delayed(_tile_from_array, pure=True)(
                darr[y0:y0 + h, x0:x0 + w], width, height, side, index, method, params, seed
            )
            for index, x0, y0, w, h in tiles
        ]
        tasks = client.compute(parts, retries=retries)
    else:
        tasks = [
            client.submit(_tile_from_array, np.ascontiguousarray(z[y0:y0 + h, x0:x0 + w]),
                          width, height, side, index, method, params, seed,
                          retries=retries, pure=False)
            for index, x0, y0, w, h in tiles
        ]
    parts = client.gather(tasks)
    millis = int((time.perf_counter() - started) * 1000)

    grid = {}
    if path is not None:
        grid["grid_path"] = path
    else:
        heights = np.asarray(darr.compute()) if darr is not None else z
        grid["z"] = _heights(heights)
        grid["spacing"] = _pair(spacing, "spacing")
        grid["origin"] = _pair(origin, "origin")
    return _native.assemble_front(width, height, side, list(parts), method, params, seed,
                                  millis, source, **grid)
