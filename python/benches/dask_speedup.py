"""Dask on 1 and on 2 worker processes against one machine: wall time and identical fronts.

    python python/benches/dask_speedup.py [SIDE] [EVALS_PER_TILE]

A SIDE² spectral fractal terrain (default 3601; `scripts/terrain.py`, seed 1) in tiles of
paretomesh.DEFAULT_TILE, memetic with EVALS_PER_TILE evaluations per tile (default: the
method's own budget, as `paretomesh run` gives a tile), seed 1.
"""

import pathlib
import sys
import time

from dask.distributed import Client, LocalCluster

import paretomesh
import paretomesh.dask

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))
from terrain import spectral  # noqa: E402  (the project's generator, scripts/terrain.py)


def members(front):
    """Every member's numbers, and the kept points of the first, the knee and the last (a tiled
    member's kept points take a triangulation of every tile)."""
    picks = (front[0], front.knee(), front[-1])
    return [(m.E_sum, m.E_max, m.T) for m in front], [m.kept.tobytes() for m in picks]


def main() -> None:
    side = int(sys.argv[1]) if len(sys.argv) > 1 else 3601
    evals = int(sys.argv[2]) if len(sys.argv) > 2 else None
    z = spectral(side, side)
    fronts, times = {}, {}
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            started = time.perf_counter()
            fronts[workers] = paretomesh.dask.simplify(z, client=client, seed=1, evals=evals)
            times[workers] = time.perf_counter() - started
            print(f"{workers} worker(s): {times[workers]:.1f} s, {fronts[workers]}", flush=True)
    started = time.perf_counter()
    native = paretomesh.simplify(z, seed=1, evals=evals, threads=2)
    print(f"one machine, 2 threads: {time.perf_counter() - started:.1f} s, {native}")
    same = members(fronts[1]) == members(fronts[2]) == members(native)
    print(f"speed-up 2 workers / 1: {times[1] / times[2]:.2f}x; identical fronts: {same}")


if __name__ == "__main__":
    main()
