#!/usr/bin/env bash
# A `paretomesh tiles` pyramid against a per-tile greedy tiler at the same error: hmm (PyPI
# `pydelatin`, fogleman's greedy insertion) run on every tile of every level with the level's
# geometric error as its max error, as Cesium Terrain Builder-like tilers mesh each tile on
# its own. Prints, per level, our triangles, hmm's and the ratio (see
# scripts/bench_tiles_vs_hmm.py). pydelatin is not a dependency of the project: it goes in a
# virtualenv outside it ($HMM_VENV, default /work/scratch/hmm-venv, made when missing).
#   bash scripts/bench-tiles-vs-hmm.sh GRID.f32 [paretomesh tiles options...]
# GRID is a raw .f32 grid with its .json sidecar (scripts/terrain.py fbm --size N --out GRID).
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || { sed -n '2,9p' "$0"; exit 2; }
source scripts/hmm-venv.sh
grid=$1
shift
exec "$venv/bin/python" scripts/bench_tiles_vs_hmm.py --bin "$bin" --grid "$grid" -- "$@"
