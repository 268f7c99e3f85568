//! Orthogonal-array crossover (OAX), after Huang & Ho 2003.
//!
//! Two parents are cut into F factors; a two-level orthogonal array L_M(2^(M−1)) says, for
//! each of its M rows, which parent gives each factor (level 0 = parent A, level 1 = parent B).
//! The M children are evaluated, factor analysis (the main effect of each level of each
//! factor, on a scalar fitness) picks the best level per factor, that combination is built and
//! evaluated as one more child, and the best two children (by the scalar fitness) are returned.
//!
//! Factors are *spatial blocks* of the grid, not contiguous row-major ranges: a mesh's quality
//! is local (a point helps the triangles around it), so a factor should be a compact patch of
//! the surface whose points work together. A row-major range of N/F genes would be a band of
//! whole rows, and a cut inside a row would split neighbouring points arbitrarily. The blocks are
//! drawn anew for every crossover (like Huang & Ho's random cut points) by recursive random
//! bisection: the largest block is split across its longer side at a random position in its
//! middle half, until there are F blocks. Compact blocks of varying shape and position, so no
//! block boundary is favoured over time.
//!
//! A child identical to a parent or to an earlier child is not evaluated again (its objectives
//! are known, so no evaluation is spent or counted): row 0 takes every factor from parent A and
//! *is* parent A, and where the parents agree on a block (often: sparse parents share empty
//! blocks) the rows that differ only in that factor coincide. Every other child is evaluated once
//! through the caller's `evaluate`, which counts it. The two children returned are the two
//! fittest with different genes (the same one twice only when all children are equal).

use super::chromosome::Chromosome;
use super::orthogonal_array::{OrthogonalArray, factor_analysis};
use crate::evaluator::Score;
use rand::RngExt;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Default number of factors: 7, the most an L8 array holds, so 7 new children per crossover.
/// More factors (L16: 15) mean finer recombination but twice the evaluations per crossover;
/// L8 is the size Huang & Ho's examples use.
pub(crate) const DEFAULT_FACTORS: usize = 7;

/// A rectangle of grid points `x0..x1 × y0..y1` (half-open); it may be empty.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Block {
    /// First column.
    pub x0: usize,
    /// First row.
    pub y0: usize,
    /// One past the last column.
    pub x1: usize,
    /// One past the last row.
    pub y1: usize,
}

impl Block {
    /// Number of grid points in the block.
    pub(crate) fn area(&self) -> usize {
        (self.x1 - self.x0) * (self.y1 - self.y0)
    }
}

/// Cuts a `width × height` grid into exactly `factors` blocks that tile it, by recursive random
/// bisection (see the module doc). When the grid has fewer points than `factors`, the extra
/// blocks are empty.
pub fn spatial_blocks(
    width: usize,
    height: usize,
    factors: usize,
    rng: &mut Pcg64Mcg,
) -> Vec<Block> {
    let mut blocks = vec![Block {
        x0: 0,
        y0: 0,
        x1: width,
        y1: height,
    }];
    while blocks.len() < factors {
        // The largest block with more than one point; ties go to the first.
        let Some((at, _)) = blocks
            .iter()
            .enumerate()
            .filter(|(_, b)| b.area() > 1)
            .fold(None::<(usize, usize)>, |best, (i, b)| match best {
                Some((_, a)) if a >= b.area() => best,
                _ => Some((i, b.area())),
            })
        else {
            blocks.push(Block {
                x0: 0,
                y0: 0,
                x1: 0,
                y1: 0,
            });
            continue;
        };
        let b = blocks[at];
        let (w, h) = (b.x1 - b.x0, b.y1 - b.y0);
        let side = w.max(h);
        // A cut in the middle half keeps the pieces compact; at least one point on each side.
        let lo = side.div_ceil(4).max(1);
        let hi = (side * 3 / 4).clamp(lo, side - 1);
        let cut = rng.random_range(lo..=hi);
        let (first, second) = if w >= h {
            (
                Block {
                    x1: b.x0 + cut,
                    ..b
                },
                Block {
                    x0: b.x0 + cut,
                    ..b
                },
            )
        } else {
            (
                Block {
                    y1: b.y0 + cut,
                    ..b
                },
                Block {
                    y0: b.y0 + cut,
                    ..b
                },
            )
        };
        blocks[at] = first;
        blocks.push(second);
    }
    blocks
}

