//! Objectives of an evaluated chromosome, the normalised weighted sum used wherever a scalar
//! fitness is needed, and the scorer that turns chromosomes into objectives and counts the
//! evaluations.
//!
//! # Incremental scoring
//! A child mostly resembles chromosomes scored shortly before it: a mutated child differs from
//! its crossed child in a gene or two, an OAX row from a parent or a sibling in a few blocks.
//! The [`Scorer`] therefore keeps the meshes ([`MeshState`]) of the most recently used
//! chromosomes, a bounded pool, and scores a new chromosome by editing the mesh of the nearest
//! one in Hamming distance ([`Evaluator::edit`]) when that is cheaper than building it from
//! scratch, i.e. when the distance is at most [`EDIT_LIMIT_PER_POINT`] of the grid. The edited
//! mesh is bit for bit the one a fresh [`Evaluator::score`] builds and its objectives are the same
//! bits (the evaluator guarantees it), so the pool changes speed only: every run, front and
//! evaluation count is exactly what scoring every chromosome from scratch gives. A chromosome
//! equal to a pooled one takes its objectives (still one evaluation in the count: the GA's
//! accounting does not depend on the pool).
//!
//! A crossed child ([`Scorer::score_crossed`]) is usually hundreds of genes from every pooled
//! chromosome but block by block equal to one of its two parents; when both parents are pooled
//! its mesh is composed from theirs ([`Evaluator::compose`]), which re-triangulates only the
//! seams between blocks; the parents' triangles are classified against the crossover's blocks
//! once for all its rows ([`PartClasses`]). Crossed children are replaced in the pool before
//! other chromosomes (beyond [`CROSSED_POOLED`] of them), as the parents of later crossovers
//! are among the others, and the GA's current population last of all
//! ([`Scorer::keep_alive`]).
//!
//! Most offspring never need a mesh: only those that join the population become parents, and
//! in the paper run on jacksboro_65x65 about one in four did. So a crossed child is scored
//! without one ([`PartScores`]), a mutant of it too (its few changed points dropping the
//! reused triangles they spoil, [`PartScores::score_changed`]), and their meshes are composed
//! only for the offspring that the next [`Scorer::keep_alive`] declares alive.

use super::chromosome::Chromosome;
use super::oax::Parentage;
use crate::evaluator::{Changes, Evaluator, MeshState, PartClasses, PartScores};
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// What the [`Evaluator`] says about one kept set.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Objectives {
    /// E = Σ |z − z̃|.
    #[serde(rename = "E_sum")]
    pub e_sum: f64,
    /// max |z − z̃|.
    #[serde(rename = "E_max")]
    pub e_max: f64,
    /// Triangle count.
    #[serde(rename = "T")]
    pub t: usize,
}

impl Objectives {
    /// The minimised pair (E_sum, T).
    pub fn pair(&self) -> [f64; 2] {
        [self.e_sum, self.t as f64]
    }
}

/// F = w·E/E₀ + (1 − w)·T/T₀, to minimise.
///
/// Normalisers: E₀ = E of the corner-only mesh (the worst sensible error; 1 if the surface is
/// flat so that E₀ > 0) and T₀ = 2(W − 1)(H − 1), the triangle count of the full grid. Both
/// terms then run over about [0, 1] whatever the surface's scale and size.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scalarisation {
    /// Weight of the error, in [0, 1].
    pub w: f64,
    /// E₀.
    pub e0: f64,
    /// T₀.
    pub t0: f64,
}

impl Scalarisation {
    /// F of `o`.
    pub fn value(&self, o: &Objectives) -> f64 {
        self.w * o.e_sum / self.e0 + (1.0 - self.w) * o.t as f64 / self.t0
    }
}

/// The largest Hamming distance, as a fraction of the grid points, at which the [`Scorer`]
/// edits a pooled mesh rather than building a new one. Measured (`cargo bench --bench evaluator
/// -- incremental`, jacksboro_65x65 at 30 % density): an edit costs ≈ 0.4 µs per differing gene
/// (plus ≈ 4 µs to copy the base mesh), a fresh build 0.8–1.4 ms, so they cross near 0.7 of the
/// grid; 0.5 keeps a margin. In the paper run on jacksboro_65x65, limits 0.5, 0.75 and 1 take
/// the same time, 0.3 about 10 % more and 0.15 twice as much.
pub const EDIT_LIMIT_PER_POINT: f64 = 0.5;

/// A crossed child is composed from its parents' meshes ([`Scorer::score_crossed`]) only when
/// every pooled chromosome is more than [`COMPOSE_MIN_GENES`] + (T_A + T_B) / this many genes
/// from it (T_A, T_B the parents' triangle counts); nearer, an edit of that one is cheaper.
/// Measured (`cargo bench --bench evaluator -- compose`, jacksboro_65x65): composing costs
/// ≈ 20–25 ns per parent triangle, an edit ≈ 27 µs plus ≈ 0.45 µs per differing gene; in the
/// paper run a composition took ≈ 207 µs for ≈ 6 000 parent triangles, more than the bench
/// predicts, hence the offset.
pub const COMPOSE_TRIANGLES_PER_GENE: usize = 20;

/// See [`COMPOSE_TRIANGLES_PER_GENE`]. Without it the weighted-sum GA, whose children are near
/// their parents, composed where an edit was cheaper and ran slower.
pub const COMPOSE_MIN_GENES: usize = 100;

/// A crossed child is scored without a mesh ([`Scorer::score_crossed`]) unless a pooled
/// chromosome is within this many genes of it, which is then edited instead.
pub const ROW_EDIT_GENES: usize = 40;

/// How many crossed children the pool keeps before it replaces them ahead of other
/// chromosomes: a crossover's rows (at most 8 with L8, plus the best-levels child) and some
/// slack, so that the children a mutant is edited from stay pooled.
pub const CROSSED_POOLED: usize = 24;

/// How many of the most recently scored chromosomes the [`Scorer`] compares with first.
const RECENT: usize = 16;

/// Most meshes the [`Scorer`] keeps until the GA declares a population larger than half of
/// it ([`Scorer::keep_alive`]), and then [`POOL_PER_MEMBER`] per member. The pool holds the
/// population, which the GAs declare alive so that both parents of every crossover are pooled
/// to compose from, the offspring that join it (their meshes are composed while the old
/// population, which holds their parents, is still pooled), and the bases of a crossover's
/// edits. Offspring meshes are built only for those that join the population, so the pool
/// need not hold whole offspring generations any more: in the paper run on jacksboro_65x65
/// (min / median of ten alternating runs, session 15) 320 meshes took 973 / 1 041 ms, 200
/// took 901 / 995 ms and 160 907 / 976 ms (fewer first touches of memory: 25.7 k page faults
/// at 320, 19.9 k at 200), but 128 took 2.8 s, as composing the offspring that join the
/// population then replaced their parents.
pub const POOL_STATES: usize = 200;

