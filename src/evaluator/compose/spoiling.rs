//! Whether a point the child takes from the other parent spoils a triangle's circle, and the
//! grid-rectangle arithmetic those searches use.

use crate::evaluator::exact::predicates::{Circle, GridPoint, Lattice, in_circle};
use crate::evaluator::mesh::disc_box::circumcentre;
use crate::evaluator::mesh::region::for_each_in;

/// Boxes holding more grid points than this are not searched for spoiling points: their
/// triangle is left to R instead (rare: a sliver's circle, clipped to the grid).
pub(crate) const MAX_SEARCHED_BOX: usize = 1024;

/// A stamp no entry of `marks` (made `n` long) holds yet, for marking without clearing: the
/// next of `stamp`, or 1 after clearing `marks` when the stamps wrap around.
pub(crate) fn next_stamp(stamp: &mut u32, marks: &mut Vec<u32>, n: usize) -> u32 {
    *stamp = stamp.wrapping_add(1);
    if *stamp == 0 {
        marks.clear();
        *stamp = 1;
    }
    marks.resize(n, 0);
    *stamp
}

/// The intersection of two half-open rectangles `[x0, y0, x1, y1]` (empty when they do not
/// meet: see [`is_empty`]).
pub(crate) fn overlap(a: [usize; 4], b: [usize; 4]) -> [usize; 4] {
    [
        a[0].max(b[0]),
        a[1].max(b[1]),
        a[2].min(b[2]),
        a[3].min(b[3]),
    ]
}

/// Does rectangle `outer` contain rectangle `inner`? (Without short-circuits, for a loop that
/// must not branch on it; and field by field: an array comparison reads the just-built arrays as
/// one vector and stalls on the stores.)
#[inline]
pub(crate) fn contains_all(outer: [usize; 4], inner: [usize; 4]) -> bool {
    (outer[0] <= inner[0])
        & (outer[1] <= inner[1])
        & (inner[2] <= outer[2])
        & (inner[3] <= outer[3])
}

/// Does the half-open rectangle `[x0, y0, x1, y1]` hold no point?
pub(crate) fn is_empty([x0, y0, x1, y1]: [usize; 4]) -> bool {
    x0 >= x1 || y0 >= y1
}

/// The number of points the summed-area table `sat` (of a `width`-wide grid: `(W + 1) ×
/// (H + 1)`, points in columns < x of rows < y at (y, x)) counts in the half-open rectangle
/// `[x0, y0, x1, y1]`; 0 when it is empty.
pub(crate) fn counted_in(sat: &[u32], width: usize, rect: [usize; 4]) -> u32 {
    if is_empty(rect) {
        return 0;
    }
    let [x0, y0, x1, y1] = rect;
    let sw = width + 1;
    sat[y1 * sw + x1] + sat[y0 * sw + x0] - sat[y0 * sw + x1] - sat[y1 * sw + x0]
}

/// Is a grid point that `counts` accepts, in the half-open rectangle `[x0, y0, x1, y1]`, inside
/// the circle of `tri` (its vertices excluded)? Points on the circle are inside or not by the
/// tie rule of [`in_circle`].
pub(crate) fn spoils(
    tri: [u32; 3],
    [x0, y0, x1, y1]: [usize; 4],
    lattice: Lattice,
    width: usize,
    counts: impl Fn(usize) -> bool,
) -> bool {
    let p = tri.map(|i| lattice.point(i));
    let circle = Circle::new(p[0], p[1], p[2]);
    for y in y0..y1 {
        for x in x0..x1 {
            let i = y * width + x;
            if !counts(i) || tri.contains(&(i as u32)) {
                continue;
            }
            let d = [x as i64, y as i64];
            let det = circle.det(d);
            if det > 0
                || (det == 0
                    && in_circle([p[0], p[1], p[2], d], [tri[0], tri[1], tri[2], i as u32]))
            {
                return true;
            }
        }
    }
    false
}

