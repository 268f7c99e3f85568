//! A quantized-mesh tileset from a DEM on a scheme grid and the tiled front run on it: each
//! quadtree level under the DEM's root tiles (a block of at most 2 × 2) shows the level's
//! whole-grid mesh chosen from the front ([`crate::pyramid::tiled_levels`]), cut into the
//! level's scheme tiles with border points shared by both sides (`pyramid::borders`),
//! so neighbours meet without cracks. The tiles above the roots, up to the scheme's own roots,
//! are flat placeholders at height 0 (the DEM's tiles are upsampled from them until the
//! DEM's roots load).

use super::bounds::{bounding_sphere, horizon_occlusion_point};
use super::raster::SchemeRaster;
use super::scheme::{Block, Scheme, TileId};
use super::tile_file::{Header, QUANTIZED_MAX, TerrainTile, WaterMask};
use super::tiles3d::{self, Implicit, TileInfo};
use crate::pyramid::borders::with_border_points;
use crate::pyramid::globe::ecef;
use crate::pyramid::quadtree::{Level, Tile};
use crate::pyramid::refine::refine_share_best;
use crate::pyramid::tile_mesh::TileMesh;
use crate::pyramid::tiled_levels;
use crate::tiling::TiledFront;
use rayon::prelude::*;
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// The finest level's default error bound, as a fraction of the z range.
pub const DEFAULT_FINEST: f64 = 0.01;

/// What a quantized-mesh tileset carries besides its meshes.
#[derive(Clone, Copy, Debug)]
pub struct TerrainOptions {
    /// Write the water-mask extension.
    pub water_mask: bool,
    /// The finest level's error bound [default: [`DEFAULT_FINEST`] of the z range, or the
    /// least the front allows when that is larger].
    pub finest_error: Option<f64>,
    /// A triangle budget for the whole tileset, spent over every tile of every level where the
    /// error falls most, down to the finest bound (`pyramid::budget`), in place of the
    /// levels' halving bounds.
    pub max_triangles: Option<u64>,
}

/// One zoom level of the tileset, as layer.json records it.
#[derive(Clone, Debug, PartialEq)]
pub struct TerrainLevel {
    /// The scheme zoom.
    pub zoom: u32,
    /// The bound the level's run tiles meet (none for the flat placeholders).
    pub bound: Option<f64>,
    /// The largest |z − z̃| over the level's tiles' grid points: its geometric error.
    pub error: f64,
    /// Tiles written.
    pub tiles: usize,
    /// Triangles over them.
    pub triangles: usize,
}

/// A tileset in memory: layer.json and every `.terrain` file (gzip), with each level's figures.
pub struct TerrainTileset {
    /// (path relative to the tileset's folder, bytes).
    pub files: Vec<(String, Vec<u8>)>,
    /// Every zoom level, the root's first.
    pub levels: Vec<TerrainLevel>,
}

/// A vertex before quantization.
struct Vertex {
    u: u16,
    v: u16,
    height: f64,
    position: [f64; 3],
    normal: [f64; 3],
}

/// The tile id of quadtree tile `tile` under the roots `block` (quadtree rows count from the
/// north, TMS rows from the south).
pub(crate) fn tile_id(block: Block, tile: &Tile) -> TileId {
    TileId {
        zoom: block.zoom + tile.level,
        x: (block.x0 << tile.level) + tile.x as u64,
        y: ((block.y0 + block.rows) << tile.level) - 1 - tile.y as u64,
    }
}

