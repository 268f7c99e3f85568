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
//! - moves: the vertices of the [`MOVE_TRIANGLES`] largest triangles, each to the best of its
//!   free grid neighbours; and, when nothing else improves, [`MOVES`] vertices of triangles
//!   drawn in proportion to their error sum, each to each of its free grid neighbours.
//!
//! A round scores each removal, insertion and move alone ([`mutation::trial`]), pairs the best
//! insertions with the cheapest removals while the gain exceeds the loss, adds the moves that
//! pay, keeping only edits that touch no vertex another one touches (so their effects add up),
//! and applies the batch, best edits first, if it improves, else its better half, and so on;
//! only when no batch improves are the drawn moves tried.
//! A visit runs rounds on one member until a round finds nothing or [`ROUNDS_PER_VISIT`] are
//! done. The single trials are remembered between the rounds of a visit ([`Memo`]) and only
//! those near the last edit are scored again, so a round costs about as many evaluations as
//! the last edit changed, not as many as there are candidates.
//!
//! Spreading the budget over the front: visits go to triangle counts on a geometric sweep
//! from the sparsest useful mesh to the densest seed ([`densest_seed`]; denser meshes have
//! errors near zero, or are too large to search for what a visit gains), [`TARGETS`] per sweep, each sweep
//! shifted by the next term of a van der Corput sequence so later sweeps fall between the
//! earlier ones. A visit takes the archive member with the most triangles at or below its
//! target and pads it up to the target with the worst points of its largest-error triangles,
//! a few at a time ([`PAD_STEP`]), so the front gains members all the way to the target and
//! the improvements of a sparser member carry to denser ones. After its rounds, the visit
//! goes on padding the improved member up to the next target of the sweep while each step
//! enters the archive: an improved member dominates the old members just above it, and this
//! fills the gap in T it would otherwise leave.

use super::guide::{Guide, NO_POINT};
use super::member::{Edit, Member, offer, on_border};
use super::mutation;
use super::seeding::densest_seed;
use crate::evaluator::Evaluator;
use crate::front::Front;
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;
use rand::RngExt;
use rand_pcg::Pcg64Mcg;
use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

/// Removal (and insertion) candidates per round: one per [`POINTS_PER_CANDIDATE`] kept points,
/// at least [`MIN_CANDIDATES`] and at most [`MAX_CANDIDATES`], so that a round on a dense mesh
/// can make many swaps at once. The remembered trials keep a long list cheap after the first
/// round, and each applied batch rebuilds the mesh's guide once for many swaps.
pub const POINTS_PER_CANDIDATE: usize = 4;
/// See [`POINTS_PER_CANDIDATE`].
pub const MIN_CANDIDATES: usize = 16;
/// See [`POINTS_PER_CANDIDATE`].
pub const MAX_CANDIDATES: usize = 1024;
/// Vertices tried at every free neighbour per round.
pub const MOVES: usize = 2;
/// A round's largest triangles whose vertices are tried at each free grid neighbour, their
/// best moves remembered and batched with the swaps.
pub const MOVE_TRIANGLES: usize = 1;
/// Most rounds per visit.
pub const ROUNDS_PER_VISIT: usize = 20;
/// New single trials a unit scores at most: a round with more candidates than this goes on
/// over several units (its trials remembered between them), so that no unit of a large mesh
/// holds up a browser frame.
pub const TRIALS_PER_UNIT: usize = 128;
/// Target triangle counts per sweep.
pub const TARGETS: usize = 32;
/// Padding inserts at most one point per this many kept points at a time (about 2 % more
/// triangles), offering each step to the archive, so that the front it passes through has no
/// wide gaps in T.
pub const PAD_STEP: usize = 50;

/// The local search's state between units; see the module doc.
#[derive(Debug)]
pub struct LocalSearch {
    /// Visits started so far.
    visits: u64,
    /// The member being improved, its rounds left and its target.
    subject: Option<Visit>,
    /// The sparsest and densest targets.
    low: f64,
    high: f64,
}

impl LocalSearch {
    /// Targets from 8 triangles (or fewer on a tiny grid) to the densest seed
    /// ([`densest_seed`]: a quarter of `hf`'s full mesh up to a 257×257 grid).
    pub fn new(hf: &Heightfield) -> Self {
        let high = densest_seed(hf) as f64;
        Self {
            visits: 0,
            subject: None,
            low: 8.0f64.min(high),
            high,
        }
    }

