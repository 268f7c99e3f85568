//! A cheap lower bound on the Hamming distance of two chromosomes.

use crate::evolution::chromosome::Chromosome;

/// How many stretches a [`Profile`] counts.
const PROFILE_PARTS: usize = 16;

/// The gene counts of [`PROFILE_PARTS`] consecutive stretches of a chromosome. The Hamming
/// distance of two chromosomes is at least the sum of the differences of their counts, a lower
/// bound far cheaper than the distance (16 subtractions instead of a pass over the words), which
/// lets the scorer's search skip most pooled chromosomes of a population whose total gene
/// counts are alike.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Profile([u32; PROFILE_PARTS]);

impl Profile {
    /// The profile of `c`.
    pub(super) fn of(c: &Chromosome) -> Self {
        let words = c.words();
        let per = words.len().div_ceil(PROFILE_PARTS).max(1);
        let mut counts = [0u32; PROFILE_PARTS];
        for (count, part) in counts.iter_mut().zip(words.chunks(per)) {
            *count = part.iter().map(|w| w.count_ones()).sum();
        }
        Self(counts)
    }

    /// The lower bound on the Hamming distance of the two chromosomes.
    pub(super) fn distance_below(&self, other: &Self) -> usize {
        self.0
            .iter()
            .zip(&other.0)
            .map(|(a, b)| a.abs_diff(*b) as usize)
            .sum()
    }
}
