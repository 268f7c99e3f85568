"""The Python call's time against the CLI's on the same grid, seed and budget.

    python python/benches/python_vs_cli.py PARETOMESH_CLI [SIDE] [EVALS] [REPEATS]

A SIDE² spectral fractal terrain (default 2048; `scripts/terrain.py`, seed 1) written as a raw
f32 grid; `paretomesh run` on it and `paretomesh.simplify` on the same heights, untiled,
memetic, seed 1, alternately REPEATS times (default 3). Prints each wall time, the runs' own millis, and whether the fronts are equal.
"""

import json
import pathlib
import subprocess
import sys
import tempfile
import time

import paretomesh

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))
from terrain import spectral, write_f32  # noqa: E402  (the project's generator, scripts/terrain.py)


def main() -> None:
    cli = sys.argv[1]
    side = int(sys.argv[2]) if len(sys.argv) > 2 else 2048
    evals = int(sys.argv[3]) if len(sys.argv) > 3 else 20000
    repeats = int(sys.argv[4]) if len(sys.argv) > 4 else 3
    folder = pathlib.Path(tempfile.mkdtemp())
    z = spectral(side, side)
    grid = folder / f"terrain_{side}.f32"
    write_f32(z, grid)
    # Untiled on both sides: a CLI that tiles is asked for one tile of the whole grid.
    help_text = subprocess.run([cli, "run", "--help"], capture_output=True, text=True).stdout
    one_tile = ["--tile", str(side)] if "--tile" in help_text else []
    cli_times, py_times = [], []
    for _ in range(repeats):
        started = time.perf_counter()
        subprocess.run([cli, "run", str(grid), "--seed", "1", "--evals", str(evals), *one_tile,
                        "--out", str(folder / "cli.json")], check=True, capture_output=True)
        cli_times.append(time.perf_counter() - started)
        started = time.perf_counter()
        front = paretomesh.simplify(z, seed=1, evals=evals, tile=side)
        front.save(folder / "py.json")
        py_times.append(time.perf_counter() - started)
        cli_file = json.loads((folder / "cli.json").read_text())
        print(f"CLI {cli_times[-1]:.2f} s (run {cli_file['millis']} ms), "
              f"Python {py_times[-1]:.2f} s (run {front.millis} ms)", flush=True)
    same = json.loads((folder / "py.json").read_text())["front"] == cli_file["front"]
    best_cli, best_py = min(cli_times), min(py_times)
    print(f"best of {repeats}: CLI {best_cli:.2f} s, Python {best_py:.2f} s, "
          f"Python/CLI {best_py / best_cli:.3f}; equal fronts: {same}")


if __name__ == "__main__":
    main()