/// Meshes the pool holds per member of the declared population, when that is more than
/// [`POOL_STATES`]: the old and the new population (see [`POOL_STATES`]). Why it scales: with a
/// fixed 200, `--pop 200` on the paper run took 3.97 s instead of 1.08 s.
pub const POOL_PER_MEMBER: usize = 2;

pub const POOL_BYTES: usize = 160 << 20;

/// The gene counts of [`PROFILE_PARTS`] consecutive stretches of a chromosome. The Hamming
/// distance of two chromosomes is at least the sum of the differences of their counts, a lower
/// bound far cheaper than the distance (16 subtractions instead of a pass over the words), which
/// lets the [`Scorer`]'s search skip most pooled chromosomes of a population whose total gene
/// counts are alike.
#[derive(Clone, Copy, Debug, Default)]
struct Profile([u32; PROFILE_PARTS]);

const PROFILE_PARTS: usize = 16;

impl Profile {
    fn of(c: &Chromosome) -> Self {
        let words = c.words();
        let per = words.len().div_ceil(PROFILE_PARTS).max(1);
        let mut counts = [0u32; PROFILE_PARTS];
        for (count, part) in counts.iter_mut().zip(words.chunks(per)) {
            *count = part.iter().map(|w| w.count_ones()).sum();
        }
        Self(counts)
    }

    /// The lower bound on the Hamming distance of the two chromosomes.
    fn distance_below(&self, other: &Self) -> usize {
        self.0
            .iter()
            .zip(&other.0)
            .map(|(a, b)| a.abs_diff(*b) as usize)
            .sum()
    }
}

/// A scored chromosome with its mesh, in the [`Scorer`]'s pool.
struct Pooled {
    genes: Chromosome,
    state: MeshState,
    objectives: Objectives,
    /// When it was last scored or used as a base (a tick of the scorer), for replacement.
    used: u64,
    /// Scored as a crossed child ([`Scorer::score_crossed`]): an intermediate that is a base
    /// for its mutant at most, replaced before the chromosomes that may become parents.
    crossed: bool,
    /// In the GA's current population ([`Scorer::keep_alive`]): a parent of the coming
    /// crossovers, replaced only after every other chromosome.
    alive: bool,
}

/// What the [`Scorer`]'s search reads first of a pooled chromosome: its number of set genes
/// and its [`Profile`], kept apart from the rest ([`Scorer::keys`]) so that the search, which
/// skips most of the pool on them, reads them contiguously.
#[derive(Clone, Copy, Debug)]
struct Key {
    ones: usize,
    profile: Profile,
}

/// Scores chromosomes on one height field and counts every evaluation. Incremental: see the
/// module doc.
pub struct Scorer {
    evaluator: Evaluator,
    indices: Vec<u32>,
    evaluations: u64,
    /// E₀ and T₀ of [`Scalarisation`].
    normalisers: (f64, f64),
    pool: Vec<Pooled>,
    /// Per pool slot, its chromosome's [`Key`] (`ones` is `usize::MAX` for a slot that nothing
    /// may match).
    keys: Vec<Key>,
    capacity: usize,
    /// The most meshes [`POOL_BYTES`] allows.
    capacity_by_bytes: usize,
    tick: u64,
    removed: Vec<u32>,
    /// The last [`RECENT`] pool slots scored (a ring; `usize::MAX` while unfilled).
    recent: [usize; RECENT],
    recent_at: usize,
    inserted: Vec<u32>,
    /// The blocks of the crossover composed last, as rectangles, and its parents' triangles
    /// classified against them: the rows of a crossover share both, so each row's
    /// composition tests a mask per triangle instead of searching circles.
    crossing_blocks: Vec<[usize; 4]>,
    crossing: PartClasses,
    /// The pool slots of the classified crossover's parents A and B.
    crossing_parents: [usize; 2],
    /// What that crossover's children share, for scoring them without their meshes.
    crossing_scores: PartScores,
    /// The children of that crossover scored without their meshes.
    rows: Vec<Row>,
    /// Offspring scored without their meshes since the last [`keep_alive`](Self::keep_alive),
    /// whose meshes are composed only if they join the population (see [`Deferred`]).
    deferred: Vec<Deferred>,
    /// The classifications the deferred offspring are composed from, and buffers for more.
    retained: Vec<PartClasses>,
    spare: Vec<PartClasses>,
}

/// An offspring that goes on without its mesh: a crossed child that no mutation changed, or a
/// mutant of one scored without a mesh ([`PartScores::score_changed`]). Most
/// offspring die at the next survival (about four in five of the paper run's), so its mesh is
/// composed only when it joins the population ([`Scorer::keep_alive`]), from its crossover's
/// parents (still pooled then: they are the population it was bred from) and classification.
#[derive(Clone, Debug)]
struct Deferred {
    genes: Chromosome,
    ones: usize,
    profile: Profile,
    objectives: Objectives,
    origin: Origin,
    /// What its mutation changed in the crossed child or the base (nothing for a crossed
    /// child that went on unchanged).
    removed: Vec<u32>,
    inserted: Vec<u32>,
}

/// What a deferred offspring's mesh is made from.
#[derive(Clone, Debug)]
enum Origin {
    /// A crossed child with `levels` (bit k: block k from parent B) of the parents in pool
    /// slots `parents`, whose classification is `retained[classes]`.
    Crossed {
        classes: usize,
        parents: [usize; 2],
        levels: u32,
    },
    /// A pooled chromosome, edited (found by its genes when the mesh is made).
    Edited { base: Chromosome },
}

/// A mutant of a crossed child scored without a mesh differs from it in at most this many
/// genes (beyond, the child's mesh is composed and edited). The paper run's mutants differ in
/// one or two.
const MUTANT_CHANGES: usize = 8;

/// Most offspring deferred at once: beyond, a GA that declares no population
/// ([`Scorer::keep_alive`]) would keep every classification; they are then dropped (their
/// offspring are scored like any chromosome should they come back).
const MAX_DEFERRED: usize = 1024;

/// Where the classification of a mesh to compose is: the current crossover's, or one retained
/// for deferred offspring ([`Scorer::retained`]).
#[derive(Clone, Copy, Debug)]
enum ClassesAt {
    Crossing,
    Retained(usize),
}

/// How to compose a mesh from pooled parents ([`Scorer::compose_pooled`]).
#[derive(Clone, Copy, Debug)]
struct Recipe {
    /// The pool slots of parents A and B.
    parents: [usize; 2],
    classes: ClassesAt,
    /// Bit k: block k from parent B.
    levels: u32,
    /// The deferred offspring whose changes are then made (none for a crossed child).
    changed_as: Option<usize>,
}

/// A child of the current crossover scored without its mesh ([`Scorer::crossing_row`]).
#[derive(Clone, Debug)]
struct Row {
    genes: Chromosome,
    ones: usize,
    profile: Profile,
    /// Bit k: block k from parent B.
    levels: u32,
    objectives: Objectives,
}

/// The base of an edit: a pooled chromosome, or a row of the current crossover (whose mesh is
/// composed first).
#[derive(Clone, Copy, Debug)]
enum Base {
    Pool(usize),
    Row(usize),
}

