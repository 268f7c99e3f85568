//! The two-sided Wilcoxon rank-sum (Mann–Whitney U) test for two independent samples.

use super::MetricsError;
use serde::Serialize;
use std::cmp::Ordering;

/// [`RankSumMethod::Auto`] uses the exact distribution when both samples have fewer than this
/// many values and there are no ties — R's `wilcox.test` rule. Below it the exact table is cheap
/// (at most 49·49·1201 additions) and the normal approximation is at its weakest.
pub(crate) const EXACT_SAMPLE_LIMIT: usize = 50;

/// Largest n1·n2 for which [`RankSumMethod::Exact`] is accepted: the table costs at most
/// n1·n2·(n1·n2/2 + 1) additions and min(n1, n2)·(n1·n2/2 + 1) numbers of memory.
pub(super) const EXACT_TABLE_LIMIT: usize = 10_000;

/// How the p-value of [`rank_sum_test_with`] is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum RankSumMethod {
    /// Exact if there are no ties and both samples have fewer than `EXACT_SAMPLE_LIMIT`
    /// values, normal approximation otherwise.
    Auto,
    /// The exact null distribution of U (no ties allowed).
    Exact,
    /// The normal approximation with tie and continuity corrections.
    Normal,
}

/// The outcome of a two-sided rank-sum test of sample 1 against sample 2.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RankSumTest {
    /// Size of sample 1.
    pub n1: usize,
    /// Size of sample 2.
    pub n2: usize,
    /// U of sample 1: the number of pairs (x, y) with x > y, plus half the pairs with x = y.
    /// Equals R1 − n1(n1+1)/2 with R1 the (mid)rank sum of sample 1.
    pub u1: f64,
    /// U of sample 2 = n1·n2 − U1.
    pub u2: f64,
    /// Two-sided p-value, in (0, 1].
    pub p_value: f64,
    /// The method actually used: `Exact` or `Normal`, never `Auto`.
    pub method: RankSumMethod,
    /// The standardised statistic (with continuity correction) when the normal approximation
    /// was used; `None` for the exact test.
    pub z: Option<f64>,
}

impl RankSumTest {
    /// U1 / (n1·n2): the probability that a random value of sample 1 exceeds a random value of
    /// sample 2 (ties count half). Above 0.5 means sample 1 tends to be larger.
    pub fn prob_first_larger(&self) -> f64 {
        self.u1 / (self.n1 as f64 * self.n2 as f64)
    }

    /// The verdict at significance level `alpha` (e.g. 0.05): `Greater` if sample 1 is
    /// significantly larger (p ≤ `alpha` and U1 > n1·n2/2), `Less` if significantly smaller,
    /// `Equal` if the difference is not significant. A table's +/−/= mark is this, read in the
    /// direction in which larger values are better or worse. A NaN `alpha` gives `Equal`.
    pub fn verdict(&self, alpha: f64) -> Ordering {
        let significant = self.p_value <= alpha; // false for a NaN alpha
        if !significant {
            return Ordering::Equal;
        }
        self.u1.partial_cmp(&self.u2).unwrap_or(Ordering::Equal)
    }
}

/// The two-sided rank-sum test with [`RankSumMethod::Auto`]. See [`rank_sum_test_with`].
///
/// ```
/// use paretomesh::metrics::rank_sum_test;
/// // Every value of the first sample is below every value of the second: U1 = 0, and only 2 of
/// // the C(10, 5) = 252 equally likely rank sets are that extreme: p = 2/252.
/// let t = rank_sum_test(&[1.0, 2.0, 3.0, 4.0, 5.0], &[6.0, 7.0, 8.0, 9.0, 10.0]).unwrap();
/// assert_eq!(t.u1, 0.0);
/// assert!((t.p_value - 2.0 / 252.0).abs() < 1e-12);
/// ```
pub fn rank_sum_test(sample1: &[f64], sample2: &[f64]) -> Result<RankSumTest, MetricsError> {
    rank_sum_test_with(sample1, sample2, RankSumMethod::Auto)
}

