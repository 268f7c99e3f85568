#!/usr/bin/env bash
# Runs every test: formatting, clippy (native and wasm32), native tests, the
# wasm-bindgen-test tests in headless Chromium, and the browser app's end-to-end test
# (playwright-core driving /usr/bin/chromium). It first runs `scripts/setup.sh`, which installs
# what is missing (the wasm32 target, wasm-bindgen-cli matching Cargo.lock, chromium and
# chromedriver, the npm tools) and skips what is already there, so it works on a fresh machine.
# Each stage's elapsed seconds are printed when it ends, and all of them at the end.
set -euo pipefail
cd "$(dirname "$0")/.."

stage_name=""
stage_start=0
timings=""
# Ends the current stage (printing its seconds, from bash's SECONDS) and starts the next.
stage() {
  if [ -n "$stage_name" ]; then
    local took=$((SECONDS - stage_start))
    echo "-- $stage_name: $took s"
    timings+="$(printf '%6d s  %s' "$took" "$stage_name")"$'\n'
  fi
  stage_name=$1
  stage_start=$SECONDS
  if [ -n "$stage_name" ]; then echo "== $stage_name"; fi
}

stage "toolchain"
bash scripts/setup.sh

stage "cargo fmt --check"
cargo fmt --all -- --check

# No import circle between files, and ARCHITECTURE.md's module table is the code's (a second).
stage "import circles and the module table"
python3 scripts/import-cycles.py > /dev/null

stage "clippy (native)"
cargo clippy --all-targets -- -D warnings

stage "clippy (wasm32)"
cargo clippy --target wasm32-unknown-unknown --lib --tests -- -D warnings

# The library's public API (rustdoc, stable) against tests/public-api.txt, and warning-free docs.
stage "public API"
bash scripts/public-api.sh

# This also builds target/debug/paretomesh, the CLI that share.test.mjs compares with.
stage "native tests"
cargo test --all-targets
cargo test --doc

# Every method's front.json on every tests/data grid, byte for byte against tests/fronts.sha256,
# with the debug CLI the native tests just built (small budgets: seconds on 2 cores).
stage "front hashes"
bash scripts/check-fronts.sh

# The wheel from python/ (PyO3, maturin) and its pytest tests, Dask cluster included; they
# compare with the debug CLI built just above.
stage "python package"
bash scripts/test-python.sh

stage "wasm tests (headless Chromium)"
CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUNNER=wasm-bindgen-test-runner \
  cargo test --target wasm32-unknown-unknown --test web

stage "browser app: build"
bash scripts/build-web.sh

stage "browser app: end-to-end tests (headless Chromium)"
node tests/e2e/app.test.mjs
node tests/e2e/import.test.mjs
# The WebGPU path through offscreen readback (Chromium with --enable-unsafe-webgpu; a WebGPU
# canvas stays blank headless), compared with the WebGL2 path.
node tests/e2e/webgpu.test.mjs
# The share-link test compares the browser's front with the CLI's debug build, the one
# `cargo test` built above (the same bits as a release build).
node tests/e2e/share.test.mjs
node tests/e2e/teaching.test.mjs
node tests/e2e/compare.test.mjs
node tests/e2e/export.test.mjs
# The 3D Tiles pyramid (the CLI's debug build): every glb through the Khronos glTF validator,
# then CesiumJS shows it offline.
node tests/e2e/tiles.test.mjs
# Runs in the pool of Web Workers, untiled and in tiles, against the CLI's (tiled) fronts.
node tests/e2e/workers.test.mjs

stage ""
echo "== stage times (total $SECONDS s)"
printf '%s' "$timings"