impl Scorer {
    /// A scorer for `hf` (the corner-only mesh is scored once for E₀; that is not counted).
    pub fn new(hf: Arc<Heightfield>) -> Self {
        let mut evaluator = Evaluator::new(hf.clone());
        let e0 = evaluator
            .score(&hf.corners())
            .expect("corner indices are grid indices")
            .e_sum;
        let t0 = hf.full_triangles().max(1) as f64;
        // A mesh state: per point an error (8 bytes), a hint (4), a kept mark (1) and a gene
        // bit; per triangle (at most 2 per point) 6 half-edge words of 4 bytes and a disc box
        // of 8.
        let state_bytes = hf.len() * (8 + 4 + 1 + 2 * (24 + 8)) + hf.len() / 8;
        let capacity_by_bytes = (POOL_BYTES / state_bytes.max(1)).max(1);
        Self {
            evaluator,
            indices: Vec::new(),
            evaluations: 0,
            normalisers: (if e0 > 0.0 { e0 } else { 1.0 }, t0),
            pool: Vec::new(),
            keys: Vec::new(),
            capacity: capacity_by_bytes.min(POOL_STATES),
            capacity_by_bytes,
            tick: 0,
            removed: Vec::new(),
            recent: [usize::MAX; RECENT],
            recent_at: 0,
            inserted: Vec::new(),
            crossing_blocks: Vec::new(),
            crossing: PartClasses::default(),
            crossing_parents: [usize::MAX; 2],
            crossing_scores: PartScores::default(),
            rows: Vec::new(),
            deferred: Vec::new(),
            retained: Vec::new(),
            spare: Vec::new(),
        }
    }

    /// Evaluates `c` (one evaluation). The result is exactly [`Evaluator::score`]'s for `c`'s
    /// kept set, whether it was built from scratch or edited from a pooled mesh.
    pub fn score(&mut self, c: &Chromosome) -> Objectives {
        self.score_made(c, None)
    }

    /// [`score`](Self::score) for a child of a crossover made as `made` says: when both
    /// parents' meshes are in the pool and no pooled chromosome is near the child (see
    /// [`COMPOSE_TRIANGLES_PER_GENE`]), its mesh is composed from theirs
    /// ([`Evaluator::compose`]). The same objectives, bit for bit, either way.
    pub fn score_crossed(&mut self, c: &Chromosome, made: Parentage<'_>) -> Objectives {
        self.score_made(c, Some(made))
    }

    fn score_made(&mut self, c: &Chromosome, made: Option<Parentage<'_>>) -> Objectives {
        self.evaluations += 1;
        self.tick += 1;
        // Both parents pooled?
        let parents = made.filter(|_| self.capacity >= 3).and_then(|m| {
            let [a, b] = [self.pooled(m.parents[0])?, self.pooled(m.parents[1])?];
            (a != b).then_some(([a, b], m.from_b))
        });
        let ones = c.count_ones();
        let profile = Profile::of(c);
        // A crossed child whose crossover's parents are classified is scored without a mesh
        // (see `crossing_row`), unless a pooled chromosome is so near that editing it is
        // cheaper (or equal to it).
        if let (Some(m), Some(([a, b], _))) = (made, parents)
            && self
                .nearest(c, ones, &profile, ROW_EDIT_GENES + 1)
                .is_none()
            && let Some(levels) = self.classify(m, [a, b])
            && let Some(o) = self.crossing_row(c, ones, profile, levels)
        {
            return o;
        }
        // Otherwise a base is worth editing only if it is nearer than where composing becomes
        // cheaper, which also cuts the search short.
        let mut limit = (EDIT_LIMIT_PER_POINT * c.len() as f64) as usize;
        if let Some(([a, b], _)) = parents {
            let triangles = self.pool[a].objectives.t + self.pool[b].objectives.t;
            limit = limit.min(COMPOSE_MIN_GENES + triangles / COMPOSE_TRIANGLES_PER_GENE);
        }
        let mut nearest = self.nearest(c, ones, &profile, limit + 1);
        if let Some((Base::Pool(i), 0)) = nearest {
            self.pool[i].used = self.tick;
            self.remember(i);
            return self.pool[i].objectives;
        }
        // A mutant of a crossed child scored without its mesh is scored without one too, its
        // mesh deferred; failing that, the child's mesh is composed now (not an evaluation: its
        // objectives are known) and edited.
        if let Some((Base::Row(r), d)) = nearest
            && made.is_none()
            && d <= MUTANT_CHANGES
            && let Some(o) = self.mutant_row(c, ones, profile, r)
        {
            return o;
        }
        // So is a mutant of a pooled chromosome that it would otherwise copy to edit.
        if let Some((Base::Pool(i), d)) = nearest
            && made.is_none()
            && d <= MUTANT_CHANGES
            && !self.pool[i].crossed
            && let Some(o) = self.mutant_of_pooled(c, ones, profile, i)
        {
            return o;
        }
        if let Some((Base::Row(r), d)) = nearest {
            nearest = self.materialize(r).map(|slot| (Base::Pool(slot), d));
        }
        let nearest = nearest.map(|(base, d)| match base {
            Base::Pool(i) => (d, i),
            Base::Row(_) => unreachable!("rows are materialised above"),
        });
        // Compose when no base is near enough.
        let parents = parents.filter(|_| nearest.is_none());
        let base = nearest.map(|(_, i)| i);
        // The slot to score into: the base itself when it is a crossed child and `c` is not
        // (a mutant of it: the crossed child is an intermediate that nothing needs once its
        // mutant is scored, so its mesh is edited in place instead of copied first); else a new
        // one while the pool grows, else the least recently used one that is neither the base
        // nor a parent (the base itself when the pool holds one mesh).
        let consumed = base.filter(|&b| made.is_none() && self.pool[b].crossed);
        let keep = [base, parents.map(|p| p.0[0]), parents.map(|p| p.0[1])];
        let slot = match consumed {
            Some(b) => b,
            None => self.free_slot(c, ones, profile, keep),
        };
        let mut score = None;
        if let Some(([a, b], from_b)) = parents {
            self.ready_parents([a, b]);
            let mut state = std::mem::take(&mut self.pool[slot].state);
            let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
            // The crossover's classification, when there is one for these parents (a failed
            // one is not `is_for` them, so the row falls back to the bitset).
            let by_parts = made
                .filter(|_| self.crossing.is_for(pa, pb))
                .and_then(|m| self.levels_of(m));
            score = match by_parts {
                Some(levels) => {
                    self.evaluator
                        .compose_parts(&mut state, pa, pb, &self.crossing, levels)
                }
                None => self.evaluator.compose(&mut state, pa, pb, from_b.words()),
            };
            self.pool[slot].state = state;
        }
        let score = match (score, base) {
            (Some(s), _) => Ok(s),
            (None, Some(b)) => {
                let corners = self.evaluator.heightfield().corners();
                (self.pool[b].genes).write_edit(c, &corners, &mut self.removed, &mut self.inserted);
                if b != slot {
                    self.copy_state(b, slot);
                    self.pool[b].used = self.tick;
                }
                self.evaluator
                    .edit(&mut self.pool[slot].state, &self.removed, &self.inserted)
            }
            (None, None) => {
                c.write_indices(&mut self.indices);
                self.evaluator
                    .score_into(&self.indices, &mut self.pool[slot].state)
            }
        };
        // A chromosome has one bit per grid point, and the pooled mesh is the one of the base's
        // genes (corners aside, which both keep), so neither call can fail.
        let s = score.expect("chromosome indices are grid indices");
        let objectives = Objectives {
            e_sum: s.e_sum,
            e_max: s.e_max,
            t: s.t,
        };
        self.keys[slot] = Key { ones, profile };
        let entry = &mut self.pool[slot];
        entry.genes.clone_from(c);
        entry.objectives = objectives;
        entry.used = self.tick;
        entry.crossed = made.is_some();
        self.remember(slot);
        objectives
    }

