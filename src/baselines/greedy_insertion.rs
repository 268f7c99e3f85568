//! Greedy insertion (Garland & Heckbert 1995, after mapbox/delatin).
//!
//! Starts from the four corners and repeatedly inserts the grid point chosen by the
//! [`InsertionRule`], keeping the mesh the canonical Delaunay triangulation of the kept points
//! (the evaluator's, tie rule included). Every triangle caches its candidate and its error
//! totals, both from one pass over the grid points it owns (see the evaluator's `raster`), and
//! sits in a priority queue with one entry per triangle; after an insertion only the triangles
//! that were split or flipped are re-rasterised and re-queued in place.
//!
//! One run gives a whole front: a solution is recorded each time the triangle count first
//! reaches the next value of a geometric sweep from 2 triangles to the full mesh
//! ([`GreedyParams::records`] values, rounded and deduplicated), and once more when the run
//! stops. The numbers of every recorded solution are those of a fresh
//! [`Evaluator::score`](crate::evaluator::Evaluator::score) of its kept set, bit for bit: they
//! are the sums of its triangles' totals, exact fixed-point integers rasterised as the
//! evaluator rasterises them, so a recording costs a pass over the triangles, not the grid.
//!
//! Unit of work: one insertion (one evaluation). [`Progress::generation`] counts the recorded
//! solutions.

use super::ParamsError;
use super::bounded_decimation;
use super::slot_heap::{Item, SlotHeap};
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
use crate::evaluator::exact::predicates::{self, GridPoint};
use crate::evaluator::mesh::canonical_form::canonical;
use crate::evaluator::mesh::canonical_triangulation::Triangulation;
use crate::evaluator::raster::peak::NO_POINT;
use crate::evaluator::raster::peak_finder::PeakFinder;
use crate::evaluator::raster::{Grid, grid_of};
use crate::evaluator::score::Score;
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;
use crate::optimizer::{Optimizer, Progress};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Which point greedy insertion inserts next.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum InsertionRule {
    /// The classic rule: the grid point with the largest vertical error |z − z̃|.
    MaxError,
    /// The paper's objective: the point whose insertion reduces E_sum the most. Computing the
    /// exact reduction of every grid point after every insertion is too dear, so it is done in
    /// two stages:
    /// 1. *Estimate* (cached per triangle, so it never goes stale): in each triangle, the
    ///    [`GreedyParams::candidates`] points with the largest vertical error are scored by the
    ///    exact reduction of Σ|z − z̃| over that triangle's own points when it alone is split at
    ///    the point (no Delaunay flips, neighbours ignored); the best is queued.
    /// 2. *Exact choice*: the [`GreedyParams::shortlist`] best queued estimates are re-scored
    ///    exactly: the Delaunay cavity of the point (the triangles whose circumcircle contains it
    ///    under the tie rule, which are exactly those its insertion replaces) is re-rasterised as
    ///    the fan of new triangles, and the point with the largest true E_sum reduction is
    ///    inserted (ties to the smaller grid index).
    ///
    /// The rule is myopic: inserting a point into large triangles often *raises* E_sum for now
    /// (the new fan tilts towards it), so on terrain it can prefer many tiny safe reductions to
    /// the big features the classic rule takes, and its front can be worse.
    SumReduction,
    /// The point of largest vertical error in the triangle whose error *sum* is largest: for a
    /// sum-type error such as E_sum this spends points where the most error is, not where one
    /// spike is, and tends to give smaller meshes for the same E_sum than
    /// [`InsertionRule::MaxError`].
    WorstTriangle,
}

/// When greedy insertion stops (the recorded front always ends with the final mesh).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind", content = "value")]
pub enum GreedyStop {
    /// Insert every grid point (the last mesh is the full grid, E = 0).
    AllPoints,
    /// Stop once this many points (corners included) are kept.
    Points(usize),
    /// Stop once the mesh has at least this many triangles.
    Triangles(usize),
    /// Stop once E_max ≤ this value (in z units).
    MaxError(f64),
    /// Stop once E_max ≤ this fraction of the z range (max z − min z), e.g. 0.01.
    MaxErrorFraction(f64),
}

