// Fronts of two outside simplifiers on one grid, as the mesh lists `paretomesh experiment
// --external` reads: [{"vertices": [grid indices], "triangles": [[a, b, c], ...]}, ...], the
// triangles indexing `vertices` (without them, the experiment triangulates the points). Run by scripts/peer-fronts.sh from a scratch folder that has
// the npm packages `delatin` and `meshoptimizer`.
//   node peer-fronts.mjs GRID.f32 W H OUT_DIR
import fs from 'fs';
import path from 'path';
import Delatin from 'delatin';
import { MeshoptSimplifier } from 'meshoptimizer';

const [file, ws, hs, outDir] = process.argv.slice(2);
const W = Number(ws), H = Number(hs);
const bytes = fs.readFileSync(file);
const z = new Float32Array(bytes.buffer, bytes.byteOffset, W * H);
const fullT = 2 * (W - 1) * (H - 1);
// meshoptimizer's triangle budgets, spaced geometrically from 2 to the full mesh, so every part
// of the front has points.
const targets = [];
for (let k = 0; k < 40; k++) {
  const t = Math.round(2 * Math.pow(fullT / 2, k / 39));
  if (!targets.includes(t)) targets.push(t);
}

// delatin (greedy insertion by max error): the mesh after every refinement, from the two corner
// triangles to the full grid, so its front is as dense as the tool allows.
function delatinFront() {
  const tin = new Delatin(Float64Array.from(z), W, H);
  const meshes = [];
  for (;;) {
    const vertices = [];
    for (let k = 0; k < tin.coords.length; k += 2) vertices.push(tin.coords[k + 1] * W + tin.coords[k]);
    const triangles = [];
    for (let k = 0; k < tin.triangles.length; k += 3) triangles.push([tin.triangles[k], tin.triangles[k + 1], tin.triangles[k + 2]]);
    meshes.push({ vertices, triangles });
    if (tin.getMaxError() <= 0) break;
    tin.refine();
  }
  return meshes;
}

// meshoptimizer: the full grid mesh simplified to each budget, with z scaled by 1, 0.2 and 0.05
// of the grid's width and with or without its border locked (every variant goes in; the front
// keeps the best). Its own triangles fold over or stand on edge in (x, y) on a height field, so
// each mesh lists only its points (plus the four corners), which the experiment scores on their
// Delaunay triangulation.
async function meshoptFront() {
  await MeshoptSimplifier.ready;
  let zmin = Infinity, zmax = -Infinity;
  for (const v of z) { zmin = Math.min(zmin, v); zmax = Math.max(zmax, v); }
  const idx = [];
  for (let y = 0; y + 1 < H; y++) {
    for (let x = 0; x + 1 < W; x++) {
      const a = y * W + x, b = a + 1, c = a + W, d = c + 1;
      idx.push(a, b, d, a, d, c);
    }
  }
  const indices = Uint32Array.from(idx);
  const corners = [0, W - 1, W * (H - 1), W * H - 1];
  const meshes = [];
  for (const scale of [1, 0.2, 0.05]) {
    const pos = new Float32Array(W * H * 3);
    for (let i = 0; i < W * H; i++) {
      pos[3 * i] = i % W;
      pos[3 * i + 1] = Math.floor(i / W);
      pos[3 * i + 2] = zmax > zmin ? ((z[i] - zmin) / (zmax - zmin)) * W * scale : 0;
    }
    for (const flags of [['LockBorder'], []]) {
      for (const t of targets) {
        const [res] = MeshoptSimplifier.simplify(indices, pos, 3, 3 * t, 1e9, flags);
        const vertices = [...new Set([...res, ...corners])].sort((a, b) => a - b);
        meshes.push({ vertices });
      }
    }
  }
  return meshes;
}

fs.mkdirSync(outDir, { recursive: true });
const stem = path.basename(file).replace(/\.f32$/, '');
fs.writeFileSync(path.join(outDir, `${stem}-delatin.json`), JSON.stringify(delatinFront()));
fs.writeFileSync(path.join(outDir, `${stem}-meshoptimizer.json`), JSON.stringify(await meshoptFront()));
console.log(`wrote ${stem}-delatin.json and ${stem}-meshoptimizer.json to ${outDir}`);
