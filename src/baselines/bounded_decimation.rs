//! Bounded-error decimation: from a mesh whose E_max is at most a bound X, remove kept vertices
//! one at a time, always the one whose removal leaves the smallest largest error in its hole,
//! for as long as some removal keeps E_max ≤ X.
//!
//! Why: greedy insertion to a bound (hmm's method) places each point knowing only the mesh so
//! far, so its final mesh holds points that later insertions made unnecessary. Removing them
//! keeps the same bound with fewer triangles.
//!
//! Exact and local: removing vertex v changes only its star, which is replaced by the canonical
//! Delaunay triangulation of the star's boundary ([`hole_fill`]), as the evaluator's incremental
//! edit does. The new triangles own exactly the grid points the star owned, and are rasterised
//! from their canonical rotation with the evaluator's kernel, so their error totals are the
//! evaluator's bits; every other triangle keeps its totals. A removal is made only when the
//! largest error of its new triangles is at most X, so E_max never exceeds X.

use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
use crate::evaluator::mesh::canonical_form::canonical;
use crate::evaluator::mesh::canonical_triangulation::{NONE, Triangulation};
use crate::evaluator::mesh::hole_fill;
use crate::evaluator::raster::grid_of;
use crate::heightfield::Heightfield;
use crate::lazy_queue::Entry;
use std::collections::BinaryHeap;

/// A decimation of one mesh (see the module doc); [`decimate`] runs it.
struct Decimation<'a> {
    hf: &'a Heightfield,
    units: ErrorUnits,
    bound: f64,
    mesh: &'a mut Triangulation,
    /// Each slot's error totals.
    totals: &'a mut Vec<ErrorTotals>,
    kept: &'a mut [bool],
    corners: [u32; 4],
    /// Whether vertices on the grid's border stay (a tile's, shared with its neighbours).
    keep_border: bool,
    /// Per grid point: a live slot that has it as a vertex (kept points only).
    hint: Vec<u32>,
    /// Per grid point: the version of its latest queued cost.
    version: Vec<u32>,
    queue: BinaryHeap<Entry>,
    /// Slots emptied by removals, filled again by [`Decimation::compact`].
    dead: Vec<u32>,
    star: Vec<u32>,
    boundary: Vec<u32>,
    outer: Vec<u32>,
    fill: Vec<[u32; 3]>,
    fill_totals: Vec<ErrorTotals>,
    diagonals: Vec<(usize, usize, u32)>,
}

/// Removes kept vertices of `mesh` (the canonical triangulation of the points `kept` marks,
/// with `totals` its slots' error totals on `hf`) while E_max stays ≤ `bound`, cheapest hole
/// first (ties to the smaller grid index), and compacts the slots. The mesh's E_max must be ≤
/// `bound` already. With `keep_border`, no vertex on the grid's border is removed: on a tile,
/// those are shared with its neighbours. Returns how many vertices went.
pub(crate) fn decimate(
    hf: &Heightfield,
    mesh: &mut Triangulation,
    totals: &mut Vec<ErrorTotals>,
    kept: &mut [bool],
    bound: f64,
    keep_border: bool,
) -> usize {
    debug_assert!(totals[..mesh.len()].iter().all(|t| t.max <= bound));
    let mut hint = vec![NONE; hf.len()];
    for t in 0..mesh.len() {
        for v in mesh.triangle(t) {
            hint[v as usize] = t as u32;
        }
    }
    let mut run = Decimation {
        hf,
        units: ErrorUnits::of(hf),
        bound,
        mesh,
        totals,
        kept,
        corners: hf.corners(),
        keep_border,
        hint,
        version: vec![0; hf.len()],
        queue: BinaryHeap::new(),
        dead: Vec::new(),
        star: Vec::new(),
        boundary: Vec::new(),
        outer: Vec::new(),
        fill: Vec::new(),
        fill_totals: Vec::new(),
        diagonals: Vec::new(),
    };
    for v in 0..hf.len() as u32 {
        if run.kept[v as usize] && !run.fixed(v) {
            run.queue_cost(v);
        }
    }
    let mut removed = 0;
    while let Some(entry) = run.queue.pop() {
        let v = entry.point;
        if entry.stamp != run.version[v as usize] || !run.kept[v as usize] {
            continue;
        }
        // The cost is current: nothing near v changed since it was measured, so the trial
        // gives the same hole and fill again, ready to apply.
        let worst = run.trial(v);
        debug_assert_eq!(worst, Some(-entry.key));
        if worst.is_none_or(|w| w > run.bound) {
            continue;
        }
        run.apply(v);
        removed += 1;
        // Each neighbour's star changed: measure it again (a trial overwrites the boundary).
        let neighbours = std::mem::take(&mut run.boundary);
        for &u in &neighbours {
            if !run.fixed(u) {
                run.queue_cost(u);
            }
        }
        run.boundary = neighbours;
    }
    run.compact();
    removed
}

