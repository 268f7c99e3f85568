//! The vertices of a tile's border lines, fixed before any optimisation from the border profile
//! alone, so that both tiles sharing a line keep the same points on it.
//!
//! A line's points are ranked by 1-D greedy insertion on its height profile: from the two end
//! points, the point farthest (in z) from the current polyline comes next, the lowest position
//! on a tie. Border level k keeps the first [`interior_points`]`(k)` of that ranking on every
//! line (all of them once a line is shorter), so the levels are nested and a line's vertex set
//! at a level depends only on its profile: the same from both sides.

use serde::{Deserialize, Serialize};

/// The four sides of a tile, in the order [`TileBorders`] keeps them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// Row 0, left to right.
    Top,
    /// The last row, left to right.
    Bottom,
    /// Column 0, top to bottom.
    Left,
    /// The last column, top to bottom.
    Right,
}

impl Side {
    /// Every side, in storage order.
    pub(crate) const ALL: [Side; 4] = [Side::Top, Side::Bottom, Side::Left, Side::Right];

    /// The tile-local index of point `position` along this side of a `w`×`h` tile.
    pub(crate) fn local_index(self, position: usize, w: usize, h: usize) -> u32 {
        let (x, y) = match self {
            Side::Top => (position, 0),
            Side::Bottom => (position, h - 1),
            Side::Left => (0, position),
            Side::Right => (w - 1, position),
        };
        (y * w + x) as u32
    }

    /// Points along this side of a `w`×`h` tile, end points included.
    pub(crate) fn length(self, w: usize, h: usize) -> usize {
        match self {
            Side::Top | Side::Bottom => w,
            Side::Left | Side::Right => h,
        }
    }
}

/// Interior points (end points excluded) a line keeps at border level `level`: 0, 1, 2, 4, 8,
/// … (before the cap of the line's own interior points).
pub(super) fn interior_points(level: usize) -> usize {
    if level == 0 {
        0
    } else {
        1usize << (level - 1).min(62)
    }
}

/// The number of border levels for tiles of at most `tile` points a side: up to the first level
/// that keeps every point of the longest line.
pub(super) fn level_count(tile: usize) -> usize {
    let interior = tile.saturating_sub(2);
    (0..).find(|&k| interior_points(k) >= interior).unwrap_or(0) + 1
}

/// The interior points of a line with heights `profile` (at least 2), ranked by 1-D greedy
/// insertion: positions 1 ..= n − 2, most important first.
pub(super) fn insertion_order(profile: &[f64]) -> Vec<u32> {
    ranked(profile).into_iter().map(|(at, _)| at).collect()
}

/// [`insertion_order`] with, beside each position, the line's largest error |z − z̃| just
/// before it is inserted: so the line keeping the first k positions has the largest error
/// of entry k (0 when k is the whole ranking).
pub(super) fn ranked(profile: &[f64]) -> Vec<(u32, f64)> {
    let n = profile.len();
    let mut order = Vec::with_capacity(n.saturating_sub(2));
    if n <= 2 {
        return order;
    }
    // Each open segment (a, b) with its worst point: a max-heap on (error, lowest position).
    let worst = |a: usize, b: usize| -> Option<(f64, usize)> {
        let (za, zb) = (profile[a], profile[b]);
        let span = (b - a) as f64;
        let mut best: Option<(f64, usize)> = None;
        for (i, &z) in profile.iter().enumerate().take(b).skip(a + 1) {
            let t = (i - a) as f64 / span;
            let d = (z - (za + (zb - za) * t)).abs();
            if best.is_none_or(|(e, _)| d > e) {
                best = Some((d, i));
            }
        }
        best
    };
    let mut heap = std::collections::BinaryHeap::new();
    let push = |heap: &mut std::collections::BinaryHeap<Entry>, a: usize, b: usize| {
        if let Some((error, at)) = worst(a, b) {
            heap.push(Entry { error, at, a, b });
        }
    };
    push(&mut heap, 0, n - 1);
    while let Some(Entry { error, at, a, b }) = heap.pop() {
        order.push((at as u32, error));
        push(&mut heap, a, at);
        push(&mut heap, at, b);
    }
    order
}

