//! `paretomesh export FRONT.json (--member K | --knee | --tradeoff | --max-triangles N |
//! --max-error E | --max-mean-error X | --max-vertical-error X) [--solid [--base-height H]
//! [--z-scale S]] [--format ply|obj|stl|glb|3mf] --out FILE [--grid GRID] [import options]`:
//! writes one member of a front as a mesh in the input's own coordinates (map coordinates for a
//! georeferenced GeoTIFF), as its surface or closed into a printable solid.

use super::export_max_error;
use super::front_reader::{self, AnyFront, find_grid};
use super::input::ImportOverrides;
use clap::{ArgGroup, Args, ValueEnum};
use paretomesh::evaluator::{Evaluator, Score, canonical_set};
use paretomesh::export::WorldMesh;
use paretomesh::export::to_3mf;
use paretomesh::export::{GlbMesh, vertex_normals, write_glb};
use paretomesh::export::{SolidOptions, solid};
use paretomesh::export::{to_obj, to_ply, to_stl};
use paretomesh::front::Solution;
use paretomesh::front_file::FrontFile;
use paretomesh::heightfield::Heightfield;
use paretomesh::import::{self, ImportOptions};
use paretomesh::pick::{Pick, pick};
use paretomesh::refine::{budget_floor, refine_to_budget};
use paretomesh::tiling::{TiledFrontFile, grow_tiled_member};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The mesh formats `export` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum MeshFormat {
    /// ASCII PLY, double-precision vertices.
    Ply,
    /// Wavefront OBJ.
    Obj,
    /// Binary STL (single precision).
    Stl,
    /// Binary glTF 2.0 with vertex normals.
    Glb,
    /// 3MF, the printing package slicers prefer.
    #[value(name = "3mf")]
    ThreeMf,
}

impl MeshFormat {
    /// The format an output file name asks for by its extension, if any.
    fn of_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Self::from_str(&ext, true).ok()
    }
}

/// Options of `paretomesh export`.
#[derive(Args, Debug)]
#[command(group(
    ArgGroup::new("choice")
        .required(true)
        .args([
            "member",
            "knee",
            "tradeoff",
            "max_triangles",
            "max_error",
            "max_mean_error",
            "max_vertical_error",
        ])
))]
pub(super) struct ExportArgs {
    /// The front.json that `paretomesh run` (or the app) wrote.
    front: PathBuf,
    /// Export the member at this index of the front, in the file's order (0 = first).
    #[arg(long, value_name = "K")]
    member: Option<usize>,
    /// Export the knee of the front: the member nearest the ideal point once E_sum and T are
    /// each scaled to [0, 1] over the front (what the app selects after a run).
    #[arg(long)]
    knee: bool,
    /// Export the paper's trade-off pick (eq. 9), its random weights drawn with the run's seed.
    #[arg(long)]
    tradeoff: bool,
    /// Export a mesh of at most N triangles and at least 0.99·N (N ≥ 2): the member with the
    /// lowest E_sum among those with at most N, grown by exact insertions of its worst points
    /// when it has fewer than 0.99·N (on a tiled front, the whole mesh's worst point goes into
    /// the tile that holds it, and into both tiles on a shared border line).
    #[arg(long, value_name = "N")]
    max_triangles: Option<usize>,
    /// Export the member with the fewest triangles among those with E_sum at most E, where
    /// E_sum is the error summed over all W·H grid points (see --max-mean-error and
    /// --max-vertical-error for limits in the surface's own units).
    #[arg(long, value_name = "E")]
    max_error: Option<f64>,
    /// Export the member with the fewest triangles among those whose mean error per grid point
    /// (E_sum / (W·H)) is at most X, in the surface's z units.
    #[arg(long, value_name = "X")]
    max_mean_error: Option<f64>,
    /// Export the member with the fewest triangles among those whose largest vertical error at
    /// any grid point (E_max) is at most X, in the surface's z units. A mesh is also made for X
    /// from the members nearest it (greedy refinement, bounded-error decimation; per tile with
    /// shared border points on a tiled front), and the one with the fewest triangles is written.
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    max_vertical_error: Option<f64>,
    /// Close the surface into a printable solid: vertical walls down from its border and a flat
    /// bottom.
    #[arg(long)]
    solid: bool,
    /// With --solid: how far the bottom lies below the lowest point, in output z units
    /// [default: 5 % of the z range].
    #[arg(
        long,
        value_name = "H",
        requires = "solid",
        allow_negative_numbers = true
    )]
    base_height: Option<f64>,
    /// With --solid: multiply heights by S (e.g. to exaggerate a terrain's relief) [default: 1].
    #[arg(
        long,
        value_name = "S",
        requires = "solid",
        allow_negative_numbers = true
    )]
    z_scale: Option<f64>,
    /// Mesh format [default: from the extension of --out].
    #[arg(long, value_enum)]
    format: Option<MeshFormat>,
    /// Where to write the mesh.
    #[arg(long)]
    out: PathBuf,
    /// The grid the front was made on [default: the file named in front.json, looked for as
    /// named, then beside front.json].
    #[arg(long)]
    grid: Option<PathBuf>,
    /// How to import the grid: front.json records the options the front was made with, and
    /// an option given here replaces the recorded one.
    #[command(flatten)]
    import: ImportOverrides,
}