    /// The nearest chromosome to `c` (`ones` set genes, `profile`) closer than `bound` genes,
    /// and its distance: a pooled one or, when strictly nearer, a child of the current
    /// crossover scored without its mesh. The first of equals among the pooled ones.
    fn nearest(
        &self,
        c: &Chromosome,
        ones: usize,
        profile: &Profile,
        mut bound: usize,
    ) -> Option<(Base, usize)> {
        let mut nearest = None;
        // The most recently scored first: a mutant's base is the crossed child scored just
        // before it, and a tight bound early lets the rest of the scan skip or stop early
        // (measured without it, min of two: the paper run 2.97 → 3.46 s, the weighted-sum GA
        // 9.33 → 9.75 s).
        // The distance to a chromosome (its genes, count and profile) when below `bound`: the
        // difference of the counts and of the profiles bound it from below and skip most.
        let below = |genes: &Chromosome, their_ones: usize, theirs: &Profile, bound: usize| {
            if their_ones.abs_diff(ones) >= bound || theirs.distance_below(profile) >= bound {
                return None;
            }
            genes.hamming_below(c, bound)
        };
        let recent = self.recent.into_iter().filter(|&i| i < self.pool.len());
        for i in recent.chain(0..self.pool.len()) {
            let key = &self.keys[i];
            if let Some(d) = below(&self.pool[i].genes, key.ones, &key.profile, bound) {
                nearest = Some((Base::Pool(i), d));
                bound = d;
                if d == 0 {
                    return nearest;
                }
            }
        }
        for (r, row) in self.rows.iter().enumerate() {
            if let Some(d) = below(&row.genes, row.ones, &row.profile, bound) {
                nearest = Some((Base::Row(r), d));
                bound = d;
            }
        }
        nearest
    }

    /// A pool slot to score `c` into: a new one while the pool grows, else the least recently
    /// used one not in `keep` (crossed children first once there are [`CROSSED_POOLED`] of
    /// them, the GA's population last).
    fn free_slot(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        keep: [Option<usize>; 3],
    ) -> usize {
        if self.pool.len() < self.capacity {
            self.keys.push(Key { ones, profile });
            self.pool.push(Pooled {
                genes: c.clone(),
                state: MeshState::default(),
                objectives: Objectives {
                    e_sum: 0.0,
                    e_max: 0.0,
                    t: 0,
                },
                used: 0,
                crossed: false,
                alive: false,
            });
            return self.pool.len() - 1;
        }
        // Crossed children are replaced first once there are CROSSED_POOLED of them: the
        // parents of later crossovers are among the others, and composing needs both.
        let crossed = self.pool.iter().filter(|p| p.crossed).count();
        (0..self.pool.len())
            .filter(|&i| !keep.contains(&Some(i)) || self.pool.len() == 1)
            .min_by_key(|&i| {
                let p = &self.pool[i];
                (p.alive, crossed < CROSSED_POOLED || !p.crossed, p.used)
            })
            .expect("the pool is not empty")
    }

    /// The levels of `made`'s blocks as a mask (bit k: block k from B).
    fn levels_of(&self, made: Parentage<'_>) -> Option<u32> {
        (made.blocks.len() <= PartClasses::MAX_PARTS).then(|| {
            (made.levels.iter().enumerate())
                .fold(0u32, |acc, (k, &l)| acc | (u32::from(l & 1) << k))
        })
    }

    /// Readies pooled parents `[a, b]` to compose or classify from (their disc boxes and
    /// lookups), and marks them used now.
    fn ready_parents(&mut self, parents: [usize; 2]) {
        for p in parents {
            self.pool[p].state.ensure_discs();
            self.pool[p].used = self.tick;
        }
    }

    /// Makes sure the current crossover's classification is for `made`'s blocks and the pooled
    /// parents `[a, b]` (making it at the crossover's first row), and returns `made`'s levels;
    /// `None` when it cannot be made.
    fn classify(&mut self, made: Parentage<'_>, [a, b]: [usize; 2]) -> Option<u32> {
        let levels = self.levels_of(made)?;
        self.ready_parents([a, b]);
        let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
        let rects = made.blocks.iter().map(|b| [b.x0, b.y0, b.x1, b.y1]);
        if !self.crossing_blocks.iter().copied().eq(rects.clone()) || !self.crossing.is_for(pa, pb)
        {
            self.crossing_blocks.clear();
            self.crossing_blocks.extend(rects);
            let hf = self.evaluator.heightfield().clone();
            self.crossing.reset(&hf, pa, pb, &self.crossing_blocks);
            self.rows.clear();
        }
        self.crossing_parents = [a, b];
        self.crossing.is_for(pa, pb).then_some(levels)
    }

    /// Scores the child `c` with `levels` of the current crossover without building its mesh
    /// ([`Evaluator::score_parts`]) and remembers it among the crossover's rows, to compose
    /// its mesh should a mutant need it ([`materialize`](Self::materialize)). `None` when a
    /// guard refuses (the child is then scored another way).
    fn crossing_row(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        levels: u32,
    ) -> Option<Objectives> {
        let [a, b] = self.crossing_parents;
        let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
        if !self.crossing_scores.is_for(&self.crossing, pa, pb) {
            let hf = self.evaluator.heightfield().clone();
            if !self.crossing_scores.prepare(&hf, pa, pb, &self.crossing) {
                return None;
            }
        }
        let s = self.evaluator.score_parts(
            pa,
            pb,
            &self.crossing,
            &mut self.crossing_scores,
            levels,
        )?;
        let objectives = Objectives {
            e_sum: s.e_sum,
            e_max: s.e_max,
            t: s.t,
        };
        self.rows.push(Row {
            genes: c.clone(),
            ones,
            profile,
            levels,
            objectives,
        });
        Some(objectives)
    }

