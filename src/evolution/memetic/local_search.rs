//! Local search at fixed T on archive members: swap moves (remove one kept point, insert a free
//! one of the same border class, so the triangle count stays), accepted when E_sum drops.
//!
//! Candidate lists, rebuilt from the [`Guide`] of the mesh at each round:
//! - removals: the kept points of smallest estimated removal cost;
//! - insertions: in the triangles of largest error sum, the worst point and the point nearest
//!   to the centre of the error mass ([`Guide::centre_point`]);
//!
//! as many of each as the mesh has kept points over [`POINTS_PER_CANDIDATE`] (within
//! [`MIN_CANDIDATES`] and [`MAX_CANDIDATES`]);
//! - moves: [`MOVES`] vertices of triangles drawn in proportion to their error sum, each to
//!   each of its free grid neighbours.
//!
//! A round scores every removal × insertion pair and every move exactly
//! ([`mutation::trial`]) and applies the best improving one; a visit runs rounds on one member
//! until a round finds nothing or [`ROUNDS_PER_VISIT`] are done.
//!
//! Spreading the budget over the front: visits go to triangle counts on a geometric sweep
//! from the sparsest useful mesh to a quarter of the full mesh (denser meshes have errors near
//! zero, so little to gain), [`TARGETS`] per sweep, each sweep
//! shifted by the next term of a van der Corput sequence so later sweeps fall between the
//! earlier ones. A visit takes the archive member with the most triangles at or below its
//! target and first pads it up to the target with the worst points of its largest-error
//! triangles, so the front gains a member at every target and the improvements of a sparser
//! member carry to denser ones.

use super::guide::{Guide, NO_POINT};
use super::member::{Edit, Member, offer, on_border};
use super::mutation;
use crate::evaluator::Evaluator;
use crate::front::Front;
use crate::heightfield::Heightfield;
use rand::RngExt;
use rand_pcg::Pcg64Mcg;

/// Removal (and insertion) candidates per round: one per [`POINTS_PER_CANDIDATE`] kept points,
/// at least [`MIN_CANDIDATES`] and at most [`MAX_CANDIDATES`], so that a round on a dense mesh
/// can make many swaps at once.
pub const POINTS_PER_CANDIDATE: usize = 8;
/// See [`POINTS_PER_CANDIDATE`].
pub const MIN_CANDIDATES: usize = 16;
/// See [`POINTS_PER_CANDIDATE`].
pub const MAX_CANDIDATES: usize = 256;
/// Vertices tried at every free neighbour per round.
pub const MOVES: usize = 2;
/// Most rounds per visit.
pub const ROUNDS_PER_VISIT: usize = 20;
/// Target triangle counts per sweep.
pub const TARGETS: usize = 32;

/// The local search's state between units; see the module doc.
#[derive(Debug)]
pub struct LocalSearch {
    /// Visits started so far.
    visits: u64,
    /// The member being improved, and its rounds left.
    subject: Option<(Member, usize)>,
    /// The sparsest and densest targets.
    low: f64,
    high: f64,
}

impl LocalSearch {
    /// Targets from 8 triangles (or fewer on a tiny grid) to a quarter of `hf`'s full mesh.
    pub fn new(hf: &Heightfield) -> Self {
        let full = hf.full_triangles() as f64;
        let high = (full / 4.0).max(2.0);
        Self {
            visits: 0,
            subject: None,
            low: 8.0f64.min(high),
            high,
        }
    }

    /// The target of visit `k`: sweep `k / TARGETS`, position `k % TARGETS`, shifted by the
    /// sweep's van der Corput term so that sweeps interleave.
    pub fn target(&self, k: u64) -> usize {
        let (sweep, at) = (k / TARGETS as u64, (k % TARGETS as u64) as f64);
        let shift = van_der_corput(sweep);
        let f = (at + shift) / TARGETS as f64;
        (self.low * (self.high / self.low).powf(f)).round() as usize
    }

    /// One unit: starts a visit (picking, building and padding its member) or runs one round of
    /// the visit in progress. Counts its evaluations in `evaluations`.
    pub fn unit(
        &mut self,
        evaluator: &mut Evaluator,
        archive: &mut Front,
        rng: &mut Pcg64Mcg,
        evaluations: &mut u64,
    ) {
        let hf = evaluator.heightfield().clone();
        let Some((member, rounds)) = self.subject.as_mut() else {
            let target = self.target(self.visits);
            self.visits += 1;
            let members = archive.solutions();
            let at = members.partition_point(|s| s.t <= target).max(1);
            let Some(start) = members.get(at - 1) else {
                return;
            };
            let mut member = Member::fresh(evaluator, start.kept.clone());
            *evaluations += 1;
            let room = target.saturating_sub(member.score.t) / 2;
            if room > 0 {
                let edit = padding(&hf, &mut member, room);
                if !edit.insert.is_empty() {
                    member.apply(evaluator, &edit);
                    *evaluations += 1;
                    offer(archive, &member.kept, &member.score);
                }
            }
            self.subject = Some((member, ROUNDS_PER_VISIT));
            return;
        };
        let improved = round(evaluator, member, rng, evaluations);
        if improved {
            offer(archive, &member.kept, &member.score);
        }
        *rounds -= 1;
        if !improved || *rounds == 0 {
            self.subject = None;
        }
    }
}

