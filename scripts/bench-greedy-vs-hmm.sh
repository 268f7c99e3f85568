#!/usr/bin/env bash
# Greedy insertion against hmm (fogleman's C++ greedy insertion, PyPI `pydelatin`), side by side:
# both on the same fractal terrains, both stopping once the largest vertical error is at most
# 1 % of the z range, both single-threaded and on the whole grid (ours untiled: `--tile` is the
# grid's side). hmm runs in a virtualenv in a scratch folder outside
# the project ($BENCH_DIR, default /tmp/paretomesh-greedy-bench), which also holds the grids.
#   bash scripts/bench-greedy-vs-hmm.sh [SIZE...]     # default sizes: 1025 2048 3601
#   REPEATS=5 bash scripts/bench-greedy-vs-hmm.sh 2048
# Each size runs REPEATS times (default 3), alternating the two, and prints each tool's fastest
# wall time (ours: the `done:` line of `paretomesh run`, which leaves out reading the grid and
# writing front.json; hmm: the `Delatin(...)` call) and the CPU seconds of that run (ours: the
# whole command, reading and writing included; hmm: the call).
set -euo pipefail
cd "$(dirname "$0")/.."
bench=${BENCH_DIR:-/tmp/paretomesh-greedy-bench}
repeats=${REPEATS:-3}
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(1025 2048 3601)
mkdir -p "$bench"
if [ ! -x "$bench/venv/bin/python" ]; then
  python3 -m venv "$bench/venv"
fi
if ! "$bench/venv/bin/python" -c 'import pydelatin, numpy' 2>/dev/null; then
  "$bench/venv/bin/pip" install --quiet pydelatin numpy
fi
py="$bench/venv/bin/python"
cargo build --release --bin paretomesh --quiet
bin=${CARGO_TARGET_DIR:-target}/release/paretomesh

# hmm on one grid: prints "wall_seconds cpu_seconds triangles".
cat > "$bench/hmm.py" <<'EOF'
import json, sys, time
import numpy as np
from pydelatin import Delatin
base, fraction = sys.argv[1], float(sys.argv[2])
meta = json.load(open(base + '.json'))
w, h = meta['width'], meta['height']
z = np.fromfile(base + '.f32', dtype='<f4').reshape(h, w)
max_error = fraction * float(z.max() - z.min())
cpu, wall = time.process_time(), time.perf_counter()
mesh = Delatin(z, height=h, width=w, max_error=max_error)
wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
print(f"{wall:.3f} {cpu:.3f} {len(mesh.triangles)}")
EOF

# Is the first "wall cpu triangles" line faster than the second?
faster() { awk -v a="$1" -v b="$2" 'BEGIN { split(a, x, " "); split(b, y, " "); exit !(x[1] < y[1]) }'; }

printf '%-11s %-6s %10s %10s %11s\n' grid tool "wall s" "cpu s" triangles
for n in "${sizes[@]}"; do
  grid="$bench/fractal_${n}x${n}"
  # The spectral fractal of scripts/terrain.py, beta 2.9, heights 0..1000, seeded by the size.
  [ -f "$grid.f32" ] || "$py" scripts/terrain.py spectral --size "$n" --beta 2.9 --seed "$n" --out "$grid.f32"
  best_ours="" best_hmm="" refused=""
  for _ in $(seq "$repeats"); do
    if [ -z "$refused" ]; then
      if log=$( { /usr/bin/time -f 'cpu %U %S' "$bin" run "$grid.f32" --algo greedy \
        --max-error-fraction 0.01 --tile "$n" --out "$bench/front.json"; } 2>&1 ); then
        ms=$(echo "$log" | sed -nE 's/^done: .* in ([0-9]+) ms.*/\1/p')
        cpu=$(echo "$log" | awk '/^cpu /{printf "%.2f", $2 + $3}')
        tris=$("$py" -c "import json,sys; print(max(m['T'] for m in json.load(open(sys.argv[1]))['front']))" "$bench/front.json")
        line="$(awk -v ms="$ms" 'BEGIN{printf "%.3f", ms / 1000}') $cpu $tris"
        if [ -z "$best_ours" ] || faster "$line" "$best_ours"; then best_ours=$line; fi
      else
        refused=$(echo "$log" | grep -v '^cpu ' | tail -n 1)
      fi
    fi
    line=$("$py" "$bench/hmm.py" "$grid" 0.01)
    if [ -z "$best_hmm" ] || faster "$line" "$best_hmm"; then best_hmm=$line; fi
  done
  [ -n "$refused" ] && printf '%-11s %-6s refused: %s\n' "${n}x${n}" ours "$refused"
  [ -n "$best_ours" ] && printf '%-11s %-6s %10s %10s %11s\n' "${n}x${n}" ours $best_ours
  [ -n "$best_hmm" ] && printf '%-11s %-6s %10s %10s %11s\n' "${n}x${n}" hmm $best_hmm
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
