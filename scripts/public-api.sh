#!/usr/bin/env bash
# Pins the library's public API: every public module, item, variant, field and method, as
# rustdoc (stable) documents them for `cargo doc --no-deps --lib`, must match
# tests/public-api.txt. A change to the API is deliberate: update the list in the same commit
# with `bash scripts/public-api.sh write` and say why. The same run fails on any rustdoc
# warning (a link into a private item, say), so the docs stay warning-free.
#   bash scripts/public-api.sh          # check
#   bash scripts/public-api.sh write    # record the working tree's API
set -euo pipefail
cd "$(dirname "$0")/.."

pinned=tests/public-api.txt
RUSTDOCFLAGS="${RUSTDOCFLAGS:-} -D warnings" cargo doc --quiet --no-deps --lib
now=$(mktemp)
trap 'rm -f "$now"' EXIT
python3 scripts/public_api.py target/doc/paretomesh > "$now"

if [ "${1:-check}" = write ]; then
  cp "$now" "$pinned"
  echo "public API: wrote $(wc -l < "$pinned") lines to $pinned"
  exit 0
fi
if ! diff -u "$pinned" "$now"; then
  echo "public API: the lines above differ from $pinned (- pinned, + now)." >&2
  echo "If the change is deliberate, run: bash scripts/public-api.sh write" >&2
  exit 1
fi
echo "public API: $(wc -l < "$pinned") lines as pinned"
