//! The grid box of a triangle's circumcircle: where to look for points that would spoil it.

use crate::evaluator::exact::predicates::GridPoint;

/// The grid box of a triangle's circumcircle disc, clipped to the grid: columns `x0..=x1`, rows
/// `y0..=y1`. Conservative: it holds every grid point on or inside the circle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct DiscBox {
    x0: u16,
    x1: u16,
    y0: u16,
    y1: u16,
}

/// The circumcentre of the counter-clockwise triangle `p` relative to its first vertex, and
/// the radius, in floating point (for conservative boxes and filters: the exact predicates
/// decide).
#[inline(always)]
pub(crate) fn circumcentre(p: [GridPoint; 3]) -> (f64, f64, f64) {
    let [a, b, c] = p;
    let (bx, by) = (b[0] - a[0], b[1] - a[1]);
    let (cx, cy) = (c[0] - a[0], c[1] - a[1]);
    let (lb, lc) = (bx * bx + by * by, cx * cx + cy * cy);
    // Exact integers below 2⁴⁴; one rounding each in the division.
    let d = 2.0 * (bx * cy - by * cx) as f64;
    let ux = (cy * lb - by * lc) as f64 / d;
    let uy = (bx * lc - cx * lb) as f64 / d;
    (ux, uy, (ux * ux + uy * uy).sqrt())
}

impl DiscBox {
    /// The box of the counter-clockwise triangle `p` on a `width × height` grid.
    pub(crate) fn of(p: [GridPoint; 3], width: usize, height: usize) -> Self {
        let a = p[0];
        let (ux, uy, r) = circumcentre(p);
        // Far above the rounding error (a few ulps of numbers below 2³⁰), so no point on the
        // circle falls out of the box.
        let margin = 1e-6 * (1.0 + r);
        // Clipped first, then rounded: for a number in [0, hi] the truncating conversion is the
        // floor, and one comparison more the ceiling (`f64::floor` and `ceil` are library calls
        // on the x86-64 baseline, which has no rounding instruction).
        let floor = |v: f64, hi: usize| v.clamp(0.0, hi as f64) as u16;
        let ceil = |v: f64, hi: usize| {
            let v = v.clamp(0.0, hi as f64);
            let t = v as u16;
            t + u16::from((t as f64) < v)
        };
        let (ox, oy) = (a[0] as f64 + ux, a[1] as f64 + uy);
        Self {
            x0: floor(ox - r - margin, width - 1),
            x1: ceil(ox + r + margin, width - 1),
            y0: floor(oy - r - margin, height - 1),
            y1: ceil(oy + r + margin, height - 1),
        }
    }

    pub(crate) fn area(&self) -> usize {
        (self.x1 - self.x0 + 1) as usize * (self.y1 - self.y0 + 1) as usize
    }

    /// The box as a half-open rectangle `[x0, y0, x1, y1]`.
    pub(crate) fn rect(&self) -> [usize; 4] {
        [
            self.x0 as usize,
            self.y0 as usize,
            self.x1 as usize + 1,
            self.y1 as usize + 1,
        ]
    }
}