/// Parameters of [`GreedyInsertion`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct GreedyParams {
    /// The insertion rule.
    pub rule: InsertionRule,
    /// Candidates per triangle for [`InsertionRule::SumReduction`] (≥ 1; ignored otherwise).
    pub candidates: usize,
    /// When to stop.
    pub stop: GreedyStop,
    /// Queued estimates re-scored exactly before each [`InsertionRule::SumReduction`] insertion
    /// (≥ 1; ignored otherwise).
    pub shortlist: usize,
    /// Number of triangle counts in the geometric recording sweep (≥ 2).
    pub records: usize,
    /// Under an error stop ([`GreedyStop::MaxError`], [`GreedyStop::MaxErrorFraction`]): once
    /// E_max is within the bound, remove every vertex whose removal keeps it so
    /// (`bounded_decimation`) and record that mesh too. Ignored
    /// under other stops.
    #[serde(skip_serializing_if = "is_false")]
    pub decimate: bool,
    /// The error the recorded front is non-dominated in (its insertions do not change). Written
    /// only when not `sum`.
    #[serde(skip_serializing_if = "ErrorMeasure::is_sum")]
    pub error: ErrorMeasure,
}

/// Leaves `decimate: false` out of front.json, as it was before the option existed.
fn is_false(b: &bool) -> bool {
    !*b
}

impl Default for GreedyParams {
    fn default() -> Self {
        Self {
            rule: InsertionRule::MaxError,
            candidates: 4,
            shortlist: 8,
            stop: GreedyStop::AllPoints,
            records: 64,
            decimate: false,
            error: ErrorMeasure::Sum,
        }
    }
}

/// What greedy insertion knows about one triangle, from the one pass that found its candidate.
#[derive(Clone, Copy, Debug, Default)]
struct TriangleInfo {
    /// The error totals over the points it owns (exact, so a mesh's are the sum of its
    /// triangles').
    totals: ErrorTotals,
    /// Σ |z − z̃| over the same points added up in f64 in raster order: the key of
    /// [`InsertionRule::WorstTriangle`] and the sums of [`InsertionRule::SumReduction`]'s gains
    /// (0 under [`InsertionRule::MaxError`], which needs neither).
    float_sum: f64,
}

/// The greedy-insertion optimizer (see the module docs).
pub struct GreedyInsertion {
    hf: Arc<Heightfield>,
    params: GreedyParams,
    /// E_max threshold when stopping on an error, else −∞.
    threshold: f64,
    units: ErrorUnits,
    finder: PeakFinder,
    mesh: Triangulation,
    kept: Vec<bool>,
    kept_count: usize,
    info: Vec<TriangleInfo>,
    /// Max-error candidate of every triangle that owns a point of error above `threshold`
    /// (the others can neither be inserted nor keep the run going: see
    /// [`current_max_error`](Self::current_max_error)).
    by_error: SlotHeap,
    /// Estimated-E_sum-reduction candidates ([`InsertionRule::SumReduction`] only).
    by_gain: SlotHeap,
    /// Each triangle's max-error point keyed by the triangle's error sum
    /// ([`InsertionRule::WorstTriangle`] only).
    by_sum: SlotHeap,
    /// The triangle counts to record at, increasing; `next_target` indexes the next one.
    targets: Vec<usize>,
    next_target: usize,
    front: Front,
    recorded: Vec<Solution>,
    last_recorded_points: usize,
    insertions: u64,
    /// Vertices the bounded decimation removed ([`GreedyParams::decimate`]).
    removed: usize,
    /// Whether the decimation leaves the grid's border vertices (a tile's shared ones).
    keep_border: bool,
    done: bool,
    stack: Vec<u32>,
    changed: Vec<u32>,
    top: Vec<(f64, u32)>,
}

