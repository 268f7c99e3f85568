"""Simplify a grid on a Dask cluster of two worker processes on this machine.

    python python/examples/dask_local_cluster.py [GRID_FILE]

Without a file, a 700×500 terrain is made by the project's generator (`scripts/terrain.py`,
its `valleys` family: valley networks and terraces). The tiles run on the two
workers; the whole-grid front is the one ``paretomesh.simplify`` gives on one machine with the
same seed and tile size. On a real cluster, replace the LocalCluster with
``Client("tcp://scheduler:8786")``.
"""

import pathlib
import sys
import time

from dask.distributed import Client, LocalCluster

import paretomesh
import paretomesh.dask

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))
from terrain import generate  # noqa: E402  (the project's generator, scripts/terrain.py)


def main() -> None:
    grid = sys.argv[1] if len(sys.argv) > 1 else generate("valleys", 700, 500, seed=1)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster, \
            Client(cluster) as client:
        started = time.perf_counter()
        front = paretomesh.dask.simplify(grid, client=client, tile=257, seed=1, evals=4000)
        print(f"{front} in {time.perf_counter() - started:.1f} s on 2 worker processes")
    knee = front.knee()
    vertices, triangles = knee.mesh()
    print(f"trade-off pick: T = {knee.T}, E_sum = {knee.E_sum:.6g}, E_max = {knee.E_max:.4g}; "
          f"{len(vertices)} vertices, {len(triangles)} triangles")
    least = front.at_most_triangles(knee.T // 4)
    print(f"least error within {knee.T // 4} triangles: T = {least.T}, E_sum = {least.E_sum:.6g}")


if __name__ == "__main__":
    main()
