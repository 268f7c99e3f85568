//! Scoring a mesh from its triangles: the fresh build of a kept set, the one-pass score, and the
//! rasterising of triangle slots that every path (build, edit, composition) shares.

use super::grid_of;
use super::triangle_memo::TriangleMemo;
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
use crate::evaluator::exact::predicates::Lattice;
use crate::evaluator::mesh::canonical_form::canonical;
use crate::evaluator::mesh::state::{LARGEST_MAXIMA, MeshState, next_revision};
use crate::evaluator::score::Score;
use crate::heightfield::Heightfield;
use std::sync::Arc;

impl MeshState {
    /// Per triangle, in the order of [`triangles`](Self::triangles), Σ |z − z̃| over the grid
    /// points it owns (its vertices excluded), from the totals the state keeps: no
    /// rasterisation. Empty before the state is scored.
    pub(crate) fn triangle_error_sums(&self) -> Vec<f64> {
        let Some(hf) = &self.hf else {
            return Vec::new();
        };
        let units = ErrorUnits::of(hf);
        self.totals[..self.mesh.len()]
            .iter()
            .map(|t| units.value(t.sum))
            .collect()
    }

    /// The error |z − z̃| of every grid point (0 at kept points), row-major, rasterised from the
    /// mesh (the state keeps only each triangle's totals).
    pub fn errors(&self) -> Vec<f64> {
        let Some(hf) = &self.hf else {
            return Vec::new();
        };
        let mut errors = vec![0.0; hf.len()];
        let (grid, lattice) = (grid_of(hf), Lattice::new(hf.width()));
        for t in 0..self.mesh.len() {
            let tri = canonical(self.mesh.triangle(t)).map(|i| lattice.point(i));
            grid.for_each_error(tri, |i, d| errors[i] = d);
        }
        errors
    }

    /// Rebuilds from scratch as the canonical triangulation of `kept` (distinct, increasing,
    /// corners included, in range) and scores it.
    pub(crate) fn rebuild(&mut self, hf: &Arc<Heightfield>, kept: &[u32]) -> Score {
        self.kept.clear();
        self.kept.resize(hf.len(), false);
        for &i in kept {
            self.kept[i as usize] = true;
        }
        self.mesh.rebuild_delaunay(hf.width(), kept);
        self.rescore_all(hf)
    }

    /// Scores the triangles in `self.mesh` from scratch (they need not be Delaunay; the state
    /// can be edited afterwards only if they are and their twins are linked).
    pub(crate) fn rescore_all(&mut self, hf: &Arc<Heightfield>) -> Score {
        if !self.hf.as_ref().is_some_and(|h| Arc::ptr_eq(h, hf)) {
            self.hf = Some(hf.clone());
        }
        // No clearing: every kept point's hint is written below, by one of its triangles.
        self.hint.resize(hf.len(), 0);
        self.totals.clear();
        self.totals.resize(self.mesh.len(), ErrorTotals::default());
        self.rasterise(hf, 0..self.mesh.len() as u32);
        self.finish(hf)
    }

    /// Scores the triangles in `self.mesh` in one pass, without the per-point errors and hints
    /// an edit needs: the same score as [`rescore_all`](Self::rescore_all) (the totals are exact
    /// integers, so the order the triangles are summed in does not matter), with no store per
    /// grid point and no pass over the row totals. The state is left not editable.
    pub(crate) fn score_once(&mut self, hf: &Heightfield) -> Score {
        let grid = grid_of(hf);
        let units = ErrorUnits::of(hf);
        let lattice = Lattice::new(hf.width());
        let mesh = &self.mesh;
        let tris = (0..mesh.len()).map(|t| canonical(mesh.triangle(t)).map(|i| lattice.point(i)));
        let all = grid.sum_all(units, tris);
        self.forget();
        self.score_from(units.values(&all), hf.len())
    }

    /// Scores the state from its triangles' totals, as a new mesh (a new revision, disc boxes
    /// stale).
    pub(crate) fn finish(&mut self, hf: &Heightfield) -> Score {
        self.discs_valid = false;
        self.lookup_valid = false;
        self.sat_valid = false;
        self.revision = next_revision();
        let units = ErrorUnits::of(hf);
        let mut all = ErrorTotals::default();
        let mut largest = [(0.0, 0); LARGEST_MAXIMA];
        for (slot, t) in self.totals[..self.mesh.len()].iter().enumerate() {
            all.add(t);
            if t.max > largest[LARGEST_MAXIMA - 1].0 {
                let at = largest.partition_point(|&(m, _)| m >= t.max);
                largest.copy_within(at..LARGEST_MAXIMA - 1, at + 1);
                largest[at] = (t.max, slot as u32);
            }
        }
        self.all = all;
        self.largest = largest;
        self.score_from(units.values(&all), hf.len())
    }

    fn score_from(&mut self, values: (f64, f64, f64), n: usize) -> Score {
        let score = Score::from_values(values, n, self.mesh.len());
        self.score = Some(score);
        score
    }

    /// Rasterises the triangles in `slots` (each in its canonical rotation) into their totals,
    /// and points their vertices' hints at them.
    pub(crate) fn rasterise(&mut self, hf: &Heightfield, slots: impl Iterator<Item = u32>) {
        let (grid, lattice) = (grid_of(hf), Lattice::new(hf.width()));
        let (mesh, hint, totals) = (&self.mesh, &mut self.hint, &mut self.totals);
        let tris = slots.map(|slot| {
            let tri = canonical(mesh.triangle(slot as usize));
            for v in tri {
                hint[v as usize] = slot;
            }
            (slot, tri.map(|i| lattice.point(i)))
        });
        grid.sum_triangles(ErrorUnits::of(hf), tris, |slot, t| {
            totals[slot as usize] = t
        });
    }

    /// [`rasterise`](Self::rasterise) through `memo` ([`TriangleMemo::sum_triangles`];
    /// `unknown`: scratch).
    pub(crate) fn rasterise_with_memo(
        &mut self,
        hf: &Arc<Heightfield>,
        slots: std::ops::Range<u32>,
        memo: &mut TriangleMemo,
        unknown: &mut Vec<(u32, [u32; 3])>,
    ) {
        memo.prepare(Some(hf));
        let (mesh, hint, totals) = (&self.mesh, &mut self.hint, &mut self.totals);
        let tris = slots.map(|slot| {
            let tri = canonical(mesh.triangle(slot as usize));
            for v in tri {
                hint[v as usize] = slot;
            }
            (slot, tri)
        });
        memo.sum_triangles(hf, tris, unknown, |slot, t| totals[slot as usize] = t);
    }
}