    /// The ratio between consecutive targets of a sweep.
    fn spacing(&self) -> f64 {
        (self.high / self.low).powf(1.0 / TARGETS as f64)
    }

    /// The target of visit `k`: sweep `k / TARGETS`, position `k % TARGETS`, shifted by the
    /// sweep's van der Corput term so that sweeps interleave.
    pub fn target(&self, k: u64) -> usize {
        let (sweep, at) = (k / TARGETS as u64, (k % TARGETS as u64) as f64);
        let shift = van_der_corput(sweep);
        let f = (at + shift) / TARGETS as f64;
        (self.low * (self.high / self.low).powf(f)).round() as usize
    }

    /// One unit: starts a visit (picking and building its member), or makes one padding step
    /// of the visit in progress (up to its target, or past it after its rounds), or runs one
    /// of its rounds. Counts its evaluations in `evaluations`.
    pub fn unit(
        &mut self,
        evaluator: &mut Evaluator,
        archive: &mut Front,
        rng: &mut Pcg64Mcg,
        evaluations: &mut u64,
    ) {
        let hf = evaluator.heightfield().clone();
        let Some(visit) = self.subject.as_mut() else {
            let target = self.target(self.visits);
            self.visits += 1;
            let Some(start) = archive.within(target).or(archive.solutions().first()) else {
                return;
            };
            let member = Member::fresh(evaluator, start.kept.clone());
            *evaluations += 1;
            self.subject = Some(Visit {
                member,
                target,
                rounds: ROUNDS_PER_VISIT,
                memo: Memo::default(),
                carrying: false,
            });
            return;
        };
        let member = &mut visit.member;
        let step_points = |member: &Member| member.kept.len().div_ceil(PAD_STEP).max(1);
        if visit.carrying {
            let edit = padding(&hf, member, step_points(member));
            let mut entered = false;
            if !edit.insert.is_empty() {
                member.apply(evaluator, &edit);
                *evaluations += 1;
                entered = offer(archive, &member.kept, &member.score);
            }
            if !entered || member.score.t as f64 >= visit.target as f64 * self.spacing() {
                self.subject = None;
            }
            return;
        }
        let room = visit.target.saturating_sub(member.score.t) / 2;
        if room > 0 {
            let edit = padding(&hf, member, room.min(step_points(member)));
            if edit.insert.is_empty() {
                visit.target = member.score.t;
            } else {
                member.apply(evaluator, &edit);
                *evaluations += 1;
                offer(archive, &member.kept, &member.score);
            }
            return;
        }
        let measure = archive.measure();
        let end = round(
            evaluator,
            member,
            measure,
            &mut visit.memo,
            rng,
            evaluations,
        );
        if end == RoundEnd::Unfinished {
            return;
        }
        if end == RoundEnd::Improved {
            offer(archive, &member.kept, &member.score);
        }
        visit.rounds -= 1;
        if end == RoundEnd::NoGain || visit.rounds == 0 {
            visit.carrying = true;
        }
    }
}

/// A visit of the local search: its member, target and progress.
#[derive(Debug)]
struct Visit {
    member: Member,
    target: usize,
    /// Rounds left.
    rounds: usize,
    memo: Memo,
    /// The rounds are over and the member is padded on past the target while each step
    /// enters the archive.
    carrying: bool,
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

/// How a call of [`round`] ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RoundEnd {
    /// The member improved (and was changed).
    Improved,
    /// Nothing improved; the member is unchanged.
    NoGain,
    /// The single trials left after [`TRIALS_PER_UNIT`] of them wait for the next call (the
    /// member is unchanged and the trials made are remembered).
    Unfinished,
}

