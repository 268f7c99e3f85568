"""ParetoMesh against hmm (fogleman's greedy insertion, PyPI `pydelatin`), side by side.

Run by scripts/bench-vs-hmm.sh inside a scratch virtualenv that has pydelatin and numpy (neither
is a dependency of the project). hmm's triangles are scored by the project's evaluator
(`paretomesh eval --triangles`), after mapping hmm's rows: its vertex (x, y) holds
z[H-1-y, x], so it is grid point (x, H-1-y). The run fails unless every hmm mesh's evaluator
E_max equals `Delatin.error`, hmm's own largest error, to f32 rounding (hmm interpolates in f32:
a difference of at most 8·2⁻²⁴·max|z|), which checks the mapping.

ParetoMesh's side is a front.json (`--front`): at each hmm mesh, the member with the most
triangles within hmm's T (E_sum, E_max, RMS and T ratios: ours / hmm's; each member re-scored
by `paretomesh export` + `eval --triangles`), and the member with the fewest triangles whose
E_max is within hmm's (its T ratio). `--greedy` adds one mesh at a max error: `paretomesh run
--algo greedy --max-vertical-error E` (untiled) at each hmm mesh's E_max, timed against hmm
at the same max error.
"""

import argparse
import re
import resource
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from pydelatin import Delatin


def load_grid(path):
    """The grid of a raw .f32 and its JSON sidecar, rows as the project indexes them."""
    if not path.endswith(".f32"):
        sys.exit(f"{path}: give a raw .f32 grid with its .json sidecar (scripts/terrain.py --out)")
    meta = json.load(open(path[:-4] + ".json"))
    w, h = meta["width"], meta["height"]
    return np.fromfile(path, dtype="<f4").reshape(h, w)


def hmm_mesh(z, **limit):
    """hmm's mesh as grid-index triangles (counter-clockwise in grid coordinates), its own
    error, and the wall and CPU seconds the Delatin call took."""
    h, w = z.shape
    start, cpu = time.perf_counter(), time.process_time()
    tin = Delatin(z, height=h, width=w, **limit)
    seconds = (time.perf_counter() - start, time.process_time() - cpu)
    v = tin.vertices
    index = ((h - 1 - v[:, 1].astype(np.int64)) * w + v[:, 0].astype(np.int64)).astype(np.int64)
    tris = index[tin.triangles.astype(np.int64)]
    # Flipping y reverses every triangle's turn; swap two corners to keep them counter-clockwise.
    tris = tris[:, [0, 2, 1]]
    return tris, float(tin.error), seconds


