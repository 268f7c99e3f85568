//! The three solutions the paper picks from each front: best error, fewest triangles, and the
//! best trade-off of its eq. 7–9.

use super::{MetricsError, Point, check_non_empty};
use rand::{Rng, RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::Serialize;
use std::cmp::Ordering;

/// The number of random weights of the paper's trade-off pick.
pub(crate) const TRADE_OFF_WEIGHTS: usize = 1000;

/// The result of [`trade_off_pick`]: which point won, and the numbers it won with.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TradeOffPick {
    /// Index of the picked point in the slice given.
    pub index: usize,
    /// α = mean of T/E over the points with E > 0 (0 if there is none).
    pub alpha: f64,
    /// The picked point's mean score over the weights.
    pub mean_score: f64,
    /// The mean of the weights drawn.
    pub mean_weight: f64,
}

/// The paper's best trade-off (eq. 7–9) with `TRADE_OFF_WEIGHTS` weights drawn from
/// `Pcg64Mcg::seed_from_u64(seed)`. See [`trade_off_pick_with`] for the contract.
pub fn trade_off_pick(front: &[Point], seed: u64) -> Result<TradeOffPick, MetricsError> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    trade_off_pick_with(front, &mut rng, TRADE_OFF_WEIGHTS)
}

/// The paper's best trade-off (eq. 7–9): α = mean of T/E over `front`; draw `weights` weights
/// w uniform in [0, 1) from `rng` (the same weights for every point); score each point by the
/// mean over the weights of α·w·E + (1−w)·T; pick the lowest mean score.
///
/// This implements "the lowest mean over 1 000 random weights" literally. Observation: the score is linear in w, so its mean over the weights equals the
/// score at the mean weight w̄: the pick is the minimiser of α·w̄·E + (1−w̄)·T, a single weighted
/// sum with w̄ ≈ 0.5 (the random draw moves w̄ by about 0.29/√1000 ≈ 0.01). A different reading
/// — the point that wins for the most weights — would favour the vertex of the front's convex
/// hull with the widest range of winning weights; it is not what the method describes and is
/// not implemented. Since α·E is in units of T, the pick does not change when E or T is rescaled
/// (normalised or not).
///
/// E = 0 (an exact mesh) makes T/E infinite; such points are left out of the mean that defines
/// α (their score is (1−w)·T, finite). If no point has E > 0, α = 0 and the pick is by T.
/// Equal mean scores go to the lower T, then the lower E, then the earlier index, so the pick is
/// deterministic. Meant for a non-dominated front but accepts any set of points.
///
/// Errors: [`MetricsError::Empty`] if `front` is empty or `weights` is 0;
/// [`MetricsError::NonFinite`] for NaN or infinite coordinates; [`MetricsError::Negative`] for
/// a negative coordinate.
pub fn trade_off_pick_with<R: Rng + ?Sized>(
    front: &[Point],
    rng: &mut R,
    weights: usize,
) -> Result<TradeOffPick, MetricsError> {
    check_picks_input(front)?;
    if weights == 0 {
        return Err(MetricsError::Empty { set: "weights" });
    }
    let ratios: Vec<f64> = front
        .iter()
        .filter(|p| p[0] > 0.0)
        .map(|p| p[1] / p[0])
        .collect();
    let alpha = if ratios.is_empty() {
        0.0
    } else {
        ratios.iter().sum::<f64>() / ratios.len() as f64
    };
    let ws: Vec<f64> = (0..weights).map(|_| rng.random::<f64>()).collect();
    let mean_weight = ws.iter().sum::<f64>() / weights as f64;
    let mean_scores: Vec<f64> = front
        .iter()
        .map(|p| {
            let total: f64 = ws
                .iter()
                .map(|&w| alpha * w * p[0] + (1.0 - w) * p[1])
                .sum();
            total / weights as f64
        })
        .collect();
    let index = (0..front.len())
        .min_by(|&i, &j| {
            mean_scores[i]
                .total_cmp(&mean_scores[j])
                .then(by_t_then_e(&front[i], &front[j]))
        })
        .unwrap_or(0);
    Ok(TradeOffPick {
        index,
        alpha,
        mean_score: mean_scores[index],
        mean_weight,
    })
}

/// The index of the point with the lowest E (ties: the lower T, then the earlier index).
///
/// Errors: as [`trade_off_pick_with`] (empty, NaN or infinite, negative).
pub fn best_error_pick(front: &[Point]) -> Result<usize, MetricsError> {
    check_picks_input(front)?;
    Ok(first_min_by(front, |a, b| {
        a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1]))
    }))
}

/// The index of the point with the lowest T (ties: the lower E, then the earlier index).
///
/// Errors: as [`trade_off_pick_with`] (empty, NaN or infinite, negative).
pub fn fewest_triangles_pick(front: &[Point]) -> Result<usize, MetricsError> {
    check_picks_input(front)?;
    Ok(first_min_by(front, by_t_then_e))
}

fn check_picks_input(front: &[Point]) -> Result<(), MetricsError> {
    check_non_empty(front, "front")?;
    match front.iter().position(|p| p[0] < 0.0 || p[1] < 0.0) {
        Some(index) => Err(MetricsError::Negative {
            set: "front",
            index,
        }),
        None => Ok(()),
    }
}

fn by_t_then_e(a: &Point, b: &Point) -> Ordering {
    a[1].total_cmp(&b[1]).then(a[0].total_cmp(&b[0]))
}

/// Index of the first minimum (`Iterator::min_by` keeps the first of equal elements).
fn first_min_by(points: &[Point], order: impl Fn(&Point, &Point) -> Ordering) -> usize {
    (0..points.len())
        .min_by(|&i, &j| order(&points[i], &points[j]))
        .unwrap_or(0)
}
