//! Scoring a crossed child by composing its two parents' meshes.
//!
//! An orthogonal-array child takes each grid point's gene from one of two parents A and B,
//! block by block: its kept set is A's on the points labelled A and B's on those labelled B.
//! Most of its canonical triangulation is already in the parents' meshes, with every error
//! rasterised: [`Evaluator::compose`](super::Evaluator::compose) keeps those triangles and
//! their errors, and triangulates and rasterises only what is new along the seams between the
//! blocks.
//!
//! Why it is exact: under the tie rule (a Simulation of Simplicity, see
//! [`predicates`](super::predicates)) a triangle belongs to the canonical triangulation of a
//! point set exactly when its vertices are in the set and no other point of the set is inside
//! its (perturbed) circumcircle. A triangle of A whose vertices the child keeps has no point of
//! A inside its circle, so only the child's points labelled B can spoil it; those are looked up
//! inside the circle's grid box (and there are none in most boxes, which a summed-area table of
//! the labels tells in four reads). Each kept triangle is taken from the parent its smallest
//! vertex's label names, so none is taken twice. Whatever the taken triangles do not cover (the
//! region R) is tiled by the child's other triangles, which are those of the canonical
//! triangulation of R's points that lie in R (as for a region removal in
//! [`incremental`](super::incremental)). A taken triangle owns the same grid points with the
//! same errors as in its parent, so only R's triangles are rasterised.
//!
//! The children of one orthogonal-array crossover share their parents and their blocks, and
//! differ only in which parent gives each block. [`PartClasses`] classifies both parents'
//! triangles once against the blocks: each triangle gets the set of blocks whose labelling for
//! the other parent would drop it, so each child's classification is a mask test per triangle
//! ([`Evaluator::compose_parts`](super::Evaluator::compose_parts)) instead of a summed-area
//! lookup and a circle search.

use super::errors::ErrorTotals;
use super::incremental::{MeshState, edge_from};
use super::predicates::{Circle, GridPoint, Lattice, in_circle};
use super::region::{BOUNDARY, Region, for_each_in};
use super::triangle_memo::TriangleMemo;
use super::triangulation::{NONE, fit};
use crate::heightfield::Heightfield;
use std::sync::Arc;

/// The grid box of a triangle's circumcircle disc, clipped to the grid: columns `x0..=x1`, rows
/// `y0..=y1`. Conservative: it holds every grid point on or inside the circle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DiscBox {
    x0: u16,
    x1: u16,
    y0: u16,
    y1: u16,
}