impl ExportArgs {
    fn rule(&self) -> Pick {
        if let Some(k) = self.member {
            Pick::Index(k)
        } else if self.knee {
            Pick::Knee
        } else if let Some(n) = self.max_triangles {
            Pick::MaxTriangles(n)
        } else if let Some(e) = self.max_error {
            Pick::MaxErrorSum(e)
        } else if let Some(x) = self.max_mean_error {
            Pick::MaxMeanError(x)
        } else if let Some(x) = self.max_vertical_error {
            Pick::MaxVerticalError(x)
        } else {
            // The argument group requires exactly one choice.
            Pick::TradeOff
        }
    }

    fn solid_options(&self) -> Option<SolidOptions> {
        self.solid.then(|| SolidOptions {
            base_height: self.base_height,
            z_scale: self.z_scale.unwrap_or(1.0),
        })
    }
}

/// The triangulation of a member checked against what the file records: a front made on
/// another grid, or with other import options, scores differently, and a mesh written from it
/// would not be the member.
fn member_mesh(
    hf: Arc<Heightfield>,
    file: &FrontFile,
    index: usize,
    front_path: &Path,
    grid_path: &Path,
) -> Result<Vec<[u32; 3]>, String> {
    let member = &file.front[index];
    let recorded = &member.solution;
    let evaluation = Evaluator::new(hf)
        .evaluate(&recorded.kept)
        .map_err(|e| format!("member {index} of {}: {e}", front_path.display()))?;
    let triangles = canonical_set(&evaluation.triangles);
    let score = evaluation.score;
    // Scores from incremental edits may differ from a fresh one in the last bits only.
    let tolerance = 1e-8 * (recorded.e_sum.abs() + score.e_sum.abs()) + 1e-12;
    if score.t != recorded.t || (score.e_sum - recorded.e_sum).abs() > tolerance {
        return Err(format!(
            "member {index} of {} records T = {} and E_sum = {}, but on {} its kept points give T = {} and E_sum = {}: that is not the grid the front was made on, or it was imported with other options",
            front_path.display(),
            recorded.t,
            recorded.e_sum,
            grid_path.display(),
            score.t,
            score.e_sum
        ));
    }
    if let Some(listed) = &member.triangles
        && canonical_set(listed) != triangles
    {
        return Err(format!(
            "member {index} of {} lists {} triangles that are not the Delaunay triangulation of its kept points ({} triangles); the file was changed after it was written",
            front_path.display(),
            listed.len(),
            triangles.len()
        ));
    }
    Ok(triangles)
}

/// The mesh of a tiled front's member, the union of its tiles' triangulations, checked against
/// what the file records as [`member_mesh`] checks an untiled one.
fn tiled_member_mesh(
    hf: &Heightfield,
    file: &TiledFrontFile,
    index: usize,
    front_path: &Path,
    grid_path: &Path,
) -> Result<Vec<[u32; 3]>, String> {
    let recorded = &file.tiled.members[index];
    let mesh = file
        .tiled
        .mesh(hf, index)
        .map_err(|e| format!("member {index} of {}: {e}", front_path.display()))?;
    let tolerance = 1e-8 * (recorded.e_sum.abs() + mesh.e_sum.abs()) + 1e-12;
    if mesh.triangles.len() as u64 != recorded.t || (mesh.e_sum - recorded.e_sum).abs() > tolerance
    {
        return Err(format!(
            "member {index} of {} records T = {} and E_sum = {}, but on {} its tiles give T = {} and E_sum = {}: that is not the grid the front was made on, or it was imported with other options",
            front_path.display(),
            recorded.t,
            recorded.e_sum,
            grid_path.display(),
            mesh.triangles.len(),
            mesh.e_sum
        ));
    }
    Ok(mesh.triangles)
}

