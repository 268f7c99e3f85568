//! front.json: the result of one optimizer run, self-contained so that any outside tool can
//! re-score every solution (kept grid indices and triangles, y·W + x). The CLI writes it and the
//! browser exports the same format.
//!
//! ```json
//! {"grid":{"width":33,"height":33,"source":"…"},"algorithm":"nsga2","params":{…},"seed":1,
//!  "evaluations":21000,"millis":812,
//!  "front":[{"E_sum":…,"E_max":…,"T":…,"kept":[…],"triangles":[[a,b,c],…]},…]}
//! ```

use crate::evaluator::{EvaluateError, Evaluator};
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
    /// The Delaunay triangles of the kept set, grid-index triples, counter-clockwise.
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
        let front = front
            .solutions()
            .iter()
            .map(|s| {
                Ok(RunSolution {
                    triangles: evaluator.evaluate(&s.kept)?.triangles,
                    solution: s.clone(),
                })
            })
            .collect::<Result<_, EvaluateError>>()?;
        Ok(Self {
            grid,
            algorithm: algorithm.to_string(),
            params,
            seed,
            evaluations,
            millis,
            front,
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