/// The two-sided Wilcoxon rank-sum (Mann–Whitney U) test: are the two samples from the same
/// distribution, against a shift either way?
///
/// The values are ranked together, ties getting the mean of their ranks (midranks).
///
/// - Exact: p = min(1, 2·P(U ≤ min(U1, U2))) under the null distribution of U for sizes
///   (n1, n2), every assignment of ranks to samples being equally likely — the same rule as R's
///   `wilcox.test` and SciPy's `mannwhitneyu(method="exact")`. Valid only without ties.
/// - Normal: z = (U1 − n1·n2/2 − c) / σ with the continuity correction c = ±0.5 towards the mean
///   (c = 0 when U1 = n1·n2/2), and the tie-corrected variance
///   σ² = n1·n2/12 · ((N+1) − Σ(t³ − t) / (N(N−1))), N = n1 + n2, t the size of each group of
///   tied values; p = 2·(1 − Φ(|z|)) = erfc(|z|/√2), computed with the `libm` crate's erfc. Same as R's
///   `wilcox.test(correct = TRUE)` and SciPy's default asymptotic method. If every value is
///   equal, σ = 0 and there is no evidence of any difference: p = 1.
///
/// Errors: [`MetricsError::Empty`] if a sample is empty; [`MetricsError::NonFinite`] for a NaN
/// or infinite value; with [`RankSumMethod::Exact`], [`MetricsError::ExactWithTies`] if values
/// are tied and [`MetricsError::ExactTooLarge`] if n1·n2 exceeds 10 000.
pub fn rank_sum_test_with(
    sample1: &[f64],
    sample2: &[f64],
    method: RankSumMethod,
) -> Result<RankSumTest, MetricsError> {
    check_sample(sample1, "sample 1")?;
    check_sample(sample2, "sample 2")?;
    let (n1, n2) = (sample1.len(), sample2.len());
    let ranking = rank(sample1, sample2);
    let pairs = n1 as f64 * n2 as f64;
    let u1 = ranking.rank_sum_1 - (n1 as f64) * (n1 as f64 + 1.0) / 2.0;
    let u2 = pairs - u1;
    let has_ties = ranking.tie_term > 0.0;
    let use_exact = match method {
        RankSumMethod::Auto => !has_ties && n1 < EXACT_SAMPLE_LIMIT && n2 < EXACT_SAMPLE_LIMIT,
        RankSumMethod::Exact => {
            if has_ties {
                return Err(MetricsError::ExactWithTies);
            }
            true
        }
        RankSumMethod::Normal => false,
    };
    if use_exact {
        // Without ties U1 is an integer; rounding only removes floating-point noise.
        let u_min = u1.min(u2).round() as usize;
        let p_value = (2.0 * exact_u_cdf(n1, n2, u_min)?).min(1.0);
        return Ok(RankSumTest {
            n1,
            n2,
            u1,
            u2,
            p_value,
            method: RankSumMethod::Exact,
            z: None,
        });
    }
    let n = (n1 + n2) as f64;
    let variance = pairs / 12.0 * ((n + 1.0) - ranking.tie_term / (n * (n - 1.0)));
    let deviation = u1 - pairs / 2.0;
    let (z, p_value) = if variance <= 0.0 {
        (0.0, 1.0)
    } else {
        let correction = 0.5 * deviation.signum() * f64::from(deviation != 0.0);
        let z = (deviation - correction) / variance.sqrt();
        let p = libm::erfc(z.abs() / std::f64::consts::SQRT_2);
        (z, p.min(1.0))
    };
    Ok(RankSumTest {
        n1,
        n2,
        u1,
        u2,
        p_value,
        method: RankSumMethod::Normal,
        z: Some(z),
    })
}

