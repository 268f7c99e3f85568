//! Read a front.json and check every member against the evaluator: either one that
//! `paretomesh run … --out front.json` wrote, or one made here from a greedy-insertion run.
//!
//! ```text
//! cargo run --release --example read_front                        # greedy insertion on volcano_33x33
//! cargo run --release --example read_front -- front.json GRID     # a front from the command line
//! ```
//!
//! front.json is self-contained: each member lists its kept grid indices (packed, see
//! `paretomesh::kept_codec`) and, with `run --triangles`, its triangles, so any tool can
//! re-score it. GRID must be the grid the front was made on.

use paretomesh::baselines::{GreedyInsertion, GreedyParams};
use paretomesh::catalogue::Config;
use paretomesh::evaluator::Evaluator;
use paretomesh::front_file::FrontFile;
use paretomesh::import;
use paretomesh::optimizer::Optimizer;
use std::path::PathBuf;
use std::sync::Arc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let (json, grid) = match args.as_slice() {
        [front, grid] => (std::fs::read_to_string(front)?, grid.clone()),
        [] => {
            // No file given: write one as the command line does.
            let grid =
                PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/volcano_33x33.f32");
            let hf = Arc::new(import::load(&grid)?);
            let params = GreedyParams::default();
            let mut run = GreedyInsertion::new(hf.clone(), params.clone())?;
            let progress = run.run_to_end();
            let mut ev = Evaluator::new(hf);
            let mut file = FrontFile::new(
                &mut ev,
                &Config::Greedy(params),
                0,
                progress.evaluations,
                0,
                run.front(),
            )?;
            // As `paretomesh run --triangles` writes it.
            file.add_triangles(&mut ev)?;
            (serde_json::to_string(&file)?, grid)
        }
        _ => return Err("usage: read_front [FRONT.json GRID]".into()),
    };

    let file: FrontFile = serde_json::from_str(&json)?;
    println!(
        "{} on a {}×{} grid, seed {}, {} evaluations: {} solutions",
        file.header.algorithm.name(),
        file.header.grid.width,
        file.header.grid.height,
        file.header.seed,
        file.header.evaluations,
        file.front.len()
    );
    let hf = Arc::new(import::load(&grid)?);
    if (hf.width(), hf.height()) != (file.header.grid.width, file.header.grid.height) {
        return Err(format!("{} is not the grid of this front", grid.display()).into());
    }

    // Re-score every member two ways: from its kept points (the evaluator triangulates them)
    // and from the triangles the file lists. Both give the file's numbers, to the bit.
    let mut ev = Evaluator::new(hf);
    for member in &file.front {
        let s = &member.solution;
        let from_kept = ev.score(&s.kept)?;
        let from_triangles = match &member.triangles {
            Some(triangles) => ev.score_triangulation(triangles)?,
            None => from_kept,
        };
        if from_kept.e_sum != s.e_sum || from_kept.t != s.t || from_triangles != from_kept {
            return Err(format!(
                "the member with T = {} does not re-score to its numbers",
                s.t
            )
            .into());
        }
    }
    let every = file.front.len().div_ceil(8).max(1);
    for member in file.front.iter().step_by(every) {
        let s = &member.solution;
        println!(
            "  T = {:>4}  E = {:>10.2}  E_max = {:>7.2}  {} kept points",
            s.t,
            s.e_sum,
            s.e_max,
            s.kept.len()
        );
    }
    println!("every member re-scores to the file's E and T");
    Ok(())
}