/// One round on `member`, or the part of it that [`TRIALS_PER_UNIT`] trials allow.
///
/// Scoring every removal × insertion pair would cost their product; instead each removal's
/// loss and each insertion's gain is scored alone, the best insertions are paired with the
/// cheapest removals while the gain exceeds the loss, the moves of the largest triangle's
/// vertices that pay join them ([`independent_edits`]), and the edits are tried together (they
/// are apart, so their effects nearly add up), then the better half of them, and so on down to
/// the best edit alone. Only when no batch improves are the drawn moves tried.
fn round(
    evaluator: &mut Evaluator,
    member: &mut Member,
    measure: ErrorMeasure,
    memo: &mut Memo,
    rng: &mut Pcg64Mcg,
    evaluations: &mut u64,
) -> RoundEnd {
    let hf = evaluator.heightfield().clone();
    member.ready_for_trials();
    let candidates =
        (member.kept.len() / POINTS_PER_CANDIDATE).clamp(MIN_CANDIDATES, MAX_CANDIDATES);
    member.guide(&hf);
    // Held apart from the member while the trials borrow it, and given back unless it goes stale.
    let guide: Guide = member.guide.take().expect("just made");
    let removals = guide.cheapest_removals(candidates, |i| !on_border(&hf, i));
    let corners = hf.corners();
    let largest = guide.largest_triangles(candidates.div_ceil(2));
    let guide_triangles = &guide.triangles;
    let mut moved: Vec<u32> = Vec::with_capacity(MOVES);
    for _ in 0..MOVES {
        if let Some(t) = guide.triangle_at(rng.random::<f64>()) {
            let tri = guide.triangles[t];
            let v = tri[rng.random_range(0..3)];
            if !corners.contains(&v) && !moved.contains(&v) {
                moved.push(v);
            }
        }
    }
    let mut trials = Trials {
        hf: &hf,
        member,
        measure,
        e: measure.of(&member.score),
        evaluations,
        left: TRIALS_PER_UNIT,
    };
    let mut losses = trials.removal_losses(evaluator, memo, &removals);
    let mut gains = trials.insertion_gains(evaluator, memo, &guide, &largest);
    let mut moves = trials.vertex_moves(evaluator, memo, guide_triangles, &largest);
    if trials.left == 0 {
        member.guide = Some(guide);
        return RoundEnd::Unfinished;
    }
    losses.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    gains.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    moves.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let batch = independent_edits(hf.len(), guide_triangles, &losses, &gains, &moves);
    let chosen = trials
        .improving_batch(evaluator, &batch)
        .or_else(|| trials.best_neighbour_move(evaluator, &moved));
    let Some(edit) = chosen else {
        member.guide = Some(guide);
        return RoundEnd::NoGain;
    };
    // The single trials that stay exact are those whose surroundings the edit left alone: the
    // removed points' old neighbours and the inserted points' new ones bound what changed.
    let mut changed: IndexSet<u32> = edit.remove.iter().chain(&edit.insert).copied().collect();
    neighbours_of(hf.len(), guide_triangles, &edit.remove, &mut changed);
    member.apply(evaluator, &edit);
    *evaluations += 1;
    neighbours_of(
        hf.len(),
        &member.guide(&hf).triangles,
        &edit.insert,
        &mut changed,
    );
    memo.forget(&changed);
    RoundEnd::Improved
}

/// What a round's trials share: the height field, the member they edit (unchanged until the round commits), its
/// E_sum before the round, and the run's evaluation count.
struct Trials<'a> {
    hf: &'a Heightfield,
    member: &'a Member,
    /// The error the round lowers.
    measure: ErrorMeasure,
    e: f64,
    evaluations: &'a mut u64,
    /// New single trials this call may still make (see [`TRIALS_PER_UNIT`]); at 0 the lists
    /// skip the candidates not yet tried.
    left: usize,
}