    /// Composes the mesh of the current crossover's row `r` into a pool slot, as an intermediate
    /// (replaced early), and returns the slot; `None` when its parents changed or composing
    /// refused.
    fn materialize(&mut self, r: usize) -> Option<usize> {
        let row = self.rows[r].clone();
        let recipe = Recipe {
            parents: self.crossing_parents,
            classes: ClassesAt::Crossing,
            levels: row.levels,
            changed_as: None,
        };
        let key = Key {
            ones: row.ones,
            profile: row.profile,
        };
        self.compose_pooled(row.genes, key, row.objectives, recipe, true)
    }

    /// Composes the mesh of `genes` (with `key`, scored `objectives`) as `recipe` says into a
    /// pool slot that is neither alive nor one of its parents, and returns the slot: a crossed
    /// child (`crossed`, an intermediate replaced early, and among the recently scored) or an
    /// offspring that joins the population (alive). `None` when its parents changed or
    /// composing refused (it then stays unpooled).
    fn compose_pooled(
        &mut self,
        genes: Chromosome,
        key: Key,
        objectives: Objectives,
        recipe: Recipe,
        crossed: bool,
    ) -> Option<usize> {
        let [a, b] = recipe.parents;
        if a >= self.pool.len() || b >= self.pool.len() {
            return None;
        }
        let slot = self.free_slot(&genes, key.ones, key.profile, [Some(a), Some(b), None]);
        let mut state = std::mem::take(&mut self.pool[slot].state);
        let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
        let classes = match recipe.classes {
            ClassesAt::Crossing => &self.crossing,
            ClassesAt::Retained(k) => &self.retained[k],
        };
        let mut score = classes
            .is_for(pa, pb)
            .then(|| {
                self.evaluator
                    .compose_parts(&mut state, pa, pb, classes, recipe.levels)
            })
            .flatten();
        if let Some(d) = recipe.changed_as.map(|d| &self.deferred[d])
            && score.is_some()
            && !(d.removed.is_empty() && d.inserted.is_empty())
        {
            score = self
                .evaluator
                .edit(&mut state, &d.removed, &d.inserted)
                .ok();
        }
        debug_assert!(score.is_none_or(|s| (s.e_sum, s.t) == (objectives.e_sum, objectives.t)));
        self.pool[slot].state = state;
        let slot = self.settle(slot, score.is_some(), genes, key, objectives, crossed)?;
        if crossed {
            // About to be a mutant's base.
            self.remember(slot);
        }
        Some(slot)
    }

    /// Makes pool slot `slot`, whose mesh has just been made (`made`) for `genes` (with `key`,
    /// scored `objectives`), hold them, as a crossed child (`crossed`, an intermediate) or an
    /// offspring that joins the population (alive), and returns it. When the mesh could not be
    /// made, the slot's mesh is unscored: nothing may match it, and `None`.
    fn settle(
        &mut self,
        slot: usize,
        made: bool,
        genes: Chromosome,
        key: Key,
        objectives: Objectives,
        crossed: bool,
    ) -> Option<usize> {
        if !made {
            self.pool[slot].genes = Chromosome::empty(0);
            self.keys[slot].ones = usize::MAX;
            return None;
        }
        self.keys[slot] = key;
        let entry = &mut self.pool[slot];
        entry.genes = genes;
        entry.objectives = objectives;
        entry.used = self.tick;
        entry.crossed = crossed;
        entry.alive = !crossed;
        Some(slot)
    }

    /// Puts pool slot `i` among the recently scored ones.
    fn remember(&mut self, i: usize) {
        self.recent[self.recent_at] = i;
        self.recent_at = (self.recent_at + 1) % RECENT;
    }

    /// Tells the scorer that `c`, scored as a crossed child, goes on unchanged (a mutation that
    /// flipped no gene): it may become a parent, so its mesh is kept like the other offspring's.
    /// Spends no evaluation.
    pub fn promote(&mut self, c: &Chromosome) {
        if let Some(i) = self.pooled(c) {
            self.pool[i].crossed = false;
            self.pool[i].used = self.tick;
        } else if let Some(r) = self.rows.iter().position(|r| r.genes == *c) {
            let row = &self.rows[r];
            let (ones, profile, objectives) = (row.ones, row.profile, row.objectives);
            self.defer(c, ones, profile, objectives, r, false);
        }
    }

    /// Scores `c` (`ones` set genes, `profile`), a mutant of the current crossover's row `r`,
    /// without a mesh, and defers its mesh; `None` when the mutant cannot be scored so.
    fn mutant_row(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        r: usize,
    ) -> Option<Objectives> {
        let [a, b] = self.crossing_parents;
        if a >= self.pool.len() || b >= self.pool.len() {
            return None;
        }
        let row = &self.rows[r];
        let corners = self.evaluator.heightfield().corners();
        (row.genes).write_edit(c, &corners, &mut self.removed, &mut self.inserted);
        let (pa, pb) = (&self.pool[a].state, &self.pool[b].state);
        let changes = Changes {
            removed: &self.removed,
            inserted: &self.inserted,
        };
        let s = self.evaluator.score_parts_changed(
            pa,
            pb,
            &self.crossing,
            &mut self.crossing_scores,
            row.levels,
            changes,
        )?;
        let objectives = Objectives {
            e_sum: s.e_sum,
            e_max: s.e_max,
            t: s.t,
        };
        self.defer(c, ones, profile, objectives, r, true);
        Some(objectives)
    }

    /// Defers the mesh of `c` (`ones` set genes, `profile`, scored `objectives`): the current
    /// crossover's row `r`, changed by `self.removed` and `self.inserted` when `changed` (see
    /// [`Deferred`]), retaining the crossover's classification for it.
    fn defer(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        objectives: Objectives,
        r: usize,
        changed: bool,
    ) {
        if self.deferred.len() >= MAX_DEFERRED {
            self.drop_deferred();
        }
        let retained = self
            .retained
            .last()
            .is_some_and(|k| k.id() == self.crossing.id());
        if !retained {
            let mut copy = self.spare.pop().unwrap_or_default();
            copy.clone_from(&self.crossing);
            self.retained.push(copy);
        }
        let (removed, inserted) = match changed {
            true => (self.removed.clone(), self.inserted.clone()),
            false => (Vec::new(), Vec::new()),
        };
        self.deferred.push(Deferred {
            genes: c.clone(),
            ones,
            profile,
            objectives,
            origin: Origin::Crossed {
                classes: self.retained.len() - 1,
                parents: self.crossing_parents,
                levels: self.rows[r].levels,
            },
            removed,
            inserted,
        });
    }

