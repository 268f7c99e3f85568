#!/usr/bin/env bash
# ParetoMesh against hmm (fogleman's C++ greedy insertion, PyPI `pydelatin`) on one grid, with
# hmm's meshes scored by the project's evaluator after mapping its bottom-up rows, checked
# against hmm's own max error (see scripts/bench_vs_hmm.py). pydelatin is not a dependency of
# the project: it goes in a virtualenv outside it ($HMM_VENV, default /work/scratch/hmm-venv,
# made when missing).
#   bash scripts/bench-vs-hmm.sh GRID.f32 [--front FRONT.json] [--budgets 0.1,0.5,1,2,5,10,20]
#        [--max-errors E1,E2,...] [--greedy [--greedy-tile N] [--threads K]]
# GRID is a raw .f32 grid with its .json sidecar (`bash scripts/make-grids.sh` makes them).
# --budgets are hmm's triangle budgets in % of the full mesh 2(W-1)(H-1); --max-errors hmm's
# max errors in z units; --front compares a ParetoMesh front.json made on GRID; --greedy times
# `paretomesh run --algo greedy --max-vertical-error E` against hmm at each hmm mesh's E_max:
# untiled, or over tiles of --greedy-tile N points a side on --threads K threads, each greedy
# mesh scored afresh by `eval`. Exits non-zero unless every hmm mesh's evaluator E_max equals
# `Delatin.error` and every greedy mesh's is within its bound.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || { sed -n '2,15p' "$0"; exit 2; }
source scripts/hmm-venv.sh
grid=$1
shift
exec "$venv/bin/python" scripts/bench_vs_hmm.py --bin "$bin" --grid "$grid" "$@"
