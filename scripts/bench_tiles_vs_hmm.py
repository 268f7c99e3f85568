"""A `paretomesh tiles` 3D Tiles pyramid against hmm (pydelatin) run tile by tile.

Run by scripts/bench-tiles-vs-hmm.sh inside a scratch virtualenv with pydelatin and numpy
(neither a project dependency). The pyramid is made on the grid's own lattice (`--format
3dtiles`), so level L's tiles are the grid windows between the lines ⌊i·(N − 1)/2^L⌋ of each
axis (src/pyramid/quadtree.rs), neighbours sharing their border line. Each level's triangles
and geometric error (the largest tile E_max) are read from the CLI's report. hmm meshes each
tile's window on its own with that error as its max error; hmm's rows run bottom-up (its vertex
(x, y) holds z[H−1−y, x]), which does not change its triangle count. The ratio is ours ÷ hmm's
per level: below 1, the pyramid spends fewer triangles for the same geometric error.
"""

import argparse
import json
import re
import subprocess
import sys
import tempfile
import time

import numpy as np
from pydelatin import Delatin


def cuts(points, tiles):
    return [i * (points - 1) // tiles for i in range(tiles + 1)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    ap.add_argument("--grid", required=True)
    ap.add_argument("tiles_args", nargs="*")
    a = ap.parse_args()
    meta = json.load(open(a.grid[:-4] + ".json"))
    w, h = meta["width"], meta["height"]
    z = np.fromfile(a.grid, dtype="<f4").reshape(h, w).astype(np.float64)
    with tempfile.TemporaryDirectory() as scratch:
        cmd = [a.bin, "tiles", a.grid, "--format", "3dtiles", "--out", f"{scratch}/t"] + a.tiles_args
        print("$", " ".join(cmd[:1] + ["tiles", a.grid] + cmd[3:5] + a.tiles_args), file=sys.stderr)
        start = time.perf_counter()
        out = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
        print(f"pyramid: {time.perf_counter() - start:.1f} s wall", file=sys.stderr)
    levels = []
    for line in out.splitlines():
        m = re.match(r"level (\d+): .*?(\d+) tiles, (\d+) triangles, tile E_max up to ([0-9.e+-]+)", line)
        if m:
            levels.append((int(m[1]), int(m[2]), int(m[3]), float(m[4])))
    if not levels:
        sys.exit("no level lines in the CLI's report:\n" + out)
    print("| level | tiles | geometric error | ParetoMesh triangles | hmm triangles (per tile) | ratio |")
    print("|---|---|---|---|---|---|")
    worst = 0.0
    for level, tiles, ours, error in levels:
        side = 1 << level
        xs, ys = cuts(w, side), cuts(h, side)
        theirs = 0
        for ty in range(side):
            for tx in range(side):
                window = np.ascontiguousarray(z[ys[ty]:ys[ty + 1] + 1, xs[tx]:xs[tx + 1] + 1])
                th, tw = window.shape
                tin = Delatin(window, height=th, width=tw, max_error=error)
                theirs += len(tin.triangles)
        ratio = ours / theirs
        worst = max(worst, ratio)
        print(f"| {level} | {tiles} | {error:.4g} | {ours} | {theirs} | {ratio:.3f} |")
    print(f"largest ratio: {worst:.3f}")


if __name__ == "__main__":
    main()
