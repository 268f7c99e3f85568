//! The AVX2 twin of [`scan::Scalar`](super::scan::Scalar): the apex search's scan four points
//! per instruction, with the same least rounded s.

use super::scan::{Band, Edge, Least, Scan};
use std::arch::x86_64::*;
use std::ops::Range;

/// The edge's constants and, per lane: the least s, its position, whether it is shared (all
/// bits set).
#[derive(Clone, Copy, Debug)]
pub(super) struct Avx2 {
    ax: __m256d,
    ay: __m256d,
    bx: __m256d,
    by: __m256d,
    ex: __m256d,
    ey: __m256d,
    least: __m256d,
    at: __m256i,
    shared: __m256d,
}

/// Does this CPU run [`Avx2`]?
pub(super) fn available() -> bool {
    std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
}

impl Avx2 {
    /// The rounded s of the four points of block `k` ([`Edge::key`] in four lanes: the
    /// same operations, so the same values).
    ///
    /// # Safety
    /// AVX2 and FMA; `k` a block of the band.
    #[inline(always)]
    unsafe fn keys(&self, band: &Band, k: usize) -> __m256d {
        unsafe {
            let x = _mm256_loadu_pd(band.x.as_ptr().add(4 * k));
            let y = _mm256_loadu_pd(band.y.as_ptr().add(4 * k));
            let (qx, qy) = (_mm256_sub_pd(x, self.ax), _mm256_sub_pd(y, self.ay));
            let (rx, ry) = (_mm256_sub_pd(x, self.bx), _mm256_sub_pd(y, self.by));
            let den = _mm256_fmsub_pd(self.ex, qy, _mm256_mul_pd(self.ey, qx));
            let num = _mm256_fmadd_pd(qx, rx, _mm256_mul_pd(qy, ry));
            let left = _mm256_cmp_pd::<_CMP_GT_OQ>(den, _mm256_setzero_pd());
            _mm256_blendv_pd(_mm256_set1_pd(f64::INFINITY), _mm256_div_pd(num, den), left)
        }
    }
}

// SAFETY (every method): called only from code compiled with AVX2 and FMA, which runs only
// where `available()` said so; the loads stay in the band's arrays (asserted).
impl Scan for Avx2 {
    #[inline(always)]
    fn new(edge: &Edge) -> Self {
        unsafe {
            Self {
                ax: _mm256_set1_pd(edge.ax),
                ay: _mm256_set1_pd(edge.ay),
                bx: _mm256_set1_pd(edge.bx),
                by: _mm256_set1_pd(edge.by),
                ex: _mm256_set1_pd(edge.ex),
                ey: _mm256_set1_pd(edge.ey),
                least: _mm256_set1_pd(f64::INFINITY),
                at: _mm256_setzero_si256(),
                shared: _mm256_setzero_pd(),
            }
        }
    }

    #[inline(always)]
    fn scan(&mut self, band: &Band, blocks: Range<usize>) {
        assert!(4 * blocks.end <= band.x.len() && band.x.len() == band.y.len());
        unsafe {
            let mut position = _mm256_add_epi64(
                _mm256_set1_epi64x(4 * blocks.start as i64),
                _mm256_setr_epi64x(0, 1, 2, 3),
            );
            let (mut least, mut at, mut shared) = (self.least, self.at, self.shared);
            for k in blocks {
                let s = self.keys(band, k);
                let less = _mm256_cmp_pd::<_CMP_LT_OQ>(s, least);
                let equal = _mm256_cmp_pd::<_CMP_EQ_OQ>(s, least);
                shared = _mm256_andnot_pd(less, _mm256_or_pd(shared, equal));
                least = _mm256_min_pd(s, least);
                at = _mm256_castpd_si256(_mm256_blendv_pd(
                    _mm256_castsi256_pd(at),
                    _mm256_castsi256_pd(position),
                    less,
                ));
                position = _mm256_add_epi64(position, _mm256_set1_epi64x(4));
            }
            (self.least, self.at, self.shared) = (least, at, shared);
        }
    }

    #[inline(always)]
    fn least(&self) -> f64 {
        unsafe {
            let half = _mm_min_pd(
                _mm256_castpd256_pd128(self.least),
                _mm256_extractf128_pd::<1>(self.least),
            );
            _mm_cvtsd_f64(_mm_min_sd(half, _mm_unpackhi_pd(half, half)))
        }
    }

    #[inline(always)]
    fn outcome(&self) -> Least {
        let least = self.least();
        if least == f64::INFINITY {
            return Least::Nothing;
        }
        unsafe {
            let lanes = _mm256_cmp_pd::<_CMP_EQ_OQ>(self.least, _mm256_set1_pd(least));
            let lanes = _mm256_movemask_pd(lanes) as u32;
            let shared = _mm256_movemask_pd(self.shared) as u32;
            if lanes.is_power_of_two() && shared & lanes == 0 {
                let mut at = [0u64; 4];
                _mm256_storeu_si256(at.as_mut_ptr().cast(), self.at);
                Least::One(at[lanes.trailing_zeros() as usize & 3] as usize)
            } else {
                Least::Shared(least)
            }
        }
    }

    #[inline(always)]
    fn each_equal(
        &self,
        band: &Band,
        blocks: Range<usize>,
        least: f64,
        mut visit: impl FnMut(usize),
    ) {
        assert!(4 * blocks.end <= band.x.len() && band.x.len() == band.y.len());
        unsafe {
            let least = _mm256_set1_pd(least);
            for k in blocks {
                let equal = _mm256_cmp_pd::<_CMP_EQ_OQ>(self.keys(band, k), least);
                let mut lanes = _mm256_movemask_pd(equal) as u32;
                while lanes != 0 {
                    visit(4 * k + lanes.trailing_zeros() as usize);
                    lanes &= lanes - 1;
                }
            }
        }
    }
}