impl Decimation<'_> {
    /// Whether vertex `v` must stay: a corner, or on the border when that is kept.
    fn fixed(&self, v: u32) -> bool {
        if self.corners.contains(&v) {
            return true;
        }
        let (w, h) = (self.hf.width() as u32, self.hf.height() as u32);
        let (x, y) = (v % w, v / w);
        self.keep_border && (x == 0 || y == 0 || x + 1 == w || y + 1 == h)
    }

    /// Measures removing `v` and queues it when the removal keeps E_max ≤ the bound,
    /// superseding any earlier entry.
    fn queue_cost(&mut self, v: u32) {
        let version = &mut self.version[v as usize];
        *version = version.wrapping_add(1);
        let stamp = *version;
        if let Some(worst) = self.trial(v)
            && worst <= self.bound
        {
            self.queue.push(Entry {
                key: -worst,
                point: v,
                slot: v,
                stamp,
            });
        }
    }

    /// Collects `v`'s star, its hole's boundary and fill, and the fill's error totals (in the
    /// scratch buffers); returns the largest error of the fill (or a number above the bound
    /// when it is, the totals then left unmade), or `None` when the hole has no Delaunay fill
    /// (which a canonical mesh never gives).
    fn trial(&mut self, v: u32) -> Option<f64> {
        let m = &*self.mesh;
        let leaving = m
            .leaving(self.hint[v as usize], v)
            .expect("a kept point's hint is a triangle of its star");
        m.star_of(leaving, &mut self.star, &mut self.boundary, &mut self.outer);
        // The fill interpolates v's own point between boundary heights, so its error there is
        // at least z_v's distance from their range: beyond the bound, no fill is needed.
        let z = self.hf.z();
        let zv = z[v as usize];
        let (lo, hi) =
            self.boundary
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &b| {
                    let zb = z[b as usize];
                    (lo.min(zb), hi.max(zb))
                });
        let slack = 4.0 * f64::EPSILON * zv.abs().max(lo.abs()).max(hi.abs());
        let outside = (zv - hi).max(lo - zv);
        if outside > self.bound + slack {
            return Some(outside);
        }
        self.fill.clear();
        let lattice = m.lattice();
        if !hole_fill::fill(&self.boundary, lattice, &mut self.fill) {
            return None;
        }
        // Most removals are refused: an error above the bound is looked for first, point by
        // point, before a fill within it is summed.
        let grid = grid_of(self.hf);
        let bound = self.bound;
        if self
            .fill
            .iter()
            .any(|&tri| grid.any_error_above(canonical(tri).map(|i| lattice.point(i)), bound))
        {
            return Some(f64::INFINITY);
        }
        self.fill_totals.clear();
        self.fill_totals
            .resize(self.fill.len(), ErrorTotals::default());
        let fill_totals = &mut self.fill_totals;
        grid.sum_triangles(
            self.units,
            self.fill
                .iter()
                .enumerate()
                .map(|(j, &tri)| (j, canonical(tri).map(|i| lattice.point(i)))),
            |j, t| fill_totals[j] = t,
        );
        Some(
            self.fill_totals
                .iter()
                .fold(0.0, |w, t| if t.max > w { t.max } else { w }),
        )
    }

    /// Replaces `v`'s star by the fill [`trial`](Self::trial) just made: the fill's triangles
    /// take the star's first slots, linked to the hole's outside and to each other; the other
    /// slots die.
    fn apply(&mut self, v: u32) {
        let m = &mut *self.mesh;
        let b = &self.boundary;
        let links = self.outer.len();
        for (j, &slot) in self.star.iter().enumerate() {
            let base = 3 * slot as usize;
            match self.fill.get(j) {
                Some(tri) => {
                    m.vertices[base..base + 3].copy_from_slice(tri);
                    self.totals[slot as usize] = self.fill_totals[j];
                    for &u in tri {
                        self.hint[u as usize] = slot;
                    }
                }
                None => {
                    m.vertices[base..base + 3].fill(NONE);
                    m.twin[base..base + 3].fill(NONE);
                    self.totals[slot as usize] = ErrorTotals::default();
                    self.dead.push(slot);
                }
            }
        }
        // A boundary edge bᵢ → bᵢ₊₁ links to the hole's outside (or to nothing: the border
        // segment that closes a border vertex's chain), a diagonal to its reverse.
        let diagonals = &mut self.diagonals;
        diagonals.clear();
        for (j, &slot) in self.star[..self.fill.len()].iter().enumerate() {
            let at = self.fill[j].map(|u| {
                b.iter()
                    .position(|&x| x == u)
                    .expect("the fill's vertices are the boundary's")
            });
            for k in 0..3 {
                let h = 3 * slot + k as u32;
                let (from, to) = (at[k], at[(k + 1) % 3]);
                let successor = if from + 1 == b.len() { 0 } else { from + 1 };
                let twin = if to == successor {
                    if from < links { self.outer[from] } else { NONE }
                } else if let Some(q) = diagonals.iter().position(|d| (d.0, d.1) == (to, from)) {
                    diagonals.swap_remove(q).2
                } else {
                    diagonals.push((from, to, h));
                    continue;
                };
                m.twin[h as usize] = twin;
                if twin != NONE {
                    m.twin[twin as usize] = h;
                }
            }
        }
        debug_assert!(diagonals.is_empty(), "every diagonal has two sides");
        self.kept[v as usize] = false;
    }

    /// Moves the last live triangles into the dead slots, so that slots are `0..T` again.
    fn compact(&mut self) {
        let m = &mut *self.mesh;
        self.dead.sort_unstable();
        let mut len = m.len();
        let live_end = |m: &Triangulation, mut len: usize| {
            while len > 0 && m.vertices[3 * (len - 1)] == NONE {
                len -= 1;
            }
            len
        };
        for &d in &self.dead {
            len = live_end(m, len);
            let d = d as usize;
            if d >= len {
                break;
            }
            let s = len - 1;
            for k in 0..3 {
                m.vertices[3 * d + k] = m.vertices[3 * s + k];
                let f = m.twin[3 * s + k];
                m.twin[3 * d + k] = f;
                if f != NONE {
                    m.twin[f as usize] = (3 * d + k) as u32;
                }
                m.vertices[3 * s + k] = NONE;
                m.twin[3 * s + k] = NONE;
            }
            self.totals[d] = self.totals[s];
            len -= 1;
        }
        let len = live_end(m, len);
        m.vertices.truncate(3 * len);
        m.twin.truncate(3 * len);
        self.totals.truncate(len);
    }
}