/// Copies `block` of a `width`-wide grid from `from` into `to`.
fn copy_block(to: &mut Chromosome, from: &Chromosome, block: &Block, width: usize) {
    for y in block.y0..block.y1 {
        to.copy_range_from(from, y * width + block.x0, y * width + block.x1);
    }
}

/// Sets, in `mask`, the genes of `block` of a `width`-wide grid.
fn mark_block(mask: &mut Chromosome, block: &Block, width: usize) {
    for y in block.y0..block.y1 {
        mask.set_range(y * width + block.x0, y * width + block.x1);
    }
}

/// How a child of a crossover is made, for a scorer that reuses the parents' meshes
/// (`Scorer::score_crossed`): each gene comes from
/// `parents[0]` where `from_b` is clear and from `parents[1]` where it is set, which is block
/// by block: from B in the blocks whose level is 1.
#[derive(Clone, Copy, Debug)]
pub struct Parentage<'a> {
    /// Parents A and B.
    pub parents: [&'a Chromosome; 2],
    /// The genes taken from B.
    pub from_b: &'a Chromosome,
    /// The crossover's blocks, which tile the grid.
    pub blocks: &'a [Block],
    /// The level of each block (0 = from A, 1 = from B).
    pub levels: &'a [u8],
}

/// One child of a crossover, as the teaching view shows it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OaxChild {
    /// The level of each factor (0 = from parent A, 1 = from parent B).
    pub levels: Vec<u8>,
    /// Its genes.
    pub genes: Chromosome,
    /// Its objectives.
    pub objectives: Score,
    /// Its scalar fitness (minimised).
    pub fitness: f64,
    /// False when its objectives were known already (it equals a parent or an earlier child),
    /// so no evaluation was spent on it.
    pub evaluated: bool,
}

/// The full record of one orthogonal-array crossover (serialisable for the browser).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OaxRecord {
    /// The array used.
    pub array: OrthogonalArray,
    /// The factors: factor f is `blocks[f]` and uses array column f + 1.
    pub blocks: Vec<Block>,
    /// The parents A and B with their objectives.
    pub parents: [(Chromosome, Score); 2],
    /// The weight w of the scalar fitness F = w·E/E₀ + (1 − w)·T/T₀.
    pub weight: f64,
    /// The M children, one per array row.
    pub rows: Vec<OaxChild>,
    /// `effects[f][l]`: the sum of the fitness of the rows with factor f at level l.
    pub effects: Vec<[f64; 2]>,
    /// The child of the best level of each factor.
    pub best_levels: OaxChild,
    /// The two children returned, as indices into `rows`, where `rows.len()` means
    /// `best_levels`.
    pub chosen: [usize; 2],
}

impl OaxRecord {
    /// Child `i` in the numbering of [`chosen`](Self::chosen).
    pub(crate) fn child(&self, i: usize) -> &OaxChild {
        self.rows.get(i).unwrap_or(&self.best_levels)
    }

    /// Number of evaluations this crossover spent.
    pub(crate) fn evaluations(&self) -> usize {
        self.rows
            .iter()
            .chain(std::iter::once(&self.best_levels))
            .filter(|c| c.evaluated)
            .count()
    }
}