impl GreedyInsertion {
    /// A run on `hf` from the four corners. Refuses parameters out of range.
    pub fn new(hf: Arc<Heightfield>, params: GreedyParams) -> Result<Self, ParamsError> {
        Self::from_kept(hf, params, &[])
    }

    /// A run on `hf` that starts from the mesh of `kept` (grid indices, any order, the corners
    /// added when missing) instead of the corners alone: how a member of a front is refined
    /// by exact insertions of its worst points. Refuses parameters out of range and indices
    /// off the grid (as [`ParamsError::OutOfRange`] of `kept`).
    pub(crate) fn from_kept(
        hf: Arc<Heightfield>,
        params: GreedyParams,
        kept: &[u32],
    ) -> Result<Self, ParamsError> {
        if let Some(&bad) = kept.iter().find(|&&i| i as usize >= hf.len()) {
            return Err(ParamsError::OutOfRange {
                name: "kept",
                value: bad as f64,
                allowed: "grid indices below W·H",
            });
        }
        if params.records < 2 {
            return Err(ParamsError::OutOfRange {
                name: "records",
                value: params.records as f64,
                allowed: "at least 2",
            });
        }
        if params.candidates < 1 {
            return Err(ParamsError::OutOfRange {
                name: "candidates",
                value: params.candidates as f64,
                allowed: "at least 1",
            });
        }
        if params.shortlist < 1 {
            return Err(ParamsError::OutOfRange {
                name: "shortlist",
                value: params.shortlist as f64,
                allowed: "at least 1",
            });
        }
        let (lo, hi) = hf.z_range();
        let threshold = match params.stop {
            GreedyStop::MaxError(e) if !(e >= 0.0 && e.is_finite()) => {
                return Err(ParamsError::OutOfRange {
                    name: "stop max-error",
                    value: e,
                    allowed: "a finite number ≥ 0",
                });
            }
            GreedyStop::MaxErrorFraction(f) if !(f >= 0.0 && f.is_finite()) => {
                return Err(ParamsError::OutOfRange {
                    name: "stop max-error-fraction",
                    value: f,
                    allowed: "a finite number ≥ 0",
                });
            }
            GreedyStop::MaxError(e) if e > 0.0 && e < exactness_floor(&hf) => {
                return Err(ParamsError::OutOfRange {
                    name: "stop max-error",
                    value: e,
                    allowed: "0 (an exact mesh) or at least the grid's exactness floor, max |z|·2⁻⁴⁰: smaller errors are the interpolation's rounding",
                });
            }
            GreedyStop::MaxError(e) => e,
            GreedyStop::MaxErrorFraction(f) => f * (hi - lo),
            _ => f64::NEG_INFINITY,
        };
        let full = hf.full_triangles();
        let records = params.records;
        // Geometric sweep 2 → full: 2·(full/2)^(k/(records−1)).
        let mut targets: Vec<usize> = (0..records)
            .map(|k| {
                let f = k as f64 / (records - 1) as f64;
                ((2.0 * (full as f64 / 2.0).powf(f)).round() as usize).clamp(2, full)
            })
            .collect();
        targets.dedup();
        let mut start: Vec<u32> = hf.corners().to_vec();
        start.extend_from_slice(kept);
        start.sort_unstable();
        start.dedup();
        let mut kept = vec![false; hf.len()];
        for &c in &start {
            kept[c as usize] = true;
        }
        let kept_count = start.len();
        let mut mesh = Triangulation::default();
        mesh.rebuild_delaunay(hf.width(), &start);
        let units = ErrorUnits::of(&hf);
        let float_sum = params.rule != InsertionRule::MaxError;
        let measure = params.error;
        let mut run = Self {
            finder: PeakFinder::new(units, float_sum),
            units,
            hf,
            params,
            threshold,
            mesh,
            kept,
            kept_count,
            info: Vec::new(),
            by_error: SlotHeap::default(),
            by_gain: SlotHeap::default(),
            by_sum: SlotHeap::default(),
            targets,
            next_target: 0,
            front: Front::new(measure),
            recorded: Vec::new(),
            last_recorded_points: 0,
            insertions: 0,
            removed: 0,
            keep_border: false,
            done: false,
            stack: Vec::new(),
            changed: Vec::new(),
            top: Vec::new(),
        };
        let all: Vec<u32> = (0..run.mesh.len() as u32).collect();
        run.rasterise(&all);
        run.record_if_due();
        Ok(run)
    }

