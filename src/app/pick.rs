//! Which mesh the 3-D view shows when a run ends: the paper's trade-off pick (eq. 7–9, see
//! [`crate::metrics::trade_off_pick`]), so a finished run shows a balanced simplification
//! instead of the full surface, unless the user (or a share link) chose one already.

use crate::front::{Front, Solution};
use crate::metrics::{Point, trade_off_pick};

/// Index in `front` of the paper's trade-off pick with weights drawn from `seed` (the run's
/// seed, as the experiment draws them); `None` for an empty front.
pub fn trade_off_index(front: &Front, seed: u64) -> Option<usize> {
    let points: Vec<Point> = front.solutions().iter().map(|s| s.objectives()).collect();
    trade_off_pick(&points, seed).ok().map(|p| p.index)
}

/// The selection once a run has ended: `current` when there is one (a choice of the user's or
/// a share link's always wins), else the trade-off pick of `front`.
pub fn selection_at_run_end(
    current: Option<&Solution>,
    front: &Front,
    seed: u64,
) -> Option<Solution> {
    if let Some(s) = current {
        return Some(s.clone());
    }
    trade_off_index(front, seed).map(|i| front.solutions()[i].clone())
}
