"""Shared fixtures: the repository's test grids and the CLI built from the same core."""

import json
import os
import pathlib
import shutil

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = REPO / "tests" / "data"


@pytest.fixture(scope="session")
def data() -> pathlib.Path:
    return DATA


@pytest.fixture(scope="session")
def cli() -> str:
    """The paretomesh CLI: $PARETOMESH_CLI, else the debug build `cargo test` leaves behind."""
    candidates = [os.environ.get("PARETOMESH_CLI")]
    target = os.environ.get("CARGO_TARGET_DIR", str(REPO / "target"))
    candidates += [os.path.join(target, "debug", "paretomesh"), shutil.which("paretomesh")]
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    pytest.fail("no paretomesh CLI: run `cargo build` first or set PARETOMESH_CLI")


def raw_grid(name: str) -> np.ndarray:
    """A tests/data raw f32 grid as a (height, width) float32 array."""
    meta = json.loads((DATA / f"{name}.json").read_text())
    z = np.fromfile(DATA / f"{name}.f32", dtype="<f4")
    return z.reshape(meta["height"], meta["width"])


def members(front):
    """A front's members as comparable tuples: E_sum, E_max, T and the kept points."""
    return [(m.E_sum, m.E_max, m.T, m.kept.tolist()) for m in front]