/// [`spoils`] for the points set in `bits` (bit `i` of word `i / 64` for grid point `i`): only
/// the set bits of each row of the rectangle are tested, not every grid point in it. Why: a
/// classification tests the circles of a thousand triangles that reach into another block
/// against the other parent's points there, which are a fraction of the rectangle's points;
/// testing each point's mark mispredicted about as often as there were marks.
pub(crate) fn spoils_bits(
    tri: [u32; 3],
    [x0, y0, x1, y1]: [usize; 4],
    circumcircle: &Circumcircle,
    lattice: Lattice,
    width: usize,
    bits: &[u64],
) -> bool {
    let p = tri.map(|i| lattice.point(i));
    let circle = Circle::new(p[0], p[1], p[2]);
    // Each row only where the circle crosses it (a conservative chord: the exact test decides),
    // and only if it has a set bit in the rectangle at all: a word or two, read before the
    // chord's square root (most rows of a sparse set have none there).
    for y in y0..y1 {
        if !any_in(bits, y * width + x0, y * width + x1) {
            continue;
        }
        let Some([cx0, cx1]) = circumcircle.chord(y as f64) else {
            continue;
        };
        let row = [
            (x0 as i64).max(cx0),
            y as i64,
            (x1 as i64).min(cx1),
            y as i64 + 1,
        ];
        let found = for_each_in(bits, width, row, |i| {
            if tri.contains(&i) {
                return false;
            }
            let d = lattice.point(i);
            let det = circle.det(d);
            det > 0 || (det == 0 && in_circle([p[0], p[1], p[2], d], [tri[0], tri[1], tri[2], i]))
        });
        if found {
            return true;
        }
    }
    false
}

/// Is any bit `lo..hi` of the bitset `bits` (bit `i` of word `i / 64`) set?
#[inline]
fn any_in(bits: &[u64], lo: usize, hi: usize) -> bool {
    if lo >= hi {
        return false;
    }
    let (first, last) = (lo / 64, (hi - 1) / 64);
    let low = u64::MAX << (lo % 64);
    let high = u64::MAX >> (63 - (hi - 1) % 64);
    if first == last {
        return bits[first] & low & high != 0;
    }
    bits[first] & low != 0
        || bits[first + 1..last].iter().any(|&w| w != 0)
        || bits[last] & high != 0
}

/// A triangle's circumcircle in floating point, for conservative geometric pre-filters (the
/// exact in-circle test decides): a margin far above the rounding error keeps every grid point
/// on or inside the circle inside every region these say the circle reaches.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Circumcircle {
    cx: f64,
    cy: f64,
    /// The square of the radius grown by the margin.
    r2: f64,
}

impl Circumcircle {
    /// The circle of the counter-clockwise triangle `p`.
    pub(crate) fn of(p: [GridPoint; 3]) -> Self {
        let a = p[0];
        let (ux, uy, r) = circumcentre(p);
        let r = r + 1e-6 * (1.0 + r);
        Self {
            cx: a[0] as f64 + ux,
            cy: a[1] as f64 + uy,
            r2: r * r,
        }
    }

    /// Might the circle reach a grid point of the half-open rectangle `[x0, y0, x1, y1]`?
    pub(crate) fn reaches(&self, [x0, y0, x1, y1]: [usize; 4]) -> bool {
        // The rectangle's grid points span [x0, x1 − 1] × [y0, y1 − 1].
        let gap = |lo: usize, hi: usize, c: f64| {
            let (lo, hi) = (lo as f64, hi as f64 - 1.0);
            if c < lo {
                lo - c
            } else if c > hi {
                c - hi
            } else {
                0.0
            }
        };
        let (dx, dy) = (gap(x0, x1, self.cx), gap(y0, y1, self.cy));
        dx * dx + dy * dy <= self.r2
    }

    /// The columns `[x0, x1)` (a superset) of the grid points of row `y` on or inside the
    /// circle, if any.
    fn chord(&self, y: f64) -> Option<[i64; 2]> {
        let dy = y - self.cy;
        let h2 = self.r2 - dy * dy;
        if h2 < 0.0 {
            return None;
        }
        let h = h2.sqrt();
        // Truncation is the floor from 0 up; below 0 it rounds up, which only moves the ends
        // among negative columns (none is a grid point) or widens the superset by one (and
        // `f64::floor` is a library call on the x86-64 baseline).
        Some([(self.cx - h) as i64, (self.cx + h) as i64 + 1])
    }
}

#[cfg(test)]
mod tests {
    use super::any_in;
    use rand::{RngExt, SeedableRng};

    /// `any_in` against a bit-by-bit scan, on sparse random bitsets (so that most ranges hold
    /// no bit and the answer turns on the words' edges), over ranges within a word, across one
    /// boundary and across several.
    #[test]
    fn any_in_finds_a_set_bit_exactly_when_a_scan_does() {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
        for _ in 0..2000 {
            let bits: Vec<u64> = (0..5)
                .map(|_| {
                    (0..rng.random_range(0..3)).fold(0, |w, _| w | 1 << rng.random_range(0..64))
                })
                .collect();
            let lo = rng.random_range(0..320);
            let hi = rng.random_range(lo..=320);
            let scan = (lo..hi).any(|i| bits[i / 64] >> (i % 64) & 1 == 1);
            assert_eq!(any_in(&bits, lo, hi), scan, "bits {bits:x?}, {lo}..{hi}");
        }
    }
}
