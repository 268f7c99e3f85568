//! `paretomesh tiles INPUT --out DIR`: a terrain tileset for web globes from a front.json
//! (untiled or tiled) or straight from a DEM (run tile by tile with the default method).
//! `--format 3dtiles` (the default) writes a 3D Tiles 1.1 pyramid (tileset.json and one .glb
//! per tile); `--format quantized-mesh` writes CesiumTerrainProvider's quantized-mesh-1.0
//! tiles and layer.json on the geographic or Web Mercator TMS scheme; `--format
//! 3dtiles-terrain` the same pyramid as 3D Tiles terrain (Cesium3DTilesTerrainProvider's
//! implicit tiling on the geographic scheme). The tileset is written
//! into a temporary folder beside DIR and renamed to DIR when complete.

use super::front_reader::{self, AnyFront, find_grid};
use super::input::ImportArgs;
use super::progress::Progress;
use clap::{Args, ValueEnum};
use paretomesh::catalogue::{Algorithm, Param, Params};
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use paretomesh::import::GridWindows;
use paretomesh::pyramid::{
    DEFAULT_LEVELS, LevelWork, MapTiles, Pyramid, build_budget, build_refined, build_with,
    default_levels, most_levels, plan, tiled_levels,
};
use paretomesh::terrain::{
    DEFAULT_FINEST, RasterOptions, Scheme, TerrainOptions, build_3dtiles_terrain, build_terrain,
    reproject,
};
use paretomesh::tiling::{
    DEFAULT_TILE, TilePlan, TileSource, TiledFront, run_tiled_with_progress, tile_config,
};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The tileset's format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum FormatArg {
    /// 3D Tiles 1.1: tileset.json and binary glTF tiles.
    #[value(name = "3dtiles")]
    ThreeDTiles,
    /// quantized-mesh-1.0 terrain: layer.json and gzip .terrain tiles.
    QuantizedMesh,
    /// 3D Tiles 1.1 as terrain (Cesium3DTilesTerrainProvider): implicit tiling on the
    /// geographic scheme, subtree files with tile metadata, glb tiles.
    #[value(name = "3dtiles-terrain")]
    ThreeDTilesTerrain,
}

/// The quantized-mesh tiling scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum SchemeArg {
    /// EPSG:4326, two root tiles.
    Geographic,
    /// EPSG:3857 Web Mercator, one root tile.
    Mercator,
}

/// What the DEM's heights are measured from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum GeoidArg {
    /// Heights are above the WGS84 ellipsoid already.
    None,
    /// Heights are above the EGM96 geoid: the undulation is added.
    Egm96,
}

/// Options of `paretomesh tiles`.
#[derive(Args, Debug)]
pub(super) struct TilesArgs {
    /// A front.json that `paretomesh run` (or the app) wrote, untiled or tiled, or a DEM (any
    /// grid the CLI reads), which is run tile by tile first.
    input: PathBuf,
    /// The folder to write the tileset into (replaced when the tileset is complete).
    #[arg(long)]
    out: PathBuf,
    /// The tileset format.
    #[arg(long, value_enum, default_value = "3dtiles")]
    format: FormatArg,
    /// The quantized-mesh tiling scheme.
    #[arg(long, value_enum, default_value = "geographic")]
    scheme: SchemeArg,
    /// What the DEM's heights are measured from (quantized-mesh).
    #[arg(long, value_enum, default_value = "none")]
    geoid: GeoidArg,
    /// Write the quantized-mesh water mask: points outside the DEM and flat water.
    #[arg(long)]
    water_mask: bool,
    /// Quadtree levels: for 3D Tiles, level L has 2^L × 2^L tiles [default: 4, or fewer when
    /// the grid or the front has fewer]; for quantized-mesh, the levels under and including
    /// the scheme tile that holds the DEM [default: until the finest tiles' cells are no
    /// larger than the DEM's].
    #[arg(long, value_name = "N")]
    levels: Option<usize>,
    /// The finest level's error bound for a tiled front or a DEM, in z units [default: 1 % of
    /// the z range, or the least the front allows when that is larger]; each level above
    /// doubles it.
    #[arg(long, value_name = "E")]
    max_error: Option<f64>,
    /// A triangle budget for the whole tileset (tiled fronts and DEMs): spent over every tile
    /// of every level where the error falls most, each level's error still falling with
    /// depth, down to the finest bound (--max-error), in place of the halving bounds.
    #[arg(long, value_name = "N")]
    max_triangles: Option<u64>,
    /// The grid a front was made on [default: the file named in front.json].
    #[arg(long)]
    grid: Option<PathBuf>,
    /// For a DEM: the method run on each tile.
    #[arg(long, value_enum, default_value = "memetic")]
    algo: Algorithm,
    /// For a DEM run with greedy insertion: stop once E_max ≤ this fraction of the z range, as
    /// `run --max-error-fraction` does (e.g. 0.01) [default: insert every point].
    #[arg(long)]
    max_error_fraction: Option<f64>,
    /// For a DEM: the run's seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// For a DEM: tile size of the run [default: 1025].
    #[arg(long, value_name = "N")]
    tile: Option<usize>,
    /// Threads [default: every core].
    #[arg(long)]
    threads: Option<usize>,
    /// How to import the grid.
    #[command(flatten)]
    import: ImportArgs,
}