impl Trials<'_> {
    /// E_sum of the member after `edit` (one evaluation).
    fn e_after(&mut self, evaluator: &mut Evaluator, edit: &Edit) -> f64 {
        *self.evaluations += 1;
        self.measure
            .of(&mutation::trial(evaluator, self.member, edit))
    }

    /// (rise of E_sum, vertex) for removing each of `removals`, remembered in `memo`.
    fn removal_losses(
        &mut self,
        evaluator: &mut Evaluator,
        memo: &mut Memo,
        removals: &[u32],
    ) -> Vec<(f64, u32)> {
        removals
            .iter()
            .filter_map(|&r| {
                if let Some(&loss) = memo.losses.get(&r) {
                    return Some((loss, r));
                }
                if self.left == 0 {
                    return None;
                }
                self.left -= 1;
                let edit = Edit {
                    remove: vec![r],
                    insert: Vec::new(),
                };
                let loss = self.e_after(evaluator, &edit) - self.e;
                memo.losses.insert(r, loss);
                Some((loss, r))
            })
            .collect()
    }

    /// (drop of E_sum, point, triangle) for inserting two candidates of each of the `largest`
    /// triangles: its worst point and its error's centre, remembered in `memo`.
    fn insertion_gains(
        &mut self,
        evaluator: &mut Evaluator,
        memo: &mut Memo,
        guide: &Guide,
        largest: &[usize],
    ) -> Vec<(f64, u32, usize)> {
        let hf = self.hf;
        let mut gains = Vec::with_capacity(2 * largest.len());
        for &t in largest {
            let key = guide.triangles[t];
            if !memo.insertions.contains_key(&key) {
                if self.left < 2 {
                    self.left = 0;
                    continue;
                }
                self.left -= 2;
            }
            let tried = memo.insertions.entry(key).or_insert_with(|| {
                let mut points = vec![guide.worst_point(hf, t), guide.centre_point(hf, t)];
                points.retain(|&p| p != NO_POINT && !on_border(hf, p));
                points.dedup();
                points
                    .into_iter()
                    .map(|p| {
                        let edit = Edit {
                            remove: Vec::new(),
                            insert: vec![p],
                        };
                        (p, self.e - self.e_after(evaluator, &edit))
                    })
                    .collect()
            });
            gains.extend(tried.iter().map(|&(p, gain)| (gain, p, t)));
        }
        gains
    }

    /// (drop of E_sum, vertex, neighbour) for the paying moves of the vertices of the largest
    /// triangles, each to its best free grid neighbour, remembered in `memo`.
    fn vertex_moves(
        &mut self,
        evaluator: &mut Evaluator,
        memo: &mut Memo,
        triangles: &[[u32; 3]],
        largest: &[usize],
    ) -> Vec<(f64, u32, u32)> {
        let hf = self.hf;
        let corners = hf.corners();
        let mut movers: Vec<u32> = Vec::new();
        for &t in largest.iter().take(MOVE_TRIANGLES) {
            for v in triangles[t] {
                if !corners.contains(&v) && !movers.contains(&v) {
                    movers.push(v);
                }
            }
        }
        let mut moves = Vec::with_capacity(movers.len());
        for &v in &movers {
            if !memo.moves.contains_key(&v) {
                if self.left < 8 {
                    self.left = 0;
                    continue;
                }
                self.left -= 8;
            }
            let best = *memo.moves.entry(v).or_insert_with(|| {
                let mut best: Option<(u32, f64)> = None;
                for n in mutation::free_neighbours(hf, self.member, v) {
                    let edit = Edit {
                        remove: vec![v],
                        insert: vec![n],
                    };
                    let gain = self.e - self.e_after(evaluator, &edit);
                    if best.is_none_or(|b| gain > b.1) {
                        best = Some((n, gain));
                    }
                }
                best
            });
            if let Some((n, gain)) = best
                && gain > 0.0
                && !self.member.state.is_kept(n)
            {
                moves.push((gain, v, n));
            }
        }
        moves
    }

    /// The largest leading part of `batch` (halved until one does) whose edits together lower
    /// E_sum.
    fn improving_batch(
        &mut self,
        evaluator: &mut Evaluator,
        batch: &[(f64, u32, u32)],
    ) -> Option<Edit> {
        let mut count = batch.len();
        while count > 0 {
            let mut edit = Edit {
                remove: batch[..count].iter().map(|u| u.1).collect(),
                insert: batch[..count].iter().map(|u| u.2).collect(),
            };
            edit.remove.sort_unstable();
            edit.insert.sort_unstable();
            if self.e_after(evaluator, &edit) < self.e {
                return Some(edit);
            }
            count /= 2;
        }
        None
    }

    /// The best move of one of `moved` to a free grid neighbour, if any lowers E_sum.
    fn best_neighbour_move(&mut self, evaluator: &mut Evaluator, moved: &[u32]) -> Option<Edit> {
        let hf = self.hf;
        let mut best = self.e;
        let mut chosen = None;
        for &v in moved {
            for n in mutation::free_neighbours(hf, self.member, v) {
                let edit = Edit {
                    remove: vec![v],
                    insert: vec![n],
                };
                let after = self.e_after(evaluator, &edit);
                if after < best {
                    best = after;
                    chosen = Some(edit);
                }
            }
        }
        chosen
    }
}

/// Adds to `out` the vertices of the `triangles` that have one of `points` as a vertex.
fn neighbours_of(grid_len: usize, triangles: &[[u32; 3]], points: &[u32], out: &mut IndexSet<u32>) {
    with_marks(grid_len, |marks| {
        for &p in points {
            marks[p as usize] = 0;
        }
        for tri in triangles {
            if tri.iter().any(|&v| marks[v as usize] == 0) {
                out.extend(tri);
            }
        }
        for &p in points {
            marks[p as usize] = u32::MAX;
        }
    });
}

