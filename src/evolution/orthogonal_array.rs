//! Two-level orthogonal arrays L_M(2^(M−1)) for orthogonal-array crossover (Huang & Ho 2003).
//!
//! Rows are `0..M`, columns `1..M` (column 0 would be constant), levels 0 and 1, and
//! `level(row, column) = parity(popcount(row & column))`. Every column is balanced (M/2 of each
//! level) and every pair of columns holds each of the four level combinations M/4 times, so the
//! main effect of a factor can be read off the M rows without the other factors biasing it.
//!
//! Relation to the printed Taguchi L8 table (levels 1/2, columns 1..7): Taguchi's level is our
//! level + 1 and Taguchi's column j is our column `reverse_bits_3(j)` (j = 1..7 → 4, 2, 6, 1, 5, 3,
//! 7); the rows are in the same order. The test below checks this against the printed table.

use serde::{Deserialize, Serialize};

/// A two-level orthogonal array with `rows` = M (a power of two ≥ 2) and M − 1 columns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct OrthogonalArray {
    rows: usize,
}

impl OrthogonalArray {
    /// The smallest array with room for `factors` factors: M = the smallest power of two > F.
    pub(crate) fn for_factors(factors: usize) -> Self {
        Self {
            rows: (factors + 1).next_power_of_two().max(2),
        }
    }

    /// Number of rows M (combinations to evaluate).
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns M − 1 (factors it can hold).
    pub fn columns(&self) -> usize {
        self.rows - 1
    }

    /// The level (0 or 1) of `row` (0..M) in `column` (1..M).
    pub fn level(&self, row: usize, column: usize) -> u8 {
        debug_assert!(row < self.rows && (1..self.rows).contains(&column));
        ((row & column).count_ones() & 1) as u8
    }

    /// The levels of `row` for the first `factors` columns (factor f ↔ column f + 1).
    pub(crate) fn row_levels(&self, row: usize, factors: usize) -> Vec<u8> {
        (0..factors).map(|f| self.level(row, f + 1)).collect()
    }
}

/// The main effects of a two-level experiment: `effects[f][l]` = sum of `fitness[row]` over the
/// rows whose factor f is at level l (factor f ↔ column f + 1), and the best level of each
/// factor for a fitness to *minimise* (ties go to level 0). `fitness.len()` must be M.
///
/// Sums rather than means are compared: each level occurs in exactly M/2 rows, so they rank
/// the same.
pub(crate) fn factor_analysis(
    array: &OrthogonalArray,
    factors: usize,
    fitness: &[f64],
) -> (Vec<[f64; 2]>, Vec<u8>) {
    debug_assert_eq!(fitness.len(), array.rows());
    let effects: Vec<[f64; 2]> = (0..factors)
        .map(|f| {
            let mut s = [0.0; 2];
            for (row, &v) in fitness.iter().enumerate() {
                s[array.level(row, f + 1) as usize] += v;
            }
            s
        })
        .collect();
    let best = effects.iter().map(|s| u8::from(s[1] < s[0])).collect();
    (effects, best)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The standard Taguchi L8(2^7) table as printed (levels 1/2).
    const TAGUCHI_L8: [[u8; 7]; 8] = [
        [1, 1, 1, 1, 1, 1, 1],
        [1, 1, 1, 2, 2, 2, 2],
        [1, 2, 2, 1, 1, 2, 2],
        [1, 2, 2, 2, 2, 1, 1],
        [2, 1, 2, 1, 2, 1, 2],
        [2, 1, 2, 2, 1, 2, 1],
        [2, 2, 1, 1, 2, 2, 1],
        [2, 2, 1, 2, 1, 1, 2],
    ];

    #[test]
    fn l8_is_the_taguchi_table_up_to_column_labels() {
        let oa = OrthogonalArray::for_factors(7);
        assert_eq!((oa.rows(), oa.columns()), (8, 7));
        for (row, printed) in TAGUCHI_L8.iter().enumerate() {
            for (j, &level) in printed.iter().enumerate() {
                let column = ((j + 1) as u8).reverse_bits() as usize >> 5; // 3-bit reversal
                assert_eq!(
                    oa.level(row, column) + 1,
                    level,
                    "row {row} column {}",
                    j + 1
                );
            }
        }
    }

    #[test]
    fn m_is_the_smallest_power_of_two_above_f() {
        let m: Vec<usize> = [1, 2, 3, 4, 7, 8, 15, 16]
            .iter()
            .map(|&f| OrthogonalArray::for_factors(f).rows())
            .collect();
        assert_eq!(m, [2, 4, 4, 8, 8, 16, 16, 32]);
    }

    #[test]
    fn every_pair_of_columns_is_balanced() {
        for m in [4, 8, 16, 32] {
            let oa = OrthogonalArray::for_factors(m - 1);
            for a in 1..m {
                for b in a + 1..m {
                    let mut count = [0; 4];
                    for row in 0..m {
                        count[(oa.level(row, a) * 2 + oa.level(row, b)) as usize] += 1;
                    }
                    assert_eq!(count, [m / 4; 4], "M={m}, columns {a} and {b}");
                }
            }
        }
    }

    #[test]
    fn factor_analysis_finds_the_optimum_of_a_separable_fitness() {
        // Fitness = Σ_f cost[f][level_f]: additive, so main effects identify the best level of
        // each factor exactly, even though row (best levels) is not among the 8 rows tried.
        let cost = [
            [3.0, 1.0],
            [0.5, 2.0],
            [4.0, 4.5],
            [1.0, 0.0],
            [2.0, 7.0],
            [0.0, 0.1],
            [9.0, 8.0],
        ];
        let oa = OrthogonalArray::for_factors(7);
        let fitness: Vec<f64> = (0..8)
            .map(|r| (0..7).map(|f| cost[f][oa.level(r, f + 1) as usize]).sum())
            .collect();
        let (effects, best) = factor_analysis(&oa, 7, &fitness);
        assert_eq!(best, [1, 0, 0, 1, 0, 0, 1]);
        assert!(
            (0..8).all(|r| oa.row_levels(r, 7) != best),
            "the optimum is a new combination"
        );
        // Level sums differ by 4 × the cost difference (each level sits in 4 rows).
        assert!((effects[0][0] - effects[0][1] - 4.0 * 2.0).abs() < 1e-12);
    }
}