def evaluate_triangles(binary, grid, tris, scratch):
    path = os.path.join(scratch, "triangles.json")
    with open(path, "w") as f:
        json.dump(tris.tolist(), f)
    out = subprocess.run([binary, "eval", grid, "--triangles", path], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def members(front_path):
    """(index, T, E_sum, E_max) of every member of a front.json, untiled or tiled."""
    data = json.load(open(front_path))
    listed = data["front"] if "front" in data else data["tiled"]["members"]
    out = []
    for k, m in enumerate(listed):
        get = lambda *names: next(m[n] for n in names if n in m)
        out.append((k, int(get("T", "t")), float(get("E_sum", "e_sum")), float(get("E_max", "e_max"))))
    return out


def rescore_member(binary, front, k, z, scratch):
    """Score of member k by the evaluator: its mesh written by `export`, its vertices mapped
    back to grid points (the corners are always kept and fix the map), then `eval`."""
    h, w = z.shape
    obj = os.path.join(scratch, "member.obj")
    subprocess.run([binary, "export", front, "--member", str(k), "--out", obj], check=True,
                   capture_output=True)
    xyz, faces = [], []
    with open(obj) as f:
        for line in f:
            if line.startswith("v "):
                xyz.append([float(t) for t in line.split()[1:4]])
            elif line.startswith("f "):
                faces.append([int(t.split("/")[0]) - 1 for t in line.split()[1:4]])
    xyz = np.array(xyz)
    x0, x1 = xyz[:, 0].min(), xyz[:, 0].max()
    y0, y1 = xyz[:, 1].min(), xyz[:, 1].max()
    col = np.rint((xyz[:, 0] - x0) / (x1 - x0) * (w - 1)).astype(np.int64)
    row = np.rint((xyz[:, 1] - y0) / (y1 - y0) * (h - 1)).astype(np.int64)
    # Map y may run with the rows or against them: the heights tell which.
    if not np.allclose(z[row, col], xyz[:, 2], rtol=1e-6, atol=1e-6):
        row = h - 1 - row
        faces = [[a, c, b] for a, b, c in faces]
    if not np.allclose(z[row, col], xyz[:, 2], rtol=1e-6, atol=1e-6):
        sys.exit(f"member {k} of {front}: its exported vertices do not lie on the grid")
    index = row * w + col
    return np.array(faces, dtype=np.int64).reshape(-1, 3), index


def ratio(a, b):
    return a / b if b else float("inf") if a else 1.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    ap.add_argument("--grid", required=True)
    ap.add_argument("--front")
    ap.add_argument("--budgets", default="0.1,0.5,1,2,5,10,20",
                    help="triangle budgets, %% of the full mesh 2(W-1)(H-1)")
    ap.add_argument("--max-errors", default="", help="max errors for hmm, in z units")
    ap.add_argument("--greedy", action="store_true")
    ap.add_argument("--greedy-tile", type=int, default=0,
                    help="tile size of the --greedy run (default: untiled)")
    ap.add_argument("--threads", type=int, default=0,
                    help="threads of a tiled --greedy run (default: every core)")
    a = ap.parse_args()
    z = load_grid(a.grid)
    h, w = z.shape
    full = 2 * (w - 1) * (h - 1)
    tolerance = 8 * 2.0**-24 * float(np.abs(z).max())
    ours = members(a.front) if a.front else []
    scratch = tempfile.mkdtemp(prefix="bench-vs-hmm-")
    runs = []
    for f in [float(s) for s in a.budgets.split(",") if s]:
        runs.append((f"T {f:g} %", dict(max_triangles=max(2, round(f / 100 * full)))))
    for e in [float(s) for s in a.max_errors.split(",") if s]:
        runs.append((f"E_max {e:g}", dict(max_error=e)))
    print(f"grid {a.grid}: {w}x{h}, full mesh {full} triangles; front {a.front or '-'}")
    print("hmm: pydelatin; its meshes scored by `paretomesh eval --triangles`; ratios are ours / hmm's")
    header = (f"{'hmm run':<13} {'hmm T':>10} {'hmm E_sum':>12} {'hmm E_max':>10} {'hmm RMS':>9} {'hmm s':>7}"
              + (f" | {'T':>6} {'E_sum':>6} {'E_max':>6} {'RMS':>6} | {'T at E_max':>10}" if ours else "")
              + (f" | {'greedy T':>9} {'run s':>6} {'cmd s':>6} {'cmd cpu':>7}" if a.greedy else ""))
    print(header)
    failed = False
    for name, limit in runs:
        tris, error, seconds = hmm_mesh(z, **limit)
        score = evaluate_triangles(a.bin, a.grid, tris, scratch)
        line = (f"{name:<13} {score['T']:>10} {score['E_sum']:>12.6g} {score['E_max']:>10.6g} "
                f"{score['rms']:>9.4g} {seconds[0]:>7.2f}")
        # hmm interpolates in f32, so its error is the evaluator's to a few f32 roundings of the
        # heights; unmapped rows miss by orders of magnitude more.
        if abs(score["E_max"] - error) > tolerance:
            failed = True
            line += f"  FAIL: evaluator E_max {score['E_max']!r} != Delatin.error {error!r}"
        if ours:
            within = [m for m in ours if m[1] <= score["T"]]
            k, t, e_sum, e_max = max(within, key=lambda m: m[1])
            faces, index = rescore_member(a.bin, a.front, k, z, scratch)
            mine = evaluate_triangles(a.bin, a.grid, index[faces], scratch)
            if mine["T"] != t or abs(mine["E_sum"] - e_sum) > 1e-9 * max(e_sum, 1.0):
                sys.exit(f"member {k}: re-scored T {mine['T']}, E_sum {mine['E_sum']}; "
                         f"front.json records T {t}, E_sum {e_sum}")
            meets = [m for m in ours if m[3] <= score["E_max"]]
            fewest = f"{ratio(min(m[1] for m in meets), score['T']):>10.3f}" if meets else f"{'none':>10}"
            line += (f" | {ratio(t, score['T']):>6.3f} {ratio(e_sum, score['E_sum']):>6.3f} "
                     f"{ratio(e_max, score['E_max']):>6.3f} {ratio(mine['rms'], score['rms']):>6.3f} | {fewest}")
        if a.greedy:
            bound = score["E_max"]
            if "max_error" in limit:
                hmm_t, hmm_seconds = score["T"], seconds
            else:
                again, _, hmm_seconds = hmm_mesh(z, max_error=bound)
                hmm_t = len(again)
            out = os.path.join(scratch, "greedy.json")
            start = time.perf_counter()
            cpu = resource.getrusage(resource.RUSAGE_CHILDREN)
            command = [a.bin, "run", a.grid, "--algo", "greedy", "--max-vertical-error",
                       repr(bound), "--tile", str(a.greedy_tile or max(w, h)), "--out", out]
            if a.threads:
                command += ["--threads", str(a.threads)]
            log = subprocess.run(command, check=True, capture_output=True, text=True)
            whole = time.perf_counter() - start
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            whole_cpu = (after.ru_utime + after.ru_stime) - (cpu.ru_utime + cpu.ru_stime)
            done = re.search(r"^done: .* in (\d+) ms", log.stdout + log.stderr, re.M)
            took = int(done.group(1)) / 1000 if done else whole
            g = [m for m in members(out) if m[3] <= bound]
            k, t, _, _ = min(g, key=lambda m: m[1])
            faces, index = rescore_member(a.bin, out, k, z, scratch)
            again = evaluate_triangles(a.bin, a.grid, index[faces], scratch)
            if again["T"] != t or again["E_max"] > bound:
                sys.exit(f"greedy at {bound!r}: member {k} scores T {again['T']}, E_max "
                         f"{again['E_max']!r} afresh; front.json records T {t}")
            line += (f" | {ratio(min(m[1] for m in g), hmm_t):>9.3f} {ratio(took, hmm_seconds[0]):>6.3f}"
                     f" {ratio(whole, hmm_seconds[0]):>6.3f} {ratio(whole_cpu, hmm_seconds[1]):>6.3f}")
        print(line, flush=True)
    load = open("/proc/loadavg").read().split()[:3] if os.path.exists("/proc/loadavg") else []
    if a.greedy:
        where = (f"over tiles of {a.greedy_tile} points a side on {a.threads or 'all'} threads"
                 if a.greedy_tile else "untiled")
        print(f"greedy: `run --algo greedy --max-vertical-error E` {where} at hmm's E_max, against hmm "
              "at max_error=E: T ratio; wall time of the run (its `done:` line) and of the whole "
              "command (reading the grid, writing front.json) over hmm's Delatin call; the "
              "command's CPU seconds (user + system) over the call's")
    print("load average: " + " ".join(load))
    if failed:
        sys.exit("hmm's E_max by the evaluator differs from Delatin.error beyond f32 rounding: the row mapping is wrong")


if __name__ == "__main__":
    main()
