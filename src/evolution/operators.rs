//! Initialisation, bit-flip mutation, and the simple crossovers (uniform, two-point) kept for
//! comparison with orthogonal-array crossover ([`super::oax`]).
//!
//! Genes: one per grid point, but the four corners are fixed (always kept), so the number of
//! *free* genes is L = N − 4 and the default mutation probability is 1/L: one expected flip per
//! child among the genes that can actually change.

use super::chromosome::{Chromosome, for_each_bernoulli};
use crate::heightfield::Heightfield;
use rand::RngExt;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Which crossover makes the children.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CrossoverKind {
    /// Orthogonal-array crossover (Huang & Ho 2003) over spatial blocks: the paper's choice.
    #[default]
    Oax,
    /// Each gene from either parent with probability ½ (the second child takes the other).
    Uniform,
    /// Two cut points in row-major gene order; the middle segment is swapped.
    TwoPoint,
}

/// The number of free genes L = N − 4 (the corners are fixed), at least 1 so that 1/L is finite.
pub(crate) fn free_genes(hf: &Heightfield) -> usize {
    hf.len().saturating_sub(4).max(1)
}

/// The corners-only chromosome of `hf`.
pub(crate) fn corners_only(hf: &Heightfield) -> Chromosome {
    Chromosome::from_indices(hf.len(), &hf.corners())
}

/// The initial density of individual `i` of `count`: log-spaced from 1/L (about one free point)
/// to 1 (the full grid), one random draw inside each of `count` equal strata.
///
/// Why: the paper places a random number of points per individual; uniform densities would put
/// most of the first population in the dense half of the grid, where E is already near 0, while
/// the interesting trade-offs lie at a few percent of the points. Log spacing gives every order
/// of magnitude of the point count (and so of the triangle count, T ≈ 2 × points) the same share
/// of the population, and stratifying keeps that spread even for small populations.
pub(crate) fn initial_density(i: usize, count: usize, free: usize, rng: &mut Pcg64Mcg) -> f64 {
    let u = (i as f64 + rng.random::<f64>()) / count.max(1) as f64;
    let d_min = 1.0 / free.max(1) as f64;
    // `libm::pow`, not `powf`: the same bits natively and in wasm (see `for_each_bernoulli`).
    libm::pow(d_min, 1.0 - u)
}

/// A random chromosome: the corners plus each free gene with probability `density`.
pub(crate) fn random_chromosome(hf: &Heightfield, density: f64, rng: &mut Pcg64Mcg) -> Chromosome {
    let mut c = corners_only(hf);
    for_each_bernoulli(hf.len(), density, rng, |i| c.set(i, true));
    c
}

/// Flips each free gene independently with probability `p` (corners are never flipped).
/// Returns the number of genes flipped.
pub(crate) fn mutate(c: &mut Chromosome, corners: &[u32; 4], p: f64, rng: &mut Pcg64Mcg) -> usize {
    let mut flipped = 0;
    for_each_bernoulli(c.len(), p, rng, |i| {
        if !corners.contains(&(i as u32)) {
            c.flip(i);
            flipped += 1;
        }
    });
    flipped
}

/// Uniform crossover: two complementary children.
pub(crate) fn uniform(a: &Chromosome, b: &Chromosome, rng: &mut Pcg64Mcg) -> [Chromosome; 2] {
    let masks: Vec<u64> = (0..a.len().div_ceil(64))
        .map(|_| rng.random::<u64>())
        .collect();
    [
        Chromosome::blend(a, b, |w| masks[w]),
        Chromosome::blend(b, a, |w| masks[w]),
    ]
}

/// Two-point crossover in row-major gene order: cut points `c1 ≤ c2` drawn in `0..=N`; each
/// child takes `c1..c2` from the other parent.
pub(crate) fn two_point(a: &Chromosome, b: &Chromosome, rng: &mut Pcg64Mcg) -> [Chromosome; 2] {
    let n = a.len();
    let (x, y) = (rng.random_range(0..=n), rng.random_range(0..=n));
    let (c1, c2) = (x.min(y), x.max(y));
    let mut first = a.clone();
    first.copy_range_from(b, c1, c2);
    let mut second = b.clone();
    second.copy_range_from(a, c1, c2);
    [first, second]
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn grid(w: usize, h: usize) -> Heightfield {
        Heightfield::new(w, h, vec![0.0; w * h]).unwrap()
    }

    #[test]
    fn initial_densities_span_one_point_to_the_full_grid() {
        // 20×20 grid: L = 396. Stratum 0 lies in [1/L, L^(-0.9)], the last in [L^(-0.1), 1].
        let mut rng = Pcg64Mcg::seed_from_u64(1);
        let d: Vec<f64> = (0..10)
            .map(|i| initial_density(i, 10, 396, &mut rng))
            .collect();
        assert!(d.windows(2).all(|p| p[0] < p[1]), "strata are increasing");
        assert!(d[0] <= 396f64.powf(-0.9) && d[0] >= 1.0 / 396.0);
        assert!(d[9] >= 396f64.powf(-0.1) && d[9] <= 1.0);
    }

    #[test]
    fn mutation_never_touches_corners_and_keeps_them() {
        // p = 1 flips every free gene: the corners-only chromosome becomes the full grid.
        let hf = grid(5, 4);
        let mut rng = Pcg64Mcg::seed_from_u64(2);
        let mut c = corners_only(&hf);
        let flipped = mutate(&mut c, &hf.corners(), 1.0, &mut rng);
        assert_eq!(flipped, 16);
        assert_eq!(c.count_ones(), 20);
    }

    #[test]
    fn crossovers_take_every_gene_from_one_parent() {
        // Parents disjoint outside the corners: each child's gene i comes from a or b, and the
        // two children are complementary.
        let hf = grid(10, 10);
        let mut rng = Pcg64Mcg::seed_from_u64(3);
        let a = random_chromosome(&hf, 0.5, &mut rng);
        let mut b = a.clone();
        for i in 0..100 {
            if !hf.corners().contains(&(i as u32)) {
                b.flip(i);
            }
        }
        for [c, d] in [uniform(&a, &b, &mut rng), two_point(&a, &b, &mut rng)] {
            for i in 0..100 {
                assert!(c.get(i) == a.get(i) || c.get(i) == b.get(i));
                if a.get(i) != b.get(i) {
                    assert_ne!(c.get(i), d.get(i), "children complementary at {i}");
                }
            }
            assert!(hf.corners().iter().all(|&k| c.get(k as usize)));
        }
    }
}
