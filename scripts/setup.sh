#!/usr/bin/env bash
# Installs what a fresh Debian 12 machine (root, Rust via rustup) lacks to build, serve and test
# ParetoMesh: the wasm32 target, clippy/rustfmt, wasm-bindgen-cli pinned to Cargo.lock,
# Chromium + chromedriver (apt), and the npm dev tools (binaryen's wasm-opt, playwright-core,
# CesiumJS and the Khronos glTF validator for the tile pyramid's test).
# Each step is skipped when the right version is already present. Shared by scripts/serve.sh
# and .ci/run.
set -euo pipefail
cd "$(dirname "$0")/.."

rustup target list --installed | grep -qx wasm32-unknown-unknown \
  || rustup target add wasm32-unknown-unknown
rustup component list --installed | grep -q '^clippy' || rustup component add clippy
rustup component list --installed | grep -q '^rustfmt' || rustup component add rustfmt

# wasm-bindgen-cli pinned to the exact wasm-bindgen in Cargo.lock (`--locked` fails here).
want=$(awk '/^name = "wasm-bindgen"$/ {getline; gsub(/version = |"/, ""); print; exit}' Cargo.lock)
have=$(wasm-bindgen --version 2>/dev/null | awk '{print $2}' || true)
if [ "$have" != "$want" ]; then
  echo "installing wasm-bindgen-cli $want (have: ${have:-none})"
  cargo install wasm-bindgen-cli --version "$want"
fi

if ! command -v chromium >/dev/null || ! command -v chromedriver >/dev/null; then
  apt-get update
  DEBIAN_FRONTEND=noninteractive apt-get install -y chromium chromium-driver
fi

# npm's binaryen (never Debian's: its wasm-opt 108 breaks wasm-bindgen's output) and
# playwright-core (drives /usr/bin/chromium; never `npx playwright install`).
if ! command -v npm >/dev/null; then
  apt-get update
  DEBIAN_FRONTEND=noninteractive apt-get install -y nodejs npm
fi
if [ ! -x node_modules/.bin/wasm-opt ] || [ ! -d node_modules/playwright-core ] \
  || [ ! -d node_modules/cesium/Build/Cesium ] || [ ! -d node_modules/gltf-validator ] \
  || [ package-lock.json -nt node_modules/.package-lock.json ]; then
  npm ci --no-audit --no-fund
fi

# The Python package's build and test tools, in a virtualenv of their own (.venv-python):
# maturin builds the wheel, pytest runs python/tests, dask[distributed] runs its cluster tests.
# Debian's python3 needs python3-venv (and pip) for it.
if [ ! -x .venv-python/bin/python ]; then
  if ! python3 -m venv --help >/dev/null 2>&1 || ! python3 -c 'import ensurepip' 2>/dev/null; then
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y python3-venv python3-pip
  fi
  python3 -m venv .venv-python
fi
if [ ! -x .venv-python/bin/maturin ] \
  || ! .venv-python/bin/python -c 'import numpy, pytest, dask, distributed' 2>/dev/null; then
  .venv-python/bin/pip install --quiet maturin numpy pytest 'dask[distributed]'
fi
