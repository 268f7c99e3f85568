//! Times the classical baselines on one height field (release build recommended):
//!
//! ```text
//! cargo run --release --example baselines_timing -- greedy GRID.f32 [FRACTION] [RECORDS] [RULE] [SHORTLIST]
//! cargo run --release --example baselines_timing -- decimation GRID.f32
//! cargo run --release --example baselines_timing -- score GRID.f32 TRIANGLES.json
//! ```
//!
//! `score` re-scores another tool's mesh (a JSON list of grid-index triples, e.g. delatin's)
//! with the project's evaluator, so both meshes are measured with the same ruler.
//!
//! `greedy` inserts points until E_max ≤ FRACTION (default 0.01) of the z range, recording
//! RECORDS solutions (default 64) with RULE `max-error` (default) or `sum-reduction` (whose
//! exact shortlist is SHORTLIST long, default 8). With `PRINT_FRONT=1` it prints the front.

use paretomesh::baselines::{
    DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams, GreedyStop, InsertionRule,
};
use paretomesh::heightfield;
use paretomesh::optimizer::Optimizer;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage =
        "usage: baselines_timing greedy|decimation|score GRID.f32 [FRACTION] [RECORDS] [RULE]";
    let (algo, path) = match (args.first(), args.get(1)) {
        (Some(a), Some(p)) => (a.as_str(), p),
        _ => return Err(usage.into()),
    };
    let hf = Arc::new(heightfield::load(Path::new(path))?);
    let (lo, hi) = hf.z_range();
    println!(
        "{path}: {}×{} = {} points, z range {lo} .. {hi}",
        hf.width(),
        hf.height(),
        hf.len()
    );
    match algo {
        "greedy" => {
            let fraction: f64 = args.get(2).map_or(Ok(0.01), |s| s.parse())?;
            let records: usize = args.get(3).map_or(Ok(64), |s| s.parse())?;
            let rule = match args.get(4).map(String::as_str) {
                None | Some("max-error") => InsertionRule::MaxError,
                Some("sum-reduction") => InsertionRule::SumReduction,
                Some(other) => return Err(format!("unknown rule {other}").into()),
            };
            let shortlist: usize = args.get(5).map_or(Ok(8), |s| s.parse())?;
            let params = GreedyParams {
                rule,
                shortlist,
                stop: GreedyStop::MaxErrorFraction(fraction),
                records,
                ..GreedyParams::default()
            };
            let start = Instant::now();
            let mut run = GreedyInsertion::new(hf.clone(), params)?;
            let p = run.run_to_end();
            let elapsed = start.elapsed();
            let last = run.recorded().last().expect("a run records its last mesh");
            println!(
                "greedy {rule:?}: {:.1} ms, {} insertions, {} points, {} triangles, E_max {} \
                 (threshold {}), E_sum {}, {} recorded, front {}",
                elapsed.as_secs_f64() * 1e3,
                p.evaluations,
                last.kept.len(),
                last.t,
                last.e_max,
                fraction * (hi - lo),
                last.e_sum,
                run.recorded().len(),
                run.front().len()
            );
            if std::env::var_os("PRINT_FRONT").is_some() {
                for s in run.front().solutions() {
                    println!("  T {} E_sum {} E_max {}", s.t, s.e_sum, s.e_max);
                }
            }
        }
        "decimation" => {
            let start = Instant::now();
            let mut run = EdgeDecimation::new(hf.clone(), DecimationParams::default())?;
            let p = run.run_to_end();
            let elapsed = start.elapsed();
            println!(
                "decimation: {:.1} ms, {} removals, front {}",
                elapsed.as_secs_f64() * 1e3,
                p.evaluations,
                run.front().len()
            );
            for (r, s) in run.recorded() {
                println!(
                    "  r {r:.2}: T {} points {} E_sum {} E_max {}",
                    s.t,
                    s.kept.len(),
                    s.e_sum,
                    s.e_max
                );
            }
        }
        "score" => {
            let file = args.get(2).ok_or(usage)?;
            let triangles: Vec<[u32; 3]> = serde_json::from_slice(&std::fs::read(file)?)?;
            let mut ev = paretomesh::evaluator::Evaluator::new(hf.clone());
            let score = ev.score_triangulation(&triangles)?;
            let mut points: Vec<u32> = triangles.iter().flatten().copied().collect();
            points.sort_unstable();
            points.dedup();
            println!(
                "{file}: {} points, T {}, E_sum {}, E_max {}",
                points.len(),
                score.t,
                score.e_sum,
                score.e_max
            );
            // The same points under the project's canonical Delaunay triangulation.
            let canonical = ev.evaluate(&points)?;
            let as_set = |tris: &[[u32; 3]]| -> std::collections::BTreeSet<[u32; 3]> {
                tris.iter()
                    .map(|t| {
                        let mut t = *t;
                        t.sort_unstable();
                        t
                    })
                    .collect()
            };
            let shared = as_set(&triangles)
                .intersection(&as_set(&canonical.triangles))
                .count();
            println!(
                "  its points, canonical Delaunay: T {}, E_sum {}, E_max {}; {shared} triangles \
                 in common",
                canonical.score.t, canonical.score.e_sum, canonical.score.e_max
            );
        }
        _ => return Err(usage.into()),
    }
    Ok(())
}
