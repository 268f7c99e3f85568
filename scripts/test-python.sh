#!/usr/bin/env bash
# Builds the Python package's wheel (python/, the `quick` profile: optimised, no LTO, so the
# build stays short) into the virtualenv that scripts/setup.sh made, and runs its tests. The
# tests compare with the CLI's debug build, which `cargo test` leaves in target/debug.
set -euo pipefail
cd "$(dirname "$0")/.."

cargo fmt --manifest-path python/Cargo.toml -- --check
cargo clippy --manifest-path python/Cargo.toml -- -D warnings

wheels=$(mktemp -d)
trap 'rm -rf "$wheels"' EXIT
.venv-python/bin/maturin build --quiet --profile quick -m python/Cargo.toml \
  -i .venv-python/bin/python -o "$wheels"
.venv-python/bin/pip install --quiet --force-reinstall --no-deps "$wheels"/paretomesh-*.whl
# Run from python/tests so that `import paretomesh` is the installed wheel, not the source tree.
cd python/tests
../../.venv-python/bin/python -m pytest -q -p no:cacheprovider .
