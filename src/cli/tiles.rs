//! `paretomesh tiles FRONT.json --out DIR [--levels N] [--grid GRID] [import options]`: writes a
//! 3D Tiles 1.1 quadtree pyramid of a front (tileset.json and one .glb per tile), each level a
//! whole-grid member, placed on the globe for a GeoTIFF in EPSG:4326 or WGS84 UTM.

use super::front_reader::{self, AnyFront, find_grid};
use super::input::ImportArgs;
use clap::Args;
use paretomesh::import;
use paretomesh::pyramid::borders::with_border_points;
use paretomesh::pyramid::globe::Frame;
use paretomesh::pyramid::quadtree::Level;
use paretomesh::pyramid::tileset::{content_uri, tile_content, tileset_json};
use paretomesh::pyramid::{frame_note, most_levels, notes, plan};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Levels when `--levels` is not given, fewer when the grid or the front has fewer.
const DEFAULT_LEVELS: usize = 4;

/// Options of `paretomesh tiles`.
#[derive(Args, Debug)]
pub struct TilesArgs {
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

pub fn run(args: &TilesArgs) -> Result<(), String> {
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
    let (w, h) = (file.grid.width, file.grid.height);
    let distinct = {
        let mut ts: Vec<usize> = scores.iter().map(|s| s.t).collect();
        ts.sort_unstable();
        ts.dedup();
        ts.len()
    };
    let levels = args
        .levels
        .unwrap_or_else(|| DEFAULT_LEVELS.min(most_levels(w, h)).min(distinct.max(1)));
    // Every check on the front and the levels comes before the grid is read or a file written.
    let picks = plan(&scores, levels, w, h).map_err(|e| e.to_string())?;
    let grid_path = match &args.grid {
        Some(path) => path.clone(),
        None => find_grid(&args.front, &file.grid.source)?,
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
    let (frame, why_local) = Frame::of(&hf);
    if let Some(why) = &why_local {
        eprintln!("the pyramid stays in the input's own coordinates: {why}");
    }

    let built = Instant::now();
    let mut contents = Vec::with_capacity(levels);
    for (depth, &member) in picks.iter().enumerate() {
        let level = Level::new(w, h, depth as u32);
        let solution = &file.front[member].solution;
        let kept = with_border_points(&hf, &level, &solution.kept, solution.score.e_max);
        let shares = level.share_out(&kept);
        let tiles = level.tiles();
        let level_contents = tiles
            .par_iter()
            .zip(shares.par_iter())
            .map(|(tile, share)| tile_content(&hf, &frame, tile, share))
            .collect::<Result<Vec<_>, _>>()?;
        contents.push(level_contents);
    }
    let tileset = tileset_json(
        &contents,
        &notes(&scores, &picks),
        &frame,
        &frame_note(&frame, why_local.as_deref()),
        hf.z_range(),
    );

    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot make {}: {e}", args.out.display()))?;
    let mut bytes = 0usize;
    for level in &contents {
        for content in level {
            let path = args.out.join(content_uri(&content.tile));
            if let Some(folder) = path.parent() {
                std::fs::create_dir_all(folder)
                    .map_err(|e| format!("cannot make {}: {e}", folder.display()))?;
            }
            write(&path, &content.glb)?;
            bytes += content.glb.len();
        }
    }
    let text = serde_json::to_string_pretty(&tileset).expect("a JSON value serialises");
    write(&args.out.join("tileset.json"), text.as_bytes())?;
    for (depth, (level, &member)) in contents.iter().zip(&picks).enumerate() {
        let s = &scores[member];
        let triangles: usize = level.iter().map(|c| c.triangles).sum();
        let worst = level.iter().map(|c| c.e_max).fold(0.0, f64::max);
        eprintln!(
            "level {depth}: member {member} (T = {}, E_max = {}), {} tiles, {triangles} triangles, tile E_max up to {worst}",
            s.t,
            s.e_max,
            level.len()
        );
    }
    eprintln!(
        "wrote {levels} levels ({} tiles, {:.1} MB) to {} in {:.2} s (reading the front and grid {:.2} s)",
        contents.iter().map(Vec::len).sum::<usize>(),
        bytes as f64 / 1e6,
        args.out.display(),
        built.elapsed().as_secs_f64(),
        loaded.as_secs_f64()
    );
    Ok(())
}
