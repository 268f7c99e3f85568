//! Per-dataset normalisation of (E, T) and the default hypervolume reference point.

use super::{MetricsError, Point};
use crate::evaluator::Evaluator;
use crate::front::Solution;
use serde::Serialize;

/// The default hypervolume reference point in normalised units: (1.1, 1.1).
///
/// Why: after [`Normalization::from_evaluator`], T/T_full lies in (0, 1] (a Delaunay
/// triangulation of a subset of the grid never has more triangles than the full grid), and
/// E/E_corner is 1 for the corner-only mesh, the coarsest mesh every method can reach; so (1, 1)
/// is the nadir of the interesting region. A reference exactly at the nadir would give both
/// extreme meshes (corner-only: E = 1; full grid: T = 1) zero contribution, so a method's
/// reaching them would not count. Adding 10 % of the range — the usual "1.1 × nadir" choice for
/// normalised fronts — gives each extreme a slab of width 0.1 while keeping the interior of the
/// front dominant. Meshes worse than 1.1 × E_corner add nothing (they are not interesting
/// trade-offs). Override it by passing another point to [`hypervolume`](super::hypervolume).
pub const DEFAULT_REFERENCE_POINT: Point = [1.1, 1.1];

/// Divides E and T by per-dataset scales, so that indicators are comparable across datasets and
/// the two objectives have similar ranges.
///
/// The paper's choice, [`Normalization::from_evaluator`], divides E by the E of the corner-only
/// mesh and T by the full grid's triangle count 2(W−1)(H−1). [`Normalization::new`] takes any
/// positive scales. Dividing by positive constants keeps every dominance relation, so filtering
/// and coverage give the same answers before and after.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Normalization {
    e_scale: f64,
    t_scale: f64,
}

impl Normalization {
    /// Explicit scales: normalised E = E / `e_scale`, normalised T = T / `t_scale`.
    ///
    /// Errors: [`MetricsError::BadScale`] unless both are positive finite numbers.
    pub fn new(e_scale: f64, t_scale: f64) -> Result<Self, MetricsError> {
        for (objective, value) in [("E", e_scale), ("T", t_scale)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(MetricsError::BadScale { objective, value });
            }
        }
        Ok(Normalization { e_scale, t_scale })
    }

    /// The paper's normalisation for the evaluator's height field: E by the E of the
    /// corner-only mesh, T by the full grid's triangle count 2(W−1)(H−1).
    ///
    /// Errors: [`MetricsError::BadScale`] for "E" if the corner-only mesh reproduces the surface
    /// exactly (E = 0: a plane, or two planes meeting on the corner-only mesh's diagonal), since
    /// nothing can be divided by it; pass explicit scales with [`Normalization::new`] then.
    /// [`MetricsError::Evaluate`] if the evaluator rejects the corner set (it should not).
    pub fn from_evaluator(evaluator: &mut Evaluator) -> Result<Self, MetricsError> {
        let hf = evaluator.heightfield().clone();
        let corner_error = evaluator
            .score(&hf.corners())
            .map_err(MetricsError::Evaluate)?
            .e_sum;
        Normalization::new(corner_error, hf.full_triangles() as f64)
    }

    /// The divisor of E.
    pub fn e_scale(&self) -> f64 {
        self.e_scale
    }

    /// The divisor of T.
    pub fn t_scale(&self) -> f64 {
        self.t_scale
    }

    /// One normalised point: (E / e_scale, T / t_scale). NaN stays NaN (the indicators reject it).
    pub(crate) fn apply(&self, point: Point) -> Point {
        [point[0] / self.e_scale, point[1] / self.t_scale]
    }

    /// Normalised copies of `points`, in the same order.
    pub fn apply_all(&self, points: &[Point]) -> Vec<Point> {
        points.iter().map(|&p| self.apply(p)).collect()
    }

    /// The normalised objective points of `solutions`, in the same order.
    pub fn solutions(&self, solutions: &[Solution]) -> Vec<Point> {
        solutions
            .iter()
            .map(|s| self.apply(s.objectives()))
            .collect()
    }

    /// Maps a normalised point back to (E, T) in the original units.
    pub fn invert(&self, point: Point) -> Point {
        [point[0] * self.e_scale, point[1] * self.t_scale]
    }
}
