//! The chromosome: one bit per grid point (bit i set = grid point i is kept), packed in `u64`
//! words. The four grid corners are always set; every operator preserves that.

use rand::RngExt;
use rand_pcg::Pcg64Mcg;
use serde::ser::{Serialize, SerializeStruct, Serializer};

/// A kept set as a compact bitset over the grid indices `0..len`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Chromosome {
    words: Vec<u64>,
    len: usize,
}

impl Chromosome {
    /// The chromosome of `len` genes with exactly the given indices set (each must be `< len`).
    pub(crate) fn from_indices(len: usize, indices: &[u32]) -> Self {
        let mut c = Self::empty(len);
        for &i in indices {
            c.set(i as usize, true);
        }
        c
    }

    /// `len` genes, all clear.
    pub fn empty(len: usize) -> Self {
        Self {
            words: vec![0; len.div_ceil(64)],
            len,
        }
    }

    /// Number of genes (grid points).
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// True when there are no genes at all.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Is gene `i` set? `i < len`.
    pub fn get(&self, i: usize) -> bool {
        self.words[i / 64] >> (i % 64) & 1 == 1
    }

    /// Sets gene `i` to `on`. `i < len`.
    pub(crate) fn set(&mut self, i: usize, on: bool) {
        let bit = 1u64 << (i % 64);
        if on {
            self.words[i / 64] |= bit;
        } else {
            self.words[i / 64] &= !bit;
        }
    }

    /// Flips gene `i`. `i < len`.
    pub(crate) fn flip(&mut self, i: usize) {
        self.words[i / 64] ^= 1u64 << (i % 64);
    }

    /// Number of set genes (kept points, corners included).
    pub(crate) fn count_ones(&self) -> usize {
        self.words.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// Number of genes that differ from `other` (same length).
    #[cfg(test)]
    pub(crate) fn hamming(&self, other: &Chromosome) -> usize {
        self.words
            .iter()
            .zip(&other.words)
            .map(|(a, b)| (a ^ b).count_ones() as usize)
            .sum()
    }

    /// The Hamming distance to `other` (same length) if it is below `bound`, else `None`; stops
    /// counting as soon as the bound is reached.
    pub(crate) fn hamming_below(&self, other: &Chromosome, bound: usize) -> Option<usize> {
        let mut d = 0;
        for (a, b) in self.words.chunks(8).zip(other.words.chunks(8)) {
            d += a
                .iter()
                .zip(b)
                .map(|(x, y)| (x ^ y).count_ones() as usize)
                .sum::<usize>();
            if d >= bound {
                return None;
            }
        }
        Some(d)
    }

    /// The genes where `self` and `other` (same length) differ, in increasing order: those set
    /// only in `self` into `only_self`, those set only in `other` into `only_other` (both
    /// cleared first).
    pub(crate) fn write_differences(
        &self,
        other: &Chromosome,
        only_self: &mut Vec<u32>,
        only_other: &mut Vec<u32>,
    ) {
        only_self.clear();
        only_other.clear();
        for (w, (&a, &b)) in self.words.iter().zip(&other.words).enumerate() {
            for (out, mut bits) in [(&mut *only_self, a & !b), (&mut *only_other, b & !a)] {
                while bits != 0 {
                    out.push((w * 64) as u32 + bits.trailing_zeros());
                    bits &= bits - 1;
                }
            }
        }
    }

    /// The edit that turns `self`'s kept set into `other`'s: [`write_differences`](Self::write_differences)
    /// without the genes in `fixed` (a grid's corners, which the evaluator keeps whatever the
    /// genes say), those only in `self` into `removed`, those only in `other` into `inserted`.
    pub(crate) fn write_edit(
        &self,
        other: &Chromosome,
        fixed: &[u32],
        removed: &mut Vec<u32>,
        inserted: &mut Vec<u32>,
    ) {
        self.write_differences(other, removed, inserted);
        removed.retain(|i| !fixed.contains(i));
        inserted.retain(|i| !fixed.contains(i));
    }

    /// The set indices in increasing order, written into `out` (cleared first): the form
    /// [`Evaluator::score`](crate::evaluator::Evaluator::score) takes.
    pub(crate) fn write_indices(&self, out: &mut Vec<u32>) {
        out.clear();
        for (w, &word) in self.words.iter().enumerate() {
            let mut bits = word;
            while bits != 0 {
                out.push((w * 64) as u32 + bits.trailing_zeros());
                bits &= bits - 1;
            }
        }
    }

    /// The set indices in increasing order.
    pub(crate) fn indices(&self) -> Vec<u32> {
        let mut out = Vec::with_capacity(self.count_ones());
        self.write_indices(&mut out);
        out
    }

    /// The genes as `u64` words, gene `i` in bit `i % 64` of word `i / 64` (bits past `len`
    /// clear).
    pub fn words(&self) -> &[u64] {
        &self.words
    }

    /// Sets genes `start..end`, leaving the rest unchanged.
    pub fn set_range(&mut self, start: usize, end: usize) {
        debug_assert!(start <= end && end <= self.len);
        // Word by word: a crossover marks a block a row at a time, and a bit at a time would
        // cost a loop iteration per gene.
        for (w, mask) in word_masks(start, end) {
            self.words[w] |= mask;
        }
    }

    /// Copies genes `start..end` from `other` (same length), leaving the rest unchanged.
    pub(crate) fn copy_range_from(&mut self, other: &Chromosome, start: usize, end: usize) {
        debug_assert!(start <= end && end <= self.len && other.len == self.len);
        for (w, mask) in word_masks(start, end) {
            self.words[w] = (self.words[w] & !mask) | (other.words[w] & mask);
        }
    }

    /// Takes each gene from `a` where `mask` has a 1 and from `b` elsewhere, word by word;
    /// `mask_word` gives the mask of each word. All three have the same length.
    pub(crate) fn blend(
        a: &Chromosome,
        b: &Chromosome,
        mut mask_word: impl FnMut(usize) -> u64,
    ) -> Chromosome {
        let words = a
            .words
            .iter()
            .zip(&b.words)
            .enumerate()
            .map(|(w, (x, y))| {
                let m = mask_word(w);
                (x & m) | (y & !m)
            })
            .collect();
        Chromosome { words, len: a.len }
    }
}

/// Serialises as `{"len": N, "kept": [set indices…]}`, the form the browser draws.
impl Serialize for Chromosome {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut st = serializer.serialize_struct("Chromosome", 2)?;
        st.serialize_field("len", &self.len)?;
        st.serialize_field("kept", &self.indices())?;
        st.end()
    }
}