/// A segment's worst point in the insertion heap.
struct Entry {
    error: f64,
    at: usize,
    a: usize,
    b: usize,
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    /// Larger error first, then the lower position.
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.error
            .total_cmp(&other.error)
            .then(other.at.cmp(&self.at))
    }
}

/// Σ |z − z̃| over the points of a line that are not kept, z̃ interpolating linearly between
/// kept neighbours; `kept` flags the kept positions (both end points must be).
pub(super) fn line_error(profile: &[f64], kept: &[bool]) -> f64 {
    line_error_with(profile, kept, f64::abs)
}

/// Σ (z − z̃)² over the line's points, as [`line_error`] interpolates them: what a tile's
/// squared-error share leaves out for a neighbour that counts the line.
pub(super) fn line_square_error(profile: &[f64], kept: &[bool]) -> f64 {
    line_error_with(profile, kept, |d| d * d)
}

/// Σ f(z − z̃) over the line's points.
fn line_error_with(profile: &[f64], kept: &[bool], f: impl Fn(f64) -> f64) -> f64 {
    let mut sum = 0.0;
    let mut a = 0;
    for b in 1..profile.len() {
        if !kept[b] {
            continue;
        }
        let (za, zb) = (profile[a], profile[b]);
        let span = (b - a) as f64;
        for (i, &z) in profile.iter().enumerate().take(b).skip(a + 1) {
            let t = (i - a) as f64 / span;
            sum += f(z - (za + (zb - za) * t));
        }
        a = b;
    }
    sum
}

/// A tile's four border lines ranked for insertion ([`insertion_order`]), in [`Side::ALL`]
/// order, positions along each line.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct TileBorders {
    /// Columns of the tile.
    pub w: usize,
    /// Rows of the tile.
    pub h: usize,
    /// Per side, its interior positions, most important first.
    pub order: [Vec<u32>; 4],
}

impl TileBorders {
    /// The ranking of the four sides of a `w`×`h` tile with heights `z` (row-major).
    pub(crate) fn new(w: usize, h: usize, z: &[f64]) -> Self {
        let order = Side::ALL.map(|side| {
            let profile: Vec<f64> = (0..side.length(w, h))
                .map(|p| z[side.local_index(p, w, h) as usize])
                .collect();
            insertion_order(&profile)
        });
        Self { w, h, order }
    }

    /// The positions `side` keeps at `level`, most important first.
    pub(crate) fn kept_on(&self, side: Side, level: usize) -> &[u32] {
        let order = &self.order[side as usize];
        &order[..interior_points(level).min(order.len())]
    }

    /// The tile-local indices of the border points kept at `level`, corners excluded,
    /// increasing, without repeats.
    pub(crate) fn kept(&self, level: usize) -> Vec<u32> {
        let mut out: Vec<u32> = Side::ALL
            .iter()
            .flat_map(|&side| {
                self.kept_on(side, level)
                    .iter()
                    .map(move |&p| side.local_index(p as usize, self.w, self.h))
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The error Σ |z − z̃| of `side`'s points at `level` (z̃ on the line's kept polyline).
    pub(crate) fn side_error(&self, side: Side, level: usize, z: &[f64]) -> f64 {
        self.side_error_with(side, level, z, line_error)
    }

    /// [`side_error`](Self::side_error) in squared errors ([`line_square_error`]).
    pub(crate) fn side_square_error(&self, side: Side, level: usize, z: &[f64]) -> f64 {
        self.side_error_with(side, level, z, line_square_error)
    }

    fn side_error_with(
        &self,
        side: Side,
        level: usize,
        z: &[f64],
        error: fn(&[f64], &[bool]) -> f64,
    ) -> f64 {
        let n = side.length(self.w, self.h);
        let profile: Vec<f64> = (0..n)
            .map(|p| z[side.local_index(p, self.w, self.h) as usize])
            .collect();
        let mut kept = vec![false; n];
        kept[0] = true;
        kept[n - 1] = true;
        for &p in self.kept_on(side, level) {
            kept[p as usize] = true;
        }
        error(&profile, &kept)
    }

    /// True when tile-local index `local` lies on the tile's border.
    pub(crate) fn on_border(&self, local: u32) -> bool {
        let (x, y) = (local as usize % self.w, local as usize / self.w);
        x == 0 || y == 0 || x == self.w - 1 || y == self.h - 1
    }
}
