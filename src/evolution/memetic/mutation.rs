//! Error-guided mutation: local edits aimed where the error is, instead of random bit flips.
//!
//! - [`insert`]: the worst point of a triangle drawn in proportion to its error sum (so big,
//!   badly fitting triangles are split first, but every triangle with error has a chance);
//! - [`remove`]: of a few kept points drawn at random, the one with the smallest estimated
//!   removal cost ([`Guide::removal_cost`]), a tournament that leans to cheap removals without
//!   always taking the same one;
//! - [`best_move`]: a vertex of a triangle drawn in proportion to its error sum moves to the
//!   best of its free grid neighbours (same border class, so T is kept), each neighbour scored
//!   exactly.

use super::guide::{Guide, NO_POINT};
use super::member::{Edit, Member, on_border};
use crate::evaluator::{Changes, Evaluator, Score};
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;
use rand::RngExt;
use rand_pcg::Pcg64Mcg;

/// Kept points drawn for the removal tournament.
pub const REMOVAL_TOURNAMENT: usize = 4;

/// The three guided operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operator {
    /// [`insert`].
    Insert,
    /// [`remove`].
    Remove,
    /// [`best_move`].
    Move,
}

impl Operator {
    /// One of the three, equally likely.
    pub fn draw(rng: &mut Pcg64Mcg) -> Self {
        match rng.random_range(0..3u32) {
            0 => Self::Insert,
            1 => Self::Remove,
            _ => Self::Move,
        }
    }
}

/// Inserts the worst point of a triangle drawn in proportion to its error sum; `None` when the
/// mesh has no error left.
pub fn insert(hf: &Heightfield, guide: &Guide, rng: &mut Pcg64Mcg) -> Option<Edit> {
    let t = guide.triangle_at(rng.random::<f64>())?;
    let p = guide.worst_point(hf, t);
    (p != NO_POINT).then(|| Edit {
        remove: Vec::new(),
        insert: vec![p],
    })
}

/// Removes the cheapest (by estimate) of [`REMOVAL_TOURNAMENT`] kept points drawn at random;
/// `None` when only the corners are kept.
pub fn remove(guide: &Guide, rng: &mut Pcg64Mcg) -> Option<Edit> {
    let n = guide.vertices.len();
    if guide.removal_cost.iter().all(|c| c.is_infinite()) {
        return None;
    }
    let mut best: Option<usize> = None;
    let mut drawn = 0;
    // Corners (infinite cost) are redrawn; there is at least one other point.
    while drawn < REMOVAL_TOURNAMENT {
        let v = rng.random_range(0..n);
        if guide.removal_cost[v].is_infinite() {
            continue;
        }
        drawn += 1;
        if best.is_none_or(|b| guide.removal_cost[v] < guide.removal_cost[b]) {
            best = Some(v);
        }
    }
    best.map(|v| Edit {
        remove: vec![guide.vertices[v]],
        insert: Vec::new(),
    })
}

/// Flips one grid point drawn uniformly among the non-corner ones: removes it when kept,
/// inserts it otherwise. The unguided mutation the error-guided operators are measured
/// against; `None` when the grid has no point but its corners.
pub fn random_flip(hf: &Heightfield, member: &Member, rng: &mut Pcg64Mcg) -> Option<Edit> {
    let corners = hf.corners();
    if hf.len() <= corners.len() {
        return None;
    }
    let p = loop {
        let p = rng.random_range(0..hf.len() as u32);
        if !corners.contains(&p) {
            break p;
        }
    };
    Some(if member.state.is_kept(p) {
        Edit {
            remove: vec![p],
            insert: Vec::new(),
        }
    } else {
        Edit {
            remove: Vec::new(),
            insert: vec![p],
        }
    })
}

/// The free grid points among the 8 neighbours of kept point `v` in its border class (interior
/// points for an interior `v`, points of the same border side for a border one), in grid order.
pub fn free_neighbours(hf: &Heightfield, member: &Member, v: u32) -> Vec<u32> {
    let (w, h) = (hf.width() as i64, hf.height() as i64);
    let (x, y) = hf.coords(v);
    let (x, y) = (x as i64, y as i64);
    let border = on_border(hf, v);
    let mut out = Vec::with_capacity(8);
    for dy in -1..=1 {
        for dx in -1..=1 {
            let (nx, ny) = (x + dx, y + dy);
            if (dx, dy) == (0, 0) || nx < 0 || ny < 0 || nx >= w || ny >= h {
                continue;
            }
            let n = (ny * w + nx) as u32;
            let fits = if border {
                // Along the same side: the row or column that makes v a border point.
                ((x == 0 || x == w - 1) && nx == x) || ((y == 0 || y == h - 1) && ny == y)
            } else {
                !on_border(hf, n)
            };
            if fits && !member.state.is_kept(n) {
                out.push(n);
            }
        }
    }
    out
}

/// Scores `member` with `edit` made, without changing it: by [`Evaluator::score_mutant`] when
/// the member is [ready for trials](Member::ready_for_trials) and no guard fails, else by editing a copy of its mesh (the same bits either way).
/// One evaluation.
pub fn trial(evaluator: &mut Evaluator, member: &Member, edit: &Edit) -> Score {
    let changes = Changes {
        removed: &edit.remove,
        inserted: &edit.insert,
    };
    if let Some(score) = evaluator.score_mutant(&member.state, changes) {
        return score;
    }
    let mut kept = member.kept.clone();
    edit.apply_to(&mut kept);
    evaluator
        .score(&kept)
        .expect("kept points are grid indices")
}

/// Moves a vertex of a triangle drawn in proportion to its error sum to the best of its free
/// neighbours ([`free_neighbours`]), scoring each ([`trial`]; `evaluations` counts them).
/// Returns the move and its score, or `None` when the drawn triangle has no movable vertex.
/// `member` must be [ready for trials](Member::ready_for_trials) and have its guide.
pub fn best_move(
    evaluator: &mut Evaluator,
    member: &Member,
    measure: ErrorMeasure,
    rng: &mut Pcg64Mcg,
    evaluations: &mut u64,
) -> Option<(Edit, Score)> {
    let hf = evaluator.heightfield().clone();
    let guide = member.guide.as_ref().expect("the member's guide is made");
    let t = match guide.triangle_at(rng.random::<f64>()) {
        Some(t) => t,
        None => rng.random_range(0..guide.triangles.len()),
    };
    let corners = hf.corners();
    let movable: Vec<u32> = guide.triangles[t]
        .into_iter()
        .filter(|v| !corners.contains(v))
        .collect();
    if movable.is_empty() {
        return None;
    }
    let v = movable[rng.random_range(0..movable.len())];
    let mut best: Option<(Edit, Score)> = None;
    for n in free_neighbours(&hf, member, v) {
        let edit = Edit {
            remove: vec![v],
            insert: vec![n],
        };
        let score = trial(evaluator, member, &edit);
        *evaluations += 1;
        if best
            .as_ref()
            .is_none_or(|(_, b)| measure.of(&score) < measure.of(b))
        {
            best = Some((edit, score));
        }
    }
    best
}