    /// Scores `c` (`ones` set genes, `profile`), a mutant of pooled chromosome `i` (not a
    /// crossed child, whose mesh is edited in place instead), without a copy of its mesh
    /// ([`Evaluator::score_mutant`]), and defers the mutant's mesh; `None` when it cannot be
    /// scored so.
    fn mutant_of_pooled(
        &mut self,
        c: &Chromosome,
        ones: usize,
        profile: Profile,
        i: usize,
    ) -> Option<Objectives> {
        let base = &mut self.pool[i];
        let corners = self.evaluator.heightfield().corners();
        (base.genes).write_edit(c, &corners, &mut self.removed, &mut self.inserted);
        base.state.ensure_lookups();
        let changes = Changes {
            removed: &self.removed,
            inserted: &self.inserted,
        };
        let s = self.evaluator.score_mutant(&base.state, changes)?;
        base.used = self.tick;
        let objectives = Objectives {
            e_sum: s.e_sum,
            e_max: s.e_max,
            t: s.t,
        };
        if self.deferred.len() >= MAX_DEFERRED {
            self.drop_deferred();
        }
        self.deferred.push(Deferred {
            genes: c.clone(),
            ones,
            profile,
            objectives,
            origin: Origin::Edited {
                base: self.pool[i].genes.clone(),
            },
            removed: self.removed.clone(),
            inserted: self.inserted.clone(),
        });
        Some(objectives)
    }

    /// Forgets the deferred offspring, keeping their classifications' buffers.
    fn drop_deferred(&mut self) {
        self.deferred.clear();
        self.spare.append(&mut self.retained);
    }

    /// Makes the mesh of deferred offspring `d` in a pool slot, alive, and returns the slot
    /// (see [`compose_pooled`](Self::compose_pooled)); `None` when what it is made from is no
    /// longer pooled or composing refused (it then stays unpooled).
    fn compose_deferred(&mut self, d: usize) -> Option<usize> {
        let (ones, profile, objectives) = {
            let d = &self.deferred[d];
            (d.ones, d.profile, d.objectives)
        };
        let genes = std::mem::replace(&mut self.deferred[d].genes, Chromosome::empty(0));
        let key = Key { ones, profile };
        let base = match &self.deferred[d].origin {
            &Origin::Crossed {
                classes,
                parents,
                levels,
            } => {
                let recipe = Recipe {
                    parents,
                    classes: ClassesAt::Retained(classes),
                    levels,
                    changed_as: Some(d),
                };
                return self.compose_pooled(genes, key, objectives, recipe, false);
            }
            Origin::Edited { base } => self.pooled(base)?,
        };
        let slot = self.free_slot(&genes, ones, profile, [Some(base), None, None]);
        self.copy_state(base, slot);
        let Deferred {
            removed, inserted, ..
        } = &self.deferred[d];
        let state = &mut self.pool[slot].state;
        let score = self.evaluator.edit(state, removed, inserted).ok();
        debug_assert!(score.is_none_or(|s| (s.e_sum, s.t) == (objectives.e_sum, objectives.t)));
        self.settle(slot, score.is_some(), genes, key, objectives, false)
    }

    /// Copies the mesh of pool slot `from` into slot `to` (another one), reusing its buffers.
    fn copy_state(&mut self, from: usize, to: usize) {
        let (from, to) = if from < to {
            let (lo, hi) = self.pool.split_at_mut(to);
            (&lo[from], &mut hi[0])
        } else {
            let (lo, hi) = self.pool.split_at_mut(from);
            (&hi[0], &mut lo[to])
        };
        to.state.clone_from(&from.state);
    }

    /// Tells the scorer which chromosomes make up the GA's population now: their meshes are
    /// replaced only after every other one, so that the parents of the coming crossovers stay
    /// pooled to compose from. Spends no evaluation.
    pub fn keep_alive<'a>(&mut self, population: impl IntoIterator<Item = &'a Chromosome>) {
        // The new population joins the old one first, so that composing its deferred members
        // replaces neither (the old one holds their parents); then the old one is let go.
        let members: Vec<&Chromosome> = population.into_iter().collect();
        // The pool never shrinks: its meshes stay where they are.
        let wanted = (POOL_PER_MEMBER * members.len()).min(self.capacity_by_bytes);
        self.capacity = self.capacity.max(wanted);
        let mut pooled: Vec<Option<usize>> = members.iter().map(|c| self.pooled(c)).collect();
        for i in pooled.iter().flatten() {
            self.pool[*i].alive = true;
        }
        if !self.deferred.is_empty() {
            for (c, at) in members.iter().zip(&mut pooled) {
                if at.is_some() {
                    continue;
                }
                if let Some(d) = self.deferred.iter().position(|d| d.genes == **c) {
                    *at = self.compose_deferred(d);
                }
            }
            self.drop_deferred();
        }
        for p in &mut self.pool {
            p.alive = false;
        }
        for i in pooled.into_iter().flatten() {
            self.pool[i].alive = true;
        }
    }

    /// The pool slot holding exactly `c`, if any.
    fn pooled(&self, c: &Chromosome) -> Option<usize> {
        let ones = c.count_ones();
        self.pool
            .iter()
            .zip(&self.keys)
            .position(|(p, key)| key.ones == ones && p.genes == *c)
    }

    /// Evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// The normalised weighted sum with weight `w` for this height field.
    pub fn scalarisation(&self, w: f64) -> Scalarisation {
        Scalarisation {
            w,
            e0: self.normalisers.0,
            t0: self.normalisers.1,
        }
    }

    /// The height field.
    pub fn heightfield(&self) -> &Arc<Heightfield> {
        self.evaluator.heightfield()
    }
}