#[cfg(test)]
mod tests {
    use crate::baselines::{GreedyInsertion, GreedyParams, GreedyStop};
    use crate::evaluator::Evaluator;
    use crate::evaluator::mesh::canonical_form::canonical_set;
    use crate::heightfield::Heightfield;
    use crate::optimizer::Optimizer;
    use rand::{RngExt, SeedableRng};
    use std::path::Path;
    use std::sync::Arc;

    fn fixture(name: &str) -> Arc<Heightfield> {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(format!("{name}.f32"));
        Arc::new(crate::import::load(&path).unwrap())
    }

    /// A rough 41×37 grid with terraces and a wall: flat runs and exact ties in the errors.
    fn rough() -> Arc<Heightfield> {
        let (w, h) = (41usize, 37usize);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let z = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64, (i / w) as f64);
                let wall = if x > 20.0 && y < 25.0 { 30.0 } else { 0.0 };
                (0.3 * x + 0.2 * y).floor() * 4.0 + wall + (rng.random::<f64>() * 3.0).floor()
            })
            .collect();
        Arc::new(Heightfield::new(w, h, z).unwrap())
    }

    fn run(hf: &Arc<Heightfield>, bound: f64, decimate: bool) -> GreedyInsertion {
        let params = GreedyParams {
            stop: GreedyStop::MaxError(bound),
            decimate,
            ..GreedyParams::default()
        };
        let mut run = GreedyInsertion::new(hf.clone(), params).unwrap();
        run.run_to_end();
        run
    }

    /// The decimated mesh is the canonical triangulation of its kept set, its recorded score is
    /// a fresh score's bits, it keeps E_max within the bound, has no more triangles than the
    /// greedy mesh it came from, and no single kept vertex could go without breaking the bound
    /// (each checked by a fresh score of the kept set without it).
    #[test]
    fn decimation_keeps_the_bound_exactly_and_leaves_no_removable_vertex() {
        let grids = [
            fixture("camera_33x33"),
            fixture("volcano_33x33"),
            fixture("jacksboro_65x65"),
            rough(),
        ];
        let mut fewer = 0;
        for hf in grids {
            let (lo, hi) = hf.z_range();
            let mut ev = Evaluator::new(hf.clone());
            for fraction in [0.0, 0.01, 0.05, 0.2] {
                let bound = fraction * (hi - lo);
                let greedy = run(&hf, bound, false);
                let decimated = run(&hf, bound, true);
                let last = decimated.recorded().last().unwrap();
                let kept = decimated.kept();
                assert_eq!(last.kept, kept);
                let fresh = ev.evaluate(&kept).unwrap();
                assert_eq!(last.score.e_sum.to_bits(), fresh.score.e_sum.to_bits());
                assert_eq!(last.score.e_max.to_bits(), fresh.score.e_max.to_bits());
                assert_eq!(last.score.rms.to_bits(), fresh.score.rms.to_bits());
                assert_eq!(last.score.t, fresh.score.t);
                assert_eq!(
                    canonical_set(&decimated.triangles()),
                    canonical_set(&fresh.triangles)
                );
                assert!(
                    fresh.score.e_max <= bound,
                    "{} > {bound}",
                    fresh.score.e_max
                );
                let before = greedy.recorded().last().unwrap().score.t;
                assert!(last.score.t <= before);
                fewer += usize::from(last.score.t < before);
                // Every kept vertex on the small grids, every seventh on the larger one.
                let step = if hf.len() > 2000 { 7 } else { 1 };
                let corners = hf.corners();
                for &v in kept.iter().filter(|v| !corners.contains(v)).step_by(step) {
                    let without: Vec<u32> = kept.iter().copied().filter(|&k| k != v).collect();
                    let e_max = ev.score(&without).unwrap().e_max;
                    assert!(
                        e_max > bound,
                        "vertex {v} could go: E_max {e_max} ≤ {bound}"
                    );
                }
            }
        }
        assert!(
            fewer >= 8,
            "decimation removed vertices in only {fewer} runs"
        );
    }

    /// Two runs give the same kept sets, and the run records greedy's own final mesh before
    /// the decimated one.
    #[test]
    fn decimation_is_deterministic_and_follows_greedy() {
        let hf = fixture("jacksboro_65x65");
        let (lo, hi) = hf.z_range();
        let bound = 0.02 * (hi - lo);
        let a = run(&hf, bound, true);
        let b = run(&hf, bound, true);
        assert_eq!(a.recorded(), b.recorded());
        let greedy = run(&hf, bound, false);
        let n = a.recorded().len();
        assert_eq!(a.recorded()[..n - 1], greedy.recorded()[..]);
    }
}