/// P(U ≤ `u`) under the null hypothesis for samples of sizes `n1` and `n2` without ties: the
/// fraction of the C(n1+n2, n1) equally likely rank sets of sample 1 whose U is at most `u`.
///
/// Computed with the recurrence c(i, j, u) = c(i−1, j, u−j) + c(i, j−1, u) on the number of rank
/// sets (the largest value belongs either to sample 1, beating all j values of sample 2, or to
/// sample 2), keeping only u' ≤ `u`. U is symmetric: P(U ≤ u) = P(U ≥ n1·n2 − u). Returns 1 for
/// `u` ≥ n1·n2.
///
/// Errors: [`MetricsError::Empty`] if a size is 0; [`MetricsError::ExactTooLarge`] if n1·n2
/// exceeds 10 000.
///
/// ```
/// use paretomesh::metrics::exact_u_cdf;
/// // Sizes 5 and 5: U = 0, 1, 2 are reached by 1, 1 and 2 of the 252 rank sets.
/// assert!((exact_u_cdf(5, 5, 2).unwrap() - 4.0 / 252.0).abs() < 1e-15);
/// ```
pub fn exact_u_cdf(n1: usize, n2: usize, u: usize) -> Result<f64, MetricsError> {
    if n1 == 0 {
        return Err(MetricsError::Empty { set: "sample 1" });
    }
    if n2 == 0 {
        return Err(MetricsError::Empty { set: "sample 2" });
    }
    if n1.saturating_mul(n2) > EXACT_TABLE_LIMIT {
        return Err(MetricsError::ExactTooLarge { n1, n2 });
    }
    if u >= n1 * n2 {
        return Ok(1.0);
    }
    // c(i, j, ·) = c(j, i, ·), so iterate over the larger size with one row per smaller size.
    let (m, n) = (n1.min(n2), n1.max(n2));
    // counts[i][v] = number of rank sets of i values of sample 1 among j values of sample 2 with
    // U = v, for the current j; truncated to v ≤ u.
    let len = |i: usize, j: usize| (i * j).min(u) + 1;
    let mut counts: Vec<Vec<f64>> = vec![vec![1.0]; m + 1];
    for j in 1..=n {
        // i increasing: counts[i − 1] already holds column j, counts[i] still holds column j − 1.
        for i in 1..=m {
            let mut next = vec![0.0; len(i, j)];
            for (v, slot) in next.iter_mut().enumerate() {
                let largest_in_2 = counts[i].get(v).copied().unwrap_or(0.0);
                let largest_in_1 = if v >= j {
                    counts[i - 1].get(v - j).copied().unwrap_or(0.0)
                } else {
                    0.0
                };
                *slot = largest_in_2 + largest_in_1;
            }
            counts[i] = next;
        }
    }
    let below: f64 = counts[m].iter().sum();
    // C(m + n, m) as a product of ratios, each ≥ 1, so no overflow before the end.
    let total: f64 = (1..=m).map(|k| (n + k) as f64 / k as f64).product();
    Ok((below / total).min(1.0))
}

/// Midrank sum of sample 1 and the tie term Σ(t³ − t) of the pooled samples.
struct Ranking {
    rank_sum_1: f64,
    tie_term: f64,
}

fn rank(sample1: &[f64], sample2: &[f64]) -> Ranking {
    let mut pooled: Vec<(f64, bool)> = sample1
        .iter()
        .map(|&v| (v, true))
        .chain(sample2.iter().map(|&v| (v, false)))
        .collect();
    // Finite values only, so partial_cmp never fails; -0.0 and 0.0 tie, as they should.
    pooled.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(Ordering::Equal));
    let mut rank_sum_1 = 0.0;
    let mut tie_term = 0.0;
    let mut start = 0;
    while start < pooled.len() {
        let mut end = start + 1;
        while end < pooled.len() && pooled[end].0 == pooled[start].0 {
            end += 1;
        }
        // Ranks start + 1 ..= end share their mean.
        let t = (end - start) as f64;
        let midrank = (start + 1 + end) as f64 / 2.0;
        let in_1 = pooled[start..end].iter().filter(|v| v.1).count() as f64;
        rank_sum_1 += in_1 * midrank;
        tie_term += t * t * t - t;
        start = end;
    }
    Ranking {
        rank_sum_1,
        tie_term,
    }
}

fn check_sample(sample: &[f64], set: &'static str) -> Result<(), MetricsError> {
    if sample.is_empty() {
        return Err(MetricsError::Empty { set });
    }
    match sample.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(MetricsError::NonFinite { set, index }),
        None => Ok(()),
    }
}