/// Offers an evaluated chromosome to `front`, building the [`Solution`] (and its index list)
/// only when it would enter. Returns true when it entered.
pub fn offer(front: &mut Front, c: &Chromosome, o: &Objectives) -> bool {
    // The front is sorted by increasing T and decreasing E: the member with the largest
    // T ≤ o.t is the only one that can dominate or equal `o`.
    let members = front.solutions();
    let at = members.partition_point(|m| m.t <= o.t);
    if at > 0 && members[at - 1].e_sum <= o.e_sum {
        return false;
    }
    front.offer(Solution {
        e_sum: o.e_sum,
        e_max: o.e_max,
        t: o.t,
        kept: c.indices(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn normalisers_are_the_corner_mesh_error_and_the_full_grid_triangles() {
        // 3×3 grid, flat but for a bump of 4 in the middle: E₀ = 4 (corners only), T₀ = 8.
        let mut z = vec![0.0; 9];
        z[4] = 4.0;
        let hf = Arc::new(Heightfield::new(3, 3, z).unwrap());
        let mut scorer = Scorer::new(hf);
        let f = scorer.scalarisation(0.25);
        assert_eq!((f.e0, f.t0), (4.0, 8.0));
        let corners = Chromosome::from_indices(9, &[0, 2, 6, 8]);
        let o = scorer.score(&corners);
        assert_eq!((o.e_sum, o.t), (4.0, 2));
        assert_eq!(f.value(&o), 0.25 * 1.0 + 0.75 * 2.0 / 8.0);
        assert_eq!(scorer.evaluations(), 1, "E₀ itself is not counted");
    }

    /// A 9×7 grid of random heights with some exact ties (integers).
    fn bumpy(seed: u64) -> Arc<Heightfield> {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
        let z = (0..63).map(|_| rng.random_range(0..6) as f64).collect();
        Arc::new(Heightfield::new(9, 7, z).unwrap())
    }

    /// A chromosome of `hf` keeping each point with probability `density`, and the corners.
    fn random_genes(hf: &Heightfield, density: f64, rng: &mut rand_pcg::Pcg64Mcg) -> Chromosome {
        let n = hf.len();
        let kept: Vec<u32> = (0..n as u32)
            .filter(|_| rng.random::<f64>() < density)
            .chain(hf.corners())
            .collect();
        Chromosome::from_indices(n, &kept)
    }

    fn fresh(hf: &Arc<Heightfield>, c: &Chromosome) -> (u64, u64, usize) {
        let o = Objectives::from_fresh(hf, c);
        (o.e_sum.to_bits(), o.e_max.to_bits(), o.t)
    }

    #[test]
    fn pooled_scoring_equals_fresh_scoring_bit_for_bit() {
        // A GA-like stream: random chromosomes, mutants (1–2 flips) and block crossovers of
        // earlier ones, and exact repeats; the pool is kept tiny (3 meshes) so that eviction,
        // editing the base in place and fresh builds all happen. Every score must be the fresh
        // score's bits, and every call counts one evaluation.
        let hf = bumpy(3);
        let n = hf.len();
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(21);
        for capacity in [1, 3] {
            let mut scorer = Scorer::new(hf.clone());
            scorer.capacity = capacity;
            let mut seen: Vec<Chromosome> = Vec::new();
            for step in 0..300 {
                let c = match (seen.len(), rng.random_range(0..4)) {
                    (0, _) | (_, 0) => {
                        let density = rng.random::<f64>();
                        let kept: Vec<u32> = (0..n as u32)
                            .filter(|_| rng.random::<f64>() < density)
                            .chain(hf.corners())
                            .collect();
                        Chromosome::from_indices(n, &kept)
                    }
                    (m, 1) => {
                        let mut c = seen[rng.random_range(0..m)].clone();
                        for _ in 0..rng.random_range(1..3) {
                            let i = rng.random_range(0..n);
                            if !hf.corners().contains(&(i as u32)) {
                                c.flip(i);
                            }
                        }
                        c
                    }
                    (m, 2) => {
                        let (a, b) = (&seen[rng.random_range(0..m)], &seen[rng.random_range(0..m)]);
                        let mut c = a.clone();
                        let start = rng.random_range(0..n);
                        c.copy_range_from(b, start, n.min(start + 20));
                        c
                    }
                    (m, _) => seen[rng.random_range(0..m)].clone(),
                };
                let o = scorer.score(&c);
                assert_eq!(
                    (o.e_sum.to_bits(), o.e_max.to_bits(), o.t),
                    fresh(&hf, &c),
                    "capacity {capacity}, step {step}"
                );
                assert_eq!(scorer.evaluations(), step as u64 + 1);
                assert!(scorer.pool.len() <= capacity);
                seen.push(c);
            }
        }
    }

    #[test]
    fn the_population_stays_pooled_while_others_come_and_go() {
        // A pool of 4 meshes: two chromosomes declared alive must survive 40 other scorings,
        // which evict everything else; once no longer alive, they are replaced like the rest.
        let hf = bumpy(5);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(8);
        let mut random = |density: f64| random_genes(&hf, density, &mut rng);
        let alive = [random(0.3), random(0.6)];
        let mut scorer = Scorer::new(hf.clone());
        scorer.capacity = 4;
        for c in &alive {
            scorer.score(c);
        }
        scorer.keep_alive(alive.iter());
        let others: Vec<Chromosome> = (0..40).map(|k| random(0.1 + 0.02 * k as f64)).collect();
        for c in &others {
            scorer.score(c);
        }
        assert!(alive.iter().all(|c| scorer.pooled(c).is_some()));
        assert!(scorer.pooled(&others[0]).is_none(), "the pool is full");
        scorer.keep_alive([]);
        // Far from every pooled chromosome (a near one would be scored without a mesh, as its
        // mutant): each takes a slot.
        for _ in 0..4 {
            let c = random(0.5);
            scorer.score(&c);
            assert!(scorer.pooled(&c).is_some());
        }
        assert!(alive.iter().all(|c| scorer.pooled(c).is_none()));
    }

    #[test]
    fn mutants_of_pooled_chromosomes_are_scored_without_copies_and_pooled_when_alive() {
        // A population on a 33×29 grid, each member mutated in 1–4 genes: every mutant scores
        // as a fresh evaluation does, none takes a pool slot (its mesh is deferred), and those
        // declared alive then hold meshes equal to fresh ones; the others stay unpooled.
        let (w, h) = (33, 29);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(21);
        let z = (0..w * h).map(|_| rng.random_range(0..40) as f64).collect();
        let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
        let n = hf.len();
        let corners = hf.corners();
        let population: Vec<Chromosome> = (0..12)
            .map(|k| random_genes(&hf, 0.05 + 0.07 * k as f64, &mut rng))
            .collect();
        let mut scorer = Scorer::new(hf.clone());
        for c in &population {
            scorer.score(c);
        }
        scorer.keep_alive(population.iter());
        let pooled_before = scorer.pool.len();
        let mut mutants = Vec::new();
        for c in &population {
            let mut m = c.clone();
            for _ in 0..rng.random_range(1..=4) {
                let i = loop {
                    let i = rng.random_range(0..n as u32);
                    if !corners.contains(&i) {
                        break i;
                    }
                };
                m.flip(i as usize);
            }
            let o = scorer.score(&m);
            assert_eq!((o.e_sum.to_bits(), o.e_max.to_bits(), o.t), fresh(&hf, &m));
            mutants.push(m);
        }
        assert_eq!(scorer.pool.len(), pooled_before, "no mutant took a slot");
        assert!(mutants.iter().all(|m| scorer.pooled(m).is_none()));
        let alive: Vec<&Chromosome> = mutants.iter().step_by(2).collect();
        scorer.keep_alive(alive.iter().copied());
        for (k, m) in mutants.iter().enumerate() {
            match scorer.pooled(m) {
                Some(i) => {
                    assert!(k % 2 == 0, "mutant {k} was not declared alive");
                    let s = scorer.pool[i].state.score().unwrap();
                    assert_eq!((s.e_sum.to_bits(), s.e_max.to_bits(), s.t), fresh(&hf, m));
                    assert!(scorer.pool[i].alive);
                }
                None => assert!(k % 2 == 1, "alive mutant {k} has no mesh"),
            }
        }
    }

    #[test]
    fn the_pool_grows_to_hold_two_populations_of_the_declared_size() {
        // A population of 150 on a small grid (the bytes allow thousands of meshes): a fixed
        // pool of POOL_STATES = 200 could not hold it and as many offspring, which is what
        // made `--pop 300` three times slower; declaring it sizes the pool for both.
        let hf = bumpy(6);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(9);
        let mut random = |density: f64| random_genes(&hf, density, &mut rng);
        let population: Vec<Chromosome> =
            (0..150).map(|k| random(0.05 + 0.005 * k as f64)).collect();
        let mut scorer = Scorer::new(hf.clone());
        assert_eq!(scorer.capacity, POOL_STATES);
        for c in &population {
            scorer.score(c);
        }
        scorer.keep_alive(population.iter());
        assert_eq!(scorer.capacity, POOL_PER_MEMBER * population.len());
        let offspring: Vec<Chromosome> = (0..150).map(|k| random(0.8 - 0.004 * k as f64)).collect();
        for c in &offspring {
            scorer.score(c);
        }
        assert!(population.iter().all(|c| scorer.pooled(c).is_some()));
        assert!(offspring.iter().all(|c| scorer.pooled(c).is_some()));
        // It never shrinks: a smaller population leaves it as it is.
        scorer.keep_alive(population[..10].iter());
        assert_eq!(scorer.capacity, POOL_PER_MEMBER * population.len());
    }

    #[test]
    fn offspring_scored_without_meshes_get_them_when_they_join_the_population() {
        // OAX crossovers of two pooled parents on a 33×29 grid, as NSGA-II runs them: the rows
        // are scored without meshes, each chosen child is mutated (0–3 flips) and scored, an
        // unchanged one promoted. Every score must be the fresh one's bits, mutants must be
        // scored without a mesh (deferred), and those declared alive afterwards must be pooled
        // with the mesh of their genes, while the others are not.
        use crate::evolution::oax;
        let (w, h) = (33, 29);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(4);
        let z = (0..w * h).map(|_| rng.random_range(0..9) as f64).collect();
        let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
        let n = hf.len();
        let corners = hf.corners();
        let random = |rng: &mut rand_pcg::Pcg64Mcg, density: f64| {
            let kept: Vec<u32> = (0..n as u32)
                .filter(|_| rng.random::<f64>() < density)
                .chain(corners)
                .collect();
            Chromosome::from_indices(n, &kept)
        };
        let mut scorer = Scorer::new(hf.clone());
        let mut population = vec![random(&mut rng, 0.3), random(&mut rng, 0.12)];
        let bits = |o: Objectives| (o.e_sum.to_bits(), o.e_max.to_bits(), o.t);
        let (mut deferred_mutants, mut deferred_rows) = (0, 0);
        for round in 0..12 {
            let scored: Vec<Objectives> = population.iter().map(|c| scorer.score(c)).collect();
            scorer.keep_alive(population.iter());
            let blocks = oax::spatial_blocks(w, h, 7, &mut rng);
            let record = oax::crossover(
                (&population[0], scored[0]),
                (&population[1], scored[1]),
                w,
                blocks,
                0.5,
                |c, made| {
                    let o = scorer.score_crossed(c, made);
                    assert_eq!(bits(o), fresh(&hf, c), "round {round}: row");
                    o
                },
                |o| o.e_sum + o.t as f64,
            );
            let mut offspring = Vec::new();
            for (k, &i) in record.chosen.iter().enumerate() {
                let mut c = record.child(i).genes.clone();
                // The first mutated by 1–3 flips, the second unchanged every other round.
                let flips = if k == 0 { 1 + round % 3 } else { round % 2 };
                for _ in 0..flips {
                    let g = rng.random_range(0..n);
                    if !corners.contains(&(g as u32)) {
                        c.flip(g);
                    }
                }
                if c == record.child(i).genes {
                    scorer.promote(&c);
                } else {
                    let o = scorer.score(&c);
                    assert_eq!(bits(o), fresh(&hf, &c), "round {round}: mutant");
                }
                offspring.push(c);
            }
            let deferred: Vec<Chromosome> =
                scorer.deferred.iter().map(|d| d.genes.clone()).collect();
            for (k, c) in offspring.iter().enumerate() {
                if deferred.contains(c) {
                    match *c == record.child(record.chosen[k]).genes {
                        true => deferred_rows += 1,
                        false => deferred_mutants += 1,
                    }
                }
            }
            // The first offspring joins the population (with the better parent); the second
            // dies.
            let next = [population[0].clone(), offspring[0].clone()];
            scorer.keep_alive(next.iter());
            assert!(scorer.deferred.is_empty());
            let i = scorer
                .pooled(&offspring[0])
                .expect("a new member is pooled");
            assert_eq!(
                scorer.pool[i]
                    .state
                    .score()
                    .map(|s| (s.e_sum.to_bits(), s.e_max.to_bits(), s.t)),
                Some(fresh(&hf, &offspring[0])),
                "round {round}: the member's mesh"
            );
            if offspring[1] != offspring[0] && deferred.contains(&offspring[1]) {
                assert!(scorer.pooled(&offspring[1]).is_none(), "round {round}");
            }
            // New parents for the next round (rounds of one lineage converge, and their
            // children come near pooled chromosomes, which are edited instead).
            population = vec![random(&mut rng, 0.3), random(&mut rng, 0.12)];
        }
        assert!(
            deferred_mutants >= 6 && deferred_rows >= 2,
            "{deferred_mutants} mutants and {deferred_rows} unchanged rows deferred"
        );
    }

    #[test]
    fn a_chromosome_without_its_corners_scores_like_one_with_them() {
        // The evaluator forces the corners in, so a chromosome missing one (built by hand) must
        // score exactly as with it, fresh or edited from a pooled mesh that has it.
        let hf = bumpy(4);
        let mut scorer = Scorer::new(hf.clone());
        let with = Chromosome::from_indices(63, &[0, 8, 30, 54, 62]);
        let without = Chromosome::from_indices(63, &[0, 30, 31, 54, 62]);
        let a = scorer.score(&with);
        let b = scorer.score(&without);
        let bits = |o: Objectives| (o.e_sum.to_bits(), o.e_max.to_bits(), o.t);
        assert_eq!(bits(a), fresh(&hf, &with));
        assert_eq!(bits(b), fresh(&hf, &without));
    }

    impl Objectives {
        /// The objectives of a fresh evaluation of `c`.
        fn from_fresh(hf: &Arc<Heightfield>, c: &Chromosome) -> Self {
            let s = Evaluator::new(hf.clone()).score(&c.indices()).unwrap();
            Objectives {
                e_sum: s.e_sum,
                e_max: s.e_max,
                t: s.t,
            }
        }
    }

    #[test]
    fn offer_agrees_with_the_front() {
        // Random (E, T) pairs on a coarse lattice, so that ties in E, in T and in both occur:
        // the shortcut must accept exactly what `Front::offer` accepts.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(8);
        let (mut fast, mut plain) = (Front::default(), Front::default());
        let c = Chromosome::from_indices(4, &[0, 1, 2, 3]);
        for _ in 0..2000 {
            let o = Objectives {
                e_sum: rng.random_range(0..40) as f64,
                e_max: 0.0,
                t: rng.random_range(2..40),
            };
            let entered = offer(&mut fast, &c, &o);
            let expected = plain.offer(Solution {
                e_sum: o.e_sum,
                e_max: o.e_max,
                t: o.t,
                kept: c.indices(),
            });
            assert_eq!(entered, expected, "{o:?}");
        }
        assert_eq!(fast, plain);
    }
}