/// Runs one orthogonal-array crossover of `parent_a` and `parent_b` (same length, on a grid
/// `width` wide) over `blocks` (one per factor). `evaluate` scores a child made as its
/// [`Parentage`] says (the caller
/// counts it); `fitness` is the scalar to minimise, reported as `weight` in the record.
pub fn crossover(
    parent_a: (&Chromosome, Score),
    parent_b: (&Chromosome, Score),
    width: usize,
    blocks: Vec<Block>,
    weight: f64,
    mut evaluate: impl FnMut(&Chromosome, Parentage<'_>) -> Score,
    fitness: impl Fn(&Score) -> f64,
) -> OaxRecord {
    let mut pending = OaxInProgress::new(parent_a, parent_b, width, blocks, weight);
    while !pending.is_complete() {
        pending.next_child(&mut evaluate, &fitness);
    }
    pending.finish()
}

/// An orthogonal-array crossover in progress, made one child at a time so that a caller can
/// spread it over several slices of work: the array's rows in order, then (once every row is
/// known) the factor analysis and the best-levels child. Each [`next_child`](Self::next_child)
/// spends at most one evaluation. Run to completion it gives exactly [`crossover`]'s record.
#[derive(Clone, Debug)]
pub(crate) struct OaxInProgress {
    array: OrthogonalArray,
    blocks: Vec<Block>,
    parents: [(Chromosome, Score); 2],
    width: usize,
    weight: f64,
    rows: Vec<OaxChild>,
    /// The factor analysis and its child, once every row is known.
    analysed: Option<(Vec<[f64; 2]>, OaxChild)>,
}

impl OaxInProgress {
    /// A crossover of `parent_a` and `parent_b` (same length, on a grid `width` wide) over
    /// `blocks` (one per factor), with no child made yet; `weight` is reported in the record.
    pub(crate) fn new(
        parent_a: (&Chromosome, Score),
        parent_b: (&Chromosome, Score),
        width: usize,
        blocks: Vec<Block>,
        weight: f64,
    ) -> Self {
        let array = OrthogonalArray::for_factors(blocks.len());
        Self {
            rows: Vec::with_capacity(array.rows()),
            array,
            blocks,
            parents: [
                (parent_a.0.clone(), parent_a.1),
                (parent_b.0.clone(), parent_b.1),
            ],
            width,
            weight,
            analysed: None,
        }
    }

    /// True once every row child and the best-levels child exist.
    pub(crate) fn is_complete(&self) -> bool {
        self.analysed.is_some()
    }

    /// Makes the next child: the next row of the array, or, after the last row, the factor
    /// analysis and the best-levels child. A child equal to a parent or to an earlier child
    /// takes the known objectives; any other is scored once through `evaluate`, so a call
    /// spends at most one evaluation. `evaluate` and `fitness` must be the same on every call
    /// of one crossover. Does nothing once complete.
    pub(crate) fn next_child(
        &mut self,
        evaluate: &mut impl FnMut(&Chromosome, Parentage<'_>) -> Score,
        fitness: &impl Fn(&Score) -> f64,
    ) {
        let factors = self.blocks.len();
        if self.rows.len() < self.array.rows() {
            let levels = self.array.row_levels(self.rows.len(), factors);
            let child = self.child(levels, evaluate, fitness);
            self.rows.push(child);
        } else if self.analysed.is_none() {
            let row_fitness: Vec<f64> = self.rows.iter().map(|c| c.fitness).collect();
            let (effects, best) = factor_analysis(&self.array, factors, &row_fitness);
            let best_levels = self.child(best, evaluate, fitness);
            self.analysed = Some((effects, best_levels));
        }
    }

    /// The child with `levels`, scored (or looked up when its genes are already known).
    fn child(
        &self,
        levels: Vec<u8>,
        evaluate: &mut impl FnMut(&Chromosome, Parentage<'_>) -> Score,
        fitness: &impl Fn(&Score) -> f64,
    ) -> OaxChild {
        let [(a, a_objectives), (b, b_objectives)] = &self.parents;
        let mut genes = a.clone();
        let mut from_b = Chromosome::empty(a.len());
        for (block, _) in self.blocks.iter().zip(&levels).filter(|(_, l)| **l == 1) {
            copy_block(&mut genes, b, block, self.width);
            mark_block(&mut from_b, block, self.width);
        }
        // A child identical to a parent or to an earlier child is not evaluated again.
        let known = if genes == *a {
            Some(*a_objectives)
        } else if genes == *b {
            Some(*b_objectives)
        } else {
            self.rows
                .iter()
                .find(|c| c.genes == genes)
                .map(|c| c.objectives)
        };
        let (objectives, evaluated) = match known {
            Some(o) => (o, false),
            None => {
                let parentage = Parentage {
                    parents: [a, b],
                    from_b: &from_b,
                    blocks: &self.blocks,
                    levels: &levels,
                };
                (evaluate(&genes, parentage), true)
            }
        };
        OaxChild {
            fitness: fitness(&objectives),
            levels,
            genes,
            objectives,
            evaluated,
        }
    }

    /// The record of the completed crossover, with the two children it returns: the best two
    /// with different genes (ties by row; the best-levels child last).
    ///
    /// # Panics
    /// When the crossover is not complete ([`is_complete`](Self::is_complete)).
    pub(crate) fn finish(self) -> OaxRecord {
        let (effects, best_levels) = self
            .analysed
            .expect("finish is called on a complete crossover");
        let rows = self.rows;
        let mut order: Vec<usize> = (0..=rows.len()).collect();
        let get = |i: usize| rows.get(i).unwrap_or(&best_levels);
        order.sort_by(|&i, &j| get(i).fitness.total_cmp(&get(j).fitness).then(i.cmp(&j)));
        let first = order[0];
        let second = order
            .iter()
            .copied()
            .find(|&i| get(i).genes != get(first).genes)
            .unwrap_or(first);
        OaxRecord {
            array: self.array,
            blocks: self.blocks,
            parents: self.parents,
            weight: self.weight,
            chosen: [first, second],
            rows,
            effects,
            best_levels,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn blocks_tile_the_grid() {
        // Every grid point lies in exactly one block, for square, thin and tiny grids.
        let mut rng = Pcg64Mcg::seed_from_u64(9);
        for (w, h, f) in [(33, 33, 7), (87, 61, 15), (2, 9, 7), (2, 2, 7), (5, 3, 3)] {
            let blocks = spatial_blocks(w, h, f, &mut rng);
            assert_eq!(blocks.len(), f);
            let mut owner = vec![0; w * h];
            for b in &blocks {
                for y in b.y0..b.y1 {
                    for x in b.x0..b.x1 {
                        owner[y * w + x] += 1;
                    }
                }
            }
            assert!(owner.iter().all(|&n| n == 1), "{w}×{h}, {f} factors");
        }
    }

    #[test]
    fn children_equal_to_a_parent_or_sibling_are_not_evaluated() {
        // Parents that differ only inside block 0: every row equals A (factor 0 at level 0) or
        // B (level 1), so the crossover costs nothing and returns both parents.
        let mut rng = Pcg64Mcg::seed_from_u64(5);
        let blocks = spatial_blocks(8, 8, 7, &mut rng);
        let a = Chromosome::from_indices(64, &[0, 7, 56, 63]);
        let mut b = a.clone();
        let b0 = blocks[0];
        b.set(b0.y0 * 8 + b0.x0, true);
        let score = |c: &Chromosome| Score {
            e_sum: c.count_ones() as f64,
            e_max: 0.0,
            rms: 0.0,
            t: 0,
        };
        let mut evaluations = 0;
        let record = crossover(
            (&a, score(&a)),
            (&b, score(&b)),
            8,
            blocks,
            1.0,
            |c, _| {
                evaluations += 1;
                score(c)
            },
            |o| o.e_sum,
        );
        assert_eq!((evaluations, record.evaluations()), (0, 0));
        let chosen = record.chosen.map(|i| record.child(i).genes.clone());
        assert_eq!(chosen, [a, b], "the two distinct children, fittest first");
    }

    #[test]
    fn factor_analysis_child_is_the_optimum_of_a_separable_toy_fitness() {
        // Toy problem on an 8×8 "grid": fitness = number of genes differing from a target. The
        // target takes half its blocks from A and half from B, in a combination that is not a
        // row of L8, so only the factor-analysis child can reach distance 0.
        let mut rng = Pcg64Mcg::seed_from_u64(4);
        let blocks = spatial_blocks(8, 8, 7, &mut rng);
        let a = Chromosome::from_indices(64, &(0..64).filter(|i| i % 3 == 0).collect::<Vec<_>>());
        let b = Chromosome::from_indices(64, &(0..64).filter(|i| i % 2 == 0).collect::<Vec<_>>());
        let target_levels = [1u8, 0, 0, 1, 0, 0, 1];
        let mut target = a.clone();
        for (block, _) in blocks.iter().zip(target_levels).filter(|(_, l)| *l == 1) {
            copy_block(&mut target, &b, block, 8);
        }
        let score = |c: &Chromosome| Score {
            e_sum: c.hamming(&target) as f64,
            e_max: 0.0,
            rms: 0.0,
            t: 0,
        };
        let mut evaluations = 0;
        let record = crossover(
            (&a, score(&a)),
            (&b, score(&b)),
            8,
            blocks,
            1.0,
            |c, made: Parentage<'_>| {
                evaluations += 1;
                // The parentage says where each gene came from.
                for i in 0..c.len() {
                    let from = made.parents[usize::from(made.from_b.get(i))];
                    assert_eq!(c.get(i), from.get(i), "gene {i}");
                }
                assert_eq!(made.parents, [&a, &b]);
                score(c)
            },
            |o| o.e_sum,
        );
        assert_eq!(record.best_levels.levels, target_levels);
        assert_eq!(record.best_levels.genes, target);
        assert_eq!(record.best_levels.objectives.e_sum, 0.0);
        assert_eq!(record.chosen[0], 8, "the factor-analysis child is the best");
        assert_eq!(evaluations, 8, "rows 1..8 and the new best-levels child");
        assert_eq!(record.evaluations(), 8);
        assert_eq!(record.rows[0].genes, a, "row 0 is parent A");
    }

    #[test]
    fn a_crossover_in_progress_makes_one_child_per_call() {
        // The toy parents of the test above: rows come one per call, each call spends at most
        // one evaluation, and the last call (factor analysis) completes it with the record
        // `crossover` gives in one go.
        let mut rng = Pcg64Mcg::seed_from_u64(4);
        let blocks = spatial_blocks(8, 8, 7, &mut rng);
        let a = Chromosome::from_indices(64, &(0..64).filter(|i| i % 3 == 0).collect::<Vec<_>>());
        let b = Chromosome::from_indices(64, &(0..64).filter(|i| i % 2 == 0).collect::<Vec<_>>());
        let score = |c: &Chromosome| Score {
            e_sum: c.count_ones() as f64,
            e_max: 0.0,
            rms: 0.0,
            t: 0,
        };
        let (pa, pb) = ((&a, score(&a)), (&b, score(&b)));
        let whole = crossover(pa, pb, 8, blocks.clone(), 0.5, |c, _| score(c), |o| o.e_sum);
        let mut pending = OaxInProgress::new(pa, pb, 8, blocks, 0.5);
        for call in 1..=9 {
            assert!(!pending.is_complete());
            let mut evaluations = 0;
            let mut counted = |c: &Chromosome, _: Parentage<'_>| {
                evaluations += 1;
                score(c)
            };
            pending.next_child(&mut counted, &|o| o.e_sum);
            assert!(evaluations <= 1, "call {call} spent {evaluations}");
            assert_eq!(pending.rows.len(), call.min(8));
        }
        assert!(pending.is_complete());
        assert_eq!(pending.finish(), whole);
    }
}
