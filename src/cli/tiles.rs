//! `paretomesh tiles FRONT.json --out DIR [--levels N] [--grid GRID] [import options]`: writes a
//! 3D Tiles 1.1 quadtree pyramid of a front (tileset.json and one .glb per tile), each level a
//! whole-grid member, placed on the globe for a GeoTIFF in EPSG:4326 or WGS84 UTM.

use super::front_reader::{self, AnyFront, find_grid};
use super::input::ImportArgs;
use clap::Args;
use paretomesh::import;
use paretomesh::pyramid::{build_with, default_levels, plan};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Options of `paretomesh tiles`.
#[derive(Args, Debug)]
pub(super) struct TilesArgs {
    /// The front.json that `paretomesh run` (or the app) wrote.
    front: PathBuf,
    /// The folder to write tileset.json and the tiles into (made if missing).
    #[arg(long)]
    out: PathBuf,
    /// Quadtree levels: level L has 2^L × 2^L tiles and shows a member of about 4^L times the
    /// root's triangles [default: 4, or fewer when the grid or the front has fewer].
    #[arg(long, value_name = "N")]
    levels: Option<usize>,
    /// The grid the front was made on [default: the file named in front.json, looked for as
    /// named, then beside front.json].
    #[arg(long)]
    grid: Option<PathBuf>,
    /// How to import the grid: the options the front was made with.
    #[command(flatten)]
    import: ImportArgs,
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

pub(super) fn run(args: &TilesArgs) -> Result<(), String> {
    let start = Instant::now();
    let file = match front_reader::read(&args.front)? {
        AnyFront::Untiled(file) => *file,
        AnyFront::Tiled(_) => {
            return Err(format!(
                "{} is a tiled front: a pyramid is made from an untiled front (run with a --tile as large as the grid)",
                args.front.display()
            ));
        }
    };
    let scores: Vec<_> = file.front.iter().map(|m| m.solution.score).collect();
    let (w, h) = (file.header.grid.width, file.header.grid.height);
    let levels = args.levels.unwrap_or_else(|| default_levels(&scores, w, h));
    // Every check on the front and the levels comes before the grid is read or a file written.
    let picks = plan(&scores, levels, w, h).map_err(|e| e.to_string())?;
    let grid_path = match &args.grid {
        Some(path) => path.clone(),
        None => find_grid(&args.front, &file.header.grid.source)?,
    };
    let hf = import::load_with(&grid_path, &args.import.options()).map_err(|e| e.to_string())?;
    if (hf.width(), hf.height()) != (w, h) {
        return Err(format!(
            "the grid {} is {}×{}, but {} was made on a {w}×{h} grid",
            grid_path.display(),
            hf.width(),
            hf.height(),
            args.front.display()
        ));
    }
    for &member in &picks {
        if let Some(&bad) = file.front[member]
            .solution
            .kept
            .iter()
            .find(|&&g| g as usize >= hf.len())
        {
            return Err(format!(
                "member {member} of {} keeps grid index {bad}, past the grid's {} points",
                args.front.display(),
                hf.len()
            ));
        }
    }
    let loaded = start.elapsed();

    let built = Instant::now();
    let kept: Vec<&[u32]> = file.front.iter().map(|m| &m.solution.kept[..]).collect();
    let pyramid = build_with(&hf, &scores, &kept, &picks, |work| {
        (0..work.tiles.len())
            .into_par_iter()
            .map(|i| work.content(i))
            .collect()
    })?;
    if let Some(why) = &pyramid.why_local {
        eprintln!("the pyramid stays in the input's own coordinates: {why}");
    }
    // Each level's tile count, triangles and worst tile E_max, for the summary.
    let summary: Vec<(usize, usize, f64)> = pyramid
        .levels
        .iter()
        .map(|level| {
            let triangles = level.iter().map(|c| c.triangles).sum();
            let worst = level.iter().map(|c| c.e_max).fold(0.0, f64::max);
            (level.len(), triangles, worst)
        })
        .collect();
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot make {}: {e}", args.out.display()))?;
    let mut bytes = 0usize;
    for (name, data) in pyramid.into_files() {
        let path = args.out.join(&name);
        if let Some(folder) = path.parent() {
            std::fs::create_dir_all(folder)
                .map_err(|e| format!("cannot make {}: {e}", folder.display()))?;
        }
        write(&path, &data)?;
        if name != "tileset.json" {
            bytes += data.len();
        }
    }
    for (depth, (&(tiles, triangles, worst), &member)) in summary.iter().zip(&picks).enumerate() {
        let s = &scores[member];
        eprintln!(
            "level {depth}: member {member} (T = {}, E_max = {}), {} tiles, {triangles} triangles, tile E_max up to {worst}",
            s.t, s.e_max, tiles
        );
    }
    eprintln!(
        "wrote {levels} levels ({} tiles, {:.1} MB) to {} in {:.2} s (reading the front and grid {:.2} s)",
        summary.iter().map(|l| l.0).sum::<usize>(),
        bytes as f64 / 1e6,
        args.out.display(),
        built.elapsed().as_secs_f64(),
        loaded.as_secs_f64()
    );
    Ok(())
}