/// The mesh's vertices are the triangles' corners, as increasing grid indices: the kept list
/// may leave out the corners, which the triangulation always has.
fn vertices_of(triangles: &[[u32; 3]]) -> Vec<u32> {
    let mut vertices: Vec<u32> = triangles.iter().flatten().copied().collect();
    vertices.sort_unstable();
    vertices.dedup();
    vertices
}

fn encode(format: MeshFormat, mesh: &WorldMesh, note: &str) -> Result<Vec<u8>, String> {
    Ok(match format {
        MeshFormat::Ply => to_ply(mesh, note).into_bytes(),
        MeshFormat::Obj => to_obj(mesh, note).into_bytes(),
        MeshFormat::Stl => to_stl(mesh, note),
        MeshFormat::Glb => {
            let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
            let normals = vertex_normals(&mesh.vertices, &indices);
            write_glb(&GlbMesh {
                positions: &mesh.vertices,
                normals: &normals,
                indices: &indices,
                colors: None,
            })
            .map_err(|e| e.to_string())?
        }
        MeshFormat::ThreeMf => to_3mf(mesh, note)?,
    })
}

pub(super) fn run(args: &ExportArgs) -> Result<(), String> {
    let format = match args.format {
        Some(f) => f,
        None => MeshFormat::of_path(&args.out).ok_or_else(|| {
            format!(
                "cannot tell the mesh format from {}: name it .ply, .obj, .stl, .glb or .3mf, or give --format",
                args.out.display()
            )
        })?,
    };
    // Bad options are refused before any file is read or written.
    if let Some(n) = args.max_triangles
        && n < 2
    {
        return Err(format!(
            "--max-triangles must be at least 2, the fewest triangles a mesh has (the two of the four corners); got {n}"
        ));
    }
    let solid_options = args.solid_options();
    if let Some(options) = &solid_options {
        options.check().map_err(|e| e.to_string())?;
    }
    if let Pick::MaxVerticalError(x) = args.rule() {
        export_max_error::check_sign(x)?;
    }
    let file = front_reader::read(&args.front)?;
    let (grid, seed) = match &file {
        AnyFront::Untiled(f) => (&f.header.grid, f.header.seed),
        AnyFront::Tiled(f) => (&f.header.grid, f.header.seed),
    };
    let scores: Vec<Score> = match &file {
        AnyFront::Untiled(f) => f.front.iter().map(|m| m.solution.score).collect(),
        AnyFront::Tiled(f) => f
            .tiled
            .members
            .iter()
            .map(|m| Solution::recorded(m.e_sum, m.e_max, m.t as usize, Vec::new()).score)
            .collect(),
    };
    let grid_points = grid.width * grid.height;
    let picked = pick(&scores, args.rule(), seed, grid_points);
    // A max vertical error is reached on demand (export_max_error.rs), so no member within
    // it is needed; the other rules take the pick as it is.
    let on_demand = match args.rule() {
        Pick::MaxVerticalError(x) => Some(x),
        _ => None,
    };
    let index = picked.clone().or_else(|e| match on_demand {
        Some(_) => Ok(usize::MAX),
        None => Err(e),
    });
    let index = index.map_err(|e| {
        let flag = match args.rule() {
            Pick::Index(_) => "--member",
            Pick::TradeOff => "--tradeoff",
            Pick::Knee => "--knee",
            Pick::MaxTriangles(_) => "--max-triangles",
            Pick::MaxErrorSum(_) => "--max-error",
            Pick::MaxMeanError(_) => "--max-mean-error",
            Pick::MaxVerticalError(_) => "--max-vertical-error",
        };
        format!("{flag}: {e}")
    })?;
    let grid_path = match &args.grid {
        Some(path) => path.clone(),
        None => find_grid(&args.front, &grid.source)?,
    };
    let recorded = match &grid.import {
        Some(record) => record
            .options()
            .map_err(|e| format!("{}: {e}", args.front.display()))?,
        None => ImportOptions::default(),
    };
    let hf =
        import::load_with(&grid_path, &args.import.over(recorded)).map_err(|e| e.to_string())?;
    let (w, h) = (grid.width, grid.height);
    if (hf.width(), hf.height()) != (w, h) {
        return Err(format!(
            "the grid {} is {}×{}, but {} was made on a {w}×{h} grid",
            grid_path.display(),
            hf.width(),
            hf.height(),
            args.front.display()
        ));
    }
    if let Pick::MaxVerticalError(x) = args.rule() {
        export_max_error::check_floor(&hf, x)?;
    }
    let hf = Arc::new(hf);
    let mut made_for = None;
    let mut triangles = match (&file, on_demand) {
        (AnyFront::Untiled(f), Some(x)) => {
            let picked = picked.ok();
            if let Some(k) = picked {
                // The member must be the grid's before anything is made from it.
                member_mesh(hf.clone(), f, k, &args.front, &grid_path)?;
            }
            let made = export_max_error::reach(hf.clone(), f, picked, x)?;
            let triangles = made.triangles.clone();
            made_for = Some(made);
            triangles
        }
        (AnyFront::Tiled(f), Some(x)) => {
            let picked = picked.ok();
            if let Some(k) = picked {
                tiled_member_mesh(&hf, f, k, &args.front, &grid_path)?;
            }
            let made = export_max_error::reach_tiled(hf.clone(), &f.tiled, picked, x)?;
            let triangles = made.triangles.clone();
            made_for = Some(made);
            triangles
        }
        (AnyFront::Untiled(f), None) => member_mesh(hf.clone(), f, index, &args.front, &grid_path)?,
        (AnyFront::Tiled(f), _) => tiled_member_mesh(&hf, f, index, &args.front, &grid_path)?,
    };
    let mut member = match &made_for {
        Some(r) => r.score,
        None => scores[index],
    };
    // How the mesh was reached when the member was grown to the budget (said after it).
    let mut grown_note = String::new();
    if let (Some(n), AnyFront::Untiled(f)) = (args.max_triangles, &file)
        && member.t < budget_floor(n)
    {
        let refined = refine_to_budget(hf.clone(), &f.front[index].solution.kept, n)?;
        let evaluation = Evaluator::new(hf.clone())
            .evaluate(&refined.kept)
            .map_err(|e| e.to_string())?;
        triangles = canonical_set(&evaluation.triangles);
        grown_note = format!(
            " (T = {}) grown by {} exact insertions of its worst points, as the front has no member between {} and {n} triangles, giving a mesh",
            member.t,
            refined.insertions,
            budget_floor(n)
        );
        member = evaluation.score;
    } else if let (Some(n), AnyFront::Tiled(f)) = (args.max_triangles, &file)
        && member.t < budget_floor(n)
    {
        let grown = grow_tiled_member(&hf, &f.tiled, index, n)
            .map_err(|e| format!("member {index}: {e}"))?;
        let score = Evaluator::new(hf.clone())
            .score_triangulation(&grown.triangles)
            .map_err(|e| format!("internal error: the grown mesh is not a whole triangulation ({e}); nothing written"))?;
        triangles = grown.triangles;
        grown_note = format!(
            " (T = {}) grown by {} exact insertions of the worst point of the whole mesh ({} on border lines two tiles share, inserted in both), as the front has no member between {} and {n} triangles, giving a mesh",
            member.t,
            grown.insertions,
            grown.on_shared_lines,
            budget_floor(n)
        );
        member = score;
    }
    let mesh = match &solid_options {
        Some(options) => solid(&hf, &triangles, options).map_err(|e| e.to_string())?,
        None => WorldMesh::new(&hf, &vertices_of(&triangles), &triangles)?,
    };
    let front_name = args
        .front
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let what = match &made_for {
        Some(r) => format!(
            "a mesh for --max-vertical-error from {front_name}, {}",
            r.how
        ),
        None => format!("member {index} of {front_name}"),
    };
    let note = format!(
        "ParetoMesh {what}{}: {} vertices, {} triangles, E_sum = {}",
        if solid_options.is_some() {
            " as a solid"
        } else {
            ""
        },
        mesh.vertices.len(),
        mesh.triangles.len(),
        member.e_sum
    );
    let bytes = encode(format, &mesh, &note)?;
    std::fs::write(&args.out, bytes)
        .map_err(|e| format!("cannot write {}: {e}", args.out.display()))?;
    eprintln!(
        "wrote {}{grown_note} (T = {}, E_sum = {}, E_max = {}{}, {} vertices) to {} as {}",
        match &made_for {
            Some(_) => what.clone(),
            None => format!("member {index} of {}", scores.len()),
        },
        member.t,
        member.e_sum,
        member.e_max,
        if solid_options.is_some() {
            format!(", closed into a solid of {} faces", mesh.triangles.len())
        } else {
            String::new()
        },
        mesh.vertices.len(),
        args.out.display(),
        format
            .to_possible_value()
            .expect("every format has a name")
            .get_name()
            .to_ascii_uppercase()
    );
    Ok(())
}
