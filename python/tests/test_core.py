"""The package on one machine: the CLI's fronts, meshes, files, errors."""

import json
import subprocess
import sys

import numpy as np
import pytest

import paretomesh
from conftest import members, raw_grid


@pytest.mark.parametrize(
    "name, method, seed, evals",
    [("jacksboro_33x33", "memetic", 3, 3000), ("volcano_33x33", "nsga2", 5, 1500)],
)
def test_front_equals_the_clis_front_json(tmp_path, data, cli, name, method, seed, evals):
    # The same grid (the f32 file's values) and seed give the CLI's front.json bit for bit,
    # and Front.save writes the members the CLI wrote.
    out = tmp_path / "cli.json"
    subprocess.run(
        [cli, "run", str(data / f"{name}.f32"), "--algo", method, "--seed", str(seed),
         "--evals", str(evals), "--out", str(out)],
        check=True, capture_output=True,
    )
    expected = json.loads(out.read_text())
    front = paretomesh.simplify(raw_grid(name), method=method, seed=seed, evals=evals)
    # Kept sets are packed in the file; load_front decodes them as the CLI does.
    assert members(front) == members(paretomesh.load_front(out))
    assert [(m.E_sum, m.E_max, m.T) for m in front] == [
        (m["E_sum"], m["E_max"], m["T"]) for m in expected["front"]
    ]
    assert front.evaluations == expected["evaluations"]
    saved = tmp_path / "py.json"
    front.save(saved)
    written = json.loads(saved.read_text())
    assert written["front"] == expected["front"]
    assert written["params"] == expected["params"]
    assert (written["algorithm"], written["seed"]) == (method, seed)


@pytest.mark.parametrize("method, error", [("memetic", "max"), ("greedy", "rms")])
def test_an_error_measure_gives_the_clis_front(tmp_path, data, cli, method, error):
    # simplify(error=...) is run --error: the same front.json, its measure and RMS on file.
    out = tmp_path / "cli.json"
    evals = ["--evals", "2000"] if method == "memetic" else []
    subprocess.run(
        [cli, "run", str(data / "camera_33x33.f32"), "--algo", method, "--seed", "4",
         "--error", error, *evals, "--out", str(out)],
        check=True, capture_output=True,
    )
    expected = json.loads(out.read_text())
    assert expected["params"]["error"] == error
    kwargs = {"evals": 2000} if method == "memetic" else {}
    front = paretomesh.simplify(raw_grid("camera_33x33"), method=method, seed=4, error=error,
                                **kwargs)
    assert members(front) == members(paretomesh.load_front(out))
    saved = tmp_path / "py.json"
    front.save(saved)
    written = json.loads(saved.read_text())
    assert written["front"] == expected["front"] and written["params"] == expected["params"]
    assert all("RMS" in m for m in written["front"])