thread_local! {
    /// [`with_marks`]'s buffer, all `u32::MAX` between calls.
    static MARKS: std::cell::Cell<Vec<u32>> = const { std::cell::Cell::new(Vec::new()) };
}

/// Runs `f` on a buffer of at least `len` entries, all `u32::MAX`, which `f` must leave so: a
/// per-grid-point mark that costs nothing to clear, for the passes over a mesh's triangles.
fn with_marks<R>(len: usize, f: impl FnOnce(&mut [u32]) -> R) -> R {
    let mut marks = MARKS.take();
    if marks.len() < len {
        marks.resize(len, u32::MAX);
    }
    let result = f(&mut marks);
    MARKS.set(marks);
    result
}

/// Single-edit trials of one visit's member, kept between its rounds while they stay exact
/// (see `round`), so that a round scores only the candidates near the last edit.
#[derive(Debug, Default)]
pub struct Memo {
    /// Per kept point, the rise of E_sum when it alone is removed.
    losses: IndexMap<u32, f64>,
    /// Per triangle, its insertion candidates with the drop of E_sum when each alone is
    /// inserted.
    insertions: IndexMap<[u32; 3], Vec<(u32, f64)>>,
    /// Per kept point, its best move to a free grid neighbour with the drop of E_sum it
    /// brings (`None` when no neighbour is free).
    moves: IndexMap<u32, Option<(u32, f64)>>,
}

impl Memo {
    /// Drops the trials that an edit changing the stars of the points `changed` may have made
    /// stale: removals of those points, insertions into triangles with one of them as a vertex.
    fn forget(&mut self, changed: &IndexSet<u32>) {
        self.losses.retain(|v, _| !changed.contains(v));
        self.moves.retain(|v, _| !changed.contains(v));
        self.insertions
            .retain(|tri, _| tri.iter().all(|v| !changed.contains(v)));
    }
}

/// Pairs the best insertions (`gains`, best first, each with the triangle holding it) with the
/// cheapest removals (`losses`, cheapest first) while the gain exceeds the loss, skipping any
/// candidate whose edit would touch the same vertices as one already paired: the removal of a
/// vertex changes its star, an insertion the triangle holding it and its surroundings, and
/// only edits that stay apart add up to what their single trials promised. Returns the
/// removals, the insertions and the promised drops of E_sum, best pair first, and leaves in
/// `touched` the points the pairs touch.
fn independent_pairs(
    grid_len: usize,
    triangles: &[[u32; 3]],
    losses: &[(f64, u32)],
    gains: &[(f64, u32, usize)],
    touched: &mut IndexSet<u32>,
) -> (Vec<u32>, Vec<u32>, Vec<f64>) {
    // Each removal candidate's neighbours, indexed like `losses`.
    let removals: Vec<u32> = losses.iter().map(|l| l.1).collect();
    let star = stars(grid_len, triangles, &removals);
    let (mut remove, mut insert, mut drops) = (Vec::new(), Vec::new(), Vec::new());
    let (mut g, mut l) = (gains.iter(), losses.iter().enumerate());
    while let Some(&(gain, p, t)) = g.find(|c| triangles[c.2].iter().all(|v| !touched.contains(v)))
    {
        let near = triangles[t];
        let removal = l.find(|(k, c)| {
            let around = &star[*k];
            !touched.contains(&c.1)
                && !near.contains(&c.1)
                && around
                    .iter()
                    .all(|v| !touched.contains(v) && !near.contains(v))
        });
        let Some((k, &(loss, r))) = removal else {
            break;
        };
        if gain <= loss {
            break;
        }
        touched.extend(near);
        touched.insert(p);
        touched.insert(r);
        touched.extend(star[k].iter().copied());
        remove.push(r);
        insert.push(p);
        drops.push(gain - loss);
    }
    (remove, insert, drops)
}

/// The edits of one batch, best first by their promised drop of E_sum: the swaps
/// [`independent_pairs`] makes, then the `moves` (drop, vertex, target, best first) whose
/// vertex and star stay apart from every edit already taken. Each is (drop, removed,
/// inserted).
fn independent_edits(
    grid_len: usize,
    triangles: &[[u32; 3]],
    losses: &[(f64, u32)],
    gains: &[(f64, u32, usize)],
    moves: &[(f64, u32, u32)],
) -> Vec<(f64, u32, u32)> {
    let mut touched: IndexSet<u32> = IndexSet::default();
    let (remove, insert, drops) =
        independent_pairs(grid_len, triangles, losses, gains, &mut touched);
    let mut batch: Vec<(f64, u32, u32)> = drops
        .into_iter()
        .zip(remove)
        .zip(insert)
        .map(|((d, r), i)| (d, r, i))
        .collect();
    let movers: Vec<u32> = moves.iter().map(|m| m.1).collect();
    let star = stars(grid_len, triangles, &movers);
    for (k, &(gain, v, n)) in moves.iter().enumerate() {
        if touched.contains(&v)
            || touched.contains(&n)
            || star[k].iter().any(|u| touched.contains(u))
        {
            continue;
        }
        touched.insert(v);
        touched.insert(n);
        touched.extend(star[k].iter().copied());
        batch.push((gain, v, n));
    }
    batch.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    batch
}

