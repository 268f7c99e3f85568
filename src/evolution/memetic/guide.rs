//! What the guided operators read off a scored mesh: each triangle's error sum and its worst
//! point, and each kept vertex's estimated removal cost.

use crate::evaluator::MeshState;
use crate::evaluator::exact::predicates::{Lattice, orient};
use crate::evaluator::mesh::canonical_form::canonical;
use crate::evaluator::raster::Grid;
use crate::heightfield::Heightfield;

thread_local! {
    /// [`Guide::of`]'s map from grid index to position in the kept list (`u32::MAX` for a
    /// point that is not kept), grown to the largest grid seen.
    static KEPT_POSITION: std::cell::RefCell<Vec<u32>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// [`Guide::worst_point`] of a triangle that owns no grid point with a nonzero error.
pub(crate) const NO_POINT: u32 = u32::MAX;

/// The error landscape of one mesh; see the module doc. The sums come from the totals the mesh
/// keeps ([`MeshState::triangle_error_sums`]), so a guide costs a pass over the triangles, and
/// a triangle's worst point is found by rasterising it when asked for
/// ([`worst_point`](Self::worst_point)).
#[derive(Clone, Debug, Default)]
pub(crate) struct Guide {
    /// The triangles (counter-clockwise grid-index triples).
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, Σ |z − z̃| over the grid points it owns.
    pub sums: Vec<f64>,
    /// Running totals of `sums`, for choosing a triangle in proportion to its sum.
    cumulative: Vec<f64>,
    /// The kept points, increasing (corners included).
    pub vertices: Vec<u32>,
    /// Per kept point (same order), the estimated rise of E_sum if it were removed: the volume
    /// of the cone between it and the mean height of its neighbours over its star,
    /// |z − mean(z of neighbours)| · area(star) / 3. Corners get +∞ (they cannot leave).
    pub removal_cost: Vec<f64>,
}

impl Guide {
    /// The guide of `state`, the scored mesh of the kept set `kept` (increasing, corners
    /// included) on `hf`.
    pub(crate) fn of(hf: &Heightfield, state: &MeshState, kept: &[u32]) -> Self {
        let lattice = Lattice::new(hf.width());
        let z = hf.z();
        let triangles = state.triangles();
        let sums = state.triangle_error_sums();
        let mut cumulative = Vec::with_capacity(triangles.len());
        let mut area = vec![0i64; kept.len()];
        let mut neighbour_z = vec![0.0f64; kept.len()];
        let mut neighbours = vec![0u32; kept.len()];
        let mut total = 0.0;
        KEPT_POSITION.with_borrow_mut(|slot| {
            // Grid index → position in `kept`, for the triangles' vertices: one map per thread,
            // set for this mesh's kept points and reset after, so a guide costs its mesh's
            // size, not the grid's.
            if slot.len() < hf.len() {
                slot.resize(hf.len(), u32::MAX);
            }
            for (v, &i) in kept.iter().enumerate() {
                slot[i as usize] = v as u32;
            }
            for (&tri, &sum) in triangles.iter().zip(&sums) {
                total += sum;
                cumulative.push(total);
                let points = tri.map(|i| lattice.point(i));
                let twice_area = orient(points[0], points[1], points[2]);
                for k in 0..3 {
                    let v = slot[tri[k] as usize] as usize;
                    if v >= kept.len() {
                        continue;
                    }
                    area[v] += twice_area;
                    neighbour_z[v] += z[tri[(k + 1) % 3] as usize] + z[tri[(k + 2) % 3] as usize];
                    neighbours[v] += 2;
                }
            }
            for &i in kept {
                slot[i as usize] = u32::MAX;
            }
        });
        let corners = hf.corners();
        let removal_cost = kept
            .iter()
            .enumerate()
            .map(|(v, &i)| {
                if corners.contains(&i) || neighbours[v] == 0 {
                    return f64::INFINITY;
                }
                let mean = neighbour_z[v] / f64::from(neighbours[v]);
                (z[i as usize] - mean).abs() * area[v] as f64 / 6.0
            })
            .collect();
        Self {
            triangles,
            sums,
            cumulative,
            vertices: kept.to_vec(),
            removal_cost,
        }
    }

    /// E_sum as the sum of the triangles' sums (in f64, so up to rounding).
    pub(crate) fn total(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }

    /// The triangle whose share of [`total`](Self::total) holds `u` ∈ [0, 1): a triangle is
    /// chosen with probability proportional to its error sum. `None` when the error is 0.
    pub(crate) fn triangle_at(&self, u: f64) -> Option<usize> {
        let total = self.total();
        if total <= 0.0 {
            return None;
        }
        let target = u * total;
        let t = self.cumulative.partition_point(|&c| c <= target);
        Some(t.min(self.triangles.len() - 1))
    }

    /// Triangle `t`'s owned point of largest error (the first in grid order on ties), or
    /// [`NO_POINT`] when it owns no point with an error.
    pub(crate) fn worst_point(&self, hf: &Heightfield, t: usize) -> u32 {
        let lattice = Lattice::new(hf.width());
        let grid = Grid {
            width: hf.width() as i64,
            height: hf.height() as i64,
            z: hf.z(),
        };
        let (mut max, mut at) = (0.0, NO_POINT);
        grid.for_each_error(
            canonical(self.triangles[t]).map(|i| lattice.point(i)),
            |i, d| {
                if d > max {
                    max = d;
                    at = i as u32;
                }
            },
        );
        at
    }

    /// The owned point of triangle `t` nearest to the centre of its error mass (the
    /// error-weighted mean position of the points it owns; ties to the first in grid order), or
    /// [`NO_POINT`] when it owns no point with an error. For a sum-type error, a split there
    /// often removes more error than one at the single worst point.
    pub(crate) fn centre_point(&self, hf: &Heightfield, t: usize) -> u32 {
        let lattice = Lattice::new(hf.width());
        let grid = Grid {
            width: hf.width() as i64,
            height: hf.height() as i64,
            z: hf.z(),
        };
        let tri = canonical(self.triangles[t]).map(|i| lattice.point(i));
        let (mut mass, mut mx, mut my) = (0.0, 0.0, 0.0);
        grid.for_each_error(tri, |i, d| {
            let (x, y) = hf.coords(i as u32);
            mass += d;
            mx += d * x as f64;
            my += d * y as f64;
        });
        if mass <= 0.0 {
            return NO_POINT;
        }
        let (cx, cy) = (mx / mass, my / mass);
        let (mut best, mut at) = (f64::INFINITY, NO_POINT);
        grid.for_each_error(tri, |i, _| {
            let (x, y) = hf.coords(i as u32);
            let d = (x as f64 - cx).powi(2) + (y as f64 - cy).powi(2);
            if d < best {
                best = d;
                at = i as u32;
            }
        });
        at
    }

    /// Up to `k` triangles of largest error sum with a nonzero sum, largest first (ties to the
    /// smaller slot).
    pub(crate) fn largest_triangles(&self, k: usize) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.triangles.len())
            .filter(|&t| self.sums[t] > 0.0)
            .collect();
        let by_sum = |a: &usize, b: &usize| self.sums[*b].total_cmp(&self.sums[*a]).then(a.cmp(b));
        if order.len() > k {
            order.select_nth_unstable_by(k, by_sum);
            order.truncate(k);
        }
        order.sort_by(by_sum);
        order
    }

    /// Up to `k` kept points, cheapest estimated removal first (ties to the smaller index),
    /// among those `allowed` accepts; corners never.
    pub(crate) fn cheapest_removals(&self, k: usize, allowed: impl Fn(u32) -> bool) -> Vec<u32> {
        let mut order: Vec<usize> = (0..self.vertices.len())
            .filter(|&v| self.removal_cost[v].is_finite() && allowed(self.vertices[v]))
            .collect();
        let by_cost = |a: &usize, b: &usize| {
            self.removal_cost[*a]
                .total_cmp(&self.removal_cost[*b])
                .then(a.cmp(b))
        };
        if order.len() > k {
            order.select_nth_unstable_by(k, by_cost);
            order.truncate(k);
        }
        order.sort_by(by_cost);
        order.into_iter().map(|v| self.vertices[v]).collect()
    }
}
