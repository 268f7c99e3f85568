#!/usr/bin/env bash
# The README's first command: installs missing tools, builds the browser app, and serves it.
# PORT=8123 bash scripts/serve.sh picks another port.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build-web.sh
port=${PORT:-8080}
echo "ParetoMesh: open http://127.0.0.1:$port/ (Ctrl-C stops the server)"
exec python3 -m http.server --bind 127.0.0.1 "$port"