/// The surface normal at grid point (`col`, `row`) from the grid's neighbours in ECEF: the
/// same for every tile that holds the point, so lighting has no seams at tile borders.
fn grid_normal(r: &SchemeRaster, col: usize, row: usize) -> [f64; 3] {
    let at = |c: usize, rw: usize| {
        let (lon, lat) = r.lon_lat(c, rw);
        ecef(lon.to_radians(), lat.to_radians(), r.hf.z_at(c, rw))
    };
    let (w, e) = (col.saturating_sub(1), (col + 1).min(r.hf.width() - 1));
    let (nn, s) = (row.saturating_sub(1), (row + 1).min(r.hf.height() - 1));
    let (pe, pw, pn, ps) = (at(e, row), at(w, row), at(col, nn), at(col, s));
    let east = [pe[0] - pw[0], pe[1] - pw[1], pe[2] - pw[2]];
    let north = [pn[0] - ps[0], pn[1] - ps[1], pn[2] - ps[2]];
    normalize(cross(east, north))
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

/// The ellipsoid's normal at longitude `lon`, latitude `lat` (degrees).
fn ellipsoid_normal(lon: f64, lat: f64) -> [f64; 3] {
    let (sl, cl) = lon.to_radians().sin_cos();
    let (sp, cp) = lat.to_radians().sin_cos();
    [cp * cl, cp * sl, sp]
}

/// A tile's vertices in ECEF, in the tile's vertex order: positions and unit normals (the glb
/// writes them as floats; the `.terrain` file oct-encodes the normals).
pub(crate) struct Placed {
    pub positions: Vec<[f64; 3]>,
    pub normals: Vec<[f64; 3]>,
}

/// A terrain tile of `vertices` and `triangles` (counter-clockwise in u, v): vertices renumbered
/// in first-use order, heights quantized over the tile's range, the header's bounds computed.
fn terrain_tile(
    scheme: Scheme,
    id: TileId,
    vertices: &[Vertex],
    triangles: &[[u32; 3]],
    water: Option<WaterMask>,
    metadata: Option<String>,
) -> (TerrainTile, Placed) {
    let mut order = vec![u32::MAX; vertices.len()];
    let mut first_use = Vec::with_capacity(vertices.len());
    let renumbered: Vec<[u32; 3]> = triangles
        .iter()
        .map(|t| {
            t.map(|i| {
                if order[i as usize] == u32::MAX {
                    order[i as usize] = first_use.len() as u32;
                    first_use.push(i as usize);
                }
                order[i as usize]
            })
        })
        .collect();
    let used: Vec<&Vertex> = first_use.iter().map(|&i| &vertices[i]).collect();
    let lo = used.iter().map(|v| v.height).fold(f64::INFINITY, f64::min);
    let hi = used
        .iter()
        .map(|v| v.height)
        .fold(f64::NEG_INFINITY, f64::max);
    let quantize = |h: f64| {
        if hi > lo {
            ((h - lo) / (hi - lo) * f64::from(QUANTIZED_MAX)).round() as u16
        } else {
            0
        }
    };
    let positions: Vec<[f64; 3]> = used.iter().map(|v| v.position).collect();
    let [w, s, e, n] = scheme.rectangle(id);
    let (lon, lat) = scheme.to_lon_lat((w + e) / 2.0, (s + n) / 2.0);
    let center = ecef(lon.to_radians(), lat.to_radians(), (lo + hi) / 2.0);
    let (sphere_center, sphere_radius) = bounding_sphere(&positions);
    let horizon_occlusion = horizon_occlusion_point(sphere_center, &positions).unwrap_or(center);
    let mut edges: [Vec<u32>; 4] = Default::default();
    let mut sorted: Vec<u32> = (0..used.len() as u32).collect();
    sorted.sort_by_key(|&i| (used[i as usize].v, used[i as usize].u));
    for &i in &sorted {
        let v = used[i as usize];
        if v.u == 0 {
            edges[0].push(i);
        }
        if v.u == QUANTIZED_MAX {
            edges[2].push(i);
        }
    }
    sorted.sort_by_key(|&i| (used[i as usize].u, used[i as usize].v));
    for &i in &sorted {
        let v = used[i as usize];
        if v.v == 0 {
            edges[1].push(i);
        }
        if v.v == QUANTIZED_MAX {
            edges[3].push(i);
        }
    }
    let tile = TerrainTile {
        header: Header {
            center,
            min_height: lo as f32,
            max_height: hi as f32,
            sphere_center,
            sphere_radius,
            horizon_occlusion,
        },
        u: used.iter().map(|v| v.u).collect(),
        v: used.iter().map(|v| v.v).collect(),
        height: used.iter().map(|v| quantize(v.height)).collect(),
        triangles: renumbered,
        edges,
        normals: Some(
            used.iter()
                .map(|v| super::codec::oct_encode(v.normal))
                .collect(),
        ),
        water,
        metadata,
    };
    let normals = used.iter().map(|v| v.normal).collect();
    (tile, Placed { positions, normals })
}

/// Levels of availability a tile's metadata gives at every [`METADATA_LEVELS`]-th zoom
/// (layer.json's `metadataAvailability`, the way CesiumJS learns availability from tiles);
/// other tiles name their children only.
pub(super) const METADATA_LEVELS: u32 = 10;

/// The metadata extension's JSON for `id`: for each zoom below it (up to [`METADATA_LEVELS`]
/// of them at a zoom that is a multiple of it, else one), the range of its descendants the
/// tileset has; `None` when it has none.
fn metadata(id: TileId, available: &BTreeMap<u32, Vec<[u64; 4]>>) -> Option<String> {
    let depth = if id.zoom.is_multiple_of(METADATA_LEVELS) {
        METADATA_LEVELS
    } else {
        1
    };
    let mut levels = Vec::new();
    for offset in 1..=depth {
        let zoom = id.zoom + offset;
        let (lo_x, lo_y) = (id.x << offset, id.y << offset);
        let (hi_x, hi_y) = (((id.x + 1) << offset) - 1, ((id.y + 1) << offset) - 1);
        let ranges: Vec<Value> = available
            .get(&zoom)
            .into_iter()
            .flatten()
            .filter_map(|&[x0, y0, x1, y1]| {
                let (a, b) = (x0.max(lo_x), y0.max(lo_y));
                let (c, d) = (x1.min(hi_x), y1.min(hi_y));
                (a <= c && b <= d).then(|| json!({"startX": a, "startY": b, "endX": c, "endY": d}))
            })
            .collect();
        if ranges.is_empty() {
            break;
        }
        levels.push(Value::Array(ranges));
    }
    (!levels.is_empty()).then(|| json!({ "available": levels }).to_string())
}

/// The 256 × 256 water mask of `tile` (rows from the north), or one byte when uniform.
fn water_mask(r: &SchemeRaster, tile: &Tile) -> WaterMask {
    let (tw, th) = tile.size();
    let mut grid = Vec::with_capacity(65536);
    for j in 0..256usize {
        let row = tile.rows.0 + (j * (th - 1) + 127) / 255;
        for i in 0..256usize {
            let col = tile.columns.0 + (i * (tw - 1) + 127) / 255;
            grid.push(if r.water[row * r.side() + col] {
                255
            } else {
                0
            });
        }
    }
    if grid.iter().all(|&b| b == grid[0]) {
        WaterMask::Uniform(grid[0])
    } else {
        WaterMask::Grid(grid)
    }
}

/// One DEM tile's terrain tile from its mesh.
fn dem_tile(
    r: &SchemeRaster,
    tile: &Tile,
    mesh: &TileMesh,
    metadata: Option<String>,
    options: TerrainOptions,
) -> (TerrainTile, Placed) {
    let n = r.side();
    let (tw, th) = tile.size();
    let vertices: Vec<Vertex> = mesh
        .vertices
        .iter()
        .map(|&g| {
            let (col, row) = (g as usize % n, g as usize / n);
            let du = (col - tile.columns.0) as f64 / (tw - 1) as f64;
            let dv = (tile.rows.1 - row) as f64 / (th - 1) as f64;
            let (lon, lat) = r.lon_lat(col, row);
            let height = r.hf.z_at(col, row);
            Vertex {
                u: (du * f64::from(QUANTIZED_MAX)).round() as u16,
                v: (dv * f64::from(QUANTIZED_MAX)).round() as u16,
                height,
                position: ecef(lon.to_radians(), lat.to_radians(), height),
                normal: grid_normal(r, col, row),
            }
        })
        .collect();
    // Counter-clockwise in grid (x, y) with y to the south is clockwise in (u, v).
    let triangles: Vec<[u32; 3]> = mesh.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect();
    let id = tile_id(r.block, tile);
    terrain_tile(
        r.scheme,
        id,
        &vertices,
        &triangles,
        options.water_mask.then(|| water_mask(r, tile)),
        metadata,
    )
}

/// A flat tile at height 0 on a `k` × `k` lattice (so that it follows the ellipsoid's curve).
fn flat_tile(
    scheme: Scheme,
    id: TileId,
    metadata: Option<String>,
    water: bool,
) -> (TerrainTile, Placed) {
    let k = 9usize;
    let [w, s, e, n] = scheme.rectangle(id);
    let vertices: Vec<Vertex> = (0..k * k)
        .map(|i| {
            let (a, b) = (
                (i % k) as f64 / (k - 1) as f64,
                (i / k) as f64 / (k - 1) as f64,
            );
            let (lon, lat) = scheme.to_lon_lat(w + a * (e - w), s + b * (n - s));
            Vertex {
                u: (a * f64::from(QUANTIZED_MAX)).round() as u16,
                v: (b * f64::from(QUANTIZED_MAX)).round() as u16,
                height: 0.0,
                position: ecef(lon.to_radians(), lat.to_radians(), 0.0),
                normal: ellipsoid_normal(lon, lat),
            }
        })
        .collect();
    let mut triangles = Vec::new();
    for j in 0..k - 1 {
        for i in 0..k - 1 {
            let a = (j * k + i) as u32;
            let (b, c, d) = (a + 1, a + k as u32, a + k as u32 + 1);
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    terrain_tile(
        scheme,
        id,
        &vertices,
        &triangles,
        water.then_some(WaterMask::Uniform(255)),
        metadata,
    )
}

/// gzip of `bytes`, as a static server hands `.terrain` files out (Content-Encoding: gzip).
fn gzip(bytes: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(bytes).expect("writing to memory");
    encoder.finish().expect("writing to memory")
}

/// The path of a tile's file.
pub(crate) fn tile_path(id: TileId) -> String {
    format!("{}/{}/{}.terrain", id.zoom, id.x, id.y)
}

/// The DEM's quadtree level `depth`, cut on the scheme's tile lines.
fn scheme_level(r: &SchemeRaster, depth: u32) -> Level {
    // A level-`depth` tile spans this many grid cells.
    let cells = r.cells_per_root >> depth;
    let cuts = |tiles: u64| (0..=(tiles << depth) as usize).map(|i| i * cells).collect();
    Level::from_cuts(
        depth,
        r.hf.width(),
        cuts(r.block.columns),
        cuts(r.block.rows),
    )
}

/// One DEM level's meshes: every quadtree tile of `depth` and its mesh over the kept points
/// with border points at `bound`.
pub(crate) fn level_meshes(
    r: &SchemeRaster,
    depth: u32,
    kept: &[u32],
    bound: f64,
) -> Result<(Vec<Tile>, Vec<TileMesh>), String> {
    let level = scheme_level(r, depth);
    let with_borders = with_border_points(&r.hf, &level, kept, bound);
    let shares = level.share_out(&with_borders);
    let tiles = level.tiles();
    let meshes = tiles
        .par_iter()
        .zip(&shares)
        .map(|(tile, share)| refine_share_best(&r.hf, tile, share, bound).map(|(_, mesh)| mesh))
        .collect::<Result<Vec<_>, String>>()?;
    Ok((tiles, meshes))
}

/// The quantized-mesh tileset of `r` from `front` (run on `r.hf`), calling
/// `progress(done, total)` as tiles are made.
pub fn build_terrain(
    r: &SchemeRaster,
    front: &TiledFront,
    options: TerrainOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<TerrainTileset, String> {
    build(r, front, options, progress, Format::QuantizedMesh)
}

/// The same pyramid as [`build_terrain`] as 3D Tiles terrain (`tiles3d`):
/// tileset.json, subtree files and glb tiles with the same normals and water mask. Geographic
/// scheme only, as `Cesium3DTilesTerrainProvider` reads.
pub fn build_3dtiles_terrain(
    r: &SchemeRaster,
    front: &TiledFront,
    options: TerrainOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<TerrainTileset, String> {
    if r.scheme != Scheme::Geographic {
        return Err(
            "3D Tiles terrain is on the geographic scheme only (Cesium3DTilesTerrainProvider reads no other); drop --scheme mercator".into(),
        );
    }
    build(r, front, options, progress, Format::Tiles3d)
}

fn build(
    r: &SchemeRaster,
    front: &TiledFront,
    options: TerrainOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    format: Format,
) -> Result<TerrainTileset, String> {
    let mut rows: Vec<(TileId, Header)> = Vec::new();
    let scheme = r.scheme;
    let depth_count = r.levels as usize;
    let (lo, hi) = r.hf.z_range();
    let finest = options.finest_error.unwrap_or(DEFAULT_FINEST * (hi - lo));
    // Above the DEM's roots, the tiles that the DEM's box touches at each zoom (and both
    // geographic roots) are flat placeholders.
    let [w, s, e, n] = r.scheme.block_rectangle(r.block);
    let inner = 1e-9 * (e - w);
    let dem_box = [w + inner, s + inner, e - inner, n - inner];
    let above: Vec<Block> = (0..r.block.zoom)
        .map(|zoom| scheme.block_at(zoom, dem_box))
        .collect();
    let roots = r.block.columns * r.block.rows;
    let total: usize = (0..depth_count)
        .map(|d| (roots as usize) << (2 * d))
        .sum::<usize>()
        + above
            .iter()
            .map(|b| (b.columns * b.rows) as usize)
            .sum::<usize>()
        + usize::from(scheme == Scheme::Geographic && r.block.zoom == 0 && roots == 1)
        + usize::from(scheme == Scheme::Geographic && r.block.zoom > 0 && above[0].columns == 1);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let tick = |k: usize| {
        let d = done.fetch_add(k, std::sync::atomic::Ordering::Relaxed) + k;
        progress(d, total);
    };
    let mut files = Vec::new();
    let mut levels = Vec::new();
    let max_z = r.hf.z().iter().fold(0.0f64, |m, &z| m.max(z.abs()));
    // Every zoom's tiles, known before any is written: each tile's metadata names its
    // descendants.
    let mut available: BTreeMap<u32, Vec<[u64; 4]>> = BTreeMap::new();
    let mut placeholders = Vec::new();
    for (zoom, block) in above.iter().enumerate() {
        let mut ids = block.tiles();
        if zoom == 0 && scheme == Scheme::Geographic {
            ids = vec![
                TileId {
                    zoom: 0,
                    x: 0,
                    y: 0,
                },
                TileId {
                    zoom: 0,
                    x: 1,
                    y: 0,
                },
            ];
        }
        placeholders.push(ids);
    }
    if r.block.zoom == 0 && scheme == Scheme::Geographic && roots == 1 {
        // The other hemisphere's root, flat.
        placeholders.push(vec![TileId {
            zoom: 0,
            x: 1 - r.block.x0,
            y: 0,
        }]);
    }
    for id in placeholders.iter().flatten() {
        available
            .entry(id.zoom)
            .or_default()
            .push([id.x, id.y, id.x, id.y]);
    }
    for depth in 0..r.levels {
        available.entry(r.block.zoom + depth).or_default().push([
            r.block.x0 << depth,
            r.block.y0 << depth,
            ((r.block.x0 + r.block.columns) << depth) - 1,
            ((r.block.y0 + r.block.rows) << depth) - 1,
        ]);
    }
    for ids in &placeholders {
        for id in ids {
            let (tile, placed) =
                flat_tile(scheme, *id, metadata(*id, &available), options.water_mask);
            let (path, bytes) = encode(format, *id, &tile, &placed);
            rows.push((*id, tile.header));
            files.push((path, bytes));
            tick(1);
        }
        if ids[0].zoom < r.block.zoom {
            levels.push(TerrainLevel {
                zoom: ids[0].zoom,
                bound: None,
                error: max_z,
                tiles: ids.len(),
                triangles: ids.len() * 128,
            });
        }
    }
    let sets = match options.max_triangles {
        None => {
            let chosen = tiled_levels(front, &r.hf, depth_count, Some(finest))?;
            let chosen = chosen.into_iter().map(|l| (l.bound, l.kept)).collect();
            halving_levels(r, front, chosen)?
        }
        Some(budget) => {
            let flat: u64 = levels.iter().map(|l| l.triangles as u64).sum::<u64>()
                + 128
                    * placeholders
                        .iter()
                        .flatten()
                        .filter(|id| id.zoom >= r.block.zoom)
                        .count() as u64;
            let room = budget.checked_sub(flat).ok_or_else(|| {
                format!("--max-triangles {budget} is too few: the flat tiles above the DEM take {flat} triangles")
            })?;
            budget_sets(r, front, finest, room)?
        }
    };
    for (depth, (tiles, meshes, bound)) in sets.into_iter().enumerate() {
        let depth = depth as u32;
        let error = meshes.iter().map(|m| m.e_max).fold(0.0, f64::max);
        let encoded: Vec<(File, (TileId, Header))> = tiles
            .par_iter()
            .zip(&meshes)
            .map(|(tile, mesh)| {
                let id = tile_id(r.block, tile);
                let meta = metadata(id, &available);
                let (tile, placed) = dem_tile(r, tile, mesh, meta, options);
                let file = encode(format, id, &tile, &placed);
                tick(1);
                (file, (id, tile.header))
            })
            .collect();
        for (file, row) in encoded {
            files.push(file);
            rows.push(row);
        }
        let zoom = r.block.zoom + depth;
        levels.push(TerrainLevel {
            zoom,
            bound: Some(bound),
            error,
            tiles: tiles.len(),
            triangles: meshes.iter().map(|m| m.triangles.len()).sum(),
        });
    }
    match format {
        Format::QuantizedMesh => {
            let layer = layer_json(r, &available, &levels, options);
            files.insert(
                0,
                (
                    "layer.json".into(),
                    serde_json::to_vec_pretty(&layer).expect("JSON serialises"),
                ),
            );
        }
        Format::Tiles3d => {
            let info = rows
                .into_iter()
                .map(|(id, h)| {
                    let row = TileInfo {
                        min_height: f64::from(h.min_height),
                        max_height: f64::from(h.max_height),
                        sphere: [
                            h.sphere_center[0],
                            h.sphere_center[1],
                            h.sphere_center[2],
                            h.sphere_radius,
                        ],
                        horizon_occlusion: h.horizon_occlusion,
                    };
                    (Implicit::of(id), row)
                })
                .collect();
            let top_error = levels.first().map_or(0.0, |l| l.error);
            let extras = json!({
                "roots": {"zoom": r.block.zoom, "x": r.block.x0, "y": r.block.y0, "columns": r.block.columns, "rows": r.block.rows},
                "demBounds": r.dem_box,
                "levels": level_notes(&levels),
            });
            let mut head = tiles3d::tileset_files(&info, top_error, extras);
            head.append(&mut files);
            files = head;
        }
    }
    Ok(TerrainTileset { files, levels })
}

/// Each DEM level's tiles, meshes and bound when each level meets its halving bound (`chosen`:
/// each level's bound and whole-grid kept set from `front`), with a tighter bound while it does not beat the level
/// above.
fn halving_levels(
    r: &SchemeRaster,
    front: &TiledFront,
    chosen: Vec<(f64, Vec<u32>)>,
) -> Result<Vec<LevelSet>, String> {
    let mut out = Vec::with_capacity(chosen.len());
    let mut previous_error = f64::INFINITY;
    for (depth, (mut bound, mut kept)) in chosen.into_iter().enumerate() {
        let depth = depth as u32;
        let (mut tiles, mut meshes) = level_meshes(r, depth, &kept, bound)?;
        let mut error = meshes.iter().map(|m| m.e_max).fold(0.0, f64::max);
        for _ in 0..6 {
            if error < previous_error || depth == 0 {
                break;
            }
            bound /= 2.0;
            match crate::pyramid::level_within(front, &r.hf, bound)? {
                Some(tighter) => kept = tighter.kept,
                None => break,
            }
            (tiles, meshes) = level_meshes(r, depth, &kept, bound)?;
            error = meshes.iter().map(|m| m.e_max).fold(0.0, f64::max);
        }
        previous_error = error;
        out.push((tiles, meshes, bound));
    }
    Ok(out)
}

/// Each DEM level's tiles, meshes and geometric error under a budget of `room` triangles, on
/// a ladder of bounds from twice the root's halving bound down to `finest` (`ladder_of`).
fn budget_sets(
    r: &SchemeRaster,
    front: &TiledFront,
    finest: f64,
    room: u64,
) -> Result<Vec<LevelSet>, String> {
    let levels: Vec<Level> = (0..r.levels).map(|depth| scheme_level(r, depth)).collect();
    let ladder = crate::pyramid::ladder_of(front, &r.hf, r.levels as usize, finest)?;
    let map: crate::pyramid::MapTiles = &|n, f| (0..n).into_par_iter().map(f).collect();
    let meshes = crate::pyramid::budget_levels(&r.hf, &levels, &ladder, room, map)?;
    Ok(levels
        .iter()
        .zip(meshes)
        .map(|(level, list)| {
            let meshes: Vec<TileMesh> = list.into_iter().map(|(_, m)| m).collect();
            let error = meshes.iter().map(|m| m.e_max).fold(0.0, f64::max);
            (level.tiles(), meshes, error)
        })
        .collect())
}

/// A DEM level's tiles, their meshes, and its bound.
type LevelSet = (Vec<Tile>, Vec<TileMesh>, f64);

/// A file of the tileset: its path in the folder and its bytes.
type File = (String, Vec<u8>);

/// The two tileset formats of one pyramid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    QuantizedMesh,
    Tiles3d,
}

/// A tile's file: a gzip `.terrain`, or a glb about its bounding sphere's centre with the same
/// normals (as floats) and water mask (as a PNG property texture).
fn encode(format: Format, id: TileId, tile: &TerrainTile, placed: &Placed) -> (String, Vec<u8>) {
    match format {
        Format::QuantizedMesh => (tile_path(id), gzip(&tile.encode())),
        Format::Tiles3d => (
            tiles3d::glb_path(id),
            tiles3d::glb(
                tile.header.sphere_center,
                &tiles3d::GlbMesh {
                    positions: &placed.positions,
                    normals: &placed.normals,
                    triangles: &tile.triangles,
                    edges: &tile.edges,
                    water: tile.water.as_ref(),
                },
            ),
        ),
    }
}

/// Each level's figures, as the tileset's notes give them.
fn level_notes(levels: &[TerrainLevel]) -> Vec<Value> {
    levels
        .iter()
        .map(|l| {
            json!({"zoom": l.zoom, "geometricError": l.error, "bound": l.bound, "tiles": l.tiles, "triangles": l.triangles})
        })
        .collect()
}

/// layer.json: the TileJSON CesiumTerrainProvider reads, with every level's available ranges
/// and, under `paretomesh`, each level's geometric error.
fn layer_json(
    r: &SchemeRaster,
    available: &BTreeMap<u32, Vec<[u64; 4]>>,
    levels: &[TerrainLevel],
    options: TerrainOptions,
) -> Value {
    let max_zoom = available.keys().copied().max().unwrap_or(0);
    let ranges: Vec<Value> = (0..=max_zoom)
        .map(|z| {
            Value::Array(
                available
                    .get(&z)
                    .map(|list| {
                        list.iter()
                            .map(|[x0, y0, x1, y1]| {
                                json!({"startX": x0, "startY": y0, "endX": x1, "endY": y1})
                            })
                            .collect()
                    })
                    .unwrap_or_default(),
            )
        })
        .collect();
    let mut extensions = vec!["octvertexnormals", "metadata"];
    if options.water_mask {
        extensions.push("watermask");
    }
    let level_notes = level_notes(levels);
    json!({
        "tilejson": "2.1.0",
        "name": "ParetoMesh terrain",
        "version": "1.0.0",
        "format": "quantized-mesh-1.0",
        "scheme": "tms",
        "tiles": ["{z}/{x}/{y}.terrain"],
        "projection": r.scheme.projection(),
        "bounds": [-180.0, -90.0, 180.0, 90.0],
        "minzoom": 0,
        "maxzoom": max_zoom,
        "available": ranges,
        "metadataAvailability": METADATA_LEVELS,
        "extensions": extensions,
        "paretomesh": {
            "roots": {"zoom": r.block.zoom, "x": r.block.x0, "y": r.block.y0, "columns": r.block.columns, "rows": r.block.rows},
            "demBounds": r.dem_box,
            "levels": level_notes,
        },
    })
}