def test_a_saved_front_loads_back_and_the_cli_exports_it(tmp_path, data, cli):
    z = raw_grid("bunny_33x33")
    front = paretomesh.simplify(z, seed=2, evals=2000)
    path = tmp_path / "front.json"
    front.save(path)
    bare = paretomesh.load_front(path)
    assert members(bare) == members(front)
    with pytest.raises(ValueError, match="without its grid"):
        bare[0].mesh()
    for grid in (str(data / "bunny_33x33.f32"), z):
        loaded = paretomesh.load_front(path, grid)
        for pick in (3, len(front) // 2):
            v1, t1 = loaded[pick].mesh()
            v2, t2 = front[pick].mesh()
            assert np.array_equal(v1, v2) and np.array_equal(t1, t2)
    with pytest.raises(ValueError, match="33×33"):
        paretomesh.load_front(path, np.zeros((4, 5)))
    # The CLI reads the file Python wrote.
    ply = tmp_path / "knee.ply"
    subprocess.run(
        [cli, "export", str(path), "--tradeoff", "--grid", str(data / "bunny_33x33.f32"),
         "--out", str(ply)],
        check=True, capture_output=True,
    )
    header = ply.read_text().split("end_header")[0]
    knee = front.knee()
    assert f"element vertex {len(knee.kept)}" in header
    assert f"element face {knee.T}" in header


def test_meshes_are_in_map_coordinates_and_cover_the_grid(data):
    z, geo = paretomesh.read(data / "volcano_87x61_int16_lzw_nodata.tif")
    assert z.shape == (61, 87) and geo["filled"] == 14 and geo["geotiff"]["nodata"] == "-9999"
    front = paretomesh.simplify(z, seed=1, evals=2000, spacing=geo["spacing"], origin=geo["origin"])
    (dx, dy), (x0, y0) = geo["spacing"], geo["origin"]
    for member in (front[0], front.knee(), front[-1]):
        vertices, triangles = member.mesh()
        assert vertices.dtype == np.float64 and vertices.shape == (len(member.kept), 3)
        assert triangles.dtype == np.uint32 and triangles.shape == (member.T, 3)
        rows, cols = np.divmod(member.kept, 87)
        assert np.array_equal(vertices[:, 0], x0 + cols * dx)
        assert np.array_equal(vertices[:, 1], y0 + rows * dy)
        assert np.array_equal(vertices[:, 2], z[rows, cols])
        # Counter-clockwise triangles that tile the grid's rectangle exactly.
        a, b, c = (vertices[triangles[:, k], :2] for k in range(3))
        area = ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]) / 2
        assert (area > 0).all()
        assert np.isclose(area.sum(), 86 * dx * 60 * dy)


