"""Simplify a grid on a Dask cluster of two worker processes on this machine.

    python python/examples/dask_local_cluster.py [GRID_FILE]

Without a file, a 700×500 fractal terrain is made with numpy. The tiles run on the two
workers; the whole-grid front is the one ``paretomesh.simplify`` gives on one machine with the
same seed and tile size. On a real cluster, replace the LocalCluster with
``Client("tcp://scheduler:8786")``.
"""

import sys
import time

import numpy as np
from dask.distributed import Client, LocalCluster

import paretomesh
import paretomesh.dask


def terrain(width: int, height: int, beta: float = 2.8, seed: int = 1) -> np.ndarray:
    """A fractal terrain by spectral synthesis: random phases, amplitude k^(−β/2)."""
    rng = np.random.default_rng(seed)
    ky = np.fft.fftfreq(height)[:, None]
    kx = np.fft.rfftfreq(width)[None, :]
    k = np.hypot(kx, ky)
    k[0, 0] = 1.0
    spectrum = k ** (-beta / 2) * np.exp(2j * np.pi * rng.random(k.shape))
    spectrum[0, 0] = 0.0
    z = np.fft.irfft2(spectrum, s=(height, width))
    return 1000.0 * (z - z.min()) / (z.max() - z.min())


def main() -> None:
    grid = sys.argv[1] if len(sys.argv) > 1 else terrain(700, 500)
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
