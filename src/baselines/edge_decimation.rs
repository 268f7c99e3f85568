//! Edge decimation, the paper's classical baseline (after Schroeder et al. 1992).
//!
//! Starts from the full grid mesh (every point kept, canonical Delaunay) and repeatedly removes
//! the kept vertex whose removal increases E_sum the least; corners are never removed. Removing
//! a vertex is the same as collapsing one of its edges onto a kept neighbour and re-triangulating
//! the hole, so vertices always stay grid points. The hole is re-triangulated as the Delaunay
//! triangles of its boundary under the project's tie rule (ear clipping, see `hole`), which keeps
//! the mesh the evaluator's canonical triangulation of the kept set.
//!
//! The error increase is exact: E_sum over the hole's new triangles minus E_sum over the removed
//! star, both rasterised with the ownership rule (the hole's boundary edges keep their
//! directions, so the hole owns the same grid points before and after). Costs sit in a priority
//! queue (smallest first, ties to the smaller grid index); after a removal exactly the stars of
//! the removed vertex's neighbours changed, so exactly their costs are recomputed.
//!
//! Recording contract: for each reduction r of [`DecimationParams::reductions`] (by default
//! 5 %, 10 %, …, 50 %), a solution is recorded as soon as T ≤ ⌊(1 − r)·T_full⌋. A removal lowers
//! T by 2 (interior vertex) or 1 (border vertex), so the recorded T is that bound or one less.
//! The run stops after the last reduction (or when only the corners are left). The recorded
//! numbers come from a fresh [`Evaluator::score`](crate::evaluator::Evaluator::score).
//!
//! Unit of work: one vertex removal (one evaluation). [`Progress::generation`] counts the
//! reductions reached.

use super::ParamsError;
use crate::evaluator::Evaluator;
use crate::evaluator::exact::predicates::{GridPoint, Lattice};
use crate::evaluator::mesh::canonical_form::canonical;
use crate::evaluator::mesh::canonical_triangulation::Triangulation;
use crate::evaluator::mesh::hole_fill as hole;
use crate::evaluator::raster::Grid;
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use crate::lazy_queue::Entry;
use crate::measure::ErrorMeasure;
use crate::optimizer::{Optimizer, Progress};
use serde::{Deserialize, Serialize};
use std::collections::BinaryHeap;
use std::sync::Arc;

/// Parameters of [`EdgeDecimation`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DecimationParams {
    /// Fractions of the full triangle count to remove, strictly increasing, each in (0, 1).
    pub reductions: Vec<f64>,
    /// The error the recorded front is non-dominated in (the collapses do not change). Written
    /// only when not `sum`.
    #[serde(skip_serializing_if = "ErrorMeasure::is_sum")]
    pub error: ErrorMeasure,
}

impl Default for DecimationParams {
    fn default() -> Self {
        Self {
            reductions: (1..=10).map(|k| k as f64 * 0.05).collect(),
            error: ErrorMeasure::Sum,
        }
    }
}

/// The edge-decimation optimizer (see the module docs).
pub struct EdgeDecimation {
    hf: Arc<Heightfield>,
    params: DecimationParams,
    /// Triangle slots; dead ones are in `free`.
    tris: Vec<[u32; 3]>,
    tri_sum: Vec<f64>,
    free: Vec<u32>,
    live: usize,
    /// Live triangle slots around each vertex.
    incident: Vec<Vec<u32>>,
    kept: Vec<bool>,
    is_corner: Vec<bool>,
    /// Version of each vertex's queued cost.
    stamp: Vec<u32>,
    queue: BinaryHeap<Entry>,
    /// T bound of each reduction, and the index of the next one to reach.
    bounds: Vec<usize>,
    next_bound: usize,
    evaluator: Evaluator,
    front: Front,
    recorded: Vec<(f64, Solution)>,
    removals: u64,
    done: bool,
    boundary: Vec<u32>,
    fill: Vec<[u32; 3]>,
    /// Index → coordinates on this grid (see `predicates::Lattice`).
    lattice: Lattice,
}

