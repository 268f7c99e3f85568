#!/usr/bin/env bash
# The byte-identity guard: runs `paretomesh run` with every method of the catalogue on every
# tests/data grid and compares the sha256 of each front.json (its `millis`, a wall time,
# blanked) with tests/fronts.sha256. A grid that the CLI refuses (tests/data holds a few on
# purpose) is recorded as `refused`, so a change that starts or stops accepting it shows too.
#   bash scripts/check-fronts.sh           # check the working tree against tests/fronts.sha256
#   bash scripts/check-fronts.sh write     # record the working tree's hashes there
# A deliberate change of any front updates tests/fronts.sha256 in the same commit and says why.
# Every tests/data grid is under the default tile size, so each method also runs in tiles of 33
# points (`--tile 33`, lines ending `tile33`) on the .f32 grids over 33 points a side, and one
# small 3D Tiles pyramid (`paretomesh tiles`, a line ending `pyramid`) is pinned by the hashes
# of all its files.
# Budgets are small so the check stays under a minute on 2 cores; each method's budget follows
# its budget kind in `paretomesh algorithms`. PROFILE=release checks the release build instead of
# the debug one (they give the same bits).
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-check}
profile=${PROFILE:-debug}
hashes=tests/fronts.sha256
if [ "$profile" = release ]; then
  cargo build --release --bin paretomesh --quiet
else
  cargo build --bin paretomesh --quiet
fi
bin=${CARGO_TARGET_DIR:-target}/$profile/paretomesh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Each line of `paretomesh algorithms` is a method's name, its budget kind and the error
# measures it supports (sum first). Every grid runs every method in sum, the default; the .f32
# grids also run each method in every other measure it supports (`--error rms|max`).
"$bin" algorithms > "$tmp/algorithms"
jobs="$tmp/jobs"
: > "$jobs"
for grid in tests/data/*.f32 tests/data/*.ply tests/data/*.tif; do
  while read -r algo budget measures; do
    case $budget in
      evaluations) options="--evals 1500" ;;
      generations) options="--pop 20 --gens 10" ;;
      *) options="" ;;
    esac
    echo "$grid $algo - $options" >> "$jobs"
    case $grid in
      *.f32)
        for measure in ${measures//,/ }; do
          [ "$measure" = sum ] || echo "$grid $algo --error=$measure $options --error $measure" >> "$jobs"
        done ;;
    esac
  done < "$tmp/algorithms"
done
for grid in tests/data/*_65x65.f32 tests/data/volcano_87x61.f32; do
  while read -r algo budget _measures; do
    case $budget in
      evaluations) options="--evals 1500" ;;
      generations) options="--pop 20 --gens 10" ;;
      *) options="" ;;
    esac
    echo "$grid $algo tile33 --tile 33 $options" >> "$jobs"
  done < "$tmp/algorithms"
done
# A georeferenced grid (UTM), so the pyramid's placement on the globe is pinned too.
echo "tests/data/jacksboro_65x65_utm16n.tif greedy pyramid" >> "$jobs"

# One job (a line of $jobs: grid, method, label, options): run, blank millis, print
# "HASH  GRID METHOD" (label `-`) or "HASH  GRID METHOD LABEL" (`--error=MEASURE` for a
# measure other than sum, `tile33` for a tiled run). Label `pyramid` hashes the files of
# `paretomesh tiles` on the run's front.json instead.
one() {
  local bin=$1 tmp=$2
  # shellcheck disable=SC2086  # the line's words are the arguments
  set -- $3
  local grid=$1 algo=$2 label=$3
  shift 3
  local name out hash
  name=$(basename "$grid")
  out="$tmp/$name.$algo.$label.json"
  # Untiled front.json files list each member's triangles too; a tiled run refuses that.
  case $label in -|--error=*) set -- --triangles "$@" ;; esac
  if "$bin" run "$grid" --algo "$algo" --seed 7 "$@" --out "$out" 2>/dev/null; then
    hash=$(sed -E 's/"millis":[0-9]+/"millis":0/' "$out" | sha256sum | cut -d' ' -f1)
    if [ "$label" = pyramid ]; then
      local dir="$tmp/$name.pyramid"
      if "$bin" tiles "$out" --levels 3 --out "$dir" > /dev/null 2>&1; then
        hash=$(cd "$dir" && find . -type f | LC_ALL=C sort | xargs sha256sum | sha256sum | cut -d' ' -f1)
      else
        hash=refused
      fi
      rm -rf "$dir"
    fi
    rm -f "$out"
  else
    hash=refused
  fi
  if [ "$label" = - ]; then
    echo "$hash  $name $algo"
  else
    echo "$hash  $name $algo $label"
  fi
}
export -f one
xargs -P "$(nproc)" -d '\n' -n 1 bash -c 'one "$@"' _ "$bin" "$tmp" < "$jobs" \
  | LC_ALL=C sort -k2 > "$tmp/now"

if [ "$mode" = write ]; then
  cp "$tmp/now" "$hashes"
  echo "wrote $(wc -l < "$hashes") front hashes to $hashes"
  exit 0
fi
if diff <(LC_ALL=C sort -k2 "$hashes") "$tmp/now" > "$tmp/diff"; then
  echo "all $(wc -l < "$tmp/now") fronts equal $hashes"
else
  echo "fronts differ from $hashes (< recorded, > now):"
  cat "$tmp/diff"
  exit 1
fi