/// Calls `visit(i)` for each `i` in `0..n` independently with probability `p`, drawing only one
/// random number per hit (geometric gaps), so a mutation with p = 1/L costs O(1) draws instead of
/// L. `p` is clamped to `[0, 1]`.
pub(crate) fn for_each_bernoulli(
    n: usize,
    p: f64,
    rng: &mut Pcg64Mcg,
    mut visit: impl FnMut(usize),
) {
    if n == 0 || p.is_nan() || p <= 0.0 {
        return;
    }
    if p >= 1.0 {
        (0..n).for_each(visit);
        return;
    }
    // Gap before the next hit ~ Geometric(p): floor(ln U / ln(1 − p)), U in (0, 1].
    // `libm` rather than std's `ln`: std calls the platform's libm (glibc natively, a Rust port
    // of musl on wasm32), which may differ in the last bit; one implementation everywhere keeps
    // runs bit-identical natively and in the browser.
    let log_q = libm::log1p(-p);
    let mut i = 0usize;
    loop {
        let u = 1.0 - rng.random::<f64>(); // (0, 1]
        let gap = (libm::log(u) / log_q).floor();
        if gap >= (n - i) as f64 {
            return;
        }
        i += gap as usize;
        visit(i);
        i += 1;
        if i >= n {
            return;
        }
    }
}

/// The bits `lo..hi` of a word (`lo < hi ≤ 64`).
/// The words that genes `start..end` touch, each with the mask of those genes in it (none when
/// the range is empty).
fn word_masks(start: usize, end: usize) -> impl Iterator<Item = (usize, u64)> {
    let (first, last) = (start / 64, end.saturating_sub(1) / 64);
    let words = if start < end { first..last + 1 } else { 0..0 };
    words.map(move |w| {
        let lo = if w == first { start % 64 } else { 0 };
        let hi = if w == last { (end - 1) % 64 + 1 } else { 64 };
        (w, word_mask(lo, hi))
    })
}

fn word_mask(lo: usize, hi: usize) -> u64 {
    if hi - lo == 64 {
        u64::MAX
    } else {
        ((1u64 << (hi - lo)) - 1) << lo
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn indices_round_trip_across_word_boundaries() {
        // Indices on both sides of the 64-bit word boundaries and the last bit.
        let idx = [0u32, 1, 63, 64, 65, 127, 128, 199];
        let c = Chromosome::from_indices(200, &idx);
        assert_eq!(c.indices(), idx);
        assert_eq!(c.count_ones(), idx.len());
    }

    #[test]
    fn serialises_as_its_kept_indices() {
        let c = Chromosome::from_indices(70, &[0, 69, 5]);
        assert_eq!(
            serde_json::to_string(&c).unwrap(),
            r#"{"len":70,"kept":[0,5,69]}"#
        );
    }

    #[test]
    fn copy_range_copies_exactly_the_range() {
        let ones = Chromosome::from_indices(150, &(0..150).collect::<Vec<_>>());
        for (start, end) in [(0, 150), (3, 5), (60, 70), (64, 128), (10, 10), (127, 129)] {
            let mut c = Chromosome::empty(150);
            c.copy_range_from(&ones, start, end);
            assert_eq!(
                c.indices(),
                (start as u32..end as u32).collect::<Vec<_>>(),
                "{start}..{end}"
            );
            // Setting the range on top of other genes adds exactly the range.
            let mut d = Chromosome::from_indices(150, &[0, 63, 64, 149]);
            d.set_range(start, end);
            let mut expected: Vec<u32> =
                (start as u32..end as u32).chain([0, 63, 64, 149]).collect();
            expected.sort_unstable();
            expected.dedup();
            assert_eq!(d.indices(), expected, "set_range {start}..{end}");
        }
    }

    #[test]
    fn bernoulli_hits_have_the_expected_rate() {
        // 200 000 trials at p = 0.01: mean 2000, sd ≈ 44; a wrong gap formula is off by far more.
        let mut rng = Pcg64Mcg::seed_from_u64(3);
        let mut hits = Vec::new();
        for_each_bernoulli(200_000, 0.01, &mut rng, |i| hits.push(i));
        assert!((1800..2200).contains(&hits.len()), "{}", hits.len());
        assert!(hits.windows(2).all(|w| w[0] < w[1]));
        let mut all = 0;
        for_each_bernoulli(10, 1.0, &mut rng, |_| all += 1);
        assert_eq!(all, 10);
        for_each_bernoulli(10, 0.0, &mut rng, |_| panic!("p = 0 never hits"));
    }
}
