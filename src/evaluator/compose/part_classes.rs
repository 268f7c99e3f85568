//! Both parents' triangles classified once for all the children of one crossover.

use super::spoiling::{
    Circumcircle, MAX_SEARCHED_BOX, contains_all, is_empty, overlap, spoils_bits,
};
use crate::evaluator::exact::fixed_point::ErrorTotals;
use crate::evaluator::exact::predicates::Lattice;
use crate::evaluator::mesh::state::{MeshState, next_revision};
use crate::heightfield::Heightfield;
use std::sync::Arc;

/// Both parents' triangles classified once against a partition of the grid into rectangles
/// (an orthogonal-array crossover's blocks), for all the children that take each rectangle
/// whole from one parent ([`Evaluator::compose_parts`](crate::evaluator::Evaluator::compose_parts)).
///
/// Why it is exact: a child labels each part for A or B. A triangle of parent P (the other
/// parent Q) is taken by [`compose`](crate::evaluator::Evaluator::compose) exactly when its smallest
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
    pub(crate) rects: Vec<[usize; 4]>,
    /// The part of every grid point.
    pub(crate) part: Vec<u8>,
    /// Per parent, per triangle slot: the part of its smallest vertex.
    pub(crate) first: [Vec<u8>; 2],
    /// Per parent, per triangle slot: its kill mask (bit `p` for part `p`; never its own part's,
    /// which cannot matter: a triangle is taken only where that part is labelled for its parent).
    pub(crate) kill: [Vec<u32>; 2],
    /// The parents' [`MeshState`] revisions, to refuse other meshes.
    pub(crate) made_from: [u64; 2],
    /// A number no other classification had (0 until made), so that what is derived from this
    /// one ([`PartScores`](crate::evaluator::PartScores)) can tell it from a later one of the same parents.
    pub(crate) id: u64,
    /// Per parent: the slots of its triangles whose disc box leaves their own part (the others'
    /// kill masks are empty).
    near: [Vec<u32>; 2],
    /// Per parent: how many of `near` are its (the rest is stale; see [`near`](Self::near)).
    near_len: [usize; 2],
    /// Per parent, per part: the error totals and number of its triangles whose smallest
    /// vertex is in the part and whose kill mask is empty.
    pub(crate) plain: [Vec<(ErrorTotals, u32)>; 2],
    /// Per axis (columns, rows), per line: the masks of the non-empty parts that start at or
    /// before it, and of those that end after it.
    reach: [[Vec<u32>; 2]; 2],
    /// Scratch of [`reset`](Self::reset): the points the other parent keeps and this one does
    /// not, as a bitset.
    only_other: Vec<u64>,
}

impl PartClasses {
    /// Most parts a classification holds (bits of a mask).
    pub(crate) const MAX_PARTS: usize = 32;

    /// Classifies the triangles of `a` and `b` (scored on `hf`, disc boxes filled) against the
    /// rectangles `parts` (`[x0, y0, x1, y1]`, half-open; empty ones allowed), which must tile the
    /// grid. `None` when they do not, when there are more than `MAX_PARTS`,
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
        let (w, h) = (hf.width(), hf.height());
        if parts.len() > Self::MAX_PARTS
            || !a.is_composable_on(hf)
            || !b.is_composable_on(hf)
            || !a.lookup_valid
            || !b.lookup_valid
        {
            return false;
        }
        if !self.assign_parts(parts, w, h) {
            return false;
        }
        self.index_reach(parts, w, h);
        let parents = [a, b];
        for side in 0..2 {
            let (parent, other) = (parents[side], parents[1 - side]);
            self.classify_own_parts(side, parent, parts);
            self.find_kill_masks(side, parent, other, parts, w);
        }
        self.made_from = [a.revision, b.revision];
        self.id = next_revision();
        true
    }

    /// Sets the part of every point and the rectangles; false unless the rectangles cover each
    /// point of the `w` × `h` grid exactly once.
    fn assign_parts(&mut self, parts: &[[usize; 4]], w: usize, h: usize) -> bool {
        let n = w * h;
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
        true
    }

    /// Which parts a disc box meets, from its four sides: a rectangle meets the box iff both
    /// its column range and its row range meet the box's. Per column x, the (non-empty) parts
    /// whose columns start at or before x, and those whose columns end after x; the same per
    /// row.
    fn index_reach(&mut self, parts: &[[usize; 4]], w: usize, h: usize) {
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
    }

    /// Gives every triangle of parent `side` its own part (that of its smallest vertex), lists
    /// those whose disc box leaves that part as near, and sums the others' totals per part: a
    /// triangle whose box stays in its own part has all its vertices there too, so no part but
    /// its own can drop it (its kill mask is empty).
    fn classify_own_parts(&mut self, side: usize, parent: &MeshState, parts: &[[usize; 4]]) {
        let m = &parent.mesh;
        let (first, kill) = (&mut self.first[side], &mut self.kill[side]);
        // Every slot is written below: only a longer parent needs more room (a clear first
        // would fill the whole length again, per parent per crossover).
        first.resize(m.len(), 0);
        kill.clear();
        kill.resize(m.len(), 0);
        // Without branches: which triangles are near a block's edge follows the blocks, not
        // the slot order, so a branch on it would mispredict often.
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
    }

    /// The kill masks of parent `side`'s near triangles (the parts whose labelling for `other`
    /// would drop each), and the totals of those with none added to their part's plain sums.
    fn find_kill_masks(
        &mut self,
        side: usize,
        parent: &MeshState,
        other: &MeshState,
        parts: &[[usize; 4]],
        w: usize,
    ) {
        // The points that may spoil a circle: those the other parent keeps and this one does
        // not. A point both keep cannot: the triangle is Delaunay among this parent's points,
        // so none of them is inside its circle under the tie rule. As a bitset, which stays in
        // cache, where the other parent's summed-area table would be read at random per
        // circle. Why not all the other parent's points: parents of a converging population
        // keep mostly the same ones, and each of those would cost an exact test per circle.
        self.only_other.clear();
        self.only_other.extend(
            (other.kept_bits.iter())
                .zip(&parent.kept_bits)
                .map(|(o, p)| o & !p),
        );
        let bits = &self.only_other;
        let [[starts_x, ends_x], [starts_y, ends_y]] = &self.reach;
        let lattice = Lattice::new(w);
        let m = &parent.mesh;
        let (first, kill) = (&self.first[side], &mut self.kill[side]);
        let part = &self.part[..];
        let plain = &mut self.plain[side];
        let kept = &other.kept[..];
        for &t in &self.near[side][..self.near_len[side]] {
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
                    if circle.reaches(both) && spoils_bits(tri, both, &circle, lattice, w, bits) {
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

    /// The slots of parent `side`'s triangles whose disc box leaves their own part (the others'
    /// kill masks are empty).
    pub(crate) fn near(&self, side: usize) -> &[u32] {
        &self.near[side][..self.near_len[side]]
    }

    /// A number no other classification had (0 until made); a copy keeps it.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// Was this classification made for parents `a` and `b`, as they are now?
    pub(crate) fn is_for(&self, a: &MeshState, b: &MeshState) -> bool {
        self.made_from == [a.revision, b.revision] && a.revision != 0
    }
}