/// True when `path` names a front.json rather than a grid.
fn is_front(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Refuses an output path that is a file, before any work.
fn check_out(out: &Path) -> Result<(), String> {
    if out.is_file() {
        return Err(format!(
            "--out {}: is a file, and a tileset is a folder; give a folder's path or remove the file",
            out.display()
        ));
    }
    Ok(())
}

/// Writes `files` into a temporary folder beside `out` and renames it to `out` (an old folder
/// there is replaced only once the new one is complete).
fn write_folder(out: &Path, files: Vec<(String, Vec<u8>)>) -> Result<usize, String> {
    check_out(out)?;
    let name = out
        .file_name()
        .ok_or_else(|| format!("--out {}: not a folder name", out.display()))?
        .to_string_lossy()
        .into_owned();
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&parent)
        .map_err(|e| format!("cannot make {}: {e}", parent.display()))?;
    let pid = std::process::id();
    let partial = parent.join(format!(".{name}.partial-{pid}"));
    let _ = std::fs::remove_dir_all(&partial);
    let mut bytes = 0;
    let result = (|| {
        for (path, data) in &files {
            let path = partial.join(path);
            if let Some(folder) = path.parent() {
                std::fs::create_dir_all(folder)
                    .map_err(|e| format!("cannot make {}: {e}", folder.display()))?;
            }
            std::fs::write(&path, data)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            bytes += data.len();
        }
        let old = parent.join(format!(".{name}.old-{pid}"));
        if out.exists() {
            std::fs::rename(out, &old)
                .map_err(|e| format!("cannot move the old {} aside: {e}", out.display()))?;
        }
        std::fs::rename(&partial, out).map_err(|e| {
            format!(
                "cannot rename {} to {}: {e}",
                partial.display(),
                out.display()
            )
        })?;
        let _ = std::fs::remove_dir_all(&old);
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&partial);
    }
    result.map(|()| bytes)
}

