"""The project's terrain generator (scripts/terrain.py): its grids and GeoTIFFs read back as
written, and its fbm family keeps the bits the figures of docs/performance.md were made on."""

import hashlib
import json
import subprocess
import sys

import numpy as np
import pytest

import paretomesh
from conftest import REPO

sys.path.insert(0, str(REPO / "scripts"))
import terrain  # noqa: E402

SCRIPT = REPO / "scripts" / "terrain.py"


def test_fbm_keeps_the_bits_of_the_generated_grids():
    # The sha256 of the raw grid the former Rust generator (examples/make_terrain.rs) wrote for
    # --size 97x61 --seed 1: make-grids.sh's grids, and so the figures measured on them.
    z = terrain.fbm_rows(97, 61, seed=1)(0, 61)
    digest = hashlib.sha256(z.astype("<f4").tobytes()).hexdigest()
    assert digest == "11fa67a43f8920c80f1e00f0b35236c881805f325369823a2f93f5bba8cacb9c"
    # Made block by block, the rows are the same.
    rows = terrain.fbm_rows(97, 61, seed=1)
    assert np.array_equal(np.vstack([rows(0, 7), rows(7, 40), rows(40, 61)]), z)


@pytest.mark.parametrize("family", terrain.FAMILIES)
def test_each_family_is_a_function_of_its_seed(family):
    a = terrain.generate(family, 70, 45, seed=3)
    assert a.shape == (45, 70) and a.dtype == np.float32 and np.isfinite(a).all()
    assert np.array_equal(a, terrain.generate(family, 70, 45, seed=3))
    assert not np.array_equal(a, terrain.generate(family, 70, 45, seed=4))
    assert a.max() > a.min()


def test_urban_walls_are_vertical():
    # A building's wall is one grid step from the street to its roof: somewhere two neighbours
    # differ by at least a storey (3 m) at 1 m spacing.
    z = terrain.generate("urban", 300, 300, seed=1).astype(np.float64)
    assert np.abs(np.diff(z, axis=1)).max() >= 3.0


@pytest.mark.parametrize("layout,compression,bigtiff", [
    ("tiles", "zlib", False), ("tiles", "none", True), ("strips", "zlib", True),
    ("strips", "none", False)])
def test_geotiff_and_raw_grid_read_back_as_written(tmp_path, layout, compression, bigtiff):
    # 300 columns: two 256-wide tiles, the second padded; 97 rows: a partial tile and strip.
    args = ["valleys", "--size", "300x97", "--seed", "2", "--spacing", "30",
            "--out", str(tmp_path / "g.f32"), "--tif", str(tmp_path / "g.tif"),
            "--layout", layout, "--compression", compression, "--epsg", "32633",
            "--origin", "400000", "4100000"] + (["--bigtiff"] if bigtiff else [])
    subprocess.run([sys.executable, str(SCRIPT), *args], check=True)
    made = terrain.generate("valleys", 300, 97, seed=2)
    raw, _ = paretomesh.read(tmp_path / "g.f32")
    tif, geo = paretomesh.read(tmp_path / "g.tif")
    assert np.array_equal(raw, made.astype(np.float64))
    assert np.array_equal(tif, raw)
    assert list(geo["spacing"]) == [30.0, 30.0]
    # Pixel is area: the first sample's centre is half a step inside the lower-left corner.
    assert list(geo["origin"]) == [400015.0, 4100015.0]
    sidecar = json.loads((tmp_path / "g.json").read_text())
    assert (sidecar["width"], sidecar["height"]) == (300, 97)
    assert sidecar["zmin"] == float(made.min()) and sidecar["zmax"] == float(made.max())


def test_parameters_of_another_family_are_refused(tmp_path):
    done = subprocess.run([sys.executable, str(SCRIPT), "urban", "--size", "9", "--beta", "2",
                           "--out", str(tmp_path / "u.f32")], capture_output=True, text=True)
    assert done.returncode != 0 and "--beta does not apply to the urban family" in done.stderr
