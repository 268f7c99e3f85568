//! `paretomesh export FRONT.json (--member K | --tradeoff | --max-triangles N | --max-error E)
//! [--format ply|obj|stl|glb] --out FILE [--grid GRID] [import options]`: writes one member of a
//! front as a mesh in the input's own coordinates (map coordinates for a georeferenced GeoTIFF).

use super::front_file::{self, AnyFront, Selector, find_grid, select};
use super::input::ImportArgs;
use clap::{ArgGroup, Args, ValueEnum};
use paretomesh::evaluator::{Evaluator, Score, canonical_set};
use paretomesh::export::glb::{GlbMesh, vertex_normals, write_glb};
use paretomesh::export::mesh::WorldMesh;
use paretomesh::export::{obj::to_obj, ply::to_ply, stl::to_stl};
use paretomesh::front::Solution;
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use paretomesh::run_file::RunFile;
use paretomesh::tiling::TiledRunFile;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The mesh formats `export` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MeshFormat {
    /// ASCII PLY, double-precision vertices.
    Ply,
    /// Wavefront OBJ.
    Obj,
    /// Binary STL (single precision).
    Stl,
    /// Binary glTF 2.0 with vertex normals.
    Glb,
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
        .args(["member", "tradeoff", "max_triangles", "max_error"])
))]
pub struct ExportArgs {
    /// The front.json that `paretomesh run` (or the app) wrote.
    front: PathBuf,
    /// Export the member at this index of the front, in the file's order (0 = first).
    #[arg(long, value_name = "K")]
    member: Option<usize>,
    /// Export the paper's trade-off pick (eq. 9), its random weights drawn with the run's seed.
    #[arg(long)]
    tradeoff: bool,
    /// Export the member with the lowest E_sum among those with at most N triangles.
    #[arg(long, value_name = "N")]
    max_triangles: Option<usize>,
    /// Export the member with the fewest triangles among those with E_sum at most E.
    #[arg(long, value_name = "E")]
    max_error: Option<f64>,
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
    /// How to import the grid: the options the front was made with.
    #[command(flatten)]
    import: ImportArgs,
}

impl ExportArgs {
    fn selector(&self) -> Selector {
        match (self.member, self.max_triangles, self.max_error) {
            (Some(k), _, _) => Selector::Index(k),
            (_, Some(n), _) => Selector::MaxTriangles(n),
            (_, _, Some(e)) => Selector::MaxError(e),
            // The argument group requires exactly one choice.
            _ => Selector::TradeOff,
        }
    }
}

/// The triangulation of a member checked against what the file records: a front made on
/// another grid, or with other import options, scores differently, and a mesh written from it
/// would not be the member.
fn member_mesh(
    hf: Arc<Heightfield>,
    file: &RunFile,
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
    file: &TiledRunFile,
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

fn encode(
    format: MeshFormat,
    mesh: &WorldMesh,
    note: &str,
) -> Result<Vec<u8>, paretomesh::export::glb::GlbError> {
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
            })?
        }
    })
}

pub fn run(args: &ExportArgs) -> Result<(), String> {
    let format = match args.format {
        Some(f) => f,
        None => MeshFormat::of_path(&args.out).ok_or_else(|| {
            format!(
                "cannot tell the mesh format from {}: name it .ply, .obj, .stl or .glb, or give --format",
                args.out.display()
            )
        })?,
    };
    let file = front_file::read(&args.front)?;
    let (grid, seed) = match &file {
        AnyFront::Untiled(f) => (&f.grid, f.seed),
        AnyFront::Tiled(f) => (&f.grid, f.seed),
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
    let index = select(&scores, args.selector(), seed)?;
    let grid_path = match &args.grid {
        Some(path) => path.clone(),
        None => find_grid(&args.front, &grid.source)?,
    };
    let hf = import::load_with(&grid_path, &args.import.options()).map_err(|e| e.to_string())?;
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
    let hf = Arc::new(hf);
    let triangles = match &file {
        AnyFront::Untiled(f) => member_mesh(hf.clone(), f, index, &args.front, &grid_path)?,
        AnyFront::Tiled(f) => tiled_member_mesh(&hf, f, index, &args.front, &grid_path)?,
    };
    let mesh = WorldMesh::new(&hf, &vertices_of(&triangles), &triangles)?;
    let member = &scores[index];
    let note = format!(
        "ParetoMesh member {index} of {}: {} vertices, {} triangles, E_sum = {}",
        args.front
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        mesh.vertices.len(),
        member.t,
        member.e_sum
    );
    let bytes = encode(format, &mesh, &note).map_err(|e| e.to_string())?;
    std::fs::write(&args.out, bytes)
        .map_err(|e| format!("cannot write {}: {e}", args.out.display()))?;
    eprintln!(
        "wrote member {index} of {} (T = {}, E_sum = {}, {} vertices) to {} as {}",
        scores.len(),
        member.t,
        member.e_sum,
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
