#!/usr/bin/env bash
# Writes the fronts of npm `delatin` and `meshoptimizer` on raw f32 grids (with their JSON
# sidecars) as mesh lists for `paretomesh experiment --external`. The npm packages are installed
# in a scratch folder outside the project ($PEERS_DIR, default /tmp/paretomesh-peers).
#   bash scripts/peer-fronts.sh OUT_DIR GRID.f32...
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=$(realpath -m "${1:?an output folder}")
shift
peers=${PEERS_DIR:-/tmp/paretomesh-peers}
mkdir -p "$peers"
if [ ! -d "$peers/node_modules/delatin" ] || [ ! -d "$peers/node_modules/meshoptimizer" ]; then
  (cd "$peers" && npm init -y >/dev/null && npm install --no-audit --no-fund delatin@0.2.0 meshoptimizer >/dev/null)
fi
cp "$here/peer-fronts.mjs" "$peers/"
for grid in "$@"; do
  sidecar="${grid%.f32}.json"
  read -r w h < <(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['width'], d['height'])" "$sidecar")
  file=$(realpath "$grid")
  (cd "$peers" && node peer-fronts.mjs "$file" "$w" "$h" "$out")
done