/// The interior worst points of up to `count` largest-error triangles, to insert.
fn padding(hf: &Heightfield, member: &mut Member, count: usize) -> Edit {
    let guide = member.guide(hf);
    let mut insert: Vec<u32> = guide
        .largest_triangles(count * 2)
        .into_iter()
        .map(|t| guide.worst_point(hf, t))
        .filter(|&p| p != NO_POINT && !on_border(hf, p))
        .collect();
    insert.sort_unstable();
    insert.dedup();
    insert.truncate(count);
    Edit {
        remove: Vec::new(),
        insert,
    }
}

/// One round on `member`; true when it improved (and was changed).
///
/// Scoring every removal × insertion pair would cost their product; instead each removal's
/// loss and each insertion's gain is scored alone, the best insertions are paired with the
/// cheapest removals while the gain exceeds the loss, and the pairs are tried together (they
/// are mostly far apart, so their effects nearly add up), then the first half of them, and so
/// on down to the best pair alone. Only when no batch improves are the moves tried.
fn round(
    evaluator: &mut Evaluator,
    member: &mut Member,
    rng: &mut Pcg64Mcg,
    evaluations: &mut u64,
) -> bool {
    let hf = evaluator.heightfield().clone();
    member.ready_for_trials();
    let candidates =
        (member.kept.len() / POINTS_PER_CANDIDATE).clamp(MIN_CANDIDATES, MAX_CANDIDATES);
    let guide: &Guide = member.guide(&hf);
    let removals = guide.cheapest_removals(candidates, |i| !on_border(&hf, i));
    // Two insertion candidates per triangle: its worst point and its error's centre.
    let mut insertions: Vec<u32> = guide
        .largest_triangles(candidates.div_ceil(2))
        .into_iter()
        .flat_map(|t| [guide.worst_point(&hf, t), guide.centre_point(&hf, t)])
        .filter(|&p| p != NO_POINT && !on_border(&hf, p))
        .collect();
    insertions.sort_unstable();
    insertions.dedup();
    let mut moved: Vec<u32> = Vec::with_capacity(MOVES);
    let corners = hf.corners();
    for _ in 0..MOVES {
        if let Some(t) = guide.triangle_at(rng.random::<f64>()) {
            let tri = guide.triangles[t];
            let v = tri[rng.random_range(0..3)];
            if !corners.contains(&v) && !moved.contains(&v) {
                moved.push(v);
            }
        }
    }
    let e = member.score.e_sum;
    let mut scored = |evaluator: &mut Evaluator, edit: &Edit| {
        *evaluations += 1;
        mutation::trial(evaluator, member, edit).e_sum
    };
    let mut losses: Vec<(f64, u32)> = removals
        .iter()
        .map(|&r| {
            let edit = Edit {
                remove: vec![r],
                insert: Vec::new(),
            };
            (scored(evaluator, &edit) - e, r)
        })
        .collect();
    let mut gains: Vec<(f64, u32)> = insertions
        .iter()
        .map(|&p| {
            let edit = Edit {
                remove: Vec::new(),
                insert: vec![p],
            };
            (e - scored(evaluator, &edit), p)
        })
        .collect();
    losses.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    gains.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut pairs = losses
        .iter()
        .zip(&gains)
        .take_while(|(l, g)| g.0 > l.0)
        .count();
    let mut chosen: Option<Edit> = None;
    while pairs > 0 {
        let edit = Edit {
            remove: losses[..pairs].iter().map(|l| l.1).collect(),
            insert: gains[..pairs].iter().map(|g| g.1).collect(),
        };
        if scored(evaluator, &edit) < e {
            chosen = Some(edit);
            break;
        }
        pairs /= 2;
    }
    if chosen.is_none() {
        let mut best = e;
        for &v in &moved {
            for n in mutation::free_neighbours(&hf, member, v) {
                let edit = Edit {
                    remove: vec![v],
                    insert: vec![n],
                };
                let after = scored(evaluator, &edit);
                if after < best {
                    best = after;
                    chosen = Some(edit);
                }
            }
        }
    }
    let Some(edit) = chosen else {
        return false;
    };
    member.apply(evaluator, &edit);
    *evaluations += 1;
    true
}

/// The `k`-th term of the base-2 van der Corput sequence, in [0, 1): 0, ½, ¼, ¾, ⅛, …
pub fn van_der_corput(mut k: u64) -> f64 {
    let (mut value, mut scale) = (0.0, 0.5);
    while k > 0 {
        if k & 1 == 1 {
            value += scale;
        }
        k >>= 1;
        scale /= 2.0;
    }
    value
}
