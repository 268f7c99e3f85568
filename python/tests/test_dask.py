"""Tiles on a Dask cluster of two worker processes: the same front as one machine, whatever
the input's form, and after a worker dies mid-run."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import paretomesh
from conftest import members, raw_grid

distributed = pytest.importorskip("distributed")
import dask.array as da  # noqa: E402
import paretomesh.dask  # noqa: E402


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_numpy_and_dask_arrays_give_the_native_front(client):
    z = raw_grid("jacksboro_65x65").astype(np.float64)
    z[10, 40] = np.nan  # nodata, filled before the grid is cut
    native = paretomesh.simplify(z, tile=33, seed=4, evals=800)
    assert native.tile == 33
    assert members(paretomesh.dask.simplify(z, tile=33, seed=4, evals=800)) == members(native)
    filled = z.copy()
    filled[10, 40] = z[9, 40]
    darr = da.from_array(filled, chunks=(20, 30))
    from_dask = paretomesh.dask.simplify(darr, client=client, tile=33, seed=4, evals=800)
    assert members(from_dask) == members(native)
    # Tiles ran on both worker processes.
    assert len(client.scheduler_info()["workers"]) == 2
    v1, t1 = from_dask.knee().mesh()
    v2, t2 = native.knee().mesh()
    assert np.array_equal(v1, v2) and np.array_equal(t1, t2)
    with pytest.raises(ValueError, match="nodata"):
        paretomesh.dask.simplify(da.from_array(z, chunks=30), client=client, tile=33, evals=50)


def test_a_one_tile_grid_runs_whole_as_simplify_does(client):
    z = raw_grid("volcano_33x33")
    assert members(paretomesh.dask.simplify(z, seed=2, evals=500)) == members(
        paretomesh.simplify(z, seed=2, evals=500))


@pytest.mark.parametrize(
    "name", ["jacksboro_65x65_float32_tiled_deflate.tif", "volcano_87x61_int16_lzw_nodata.tif",
             "volcano_87x61_uint16_packbits.tif"])
def test_windows_of_a_geotiff_are_the_importers_values(data, name):
    z, _ = paretomesh.read(data / name)
    height, width = z.shape
    assert paretomesh._native.grid_size(str(data / name)) == (width, height)
    for x0, y0, w, h in [(0, 0, width, height), (5, 7, 20, 30), (width - 33, height - 33, 33, 33)]:
        window = paretomesh._native.read_window(str(data / name), x0, y0, w, h)
        assert np.array_equal(window, z[y0:y0 + h, x0:x0 + w])


def test_a_geotiff_read_by_windows_on_the_workers_gives_the_native_front(client, data):
    path = data / "volcano_87x61_int16_lzw_nodata.tif"
    z, geo = paretomesh.read(path)
    native = paretomesh.simplify(z, tile=33, seed=3, evals=500, spacing=geo["spacing"],
                                 origin=geo["origin"])
    front = paretomesh.dask.simplify(str(path), client=client, tile=33, seed=3, evals=500)
    assert members(front) == members(native)
    v1, t1 = front.knee().mesh()
    v2, t2 = native.knee().mesh()
    assert np.array_equal(v1, v2) and np.array_equal(t1, t2)


def test_a_worker_killed_mid_run_is_replaced_and_the_front_is_the_same(client):
    # Tiles long enough to be caught running; one worker process is killed while it runs a
    # tile, the nanny starts another, the scheduler re-runs the lost tile, and the front is the
    # native one.
    z = raw_grid("camera_65x65")
    native = paretomesh.simplify(z, tile=33, seed=6, evals=30000)
    pids = client.run(os.getpid)
    result = {}

    def run():
        try:
            result["front"] = paretomesh.dask.simplify(
                z, client=client, tile=33, seed=6, evals=30000)
        except Exception as e:  # shown by the assertion below
            result["error"] = e

    runner = threading.Thread(target=run)
    runner.start()
    killed = None
    deadline = time.monotonic() + 120
    while killed is None and time.monotonic() < deadline and runner.is_alive():
        busy = [w for w, keys in client.processing().items() if keys and w in pids]
        if busy:
            killed = busy[0]
            os.kill(pids[killed], signal.SIGKILL)
        time.sleep(0.02)
    runner.join(timeout=900)
    assert killed is not None, "no tile was caught running"
    assert not runner.is_alive(), "the run did not finish"
    assert "error" not in result, result.get("error")
    assert members(result["front"]) == members(native)
    client.wait_for_workers(2, timeout=300)
    assert pids[killed] not in client.run(os.getpid).values()