/// The circumcentre of the counter-clockwise triangle `p` relative to its first vertex, and
/// the radius, in floating point (for conservative boxes and filters: the exact predicates
/// decide).
#[inline(always)]
fn circumcentre(p: [GridPoint; 3]) -> (f64, f64, f64) {
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
    pub fn of(p: [GridPoint; 3], width: usize, height: usize) -> Self {
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

    fn area(&self) -> usize {
        (self.x1 - self.x0 + 1) as usize * (self.y1 - self.y0 + 1) as usize
    }

    /// The box as a half-open rectangle `[x0, y0, x1, y1]`.
    pub(super) fn rect(&self) -> [usize; 4] {
        [
            self.x0 as usize,
            self.y0 as usize,
            self.x1 as usize + 1,
            self.y1 as usize + 1,
        ]
    }
}

/// Boxes holding more grid points than this are not searched for spoiling points: their
/// triangle is left to R instead (rare: a sliver's circle, clipped to the grid).
const MAX_SEARCHED_BOX: usize = 1024;

/// Scratch buffers of [`Evaluator::compose`](super::Evaluator::compose), kept between calls.
#[derive(Clone, Debug, Default)]
pub struct ComposeScratch {
    /// Summed-area table of the B labels, `(W + 1) × (H + 1)`.
    sat: Vec<u32>,
    /// Per grid point: 1 when labelled B.
    labels: Vec<u8>,
    /// Per slot of A and of B: its slot in the child, or [`NONE`] when not taken.
    map: [Vec<u32>; 2],
    /// The taken slots of A, then of B.
    taken: [Vec<u32>; 2],
    /// Half-edges of taken triangles with R across: (child half-edge, from, to).
    open: Vec<(u32, u32, u32)>,
    /// Per grid point: listed in `points`.
    listed: Vec<bool>,
    /// R's points and the grid corners.
    points: Vec<u32>,
    /// R's triangles (the tags of its boundary edges are the child's half-edges across).
    region: Region,
    /// Per grid point: the stamp of the last composition one of whose taken triangles has it.
    covered: Vec<u32>,
    stamp: u32,
    /// R's slots whose totals the memo did not know.
    unknown: Vec<(u32, [u32; 3])>,
}

/// Where a child's labels come from: a bitset over the grid (bit set: from B), or parts of
/// a [`PartClasses`] with a level per part (bit `part` set: from B).
#[derive(Clone, Copy)]
enum Labels<'a> {
    Bits(&'a [u64]),
    Parts(&'a PartClasses, u32),
}

/// Is `s` scored on `hf` with its disc boxes filled?
fn composable(s: &MeshState, hf: &Arc<Heightfield>) -> bool {
    s.hf.as_ref().is_some_and(|h| Arc::ptr_eq(h, hf)) && s.score.is_some() && s.discs_valid
}

/// Both parents' triangles classified once against a partition of the grid into rectangles
/// (an orthogonal-array crossover's blocks), for all the children that take each rectangle
/// whole from one parent ([`Evaluator::compose_parts`](super::Evaluator::compose_parts)).
///
/// Why it is exact: a child labels each part for A or B. A triangle of parent P (the other
/// parent Q) is taken by [`compose`](super::Evaluator::compose) exactly when its smallest
/// vertex's part is labelled P, each vertex is kept by the child, and no point the child takes
/// from Q spoils its circle (or, for a circle whose grid box is too large to search, no point
/// of the box is labelled Q). Each of these conditions fails exactly when some part labelled Q
/// is among a set of parts that depends on the triangle and the parents alone: the parts of its
/// vertices that Q does not keep, and the parts of the points of Q inside its circle (or of the
/// whole box). That set, the triangle's *kill mask*, is found once here, so a child's
/// classification is one mask test per triangle instead of a search per child.
#[derive(Clone, Debug, Default)]
pub struct PartClasses {
    /// The parts, as rectangles `[x0, y0, x1, y1]` (half-open).
    pub(super) rects: Vec<[usize; 4]>,
    /// The part of every grid point.
    pub(super) part: Vec<u8>,
    /// Per parent, per triangle slot: the part of its smallest vertex.
    pub(super) first: [Vec<u8>; 2],
    /// Per parent, per triangle slot: its kill mask (bit `p` for part `p`; never its own part's,
    /// which cannot matter: a triangle is taken only where that part is labelled for its parent).
    pub(super) kill: [Vec<u32>; 2],
    /// The parents' [`MeshState`] revisions, to refuse other meshes.
    pub(super) made_from: [u64; 2],
    /// A number no other classification had (0 until made), so that what is derived from this
    /// one ([`PartScores`](super::PartScores)) can tell it from a later one of the same parents.
    pub(super) id: u64,
    /// Per parent: the slots of its triangles whose disc box leaves their own part (the others'
    /// kill masks are empty).
    near: [Vec<u32>; 2],
    /// Per parent: how many of `near` are its (the rest is stale; see [`near`](Self::near)).
    near_len: [usize; 2],
    /// Per parent, per part: the error totals and number of its triangles whose smallest
    /// vertex is in the part and whose kill mask is empty.
    pub(super) plain: [Vec<(ErrorTotals, u32)>; 2],
    /// Per axis (columns, rows), per line: the masks of the non-empty parts that start at or
    /// before it, and of those that end after it.
    reach: [[Vec<u32>; 2]; 2],
    /// Scratch of [`reset`](Self::reset): the points the other parent keeps and this one does
    /// not, as a bitset.
    only_other: Vec<u64>,
}

impl PartClasses {
    /// Most parts a classification holds (bits of a mask).
    pub const MAX_PARTS: usize = 32;

    /// Classifies the triangles of `a` and `b` (scored on `hf`, disc boxes filled) against the
    /// rectangles `parts` (`[x0, y0, x1, y1]`, half-open; empty ones allowed), which must tile the
    /// grid. `None` when they do not, when there are more than [`MAX_PARTS`](Self::MAX_PARTS),
    /// or when a parent is not ready to compose from.
    pub fn new(
        hf: &Arc<Heightfield>,
        a: &MeshState,
        b: &MeshState,
        parts: &[[usize; 4]],
    ) -> Option<Self> {
        let mut classes = Self::default();
        classes.reset(hf, a, b, parts).then_some(classes)
    }

    /// [`new`](Self::new) into this classification's buffers; false (and unusable) on refusal.
    pub fn reset(
        &mut self,
        hf: &Arc<Heightfield>,
        a: &MeshState,
        b: &MeshState,
        parts: &[[usize; 4]],
    ) -> bool {
        self.made_from = [0; 2];
        self.id = 0;
        let (w, h, n) = (hf.width(), hf.height(), hf.len());
        if parts.len() > Self::MAX_PARTS
            || !composable(a, hf)
            || !composable(b, hf)
            || !a.lookup_valid
            || !b.lookup_valid
        {
            return false;
        }
        // The part of every point; the rectangles must cover each exactly once.
        self.part.clear();
        self.part.resize(n, u8::MAX);
        let mut covered = 0usize;
        for (p, &[x0, y0, x1, y1]) in parts.iter().enumerate() {
            if x0 > x1 || y0 > y1 || x1 > w || y1 > h {
                return false;
            }
            for y in y0..y1 {
                for slot in &mut self.part[y * w + x0..y * w + x1] {
                    if *slot != u8::MAX {
                        return false;
                    }
                    *slot = p as u8;
                }
            }
            covered += (x1 - x0) * (y1 - y0);
        }
        if covered != n {
            return false;
        }
        self.rects.clear();
        self.rects.extend_from_slice(parts);
        // Which parts a disc box meets, from its four sides: a rectangle meets the box iff
        // both its column range and its row range meet the box's. Per column x, the (non-empty)
        // parts whose columns start at or before x, and those whose columns end after x; the
        // same per row.
        for (axis, len) in [(0, w), (1, h)] {
            let [starts, ends] = &mut self.reach[axis];
            starts.clear();
            starts.resize(len, 0);
            ends.clear();
            ends.resize(len, 0);
            for (p, r) in parts.iter().enumerate() {
                if is_empty(*r) {
                    continue;
                }
                let (lo, hi) = (r[axis], r[axis + 2]);
                for s in &mut starts[lo..] {
                    *s |= 1 << p;
                }
                for e in &mut ends[..hi] {
                    *e |= 1 << p;
                }
            }
        }
        let [[starts_x, ends_x], [starts_y, ends_y]] = &self.reach;
        let lattice = Lattice::new(w);
        let parents = [a, b];
        for side in 0..2 {
            let (parent, other) = (parents[side], parents[1 - side]);
            // The points that may spoil a circle: those the other parent keeps and this one
            // does not. A point both keep cannot: the triangle is Delaunay among this parent's
            // points, so none of them is inside its circle under the tie rule. As a bitset (a
            // few hundred bytes, which stay in cache; the other parent's summed-area table,
            // 17 KB on a 65×65 grid, read at random per circle to skip empty overlaps, cost
            // more than scanning the bits: measured on the paper run, the pass over the
            // triangles near the blocks' edges took 10 % less without). Why not all the other
            // parent's points: parents of a converging population keep mostly the same ones,
            // and each of those cost an exact test per circle it fell in.
            self.only_other.clear();
            self.only_other.extend(
                (other.kept_bits.iter())
                    .zip(&parent.kept_bits)
                    .map(|(o, p)| o & !p),
            );
            let bits = &self.only_other;
            let m = &parent.mesh;
            let (first, kill) = (&mut self.first[side], &mut self.kill[side]);
            // Every slot is written below: only a longer parent needs more room (a clear
            // first would fill the whole length again, per parent per crossover).
            first.resize(m.len(), 0);
            kill.clear();
            kill.resize(m.len(), 0);
            // First every triangle's own part and whether its disc box leaves that part, without
            // branches (which triangles are near a block's edge follows the blocks, not the slot
            // order; branches on it mispredicted several times per triangle). A triangle whose
            // box stays in its own part has all its vertices there too, so no part but its own
            // can drop it: its kill mask is empty.
            // Written up to its length below, so only grown (as `first`).
            let near = &mut self.near[side];
            if near.len() < m.len() {
                near.resize(m.len(), 0);
            }
            let mut near_len = 0;
            let part = &self.part[..];
            let plain = &mut self.plain[side];
            plain.clear();
            plain.resize(parts.len(), (ErrorTotals::default(), 0));
            let rows = m
                .vertices
                .chunks_exact(3)
                .zip(&parent.discs)
                .zip(&parent.totals);
            for (t, (((tri, disc), totals), f)) in rows.zip(first.iter_mut()).enumerate() {
                let own = part[tri[0].min(tri[1]).min(tri[2]) as usize];
                *f = own;
                let inside = contains_all(parts[own as usize], disc.rect());
                near[near_len] = t as u32;
                near_len += usize::from(!inside);
                if inside {
                    let p = &mut plain[own as usize];
                    p.0.add(totals);
                    p.1 += 1;
                }
            }
            self.near_len[side] = near_len;
            let kept = &other.kept[..];
            for &t in &near[..near_len] {
                let t = t as usize;
                let tri = m.triangle(t);
                let own = first[t];
                kill[t] = tri.iter().fold(0u32, |mask, &v| {
                    mask | (u32::from(!kept[v as usize]) << part[v as usize])
                });
                let disc = parent.discs[t].rect();
                // The parts the box meets (its rectangle's last column and row are x1 − 1 and
                // y1 − 1), but its own.
                let [x0, y0, x1, y1] = disc;
                // A part that already drops the triangle (the other parent lacks a vertex there)
                // needs no search.
                let mut met = starts_x[x1 - 1]
                    & ends_x[x0]
                    & starts_y[y1 - 1]
                    & ends_y[y0]
                    & !(1 << own)
                    & !kill[t];
                if met != 0 && parent.discs[t].area() > MAX_SEARCHED_BOX {
                    kill[t] |= met;
                } else if met != 0 {
                    // Each met part, where the box overlaps it, holds a spoiling point of the
                    // other parent or not. The box is square, so an overlap is often a corner
                    // of it that the circle does not reach; the others' rows are scanned where
                    // the circle crosses them, a word of the bitset at a time.
                    let circle = Circumcircle::of(tri.map(|i| lattice.point(i)));
                    while met != 0 {
                        let p = met.trailing_zeros();
                        met &= met - 1;
                        let both = overlap(parts[p as usize], disc);
                        if circle.reaches(both) && spoils_bits(tri, both, &circle, lattice, w, bits)
                        {
                            kill[t] |= 1 << p;
                        }
                    }
                }
                kill[t] &= !(1 << own);
                if kill[t] == 0 {
                    let p = &mut plain[own as usize];
                    p.0.add(&parent.totals[t]);
                    p.1 += 1;
                }
            }
        }
        self.made_from = [a.revision, b.revision];
        self.id = super::incremental::next_revision();
        true
    }

    /// The slots of parent `side`'s triangles whose disc box leaves their own part (the others'
    /// kill masks are empty).
    pub(super) fn near(&self, side: usize) -> &[u32] {
        &self.near[side][..self.near_len[side]]
    }

    /// A number no other classification had (0 until made); a copy keeps it.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// Was this classification made for parents `a` and `b`, as they are now?
    pub fn is_for(&self, a: &MeshState, b: &MeshState) -> bool {
        self.made_from == [a.revision, b.revision] && a.revision != 0
    }
}

/// A stamp no entry of `marks` (made `n` long) holds yet, for marking without clearing: the
/// next of `stamp`, or 1 after clearing `marks` when the stamps wrap around.
pub(super) fn next_stamp(stamp: &mut u32, marks: &mut Vec<u32>, n: usize) -> u32 {
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
pub(super) fn overlap(a: [usize; 4], b: [usize; 4]) -> [usize; 4] {
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
fn contains_all(outer: [usize; 4], inner: [usize; 4]) -> bool {
    (outer[0] <= inner[0])
        & (outer[1] <= inner[1])
        & (inner[2] <= outer[2])
        & (inner[3] <= outer[3])
}

/// Does the half-open rectangle `[x0, y0, x1, y1]` hold no point?
fn is_empty([x0, y0, x1, y1]: [usize; 4]) -> bool {
    x0 >= x1 || y0 >= y1
}

/// The number of points the summed-area table `sat` (of a `width`-wide grid: `(W + 1) ×
/// (H + 1)`, points in columns < x of rows < y at (y, x)) counts in the half-open rectangle
/// `[x0, y0, x1, y1]`; 0 when it is empty.
pub(super) fn counted_in(sat: &[u32], width: usize, rect: [usize; 4]) -> u32 {
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
fn spoils(
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
fn spoils_bits(
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
struct Circumcircle {
    cx: f64,
    cy: f64,
    /// The square of the radius grown by the margin.
    r2: f64,
}

impl Circumcircle {
    /// The circle of the counter-clockwise triangle `p`.
    fn of(p: [GridPoint; 3]) -> Self {
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
    fn reaches(&self, [x0, y0, x1, y1]: [usize; 4]) -> bool {
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

impl MeshState {
    /// Fills the disc boxes of this state's triangles, and its kept points' bitset and
    /// summed-area table, if they are stale (a build or an edit leaves them so). A parent is
    /// composed from many times, so this is paid once per parent.
    pub fn ensure_discs(&mut self) {
        let Some(hf) = self.hf.clone() else {
            return;
        };
        let (w, h) = (hf.width(), hf.height());
        if !self.discs_valid {
            let lattice = Lattice::new(w);
            self.discs.clear();
            self.discs.extend((0..self.mesh.len()).map(|t| {
                let p = self.mesh.triangle(t).map(|i| lattice.point(i));
                DiscBox::of(p, w, h)
            }));
            self.discs_valid = true;
        }
        self.ensure_lookups();
    }

    /// Fills this state's kept points' bitset and summed-area table if they are stale (part of
    /// [`ensure_discs`](Self::ensure_discs), and all that
    /// [`Evaluator::score_mutant`](super::Evaluator::score_mutant) needs).
    pub fn ensure_lookups(&mut self) {
        let Some(hf) = self.hf.clone() else {
            return;
        };
        let (w, h) = (hf.width(), hf.height());
        if !self.lookup_valid {
            let kept = &self.kept[..w * h];
            self.kept_bits.clear();
            self.kept_bits.extend(kept.chunks(64).map(|c| {
                c.iter()
                    .enumerate()
                    .fold(0u64, |word, (k, &b)| word | (u64::from(b) << k))
            }));
            let sat = &mut self.kept_sat;
            sat.clear();
            sat.resize((w + 1) * (h + 1), 0);
            for (y, row) in kept.chunks_exact(w).enumerate() {
                let (below, here) = sat[y * (w + 1)..].split_at_mut(w + 1);
                let mut run = 0;
                for (x, &k) in row.iter().enumerate() {
                    run += u32::from(k);
                    here[x + 1] = below[x + 1] + run;
                }
            }
            self.lookup_valid = true;
        }
    }

    /// Makes `self` the scored mesh of the child that keeps `a`'s kept points where `from_b`
    /// is clear and `b`'s where it is set (`from_b` a bitset over the grid indices, bit `i` of
    /// word `i / 64`), reusing the parents' triangles and errors. The score is bit for bit the
    /// fresh evaluation's. Returns `None`, with `self` unscored, when `a` and `b` are not both
    /// scored on `hf` with their disc boxes filled ([`ensure_discs`](Self::ensure_discs)), or
    /// when a guard fails; the caller then scores the child another way.
    pub(super) fn compose(
        &mut self,
        hf: &Arc<Heightfield>,
        a: &MeshState,
        b: &MeshState,
        from_b: &[u64],
        scratch: &mut ComposeScratch,
    ) -> Option<super::Score> {
        self.compose_with(hf, a, b, Labels::Bits(from_b), scratch, None)
    }

    /// [`compose`](Self::compose) for the child that takes each part of `classes` from `b`
    /// where bit `part` of `levels` is set and from `a` elsewhere, with both parents'
    /// triangles classified once for all such children ([`PartClasses::new`]). The same mesh
    /// and bits as [`compose`](Self::compose) with the equivalent bitset. Returns `None`, with
    /// `self` unscored, also when `classes` was not made for `a` and `b`.
    #[allow(clippy::too_many_arguments)] // the parents, their classification, and two scratches
    pub(super) fn compose_parts(
        &mut self,
        hf: &Arc<Heightfield>,
        a: &MeshState,
        b: &MeshState,
        classes: &PartClasses,
        levels: u32,
        scratch: &mut ComposeScratch,
        memo: &mut TriangleMemo,
    ) -> Option<super::Score> {
        self.compose_with(
            hf,
            a,
            b,
            Labels::Parts(classes, levels),
            scratch,
            Some(memo),
        )
    }

    #[allow(clippy::needless_range_loop)] // slots and grid indices index several arrays at once
    fn compose_with(
        &mut self,
        hf: &Arc<Heightfield>,
        a: &MeshState,
        b: &MeshState,
        source: Labels<'_>,
        scratch: &mut ComposeScratch,
        memo: Option<&mut TriangleMemo>,
    ) -> Option<super::Score> {
        self.score = None;
        self.hf = None;
        self.revision = 0;
        let (w, h, n) = (hf.width(), hf.height(), hf.len());
        let labels_fit = match source {
            Labels::Bits(from_b) => from_b.len() >= n.div_ceil(64),
            Labels::Parts(classes, _) => classes.is_for(a, b) && classes.part.len() == n,
        };
        if !labels_fit || !composable(a, hf) || !composable(b, hf) {
            return None;
        }
        let parents = [a, b];
        // Per grid point its label (one byte: read per triangle vertex and per point below),
        // the child's kept marks, and for a bitset the labels' summed-area table (B labels in
        // columns < x of rows < y at (y, x)), in one pass.
        // Each entry is written once, in order: pushed, rather than zeroed first and then
        // overwritten (a second pass over ≈30 KB per composition).
        self.kept.clear();
        scratch.labels.clear();
        let sw = w + 1;
        scratch.sat.clear();
        let mut vertices = 0usize;
        match source {
            Labels::Bits(from_b) => {
                scratch.sat.resize(sw, 0);
                for y in 0..h {
                    let mut row = 0;
                    scratch.sat.push(0);
                    for x in 0..w {
                        let i = y * w + x;
                        let l = ((from_b[i / 64] >> (i % 64)) & 1) as u8;
                        scratch.labels.push(l);
                        let k = parents[l as usize].kept[i];
                        self.kept.push(k);
                        vertices += usize::from(k);
                        row += u32::from(l);
                        let below = scratch.sat[y * sw + x + 1];
                        scratch.sat.push(below + row);
                    }
                }
            }
            Labels::Parts(classes, levels) => {
                // Part by part, row by row: copies of the labelled parent's kept marks (the
                // parts' labels decide which triangles are taken, so no label per point).
                self.kept.resize(n, false);
                for (p, &[x0, y0, x1, y1]) in classes.rects.iter().enumerate() {
                    let l = (levels >> p) & 1;
                    let from = &parents[l as usize].kept;
                    for y in y0..y1 {
                        let row = y * w + x0..y * w + x1;
                        self.kept[row.clone()].copy_from_slice(&from[row]);
                    }
                }
                vertices = self.kept.iter().map(|&k| usize::from(k)).sum();
            }
        }
        // The child's triangle count, by Euler: a triangulation of the grid rectangle with V
        // vertices, B of them on its border, has 2V − B − 2 triangles. It sizes the child's
        // arrays, and guards the reasoning below (a leak or a gap would change the count).
        let on_border = (0..w)
            .flat_map(|x| [x, (h - 1) * w + x])
            .chain((1..h - 1).flat_map(|y| [y * w, y * w + w - 1]))
            .filter(|&i| self.kept[i])
            .count();
        let expected = (2 * vertices).checked_sub(on_border + 2)? as u32;
        let labels = &scratch.labels;
        let label = |i: u32| u64::from(labels[i as usize]);
        let child_kept = &self.kept;
        let kept_in_child = |i: u32| child_kept[i as usize];
        let lattice = Lattice::new(w);
        let sat = &scratch.sat;
        let labelled_b = |d: &DiscBox| counted_in(sat, w, d.rect()) as usize;

        // Which triangles of each parent the child keeps.
        let mut next_slot = 0u32;
        for side in 0..2 {
            let parent = parents[side];
            let m = &parent.mesh;
            let (map, taken) = (&mut scratch.map[side], &mut scratch.taken[side]);
            map.clear();
            map.resize(m.len(), NONE);
            taken.clear();
            if let Labels::Parts(classes, levels) = source {
                // The parts labelled for the other parent; a triangle is taken when the part
                // of its smallest vertex is labelled for this one and none of its kill parts
                // is labelled for the other (see `PartClasses`).
                // (A classification has one to 32 parts.)
                let all = u32::MAX >> (32 - classes.rects.len());
                let other = if side == 0 { levels } else { !levels } & all;
                let (first, kill) = (&classes.first[side], &classes.kill[side]);
                // Without branches: which triangles a row takes follows the blocks, which the
                // slot order does not.
                taken.resize(m.len(), 0);
                let mut count = 0usize;
                for (t, (&f, &k)) in first.iter().zip(kill).enumerate() {
                    let take = ((other >> f) & 1 == 0) & (k & other == 0);
                    map[t] = if take { next_slot + count as u32 } else { NONE };
                    taken[count] = t as u32;
                    count += usize::from(take);
                }
                taken.truncate(count);
                next_slot += count as u32;
                continue;
            }
            for t in 0..m.len() {
                let tri = m.triangle(t);
                let first = tri[0].min(tri[1]).min(tri[2]);
                if label(first) as usize != side || !tri.iter().all(|&v| kept_in_child(v)) {
                    continue;
                }
                let disc = &parent.discs[t];
                let b_points = labelled_b(disc);
                let other = if side == 0 {
                    b_points
                } else {
                    disc.area() - b_points
                };
                let keep = other == 0
                    || (disc.area() <= MAX_SEARCHED_BOX
                        && !spoils(tri, disc.rect(), lattice, w, |i| {
                            label(i as u32) != side as u64 && kept_in_child(i as u32)
                        }));
                if keep {
                    map[t] = next_slot;
                    next_slot += 1;
                    taken.push(t as u32);
                }
            }
        }
        if next_slot == 0 {
            // Nothing to reuse (say, a corners-only parent whose corner 0 is labelled B): the
            // child is built from scratch.
            let kept: Vec<u32> = (0..n as u32).filter(|&i| kept_in_child(i)).collect();
            let score = self.rebuild(hf, &kept);
            self.ensure_discs();
            return Some(score);
        }

        // The taken triangles, linked to each other where they meet, with their totals; the
        // half-edges with R across are listed, and each vertex's hint points at one of them.
        // The taken slots were numbered parent by parent in slot order, so each parent's taken
        // triangles fill a run of the child's arrays in order (a push per entry cost a third of
        // a composition); which kept points a taken triangle has is marked by a stamp, for R's
        // points below.
        let taken = next_slot as usize;
        self.hint.resize(n, 0);
        let stamp = next_stamp(&mut scratch.stamp, &mut scratch.covered, n);
        self.mesh.clear_for(w);
        let room = expected.max(next_slot) as usize;
        fit(&mut self.mesh.vertices, 3 * room);
        self.mesh.vertices.resize(3 * taken, 0);
        fit(&mut self.mesh.twin, 3 * room);
        self.mesh.twin.resize(3 * taken, NONE);
        fit(&mut self.discs, room);
        self.discs.resize(taken, DiscBox::default());
        fit(&mut self.totals, room);
        self.totals.resize(taken, ErrorTotals::default());
        scratch.open.clear();
        let hints = &mut self.hint;
        let covered = &mut scratch.covered;
        let mut first_slot = 0;
        for side in 0..2 {
            let (parent, other) = (parents[side], parents[1 - side]);
            let (map, other_map) = (&scratch.map[side], &scratch.map[1 - side]);
            let list = &scratch.taken[side];
            let range = first_slot..first_slot + list.len();
            let (from_vertices, from_twins) = (&parent.mesh.vertices, &parent.mesh.twin);
            let child_vertices =
                self.mesh.vertices[3 * range.start..3 * range.end].chunks_exact_mut(3);
            let child_twins = self.mesh.twin[3 * range.start..3 * range.end].chunks_exact_mut(3);
            let rows = list.iter().zip(child_vertices.zip(child_twins));
            for (slot, (&t, (vertices, twins))) in (range.start as u32..).zip(rows) {
                let src = 3 * t as usize;
                let tri = &from_vertices[src..src + 3];
                vertices.copy_from_slice(tri);
                for &v in tri {
                    hints[v as usize] = slot;
                    covered[v as usize] = stamp;
                }
                for (k, (twin, &g)) in twins.iter_mut().zip(&from_twins[src..src + 3]).enumerate() {
                    *twin = if g == NONE {
                        NONE
                    } else if map[(g / 3) as usize] != NONE {
                        3 * map[(g / 3) as usize] + g % 3
                    } else {
                        let (u, v) = (tri[k], tri[(k + 1) % 3]);
                        twin_in(other, other_map, v, u).unwrap_or_else(|| {
                            scratch.open.push((3 * slot + k as u32, u, v));
                            NONE
                        })
                    };
                }
            }
            for (dst, &t) in self.discs[range.clone()].iter_mut().zip(list) {
                *dst = parent.discs[t as usize];
            }
            for (dst, &t) in self.totals[range.clone()].iter_mut().zip(list) {
                *dst = parent.totals[t as usize];
            }
            first_slot = range.end;
        }
        debug_assert_eq!(self.totals.len(), taken);

        // R's points: the kept points no taken triangle has, and the ends of the half-edges
        // with R across.
        scratch.listed.resize(n, false);
        scratch.points.clear();
        for (i, (&k, &c)) in self.kept.iter().zip(covered.iter()).enumerate() {
            if k && c != stamp {
                scratch.listed[i] = true;
                scratch.points.push(i as u32);
            }
        }
        let (taken_len, open_len) = (next_slot, scratch.open.len());
        for j in 0..open_len {
            let (_, u, v) = scratch.open[j];
            for p in [u, v] {
                if !std::mem::replace(&mut scratch.listed[p as usize], true) {
                    scratch.points.push(p);
                }
            }
        }
        for &p in &scratch.points {
            scratch.listed[p as usize] = false;
        }
        if open_len == 0 {
            // Nothing is new: the parents' triangles tile the grid (or the guard fails).
            if taken_len != expected || !scratch.points.is_empty() {
                return None;
            }
        } else {
            // R's triangles, wrapped from its boundary (see `region`).
            let region = &mut scratch.region;
            region.wrap(w, h, &scratch.points, &scratch.open)?;
            let next_new = taken_len + region.triangles.len() as u32;
            if next_new != expected {
                debug_assert!(false, "composed {next_new} triangles, not {expected}");
                return None;
            }
            // R's triangles after the taken ones, in the order found, linked inside R and
            // across its boundary.
            for (t, tri) in region.triangles.iter().enumerate() {
                let slot = taken_len + t as u32;
                self.mesh.vertices.extend_from_slice(tri);
                for k in 0..3 {
                    let twin = region.twins[3 * t + k];
                    let twin = if twin == NONE {
                        NONE
                    } else if twin & BOUNDARY != 0 {
                        let outer = scratch.open[(twin & !BOUNDARY) as usize].0;
                        self.mesh.twin[outer as usize] = 3 * slot + k as u32;
                        outer
                    } else {
                        3 * taken_len + twin
                    };
                    self.mesh.twin.push(twin);
                }
                let p = tri.map(|i| lattice.point(i));
                self.discs.push(DiscBox::of(p, w, h));
            }
            self.totals
                .resize(next_new as usize, ErrorTotals::default());
            match memo {
                Some(memo) => {
                    self.rasterise_with_memo(hf, taken_len..next_new, memo, &mut scratch.unknown)
                }
                None => self.rasterise(hf, taken_len..next_new),
            }
        }
        self.hf = Some(hf.clone());
        let score = self.finish(hf);
        self.discs_valid = true;
        Some(score)
    }
}

/// The child's half-edge `from → to` when it is an edge of a triangle taken from `parent`
/// (`map` its taken slots).
fn twin_in(parent: &MeshState, map: &[u32], from: u32, to: u32) -> Option<u32> {
    if !parent.kept[from as usize] || !parent.kept[to as usize] {
        return None;
    }
    let t = parent.hint[from as usize];
    let m = &parent.mesh;
    let e = edge_from(m, m.leaving(t, from)?, to)?;
    let slot = map[(e / 3) as usize];
    (slot != NONE).then(|| 3 * slot + e % 3)
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