fn threads(args: &TilesArgs) -> Result<usize, String> {
    match args.threads {
        Some(0) => Err("--threads must be at least 1".into()),
        Some(n) => Ok(n),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

/// The finest level's error bound on `hf`: `--max-error`, or [`DEFAULT_FINEST`] of its z range.
fn finest_bound(args: &TilesArgs, hf: &Heightfield) -> f64 {
    let (lo, hi) = hf.z_range();
    args.max_error.unwrap_or(DEFAULT_FINEST * (hi - lo))
}

/// Runs `args.algo` tile by tile on `hf` (the default method of `paretomesh run`), a grid in
/// memory or its file's windows.
fn run_dem(args: &TilesArgs, hf: &dyn TileSource) -> Result<TiledFront, String> {
    let (width, height) = hf.size();
    let plan = TilePlan::new(width, height, args.tile.unwrap_or(DEFAULT_TILE))
        .map_err(|e| e.to_string())?;
    let name = args.algo.name();
    if args.max_error_fraction.is_some()
        && let Some(why) = args.algo.refusal(Param::MaxErrorFraction)
    {
        return Err(format!(
            "--max-error-fraction does not apply to --algo {name}: {why}"
        ));
    }
    let params = Params {
        max_error_fraction: args.max_error_fraction,
        ..Params::default()
    };
    let config = tile_config(&plan, &args.algo.configure(&params)?);
    let threads = threads(args)?;
    eprintln!(
        "running {name} on the {width}×{height} grid in {} tiles on {threads} threads",
        plan.len()
    );
    let progress = Progress::new("tiles run");
    let done = std::sync::atomic::AtomicUsize::new(0);
    let report = |_| {
        let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        progress.report(n, plan.len());
    };
    run_tiled_with_progress(hf, &plan, &config, args.seed, threads, &report)
        .map_err(|e| e.to_string())
}

/// A DEM's tiled front made from its file's windows, before the grid is read whole: the run
/// and the pyramid then never hold the grid and the tiles' work at once. `None` for a file
/// read whole or a grid of one tile.
fn run_dem_by_windows(args: &TilesArgs) -> Result<Option<TiledFront>, String> {
    let Some(windows) =
        GridWindows::open(&args.input, &args.import.options()).map_err(|e| e.to_string())?
    else {
        return Ok(None);
    };
    let (w, h) = (windows.width(), windows.height());
    let plan = TilePlan::new(w, h, args.tile.unwrap_or(DEFAULT_TILE)).map_err(|e| e.to_string())?;
    if plan.is_single() {
        return Ok(None);
    }
    levels_for(args, w, h)?;
    // The pyramid reads the grid whole after the run: a grid over the importer's limits is
    // refused before the run, with the importer's message.
    paretomesh::heightfield::check_size(w, h)
        .map_err(|e| import::ImportError::from(e).to_string())?;
    let windows = windows.scan().map_err(|e| e.to_string())?;
    run_dem(args, &windows).map(Some)
}

pub(super) fn run(args: &TilesArgs) -> Result<(), String> {
    check_out(&args.out)?;
    threads(args)?;
    if let Some(n) = args.threads {
        // Tiles, levels and encoding all run on rayon's global pool.
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global();
    }
    match args.format {
        FormatArg::QuantizedMesh | FormatArg::ThreeDTilesTerrain => quantized_mesh(args),
        FormatArg::ThreeDTiles => three_d_tiles(args),
    }
}

fn quantized_mesh(args: &TilesArgs) -> Result<(), String> {
    if is_front(&args.input) {
        let format = match args.format {
            FormatArg::ThreeDTilesTerrain => "3dtiles-terrain",
            _ => "quantized-mesh",
        };
        return Err(format!(
            "{}: {format} tiles are cut on the tiling scheme's grid (the DEM reprojected onto the scheme's tiles), which a front made on the DEM's own grid does not follow, so its meshes cannot be cut into the scheme's tiles without new errors; give the DEM itself, which is run on the scheme's grid with the same method: paretomesh tiles DEM.tif --format {format} --algo ALGO --seed N --out DIR (or --format 3dtiles for a pyramid on the front's own grid)",
            args.input.display()
        ));
    }
    let start = Instant::now();
    let dem = import::load_with(&args.input, &args.import.options()).map_err(|e| e.to_string())?;
    let scheme = match args.scheme {
        SchemeArg::Geographic => Scheme::Geographic,
        SchemeArg::Mercator => Scheme::Mercator,
    };
    let raster = reproject(
        &dem,
        RasterOptions {
            scheme,
            geoid: args.geoid == GeoidArg::Egm96,
            cells_per_tile: 64,
            levels: args.levels.map(|l| l.max(1) as u32),
        },
    )
    .map_err(|e| format!("{}: {e}", args.input.display()))?;
    drop(dem);
    let b = raster.block;
    eprintln!(
        "the DEM lies in {}×{} {} tiles from {}/{}/{}: a {}×{} grid for {} levels (zoom {} to {})",
        b.columns,
        b.rows,
        scheme.projection(),
        b.zoom,
        b.x0,
        b.y0,
        raster.hf.width(),
        raster.hf.height(),
        raster.levels,
        b.zoom,
        b.zoom + raster.levels - 1
    );
    let front = run_dem(args, &raster.hf)?;
    let progress = Progress::new("tiles written");
    let build = if args.format == FormatArg::ThreeDTilesTerrain {
        build_3dtiles_terrain
    } else {
        build_terrain
    };
    let tileset = build(
        &raster,
        &front,
        TerrainOptions {
            water_mask: args.water_mask,
            finest_error: args.max_error,
            max_triangles: args.max_triangles,
        },
        &|done, total| progress.report(done, total),
    )?;
    for level in &tileset.levels {
        eprintln!(
            "zoom {}: {} tiles, {} triangles, geometric error {:.4}{}",
            level.zoom,
            level.tiles,
            level.triangles,
            level.error,
            if level.bound.is_none() {
                " (flat, outside the DEM's tiles)"
            } else {
                ""
            }
        );
    }
    let count = tileset.files.len() - 1;
    let index = match args.format {
        FormatArg::ThreeDTilesTerrain => "tileset.json and subtree files",
        _ => "layer.json",
    };
    let bytes = write_folder(&args.out, tileset.files)?;
    eprintln!(
        "wrote {count} files ({:.1} MB) with {index} to {} in {:.1} s",
        bytes as f64 / 1e6,
        args.out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn three_d_tiles(args: &TilesArgs) -> Result<(), String> {
    if let Some(budget) = args.max_triangles {
        return three_d_tiles_budget(args, budget);
    }
    let start = Instant::now();
    // Each level's member: its score and kept set, from an untiled front's members or chosen
    // from a tiled front's tiles.
    let (hf, scores, kept, picks, bounds, source) = if is_front(&args.input) {
        match front_reader::read(&args.input)? {
            AnyFront::Untiled(file) => {
                let scores: Vec<_> = file.front.iter().map(|m| m.solution.score).collect();
                let (w, h) = (file.header.grid.width, file.header.grid.height);
                let levels = args.levels.unwrap_or_else(|| default_levels(&scores, w, h));
                // Every check on the front and the levels comes before the grid is read.
                let picks = plan(&scores, levels, w, h).map_err(|e| e.to_string())?;
                let hf = load_grid(args, &file.header.grid.source, w, h)?;
                for &member in &picks {
                    if let Some(&bad) = file.front[member]
                        .solution
                        .kept
                        .iter()
                        .find(|&&g| g as usize >= hf.len())
                    {
                        return Err(format!(
                            "member {member} of {} keeps grid index {bad}, past the grid's {} points",
                            args.input.display(),
                            hf.len()
                        ));
                    }
                }
                let kept: Vec<Vec<u32>> = file.front.into_iter().map(|m| m.solution.kept).collect();
                (hf, scores, kept, picks, None, "front")
            }
            AnyFront::Tiled(file) => {
                let (w, h) = (file.header.grid.width, file.header.grid.height);
                let levels = levels_for(args, w, h)?;
                let hf = load_grid(args, &file.header.grid.source, w, h)?;
                let (scores, kept, bounds) = from_tiled(&file.tiled, &hf, levels, args.max_error)?;
                (
                    hf,
                    scores,
                    kept,
                    (0..levels).collect(),
                    Some(bounds),
                    "tiled front",
                )
            }
        }
    } else {
        let by_windows = run_dem_by_windows(args)?;
        let hf =
            import::load_with(&args.input, &args.import.options()).map_err(|e| e.to_string())?;
        let levels = levels_for(args, hf.width(), hf.height())?;
        let front = match by_windows {
            Some(front) => front,
            None => run_dem(args, &hf)?,
        };
        let (scores, kept, bounds) = from_tiled(&front, &hf, levels, args.max_error)?;
        (hf, scores, kept, (0..levels).collect(), Some(bounds), "DEM")
    };
    let loaded = start.elapsed();
    let built = Instant::now();
    let kept_refs: Vec<&[u32]> = kept.iter().map(|k| &k[..]).collect();
    let progress = Progress::new("tiles written");
    let total: usize = (0..picks.len()).map(|d| 1usize << (2 * d)).sum();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let contents = |work: &LevelWork| {
        (0..work.tiles.len())
            .into_par_iter()
            .map(|i| {
                let c = work.content(i);
                let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                progress.report(n, total);
                c
            })
            .collect()
    };
    let pyramid = match &bounds {
        None => build_with(&hf, &scores, &kept_refs, &picks, contents)?,
        Some(bounds) => build_refined(&hf, &scores, &kept_refs, bounds, contents)?,
    };
    if let Some(why) = &pyramid.why_local {
        eprintln!("the pyramid stays in the input's own coordinates: {why}");
    }
    let summary = level_summary(&pyramid);
    let files = pyramid.into_files();
    let json_bytes = files[0].1.len();
    let bytes = write_folder(&args.out, files)? - json_bytes;
    for (depth, (&(tiles, triangles, worst), &member)) in summary.iter().zip(&picks).enumerate() {
        let s = &scores[member];
        eprintln!(
            "level {depth}: {source} member {member} (T = {}, E_max = {}), {tiles} tiles, {triangles} triangles, tile E_max up to {worst}",
            s.t, s.e_max
        );
    }
    eprintln!(
        "wrote {} levels ({} tiles, {:.1} MB) to {} in {:.2} s (reading and running {:.2} s)",
        picks.len(),
        summary.iter().map(|l| l.0).sum::<usize>(),
        bytes as f64 / 1e6,
        args.out.display(),
        built.elapsed().as_secs_f64(),
        loaded.as_secs_f64()
    );
    Ok(())
}

/// A 3D Tiles pyramid from a tiled front or a DEM under a triangle budget.
fn three_d_tiles_budget(args: &TilesArgs, budget: u64) -> Result<(), String> {
    let start = Instant::now();
    let (hf, front) = if is_front(&args.input) {
        match front_reader::read(&args.input)? {
            AnyFront::Untiled(_) => {
                return Err(format!(
                    "{}: --max-triangles spends a budget over the tiles of a tiled front or a DEM; an untiled front's levels are its members (drop --max-triangles, or give the DEM)",
                    args.input.display()
                ));
            }
            AnyFront::Tiled(file) => {
                let (w, h) = (file.header.grid.width, file.header.grid.height);
                levels_for(args, w, h)?;
                let hf = load_grid(args, &file.header.grid.source, w, h)?;
                (hf, file.tiled)
            }
        }
    } else {
        let by_windows = run_dem_by_windows(args)?;
        let hf =
            import::load_with(&args.input, &args.import.options()).map_err(|e| e.to_string())?;
        levels_for(args, hf.width(), hf.height())?;
        let front = match by_windows {
            Some(front) => front,
            None => run_dem(args, &hf)?,
        };
        (hf, front)
    };
    let levels = levels_for(args, hf.width(), hf.height())?;
    let finest = finest_bound(args, &hf);
    let map: MapTiles = &|n, f| (0..n).into_par_iter().map(f).collect();
    let contents = |work: &LevelWork| {
        (0..work.tiles.len())
            .into_par_iter()
            .map(|i| work.content(i))
            .collect()
    };
    let pyramid = build_budget(&hf, &front, levels, finest, budget, map, contents)?;
    let summary = level_summary(&pyramid);
    let files = pyramid.into_files();
    let bytes = write_folder(&args.out, files)?;
    for (depth, &(tiles, triangles, worst)) in summary.iter().enumerate() {
        eprintln!("level {depth}: {tiles} tiles, {triangles} triangles, tile E_max up to {worst}");
    }
    eprintln!(
        "wrote {levels} levels ({} triangles of the budget's {budget}, {:.1} MB) to {} in {:.2} s",
        summary.iter().map(|l| l.1).sum::<usize>(),
        bytes as f64 / 1e6,
        args.out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Levels of a 3D Tiles pyramid from a tiled front or a DEM: asked for, or the default.
fn levels_for(args: &TilesArgs, w: usize, h: usize) -> Result<usize, String> {
    let most = most_levels(w, h);
    match args.levels {
        Some(0) => Err("a pyramid needs at least one level".into()),
        Some(n) if n > most => Err(format!(
            "too many levels: the {w}×{h} grid takes at most {most} levels"
        )),
        Some(n) => Ok(n),
        None => Ok(DEFAULT_LEVELS.min(most)),
    }
}

/// Each level's score, kept set and error bound chosen from a tiled front (the root's first).
type Levels = (Vec<paretomesh::evaluator::Score>, Vec<Vec<u32>>, Vec<f64>);

fn from_tiled(
    front: &TiledFront,
    hf: &Heightfield,
    levels: usize,
    finest: Option<f64>,
) -> Result<Levels, String> {
    let (lo, hi) = hf.z_range();
    let finest = finest.unwrap_or(paretomesh::terrain::DEFAULT_FINEST * (hi - lo));
    let chosen = tiled_levels(front, hf, levels, Some(finest))?;
    let bounds = chosen.iter().map(|l| l.bound).collect();
    let (scores, kept) = chosen.into_iter().map(|l| (l.score, l.kept)).unzip();
    Ok((scores, kept, bounds))
}

/// The grid a front was made on, checked against its size.
fn load_grid(args: &TilesArgs, source: &str, w: usize, h: usize) -> Result<Heightfield, String> {
    let grid_path = match &args.grid {
        Some(path) => path.clone(),
        None => find_grid(&args.input, source)?,
    };
    let hf = import::load_with(&grid_path, &args.import.options()).map_err(|e| e.to_string())?;
    if (hf.width(), hf.height()) != (w, h) {
        return Err(format!(
            "the grid {} is {}×{}, but {} was made on a {w}×{h} grid",
            grid_path.display(),
            hf.width(),
            hf.height(),
            args.input.display()
        ));
    }
    Ok(hf)
}

/// Each level's tiles, triangles and largest tile E_max, for the lines printed after writing.
fn level_summary(pyramid: &Pyramid) -> Vec<(usize, usize, f64)> {
    pyramid
        .levels
        .iter()
        .map(|level| {
            let triangles = level.iter().map(|c| c.triangles).sum();
            let worst = level.iter().map(|c| c.e_max).fold(0.0, f64::max);
            (level.len(), triangles, worst)
        })
        .collect()
}