impl EdgeDecimation {
    /// A run on `hf` from the full grid mesh. Refuses reductions that are not strictly
    /// increasing within (0, 1).
    pub fn new(hf: Arc<Heightfield>, params: DecimationParams) -> Result<Self, ParamsError> {
        let mut previous = 0.0;
        for &r in &params.reductions {
            if !(r > previous && r < 1.0) {
                return Err(ParamsError::OutOfRange {
                    name: "reductions",
                    value: r,
                    allowed: "strictly increasing and within (0, 1)",
                });
            }
            previous = r;
        }
        let n = hf.len();
        let full = hf.full_triangles();
        let bounds = params
            .reductions
            .iter()
            .map(|r| ((1.0 - r) * full as f64).floor() as usize)
            .collect();
        let all: Vec<u32> = (0..n as u32).collect();
        let mut mesh = Triangulation::default();
        mesh.rebuild_delaunay(hf.width(), &all);
        let tris = mesh.triangles();
        let mut is_corner = vec![false; n];
        for c in hf.corners() {
            is_corner[c as usize] = true;
        }
        let measure = params.error;
        let mut run = Self {
            evaluator: Evaluator::new(hf.clone()),
            hf,
            params,
            tri_sum: vec![0.0; tris.len()],
            live: tris.len(),
            tris,
            free: Vec::new(),
            incident: vec![Vec::new(); n],
            kept: vec![true; n],
            is_corner,
            stamp: vec![0; n],
            queue: BinaryHeap::new(),
            bounds,
            next_bound: 0,
            front: Front::new(measure),
            recorded: Vec::new(),
            removals: 0,
            done: false,
            boundary: Vec::new(),
            fill: Vec::new(),
            lattice: mesh.lattice(),
        };
        for s in 0..run.tris.len() {
            run.tri_sum[s] = run.error_sum(run.tris[s]);
            for v in run.tris[s] {
                run.incident[v as usize].push(s as u32);
            }
        }
        for v in 0..n as u32 {
            run.queue_cost(v);
        }
        run.record_due();
        Ok(run)
    }

    /// The parameters.
    pub fn params(&self) -> &DecimationParams {
        &self.params
    }

    /// Every recorded solution with the reduction it was recorded for, in order (a solution
    /// appears once per reduction, so it may repeat on tiny grids; reductions that cannot be
    /// reached because only the corners are left, as on a 2×2 grid, are missing).
    pub fn recorded(&self) -> &[(f64, Solution)] {
        &self.recorded
    }