    /// Makes the bounded decimation ([`GreedyParams::decimate`]) leave every vertex on the
    /// grid's border: on a tile, those are shared with its neighbours.
    pub(crate) fn keep_border_in_decimation(&mut self) {
        self.keep_border = true;
    }

    /// How many vertices the bounded decimation removed (0 until it has run).
    pub fn removed(&self) -> usize {
        self.removed
    }

    /// The parameters.
    pub fn params(&self) -> &GreedyParams {
        &self.params
    }

    /// Every recorded solution in recording order (increasing T), dominated ones included.
    pub(crate) fn recorded(&self) -> &[Solution] {
        &self.recorded
    }

    /// The current mesh's triangles (grid-index triples, counter-clockwise).
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.mesh.triangles()
    }

    /// The currently kept grid indices, increasing.
    pub(crate) fn kept(&self) -> Vec<u32> {
        let mut kept = Vec::with_capacity(self.kept_count);
        // Whole words of unkept points are skipped at once: at 1 % of the z range a large
        // grid keeps about one point in ten, and a recording lists them all.
        let mut chunks = self.kept.chunks_exact(8);
        let mut base = 0u32;
        for chunk in &mut chunks {
            if chunk.iter().any(|&k| k) {
                kept.extend((0..8).filter(|&j| chunk[j as usize]).map(|j| base + j));
            }
            base += 8;
        }
        let rest = chunks.remainder();
        kept.extend(
            (0..rest.len() as u32)
                .filter(|&j| rest[j as usize])
                .map(|j| base + j),
        );
        kept
    }

    /// E_sum of the current mesh from the triangles' totals: the evaluator's bits for the
    /// current kept set.
    pub fn incremental_e_sum(&self) -> f64 {
        self.current_score().e_sum
    }

    /// The score of the current mesh: a fresh [`Evaluator::score`](crate::evaluator::Evaluator::score)
    /// of [`kept`](Self::kept), bit for bit.
    pub(crate) fn score(&self) -> Score {
        self.current_score()
    }

    /// The grid point the max-error rule inserts next (the one of largest vertical error, ties
    /// to the smaller index), or `None` when every point within the stopping threshold is kept.
    pub(crate) fn worst_point(&self) -> Option<u32> {
        self.by_error.top().map(|e| e.point)
    }

    /// The largest vertical error of the current mesh and the point that has it (ties to the
    /// smaller index), or `None` when every point within the stopping threshold is kept.
    pub(crate) fn worst(&self) -> Option<(f64, u32)> {
        self.by_error.top().map(|e| (e.key, e.point))
    }

    /// Inserts grid point `point` (not kept) whatever its error: how a tile takes a point its
    /// neighbour inserted on their shared border line. Returns false, inserting nothing, when
    /// `point` is kept already or off the grid.
    pub(crate) fn insert_at(&mut self, point: u32) -> bool {
        if self.kept.get(point as usize) != Some(&false) {
            return false;
        }
        let q = self.point(point);
        let slot = (0..self.mesh.len() as u32).find(|&t| {
            let [a, b, c] = self.mesh.triangle(t as usize).map(|i| self.point(i));
            predicates::orient(a, b, q) >= 0
                && predicates::orient(b, c, q) >= 0
                && predicates::orient(c, a, q) >= 0
        });
        let Some(slot) = slot else {
            return false;
        };
        self.insert(slot, point);
        true
    }

    /// The current mesh's triangle count.
    pub(crate) fn triangle_count(&self) -> usize {
        self.mesh.len()
    }

    /// The largest vertical error of the current mesh (0 when every point is kept).
    pub(crate) fn current_max_error(&mut self) -> f64 {
        match self.by_error.top() {
            Some(e) => e.key,
            // Every error is within the threshold (or zero): the largest is a triangle's.
            None => self.info[..self.mesh.len()]
                .iter()
                .fold(0.0, |m, i| if i.totals.max > m { i.totals.max } else { m }),
        }
    }

    /// The score of the current mesh, from its triangles' totals: the sums are exact integers,
    /// so this is what a fresh [`Evaluator::score`](crate::evaluator::Evaluator::score) of the
    /// kept set gives, bit for bit (the mesh is its canonical triangulation, and each
    /// triangle's totals were rasterised from its canonical rotation as the evaluator's are).
    fn current_score(&self) -> Score {
        let mut all = ErrorTotals::default();
        for i in &self.info[..self.mesh.len()] {
            all.add(&i.totals);
        }
        Score::from_values(self.units.values(&all), self.hf.len(), self.mesh.len())
    }

    fn grid(&self) -> Grid<'_> {
        Grid {
            width: self.hf.width() as i64,
            height: self.hf.height() as i64,
            z: self.hf.z(),
        }
    }

    fn point(&self, i: u32) -> GridPoint {
        self.mesh.lattice().point(i)
    }

    /// Triangle `t`'s corners in the evaluator's rotation ([`canonical`]), so that its errors
    /// are the evaluator's bits.
    fn corners_of(&self, t: u32) -> [GridPoint; 3] {
        canonical(self.mesh.triangle(t as usize)).map(|i| self.point(i))
    }

    /// Recomputes the totals and candidates of the triangles `slots` and queues them (a
    /// triangle that owns no point leaves the queues).
    fn rasterise(&mut self, slots: &[u32]) {
        let len = self.mesh.len();
        if self.info.len() < len {
            self.info.resize(len, TriangleInfo::default());
        }
        let grid = grid_of(&self.hf);
        let lattice = self.mesh.lattice();
        let mesh = &self.mesh;
        // First touch what rasterising and re-queuing each triangle reads first: its vertices'
        // heights, its info and its queue entry. Why: on a large grid each of these is a cache
        // miss; here the reads are independent, so the misses overlap, whereas in the loop
        // below each triangle's misses wait for the previous triangle's work.
        let mut touched = 0.0;
        for &t in slots {
            let [a, b, c] = mesh.triangle(t as usize).map(|v| grid.z[v as usize]);
            touched += a + b + c + self.info[t as usize].float_sum + self.by_error.key_of(t);
        }
        std::hint::black_box(touched);
        let tris = slots.iter().map(|&t| {
            (
                t,
                canonical(mesh.triangle(t as usize)).map(|i| lattice.point(i)),
            )
        });
        let (info, by_error, by_sum) = (&mut self.info, &mut self.by_error, &mut self.by_sum);
        let worst_triangle = self.params.rule == InsertionRule::WorstTriangle;
        let threshold = self.threshold;
        self.finder.peaks(&grid, tris, |t, peak| {
            info[t as usize] = TriangleInfo {
                totals: peak.totals,
                float_sum: peak.float_sum,
            };
            if peak.at == NO_POINT {
                by_error.remove(t);
                by_sum.remove(t);
                return;
            }
            // A point within the threshold is never inserted under the max-error rule (the run
            // stops first), and a queue with nothing above it stops the run as its top would.
            // Leaving such triangles out keeps the heap small once most of the mesh is done.
            if peak.totals.max > threshold {
                by_error.set(Item {
                    key: peak.totals.max,
                    point: peak.at,
                    slot: t,
                });
            } else {
                by_error.remove(t);
            }
            if worst_triangle {
                by_sum.set(Item {
                    key: peak.float_sum,
                    point: peak.at,
                    slot: t,
                });
            }
        });
        if self.params.rule == InsertionRule::SumReduction {
            for &t in slots {
                self.queue_gain(t);
            }
        }
    }

    /// Queues triangle `t`'s estimated-reduction candidate ([`InsertionRule::SumReduction`]):
    /// the best split of its [`GreedyParams::candidates`] points of largest error.
    fn queue_gain(&mut self, t: u32) {
        let mut top = std::mem::take(&mut self.top);
        let tri = self.corners_of(t);
        let z = self.hf.z();
        let grid = self.grid();
        let k = self.params.candidates;
        // The k points of largest error, largest first, ties to the smaller index (points are
        // visited in increasing index order, so a later equal error never displaces).
        top.clear();
        grid.for_each_point(tri, |i, zt| {
            let d = (z[i] - zt).abs();
            if top.len() < k || d > top[top.len() - 1].0 {
                let at = top.partition_point(|&(e, _)| e >= d);
                top.insert(at, (d, i as u32));
                top.truncate(k);
            }
        });
        let sum = self.info[t as usize].float_sum;
        let best = top
            .iter()
            .map(|&(_, p)| (sum - self.split_sum(tri, p), p))
            .fold(None, |best: Option<(f64, u32)>, (g, p)| match best {
                Some((bg, bp)) if bg > g || (bg == g && bp < p) => Some((bg, bp)),
                _ => Some((g, p)),
            });
        match best {
            Some((gain, p)) => self.by_gain.set(Item {
                key: gain,
                point: p,
                slot: t,
            }),
            None => self.by_gain.remove(t),
        }
        self.top = top;
    }

    /// Σ|z − z̃| over the points of triangle `tri` once it is split at its owned point `p`.
    fn split_sum(&self, tri: [GridPoint; 3], p: u32) -> f64 {
        let grid = self.grid();
        let q = self.point(p);
        let [a, b, c] = tri;
        let parts = [[a, b, q], [b, c, q], [c, a, q]];
        parts
            .iter()
            // A part is empty when q lies on that edge of the triangle.
            .filter(|s| predicates::orient(s[0], s[1], s[2]) != 0)
            .map(|&s| grid.triangle_error(s).sum)
            .sum()
    }

    /// Pops the shortlist of estimates, returns the one with the largest exact E_sum reduction
    /// (key = that reduction) and queues the others back unchanged.
    fn best_of_shortlist(&mut self) -> Option<Item> {
        let mut list = Vec::with_capacity(self.params.shortlist);
        while list.len() < self.params.shortlist {
            let Some(e) = self.by_gain.pop() else {
                break;
            };
            list.push(e);
        }
        let mut best: Option<(Item, f64)> = None;
        for &e in &list {
            let gain = self.exact_gain(e.slot, e.point);
            let better = match best {
                None => true,
                Some((b, g)) => gain > g || (gain == g && e.point < b.point),
            };
            if better {
                best = Some((e, gain));
            }
        }
        let (chosen, gain) = best?;
        for e in list {
            if e.point != chosen.point {
                self.by_gain.set(e);
            }
        }
        Some(Item {
            key: gain,
            ..chosen
        })
    }

    /// The exact reduction of E_sum if grid point `p`, owned by triangle `t`, were inserted:
    /// Σ over its Delaunay cavity of the cached sums minus Σ over the fan of new triangles
    /// (f64 sums: only under a rule that keeps them, [`InsertionRule::MaxError`] does not).
    pub(crate) fn exact_gain(&mut self, t: u32, p: u32) -> f64 {
        use crate::evaluator::mesh::canonical_triangulation::{NONE, next};
        let q = self.point(p);
        let mut cavity = std::mem::take(&mut self.changed);
        cavity.clear();
        cavity.push(t);
        let mut k = 0;
        // Flood fill from the owner: a neighbour joins when `p` is in its circumcircle.
        while k < cavity.len() {
            let c = cavity[k];
            k += 1;
            for e in 3 * c..3 * c + 3 {
                let f = self.mesh.twin[e as usize];
                if f == NONE || cavity.contains(&(f / 3)) {
                    continue;
                }
                let ids = self.mesh.triangle((f / 3) as usize);
                let pts = ids.map(|i| self.point(i));
                if predicates::in_circle([pts[0], pts[1], pts[2], q], [ids[0], ids[1], ids[2], p]) {
                    cavity.push(f / 3);
                }
            }
        }
        let grid = self.grid();
        let mut before = 0.0;
        let mut after = 0.0;
        for &c in &cavity {
            before += self.info[c as usize].float_sum;
            for e in 3 * c..3 * c + 3 {
                let f = self.mesh.twin[e as usize];
                if f != NONE && cavity.contains(&(f / 3)) {
                    continue;
                }
                let a = self.point(self.mesh.vertices[e as usize]);
                let b = self.point(self.mesh.vertices[next(e) as usize]);
                // A boundary edge through `p` (p on the grid border) makes no triangle.
                if predicates::orient(a, b, q) != 0 {
                    after += grid.triangle_error([a, b, q]).sum;
                }
            }
        }
        self.changed = cavity;
        before - after
    }

    fn should_stop(&mut self) -> bool {
        match self.params.stop {
            GreedyStop::AllPoints => false,
            GreedyStop::Points(n) => self.kept_count >= n,
            GreedyStop::Triangles(n) => self.mesh.len() >= n,
            GreedyStop::MaxError(_) | GreedyStop::MaxErrorFraction(_) => {
                self.current_max_error() <= self.threshold
            }
        }
    }

    /// One unit: one insertion, or the decision to stop.
    fn advance(&mut self) {
        let chosen = if self.should_stop() {
            None
        } else {
            match self.params.rule {
                InsertionRule::MaxError => self.by_error.top(),
                InsertionRule::SumReduction => self.best_of_shortlist(),
                InsertionRule::WorstTriangle => self.by_sum.top(),
            }
        };
        let Some(entry) = chosen else {
            self.finish();
            return;
        };
        self.insert(entry.slot, entry.point);
    }

    /// Inserts grid point `point`, which triangle `slot` holds, and updates the queues.
    fn insert(&mut self, slot: u32, point: u32) {
        let mut changed = std::mem::take(&mut self.changed);
        changed.clear();
        self.mesh
            .insert_point(slot, point, &mut self.stack, |s| changed.push(s));
        self.kept[point as usize] = true;
        self.kept_count += 1;
        self.insertions += 1;
        changed.sort_unstable();
        changed.dedup();
        self.rasterise(&changed);
        self.changed = changed;
        self.record_if_due();
    }

    fn record_if_due(&mut self) {
        let t = self.mesh.len();
        if self.next_target < self.targets.len() && t >= self.targets[self.next_target] {
            while self.next_target < self.targets.len() && t >= self.targets[self.next_target] {
                self.next_target += 1;
            }
            self.record();
        }
    }

    fn record(&mut self) {
        if self.last_recorded_points == self.kept_count {
            return;
        }
        let s = Solution {
            score: self.current_score(),
            kept: self.kept(),
        };
        self.last_recorded_points = self.kept_count;
        self.front.offer(s.clone());
        self.recorded.push(s);
    }

    fn finish(&mut self) {
        self.record();
        if self.params.decimate && self.threshold >= 0.0 {
            self.decimate();
            self.record();
        }
        self.done = true;
    }

    /// Bounded-error decimation of the final mesh to the stop's threshold.
    fn decimate(&mut self) {
        let len = self.mesh.len();
        let mut totals: Vec<ErrorTotals> = self.info[..len].iter().map(|i| i.totals).collect();
        let removed = bounded_decimation::decimate(
            &self.hf,
            &mut self.mesh,
            &mut totals,
            &mut self.kept,
            self.threshold,
            self.keep_border,
        );
        self.kept_count -= removed;
        self.removed = removed;
        // The max-error queue is empty at an error stop (it holds only triangles above the
        // threshold); the others would name slots that moved, and the run is over.
        self.by_gain = SlotHeap::default();
        self.by_sum = SlotHeap::default();
        self.info = totals
            .into_iter()
            .map(|totals| TriangleInfo {
                totals,
                float_sum: 0.0,
            })
            .collect();
    }
}