def test_picks_follow_their_rules():
    z = raw_grid("camera_33x33").astype(np.float64)
    front = paretomesh.simplify(z, seed=4, evals=2000)
    ts = np.array([m.T for m in front])
    es = np.array([m.E_sum for m in front])
    emax = np.array([m.E_max for m in front])
    assert (np.diff(ts) > 0).all() and (np.diff(es) < 0).all()
    n = int(ts[len(ts) // 3]) + 1
    assert front.at_most_triangles(n).E_sum == es[ts <= n].min()
    x = float(np.median(emax))
    assert front.at_most_vertical_error(x).T == ts[emax <= x].min()
    with pytest.raises(ValueError, match="no member has at most 1 triangles"):
        front.at_most_triangles(1)
    with pytest.raises(ValueError, match="no member has E_max at most -1"):
        front.at_most_vertical_error(-1.0)
    assert 0 <= front.knee().index < len(front)
    assert front[-1].index == len(front) - 1
    with pytest.raises(IndexError):
        front[len(front)]


def test_nodata_is_filled_from_the_nearest_valid_cell():
    z = np.arange(25, dtype=np.float64).reshape(5, 5)
    holed = z.copy()
    holed[2, 2] = np.nan
    holed[0, 4] = np.inf
    filled = z.copy()
    filled[2, 2] = z[1, 2]  # equally near cells: the one reached first from the lower index
    filled[0, 4] = z[0, 3]
    assert members(paretomesh.simplify(holed, evals=300)) == members(
        paretomesh.simplify(filled, evals=300))
    assert members(paretomesh.simplify(holed.astype(np.float32), evals=300)) == members(
        paretomesh.simplify(filled, evals=300))


@pytest.mark.parametrize(
    "z, message",
    [
        (np.zeros(16), "2-D array"),
        (np.zeros((2, 2, 2)), "2-D array"),
        (np.zeros((1, 9)), "at least 2×2"),
        (np.zeros((9, 1)), "at least 2×2"),
        (np.full((4, 4), np.nan), "no height"),
        (np.full((4, 4), np.inf, dtype=np.float32), "no height"),
        (np.zeros((4, 4), dtype=np.complex128), "dtype complex128"),
        (np.zeros((4, 4), dtype=np.float16), "dtype float16"),
        (np.zeros((4, 4), dtype=bool), "dtype bool"),
        (np.array([["a", "b"], ["c", "d"]]), "dtype <U1"),
    ],
)
def test_bad_arrays_get_a_clear_value_error(z, message):
    with pytest.raises(ValueError, match=message):
        paretomesh.simplify(z)


def test_bad_options_and_files_get_the_clis_messages(tmp_path, data):
    z = np.zeros((8, 8))
    with pytest.raises(ValueError, match="unknown method 'fast'"):
        paretomesh.simplify(z, method="fast")
    with pytest.raises(ValueError, match="evals does not apply"):
        paretomesh.simplify(z, method="decimation", evals=10)
    with pytest.raises(ValueError, match="unknown error measure \"mean\""):
        paretomesh.simplify(z, error="mean")
    with pytest.raises(ValueError, match="--algo nsga2 does not take --error max"):
        paretomesh.simplify(z, method="nsga2", error="max")
    with pytest.raises(ValueError, match="spacing must be positive"):
        paretomesh.simplify(z, spacing=(0.0, 1.0))
    with pytest.raises(ValueError, match="too small"):
        paretomesh.simplify(np.zeros((40, 40)), tile=8)
    with pytest.raises(OSError, match="cannot read"):
        paretomesh.read(tmp_path / "missing.tif")
    with pytest.raises(ValueError, match="two_bands|bands"):
        paretomesh.read(data / "camera_33x33_two_bands.tif")
    with pytest.raises(OSError, match="cannot read"):
        paretomesh.load_front(tmp_path / "missing.json")
    (tmp_path / "bad.json").write_text("{}")
    with pytest.raises(ValueError, match="is not a front.json"):
        paretomesh.load_front(tmp_path / "bad.json")


def test_a_tiled_run_is_the_same_for_any_number_of_threads(tmp_path):
    z = raw_grid("jacksboro_65x65")
    one = paretomesh.simplify(z, tile=33, threads=1, seed=7, evals=600)
    two = paretomesh.simplify(z, tile=33, threads=2, seed=7, evals=600)
    assert one.tile == 33 and len(one) > 10
    assert members(one) == members(two)
    vertices, triangles = one.knee().mesh()
    assert triangles.shape == (one.knee().T, 3)
    # Saved as a tiled front.json (every tile's kept sets, each member's choice of one per
    # tile), and read back to the same members and meshes.
    path = tmp_path / "tiled.json"
    one.save(path)
    written = json.loads(path.read_text())
    assert written["tiled"]["plan"] and len(written["tiled"]["members"]) == len(one)
    assert "front" not in written
    loaded = paretomesh.load_front(path, z)
    assert loaded.tile == 33
    assert [(m.E_sum, m.E_max, m.T) for m in loaded] == [(m.E_sum, m.E_max, m.T) for m in one]
    for k in (0, len(one) // 2, len(one) - 1):
        assert all(np.array_equal(a, b) for a, b in zip(loaded[k].mesh(), one[k].mesh()))
        assert np.array_equal(loaded[k].kept, one[k].kept)


def test_the_core_package_needs_only_numpy():
    # Dask, distributed and rasterio blocked: importing and running still work, and the
    # package declares numpy as its one requirement.
    code = (
        "import sys\n"
        "for m in ('dask', 'distributed', 'rasterio', 'xarray'): sys.modules[m] = None\n"
        "import numpy as np, paretomesh\n"
        "f = paretomesh.simplify(np.random.default_rng(1).random((9, 9)), evals=200)\n"
        "z, g = paretomesh.read(sys.argv[1])\n"
        "print(len(f), z.shape)\n"
    )
    from conftest import DATA
    out = subprocess.run([sys.executable, "-c", code, str(DATA / "volcano_87x61_uint16_packbits.tif")],
                         check=True, capture_output=True, text=True)
    assert out.stdout.strip().endswith("(61, 87)")
    from importlib.metadata import requires
    core = [r for r in requires("paretomesh") if "extra ==" not in r]
    assert [r.split(">")[0].split("=")[0].strip() for r in core] == ["numpy"]


def test_help_is_useful():
    for text in (paretomesh.simplify.__doc__, paretomesh.read.__doc__,
                 paretomesh.Front.knee.__doc__, paretomesh.Member.mesh.__doc__):
        assert text and len(text) > 60
