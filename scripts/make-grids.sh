#!/usr/bin/env bash
# Makes the generated grids that docs/performance.md and the benchmarks name, from seeds, so
# that a clone reproduces every figure: fbm fractal terrains (scripts/terrain.py) at 257²,
# 1025², 2048² (raw .f32 with .json sidecars) and 3601² (a float32 GeoTIFF in 16-row strips,
# uncompressed, as the figures measured it). `--big` adds 10 801² (466 MB as .f32). Existing
# files are kept. Needs numpy: the project's .venv-python (scripts/setup.sh) when present.
#
#   bash scripts/make-grids.sh [DIR] [--big]     # DIR defaults to out/grids
set -euo pipefail
cd "$(dirname "$0")/.."
dir=out/grids
big=0
for arg in "$@"; do
  case "$arg" in
    --big) big=1 ;;
    *) dir="$arg" ;;
  esac
done
mkdir -p "$dir"
python=python3
[ -x .venv-python/bin/python ] && python=.venv-python/bin/python
make() { # NAME ARGS...: runs the generator unless DIR/NAME exists
  local name=$1
  shift
  if [ -e "$dir/$name" ]; then
    echo "kept $dir/$name"
  else
    "$python" scripts/terrain.py fbm --seed 1 "$@"
    echo "made $dir/$name"
  fi
}
make fractal_257.f32 --size 257 --out "$dir/fractal_257.f32"
make fractal_1025.f32 --size 1025 --out "$dir/fractal_1025.f32"
make fractal_2048.f32 --size 2048 --out "$dir/fractal_2048.f32"
make fractal_3601.tif --size 3601 --tif "$dir/fractal_3601.tif" --layout strips --compression none
if [ "$big" = 1 ]; then
  make fractal_10801.f32 --size 10801 --out "$dir/fractal_10801.f32"
fi