impl Optimizer for GreedyInsertion {
    /// Unit: one insertion (one evaluation).
    fn unit(&mut self) {
        self.advance();
    }

    fn front(&self) -> &Front {
        &self.front
    }

    fn progress(&self) -> Progress {
        Progress {
            evaluations: self.insertions,
            generation: self.recorded.len() as u64,
            done: self.done,
        }
    }
}

/// The smallest positive max error worth asking of `hf`: errors are interpolated in f64, whose
/// rounding at heights of magnitude M reaches a few units of M·2⁻⁵², so a bound below M·2⁻⁴⁰
/// would tell rounding apart rather than surfaces. 0 (an exact mesh) is always allowed.
pub fn exactness_floor(hf: &Heightfield) -> f64 {
    let (lo, hi) = hf.z_range();
    lo.abs().max(hi.abs()) * 2f64.powi(-40)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::Evaluator;
    use crate::import::raw;

    fn camera() -> Arc<Heightfield> {
        let data = include_bytes!("../../tests/data/camera_33x33.f32");
        let json = include_bytes!("../../tests/data/camera_33x33.json");
        Arc::new(raw::parse(data, json, "camera_33x33").unwrap())
    }

    #[test]
    fn exact_gain_is_the_true_change_of_e_sum() {
        // For the first 300 insertions of a real grid, the cavity-based reduction of each
        // triangle's max-error point (inside triangles, on shared edges and on the border) must
        // equal the evaluator's E_sum before minus after inserting it.
        // (Under the E_sum rule, which keeps the f64 sums the gains are made of.)
        let hf = camera();
        let params = GreedyParams {
            rule: InsertionRule::SumReduction,
            ..GreedyParams::default()
        };
        let mut run = GreedyInsertion::new(hf.clone(), params).unwrap();
        let mut ev = Evaluator::new(hf.clone());
        let mut checked = 0;
        for _ in 0..300 {
            let kept = run.kept();
            let before = ev.score(&kept).unwrap().e_sum;
            let entries: Vec<Item> = run.by_error.items().iter().copied().take(5).collect();
            for e in entries {
                let gain = run.exact_gain(e.slot, e.point);
                let mut with = kept.clone();
                with.push(e.point);
                let after = ev.score(&with).unwrap().e_sum;
                assert!(
                    (gain - (before - after)).abs() <= 1e-9 * before.max(1.0),
                    "point {}: gain {gain}, true {}",
                    e.point,
                    before - after
                );
                checked += 1;
            }
            run.step(1);
        }
        assert!(checked > 1000);
    }

    #[test]
    fn sum_reduction_inserts_the_best_exact_gain_of_its_shortlist() {
        // With a shortlist as long as the number of triangles, the E_sum rule picks the best
        // exact reduction among every triangle's estimate, so no queued point may beat it.
        let hf = camera();
        let params = GreedyParams {
            rule: InsertionRule::SumReduction,
            shortlist: 10_000,
            ..GreedyParams::default()
        };
        let mut run = GreedyInsertion::new(hf.clone(), params).unwrap();
        let mut ev = Evaluator::new(hf.clone());
        for _ in 0..40 {
            let before = ev.score(&run.kept()).unwrap().e_sum;
            let entries: Vec<Item> = run.by_gain.items().to_vec();
            let best = entries
                .iter()
                .map(|e| run.exact_gain(e.slot, e.point))
                .fold(f64::NEG_INFINITY, f64::max);
            run.step(1);
            let after = ev.score(&run.kept()).unwrap().e_sum;
            assert!((before - after - best).abs() <= 1e-9 * before);
        }
    }
}
