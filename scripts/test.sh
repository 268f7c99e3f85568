#!/usr/bin/env bash
# Runs every test: formatting, clippy (native and wasm32), native tests, the
# wasm-bindgen-test tests in headless Chromium, and the browser app's end-to-end test
# (playwright-core driving /usr/bin/chromium). It first runs `scripts/setup.sh`, which installs
# what is missing (the wasm32 target, wasm-bindgen-cli matching Cargo.lock, chromium and
# chromedriver, the npm tools) and skips what is already there, so it works on a fresh machine.
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== toolchain"
bash scripts/setup.sh

echo "== cargo fmt --check"
cargo fmt --all -- --check

echo "== clippy (native)"
cargo clippy --all-targets -- -D warnings

echo "== clippy (wasm32)"
cargo clippy --target wasm32-unknown-unknown --lib --tests -- -D warnings

echo "== native tests"
cargo test --all-targets
cargo test --doc

echo "== wasm tests (headless Chromium)"
CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUNNER=wasm-bindgen-test-runner \
  cargo test --target wasm32-unknown-unknown --test web

echo "== browser app: build and end-to-end test (headless Chromium)"
bash scripts/build-web.sh
node tests/e2e/app.test.mjs
node tests/e2e/import.test.mjs
# The WebGPU path through offscreen readback (Chromium with --enable-unsafe-webgpu; a WebGPU
# canvas stays blank headless), compared with the WebGL2 path.
node tests/e2e/webgpu.test.mjs
# The share-link test compares the browser's front with the CLI's debug build (the same bits as
# a release build, and cheaper: `cargo test` above built most of it; only the dependencies whose
# features dev-dependencies unify differently are compiled again).
cargo build --bin paretomesh
node tests/e2e/share.test.mjs
node tests/e2e/teaching.test.mjs
node tests/e2e/compare.test.mjs
