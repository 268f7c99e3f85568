#!/usr/bin/env bash
# Proves that a change leaves every algorithm's output alone: runs `paretomesh run` with each
# algorithm on every tests/data grid and compares front.json byte for byte (the `millis` field,
# a wall time, is blanked first).
#   bash scripts/check-fronts.sh write DIR    # record the fronts of the working tree in DIR
#   bash scripts/check-fronts.sh check DIR    # compare the working tree's fronts with DIR
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:?write or check}
dir=${2:?a folder for the fronts}
mkdir -p "$dir"
cargo build --release --bin paretomesh --quiet
bin=${CARGO_TARGET_DIR:-target}/release/paretomesh
tmp=$(mktemp -d)
status=0
for grid in tests/data/*.f32 tests/data/*.ply; do
  name=$(basename "$grid")
  for algo in nsga2 weighted greedy decimation; do
    out="$tmp/$name.$algo.json"
    "$bin" run "$grid" --algo "$algo" --seed 7 --triangles --out "$out" 2>/dev/null
    sed -E 's/"millis":[0-9]+/"millis":0/' "$out" > "$out.norm"
    if [ "$mode" = write ]; then
      cp "$out.norm" "$dir/$name.$algo.json"
    elif cmp -s "$out.norm" "$dir/$name.$algo.json"; then
      echo "same     $name $algo"
    else
      echo "DIFFERS  $name $algo"; status=1
    fi
  done
done
rm -rf "$tmp"
[ "$mode" = write ] && echo "wrote $(ls "$dir" | wc -l) fronts to $dir"
exit $status