    /// The current mesh's triangles (grid-index triples, counter-clockwise).
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        let dead: std::collections::BTreeSet<u32> = self.free.iter().copied().collect();
        (0..self.tris.len() as u32)
            .filter(|s| !dead.contains(s))
            .map(|s| self.tris[s as usize])
            .collect()
    }

    /// The currently kept grid indices, increasing.
    pub(crate) fn kept(&self) -> Vec<u32> {
        (0..self.kept.len() as u32)
            .filter(|&i| self.kept[i as usize])
            .collect()
    }

    /// Number of triangles of the current mesh.
    pub fn triangle_count(&self) -> usize {
        self.live
    }

    fn point(&self, i: u32) -> GridPoint {
        self.lattice.point(i)
    }

    fn error_sum(&self, tri: [u32; 3]) -> f64 {
        let grid = Grid {
            width: self.hf.width() as i64,
            height: self.hf.height() as i64,
            z: self.hf.z(),
        };
        // The evaluator's rotation, so that a triangle's sum does not depend on how it was made.
        grid.triangle_error(canonical(tri).map(|i| self.point(i)))
            .sum
    }

    /// The ordered hole boundary of `v` into `self.boundary` and its Delaunay fill into
    /// `self.fill`; false if `v` cannot be removed.
    fn plan_removal(&mut self, v: u32) -> bool {
        if self.is_corner[v as usize] || !self.kept[v as usize] {
            return false;
        }
        // Each star triangle (v, a, b), counter-clockwise, contributes the link edge a → b.
        let star = &self.incident[v as usize];
        let mut links: Vec<(u32, u32)> = star
            .iter()
            .map(|&s| {
                let t = self.tris[s as usize];
                let k = t.iter().position(|&x| x == v).expect("incident");
                (t[(k + 1) % 3], t[(k + 2) % 3])
            })
            .collect();
        links.sort_unstable();
        // A border vertex's link is an open chain: start where no edge ends.
        let start = links
            .iter()
            .map(|&(a, _)| a)
            .find(|a| links.iter().all(|&(_, b)| b != *a))
            .unwrap_or(links[0].0);
        self.boundary.clear();
        let mut at = start;
        loop {
            self.boundary.push(at);
            match links.binary_search_by_key(&at, |&(a, _)| a) {
                Ok(k) if links[k].1 != start => at = links[k].1,
                Ok(_) => break,
                Err(_) => break,
            }
            if self.boundary.len() > links.len() + 1 {
                return false;
            }
        }
        self.fill.clear();
        hole::fill(&self.boundary, self.lattice, &mut self.fill)
    }

    fn queue_cost(&mut self, v: u32) {
        self.stamp[v as usize] = self.stamp[v as usize].wrapping_add(1);
        if !self.plan_removal(v) {
            return;
        }
        let before: f64 = self.incident[v as usize]
            .iter()
            .map(|&s| self.tri_sum[s as usize])
            .sum();
        let after: f64 = self.fill.iter().map(|&t| self.error_sum(t)).sum();
        // Smallest increase first: the queue pops the largest key.
        self.queue.push(Entry {
            key: -(after - before),
            point: v,
            slot: v,
            stamp: self.stamp[v as usize],
        });
    }

    fn remove(&mut self, v: u32) {
        let planned = self.plan_removal(v);
        debug_assert!(planned, "queued vertices are removable");
        let star = std::mem::take(&mut self.incident[v as usize]);
        for &s in &star {
            for u in self.tris[s as usize] {
                if u != v {
                    self.incident[u as usize].retain(|&x| x != s);
                }
            }
            self.free.push(s);
        }
        self.live -= star.len();
        let fill = std::mem::take(&mut self.fill);
        for &t in &fill {
            let s = match self.free.pop() {
                Some(s) => s,
                None => {
                    self.tris.push([0; 3]);
                    self.tri_sum.push(0.0);
                    (self.tris.len() - 1) as u32
                }
            };
            self.tris[s as usize] = t;
            self.tri_sum[s as usize] = self.error_sum(t);
            for u in t {
                self.incident[u as usize].push(s);
            }
        }
        self.live += fill.len();
        self.fill = fill;
        self.kept[v as usize] = false;
        self.stamp[v as usize] = self.stamp[v as usize].wrapping_add(1);
        let neighbours = self.boundary.clone();
        for u in neighbours {
            self.queue_cost(u);
        }
    }

    fn record_due(&mut self) {
        let mut reached = None;
        while self.next_bound < self.bounds.len() && self.live <= self.bounds[self.next_bound] {
            reached = Some(self.next_bound);
            self.next_bound += 1;
        }
        let Some(last) = reached else { return };
        let kept = self.kept();
        let score = self
            .evaluator
            .score(&kept)
            .expect("kept indices are grid indices");
        let s = Solution { score, kept };
        self.front.offer(s.clone());
        let first = self.recorded.len();
        for k in first..=last {
            self.recorded.push((self.params.reductions[k], s.clone()));
        }
        if self.next_bound == self.bounds.len() {
            self.done = true;
        }
    }

    /// One unit: one removal, or the finding that nothing is left to remove.
    fn advance(&mut self) {
        if self.next_bound == self.bounds.len() {
            self.done = true;
            return;
        }
        let entry = loop {
            match self.queue.pop() {
                None => {
                    self.done = true;
                    return;
                }
                Some(e) if self.stamp[e.slot as usize] == e.stamp => break e,
                Some(_) => {}
            }
        };
        self.remove(entry.point);
        self.removals += 1;
        self.record_due();
    }
}

impl Optimizer for EdgeDecimation {
    /// Unit: one vertex removal (one evaluation).
    fn unit(&mut self) {
        self.advance();
    }

    fn front(&self) -> &Front {
        &self.front
    }

    fn progress(&self) -> Progress {
        Progress {
            evaluations: self.removals,
            generation: self.recorded.len() as u64,
            done: self.done,
        }
    }
}
