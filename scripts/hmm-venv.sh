# Sourced by the hmm benches: makes $venv, a virtualenv outside the project ($HMM_VENV, default
# /work/scratch/hmm-venv) with PyPI `pydelatin` (fogleman's hmm) and numpy, which are not
# dependencies of the project, and builds the release CLI as $bin.
venv=${HMM_VENV:-/work/scratch/hmm-venv}
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c 'import pydelatin, numpy' 2>/dev/null; then
  "$venv/bin/pip" install --quiet pydelatin numpy
fi
cargo build --release --bin paretomesh --quiet
bin=${CARGO_TARGET_DIR:-target}/release/paretomesh
