#!/usr/bin/env bash
# Builds the browser app into www/pkg/: the library for wasm32 (profile `wasm-release`, see
# Cargo.toml), wasm-bindgen's ES-module glue, then wasm-opt -Oz from npm's binaryen.
# Prints the build time and the optimised .wasm size (raw and gzip).
set -euo pipefail
cd "$(dirname "$0")/.."

start=$(date +%s)
cargo build --profile wasm-release --target wasm32-unknown-unknown --lib
wasm-bindgen --target web --no-typescript --out-dir www/pkg \
  target/wasm32-unknown-unknown/wasm-release/paretomesh.wasm
node_modules/.bin/wasm-opt -Oz --enable-bulk-memory --enable-nontrapping-float-to-int \
  --enable-sign-ext --enable-mutable-globals --enable-reference-types \
  www/pkg/paretomesh_bg.wasm -o www/pkg/paretomesh_bg.wasm
raw=$(stat -c %s www/pkg/paretomesh_bg.wasm)
gz=$(gzip -9 -c www/pkg/paretomesh_bg.wasm | wc -c)
echo "built www/pkg in $(( $(date +%s) - start )) s; paretomesh_bg.wasm: $raw bytes raw, $gz bytes gzip"
