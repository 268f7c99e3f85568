#!/usr/bin/env bash
# The byte-identity guard: runs `paretomesh run` with every method of the catalogue on every
# tests/data grid and compares the sha256 of each front.json (its `millis`, a wall time,
# blanked) with tests/fronts.sha256. A grid that the CLI refuses (tests/data holds a few on
# purpose) is recorded as `refused`, so a change that starts or stops accepting it shows too.
#   bash scripts/check-fronts.sh           # check the working tree against tests/fronts.sha256
#   bash scripts/check-fronts.sh write     # record the working tree's hashes there
# A deliberate change of any front updates tests/fronts.sha256 in the same commit and says why.
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
    echo "$grid $algo $options" >> "$jobs"
    case $grid in
      *.f32)
        for measure in ${measures//,/ }; do
          [ "$measure" = sum ] || echo "$grid $algo $options --error $measure" >> "$jobs"
        done ;;
    esac
  done < "$tmp/algorithms"
done

# One job (a line of $jobs: grid, method, options): run, blank millis, print "HASH  GRID METHOD".
one() {
  local bin=$1 tmp=$2
  # shellcheck disable=SC2086  # the line's words are the arguments
  set -- $3
  local grid=$1 algo=$2
  shift 2
  local name out hash label=$algo
  name=$(basename "$grid")
  # A measure other than sum is named after the method: "greedy --error=max".
  case "$*" in *--error*) label="$algo --error=${*: -1}" ;; esac
  out="$tmp/$name.$algo.$$.json"
  if "$bin" run "$grid" --algo "$algo" --seed 7 --triangles "$@" --out "$out" 2>/dev/null; then
    hash=$(sed -E 's/"millis":[0-9]+/"millis":0/' "$out" | sha256sum | cut -d' ' -f1)
    rm -f "$out"
  else
    hash=refused
  fi
  echo "$hash  $name $label"
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
