//! front.json: the result of one optimizer run, self-contained so that any outside tool can
//! re-score every solution (kept grid indices and triangles, y·W + x). The CLI writes it and the
//! browser exports the same format.
//!
//! ```json
//! {"grid":{"width":33,"height":33,"source":"…"},"algorithm":"nsga2","params":{…},"seed":1,
//!  "evaluations":21000,"millis":812,
//!  "front":[{"E_sum":…,"E_max":…,"T":…,"kept":[…],"triangles":[[a,b,c],…]},…]}
//! ```

use crate::evaluator::incremental::canonical_set;
use crate::evaluator::{EvaluateError, Evaluator, MeshState};
use crate::evolution::chromosome::Chromosome;
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use serde::{Deserialize, Serialize};

/// The grid a run was made on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridInfo {
    /// W.
    pub width: usize,
    /// H.
    pub height: usize,
    /// How the grid was made (the height field's source note).
    pub source: String,
}

/// One front member with its triangles.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSolution {
    /// E_sum, E_max, T and the kept indices.
    #[serde(flatten)]
    pub solution: Solution,
    /// The Delaunay triangles of the kept set, grid-index triples, counter-clockwise, each
    /// starting at its smallest index, sorted.
    pub triangles: Vec<[u32; 3]>,
}

/// The whole file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunFile {
    /// The grid.
    pub grid: GridInfo,
    /// The algorithm's name as the CLI spells it (`nsga2`, `weighted`, …).
    pub algorithm: String,
    /// The algorithm's parameters, as its params type serialises them.
    pub params: serde_json::Value,
    /// The seed of the run's random generator.
    pub seed: u64,
    /// Evaluations spent.
    pub evaluations: u64,
    /// Wall time of the run in milliseconds (0 when unknown).
    pub millis: u64,
    /// The front, by increasing T.
    pub front: Vec<RunSolution>,
}

impl RunFile {
    /// Builds the file of a run that produced `front` on `evaluator`'s height field. The
    /// triangles are recomputed with `evaluator`; fails only when a kept index is out of range.
    pub fn new(
        evaluator: &mut Evaluator,
        algorithm: &str,
        params: serde_json::Value,
        seed: u64,
        evaluations: u64,
        millis: u64,
        front: &Front,
    ) -> Result<Self, EvaluateError> {
        let hf: &Heightfield = evaluator.heightfield();
        let grid = GridInfo {
            width: hf.width(),
            height: hf.height(),
            source: hf.source().to_string(),
        };
        // Members next to each other on the front (by T) usually share most of their points (a
        // median of 200 genes apart on a paper run's front of jacksboro_65x65, out of ≈1 660
        // kept), so each is scored by editing the previous one's mesh when that is nearer than
        // half its kept points, else from scratch: the triangles are the same either way (the
        // evaluator's contract), listed in canonical order so that the file does not depend on
        // which way they were made.
        let (n, corners) = (hf.len(), hf.corners());
        let mut state = MeshState::default();
        let mut previous: Option<Chromosome> = None;
        let (mut removed, mut inserted) = (Vec::new(), Vec::new());
        let mut members = Vec::with_capacity(front.solutions().len());
        for s in front.solutions() {
            // An index out of range is left to the fresh evaluation, which reports it.
            let genes = s
                .kept
                .iter()
                .all(|&i| (i as usize) < n)
                .then(|| Chromosome::from_indices(n, &s.kept));
            let near = match (&previous, &genes) {
                (Some(p), Some(g)) => {
                    p.write_edit(g, &corners, &mut removed, &mut inserted);
                    2 * (removed.len() + inserted.len()) < s.kept.len()
                }
                _ => false,
            };
            if !near || evaluator.edit(&mut state, &removed, &inserted).is_err() {
                evaluator.score_into(&s.kept, &mut state)?;
            }
            members.push(RunSolution {
                triangles: canonical_set(&state.triangles()),
                solution: s.clone(),
            });
            previous = genes;
        }
        Ok(Self {
            grid,
            algorithm: algorithm.to_string(),
            params,
            seed,
            evaluations,
            millis,
            front: members,
        })
    }

    /// The front's (E_sum, T) rows as CSV with a header line.
    pub fn csv(&self) -> String {
        let mut out = String::from("E_sum,T\n");
        for s in &self.front {
            out.push_str(&format!("{},{}\n", s.solution.e_sum, s.solution.t));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use std::sync::Arc;

    #[test]
    fn triangles_are_the_canonical_fresh_ones_whether_edited_or_rebuilt() {
        // A 17×13 grid of integer heights (many co-circular ties) and a chain of kept sets: most
        // a few points from the previous one (scored by an edit), some far (rebuilt), some with
        // a corner missing from the list. Each member's triangles must be its fresh
        // triangulation, in canonical order.
        let (w, h) = (17usize, 13usize);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        let z = (0..w * h).map(|_| rng.random_range(0..5) as f64).collect();
        let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
        let n = (w * h) as u32;
        let mut keep: Vec<bool> = (0..n).map(|_| rng.random::<f64>() < 0.3).collect();
        let mut front = Front::default();
        for step in 0..40usize {
            if step % 9 == 8 {
                let density = rng.random::<f64>();
                keep = (0..n).map(|_| rng.random::<f64>() < density).collect();
            } else {
                for _ in 0..rng.random_range(1..6) {
                    let i = rng.random_range(0..n) as usize;
                    keep[i] = !keep[i];
                }
            }
            let kept: Vec<u32> = (0..n).filter(|&i| keep[i as usize]).collect();
            // Objectives made up so that every member enters, in this order (the file takes
            // the triangles from the kept points alone).
            assert!(front.offer(Solution {
                e_sum: 100.0 - step as f64,
                e_max: 0.0,
                t: step,
                kept,
            }));
        }
        let mut ev = Evaluator::new(hf.clone());
        let file = RunFile::new(&mut ev, "test", serde_json::Value::Null, 1, 0, 0, &front).unwrap();
        assert_eq!(file.front.len(), 40);
        let mut fresh = Evaluator::new(hf);
        for m in &file.front {
            let expected = canonical_set(&fresh.evaluate(&m.solution.kept).unwrap().triangles);
            assert_eq!(m.triangles, expected, "T {}", m.solution.t);
        }
    }
}