/// Per point of `points` (kept vertices), its neighbours in `triangles` (with repeats).
fn stars(grid_len: usize, triangles: &[[u32; 3]], points: &[u32]) -> Vec<Vec<u32>> {
    let mut star: Vec<Vec<u32>> = vec![Vec::new(); points.len()];
    with_marks(grid_len, |marks| {
        for (k, &p) in points.iter().enumerate() {
            marks[p as usize] = k as u32;
        }
        for tri in triangles {
            for k in 0..3 {
                let at = marks[tri[k] as usize];
                if at != u32::MAX {
                    star[at as usize].extend([tri[(k + 1) % 3], tri[(k + 2) % 3]]);
                }
            }
        }
        for &p in points {
            marks[p as usize] = u32::MAX;
        }
    });
    star
}

/// A multiply-rotate hasher for grid indices and their triples: the maps of a round are keyed
/// by small integers and never iterated, so neither flooding resistance nor order matters, and
/// the default hasher's cost would rival the trials'.
#[derive(Default)]
struct IndexHasher(u64);

impl IndexHasher {
    fn add(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

impl Hasher for IndexHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(4) {
            let mut word = [0u8; 4];
            word[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from(u32::from_le_bytes(word)));
        }
    }

    fn write_u32(&mut self, n: u32) {
        self.add(u64::from(n));
    }

    fn write_usize(&mut self, n: usize) {
        self.add(n as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

type IndexMap<K, V> = HashMap<K, V, BuildHasherDefault<IndexHasher>>;
type IndexSet<K> = HashSet<K, BuildHasherDefault<IndexHasher>>;

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paired_edits_stay_apart_and_stop_when_the_gain_no_longer_pays() {
        // A strip of triangles 0-1-2, 1-2-3, 2-3-4, 3-4-5, 4-5-6, 5-6-7 on a grid of 8 points.
        let triangles: Vec<[u32; 3]> = (0..6).map(|k| [k, k + 1, k + 2]).collect();
        // Insertions in triangles 0 and 1 (sharing vertices 1 and 2), and in triangle 5.
        let gains = [(10.0, 100, 0), (9.0, 101, 1), (8.0, 102, 5)];
        // Removing 3 touches 1..=5 (its star), removing 7 touches 5 and 6.
        let losses = [(1.0, 3), (2.0, 7), (3.0, 6)];
        let mut touched = IndexSet::default();
        let (remove, insert, _) = independent_pairs(200, &triangles, &losses, &gains, &mut touched);
        // The best insertion (into 0-1-2) cannot pair with removing 3, whose star holds 1 and
        // 2: it pairs with 7. The second insertion shares vertices with the first, the third
        // with removing 7.
        assert_eq!((remove, insert), (vec![7], vec![100]));
        // A gain that does not exceed the loss ends the pairing.
        let mut touched = IndexSet::default();
        let (remove, insert, _) =
            independent_pairs(200, &triangles, &[(20.0, 7)], &gains, &mut touched);
        assert!(remove.is_empty() && insert.is_empty());
    }

    #[test]
    fn the_memo_forgets_the_trials_around_changed_points() {
        let mut memo = Memo::default();
        memo.losses.insert(3, 1.0);
        memo.losses.insert(9, 2.0);
        memo.insertions.insert([1, 2, 3], vec![(50, 4.0)]);
        memo.insertions.insert([7, 8, 9], vec![(60, 5.0)]);
        let changed: IndexSet<u32> = [3, 4].into_iter().collect();
        memo.forget(&changed);
        assert!(!memo.losses.contains_key(&3) && memo.losses.contains_key(&9));
        assert!(!memo.insertions.contains_key(&[1, 2, 3]));
        assert!(memo.insertions.contains_key(&[7, 8, 9]));
    }
}
