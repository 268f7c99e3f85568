//! What a crossover's children share and the functions both ways of scoring them use: the
//! classes of parent triangles, level sets, the prepared data and per-child scratch.

use crate::evaluator::compose::PartClasses;
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
use crate::evaluator::exact::predicates::Lattice;
use crate::evaluator::mesh::canonical_form::canonical;
use crate::evaluator::mesh::canonical_triangulation::{NONE, Triangulation, edge_from};
use crate::evaluator::mesh::region::Region;
use crate::evaluator::mesh::state::MeshState;
use crate::evaluator::raster::grid_of;
use crate::evaluator::raster::triangle_memo::TriangleMemo;
use crate::evaluator::score::Score;
use crate::heightfield::Heightfield;

/// Changes to a crossover child's kept points: `removed` ones it keeps (not grid corners) and
/// `inserted` ones it does not keep, each listed once.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Changes<'a> {
    /// Points the child keeps that the mutant does not.
    pub removed: &'a [u32],
    /// Points the mutant keeps that the child does not.
    pub inserted: &'a [u32],
}

/// Scratch of [`PartScores::change`], kept between calls.
#[derive(Clone, Debug, Default)]
pub(crate) struct ChangeScratch {
    /// The reused triangles the changes drop: (parent, slot).
    pub(super) dropped: Vec<(usize, u32)>,
    /// The triangles of a cavity search, seen so far, and those still to visit.
    pub(super) seen: Vec<u32>,
    pub(super) queue: Vec<u32>,
    /// Per dropped class: whether a dropped triangle may hold its largest error.
    pub(super) classes: Vec<u32>,
}

/// A class of parent triangles (see the module docs) and the totals of its triangles.
#[derive(Clone, Copy, Debug)]
pub(super) struct Class {
    pub(super) side: u8,
    /// The part of the triangles' smallest vertex.
    pub(super) home: u8,
    /// The kill mask, without the home part's bit (which never matters: a triangle is reused
    /// only where its home part is labelled for its own parent).
    pub(super) kill: u32,
    pub(super) totals: ErrorTotals,
    pub(super) count: u32,
}

impl Class {
    /// The children that reuse this class (with at most [`LEVEL_SET_PARTS`] parts): those that
    /// label its home part and all its kill parts for its own parent.
    pub(super) fn levels(&self) -> LevelSet {
        let side = usize::from(self.side);
        let mut set = LABELLED[usize::from(self.home)][side];
        let mut kill = self.kill;
        while kill != 0 {
            set = set.and(LABELLED[kill.trailing_zeros() as usize][side]);
            kill &= kill - 1;
        }
        set
    }
}

/// A half-edge between triangles of two different classes of one parent.
#[derive(Clone, Copy, Debug)]
pub(super) struct Candidate {
    pub(super) side: u8,
    /// The half-edge, u → v.
    pub(super) edge: u32,
    /// The classes of its triangle and of the triangle across (of the same parent).
    pub(super) class: u32,
    pub(super) twin_class: u32,
    /// The other parent's half-edge v → u: [`NONE`] when it has none, [`UNKNOWN`] until looked
    /// up (on the first child that needs it).
    pub(super) cross: u32,
    /// The class of `cross`'s triangle, once looked up.
    pub(super) cross_class: u32,
}

/// [`Candidate::cross`] not looked up yet.
pub(super) const UNKNOWN: u32 = u32::MAX - 1;

/// Most parts for which [`PartScores`] reads each child off [`LevelSet`]s: 7, the factors of
/// an L8 array (OAX's default).
pub(super) const LEVEL_SET_PARTS: usize = 7;

/// Slots of [`PartScores::special_index`]: a side, a home part and a kill mask of at most
/// [`LEVEL_SET_PARTS`] parts.
pub(super) const SPECIAL_SLOTS: usize = 2 << (3 + LEVEL_SET_PARTS);

/// The [`PartScores::special_index`] slot of a special class (at most [`LEVEL_SET_PARTS`]
/// parts: the home part in 3 bits, the kill mask in 7).
pub(super) fn special_slot(side: usize, home: u8, kill: u32) -> usize {
    (side << (3 + LEVEL_SET_PARTS)) | (usize::from(home) << LEVEL_SET_PARTS) | kill as usize
}

/// Per part, per parent: the children that label the part for that parent.
pub(super) const LABELLED: [[LevelSet; 2]; LEVEL_SET_PARTS] = {
    let mut table = [[LevelSet([0; 2]); 2]; LEVEL_SET_PARTS];
    let mut l = 0;
    while l < 1 << LEVEL_SET_PARTS {
        let mut p = 0;
        while p < LEVEL_SET_PARTS {
            table[p][(l >> p) & 1].0[l >> 6] |= 1 << (l & 63);
            p += 1;
        }
        l += 1;
    }
    table
};

/// A set of a crossover's children with at most [`LEVEL_SET_PARTS`] parts: bit `l` for the
/// child with levels `l`. Why: a child's R is the points and edges of which each obeys a rule
/// over the parts' labels (a class is reused when some parts are labelled one way); testing a
/// bit per point and edge replaces, per child, a pass over the triangles near the blocks' edges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct LevelSet(pub(super) [u64; 2]);

impl LevelSet {
    pub(super) fn has(self, levels: u32) -> bool {
        (self.0[(levels >> 6) as usize] >> (levels & 63)) & 1 != 0
    }

    pub(super) fn and(self, other: Self) -> Self {
        Self([self.0[0] & other.0[0], self.0[1] & other.0[1]])
    }

    pub(super) fn or(self, other: Self) -> Self {
        Self([self.0[0] | other.0[0], self.0[1] | other.0[1]])
    }

    pub(super) fn and_not(self, other: Self) -> Self {
        Self([self.0[0] & !other.0[0], self.0[1] & !other.0[1]])
    }

    pub(super) fn is_empty(self) -> bool {
        self.0 == [0; 2]
    }
}

/// What the children of one crossover share, for scoring them without their meshes (see the
/// module docs). Made by [`prepare`](Self::prepare) from a [`PartClasses`] and its parents.
#[derive(Clone, Debug, Default)]
pub struct PartScores {
    /// The classification it was made from ([`PartClasses`]' id; 0 when not made).
    pub(super) made_from: u64,
    pub(super) units: ErrorUnits,
    pub(super) classes: Vec<Class>,
    /// The candidate edges (without level sets).
    pub(super) candidates: Vec<Candidate>,
    /// Per parent: its kept points that are variable (see the module docs).
    pub(super) variable: [Vec<u32>; 2],
    /// Per parent: its triangles with a vertex variable in either parent, with their classes
    /// (without level sets).
    pub(super) coverage: [Vec<(u32, u32)>; 2],
    /// Per parent, per triangle slot near a block's edge with a kill mask: its class.
    pub(super) special: [Vec<u32>; 2],
    /// Per parent, per part: (kept points, kept points on the grid border).
    pub(super) counts: [Vec<(u32, u32)>; 2],
    /// With at most [`LEVEL_SET_PARTS`] parts, what each child does is read off sets of
    /// children ([`LevelSet`]), made once here: per class, the children that reuse it...
    pub(super) class_levels: Vec<LevelSet>,
    /// ...per variable point (a point variable in both parents twice), the children in whose
    /// R it lies...
    pub(super) r_points: Vec<(u32, LevelSet)>,
    /// ...and per candidate edge u → v, the children on whose R boundary it lies (only edges
    /// on some child's). Empty with more parts, which `candidates` and `coverage` serve.
    pub(super) r_edges: Vec<(u32, u32, LevelSet)>,
    /// Scratch of `prepare`: per grid point, the children that reuse a triangle with it (for
    /// the variable points only; the other entries are stale).
    pub(super) reused_by: Vec<LevelSet>,
    /// Scratch of `prepare`: the points variable in parent A, in B, and in either, as bitsets
    /// (bit `i` of word `i / 64`; 66 words on a 65×65 grid, which the pass over every triangle
    /// reads at random).
    pub(super) is_variable: [Vec<u64>; 2],
    pub(super) either: Vec<u64>,
    /// Scratch of `prepare`, with at most [`LEVEL_SET_PARTS`] parts: per (side, home part,
    /// kill mask), its class among the special ones, or [`NONE`] (reset after use).
    pub(super) special_index: Vec<u32>,
    /// Scratch of `prepare`: the edges (3t + k) of one parent's triangles with a variable
    /// vertex that some child reuses on one side only, with those children.
    pub(super) staged: Vec<(u32, LevelSet)>,
    /// Scratch of `prepare`: one parent's triangles with a variable vertex.
    pub(super) covering: Vec<u32>,
    /// Scratch of `prepare`: the candidate edges (parent, u, v, children) that the other parent
    /// may have too (it keeps both ends), with level sets.
    pub(super) crossing: Vec<(u8, u32, u32, LevelSet)>,
}

/// Per-child scratch of [`PartScores::score`], kept by the evaluator between calls.
#[derive(Clone, Debug, Default)]
pub(crate) struct RowScratch {
    /// Per class: is it reused by the child?
    pub(super) taken: Vec<bool>,
    /// Per grid point: the stamp of the last child one of whose reused triangles has it.
    pub(super) covered: Vec<u32>,
    pub(super) stamp: u32,
    /// Per grid point: listed in `points`.
    pub(super) listed: Vec<bool>,
    /// R's points and the grid corners.
    pub(super) points: Vec<u32>,
    /// R's boundary edges (0, u, v): R lies left of v → u.
    pub(super) open: Vec<(u32, u32, u32)>,
    pub(super) region: Region,
    /// R's triangles whose totals the memo does not know.
    pub(super) unknown: Vec<((), [u32; 3])>,
    /// The totals of the latest R triangles, of rows and compositions (see
    /// [`TriangleMemo`]).
    pub(crate) memo: TriangleMemo,
    /// A child built from scratch (when it reuses nothing).
    pub(super) sub: Triangulation,
    /// Scratch of [`PartScores::change`].
    pub(super) changes: ChangeScratch,
}

/// The class (in [`PartScores::classes`]) of triangle `t` of parent `side`: its part's plain one
/// when its kill mask is empty, else the one `prepare` found for it (`special`).
/// Both are read and one is selected without a branch (whether a triangle near a block's edge
/// has a kill mask follows no pattern; `prepare` makes `special` as long as the parent).
#[inline]
pub(super) fn class_of(
    classes: &PartClasses,
    special: &[Vec<u32>; 2],
    side: usize,
    t: usize,
) -> u32 {
    let plain = (side * classes.rects.len() + classes.first[side][t] as usize) as u32;
    let found = special[side][t];
    let is_special = 0u32.wrapping_sub(u32::from(classes.kill[side][t] != 0));
    (plain & !is_special) | (found & is_special)
}

/// Bit `i` of the bitset `bits` (bit `i` of word `i / 64`), as 0 or 1.
pub(super) fn bit_of(bits: &[u64], i: u32) -> usize {
    ((bits[(i / 64) as usize] >> (i % 64)) & 1) as usize
}

/// The half-edge `v → u` of `parent`, or [`NONE`] when it has no such edge.
pub(super) fn cross_twin(parent: &MeshState, u: u32, v: u32) -> u32 {
    if !parent.kept[u as usize] || !parent.kept[v as usize] {
        return NONE;
    }
    let m = &parent.mesh;
    m.leaving(parent.hint[v as usize], v)
        .and_then(|e| edge_from(m, e, u))
        .unwrap_or(NONE)
}

/// The score of the canonical triangulation of `points` (increasing, the grid's corners
/// included) on `hf`, built from scratch into `sub`.
pub(super) fn score_from_scratch(
    hf: &Heightfield,
    units: ErrorUnits,
    points: &[u32],
    sub: &mut Triangulation,
) -> Score {
    let lattice = Lattice::new(hf.width());
    sub.rebuild_delaunay(hf.width(), points);
    let mut totals = ErrorTotals::default();
    let tris = (0..sub.len()).map(|t| ((), canonical(sub.triangle(t)).map(|i| lattice.point(i))));
    grid_of(hf).sum_triangles(units, tris, |_, t| totals.add(&t));
    score_of(units, &totals, sub.len() as u32, hf.len())
}

/// Is grid point `p` of `hf` on the grid's border (B of Euler's count 2V − B − 2)?
pub(super) fn on_grid_border(hf: &Heightfield, p: u32) -> bool {
    let (w, h) = (hf.width(), hf.height());
    let (x, y) = ((p as usize) % w, (p as usize) / w);
    x == 0 || y == 0 || x == w - 1 || y == h - 1
}

pub(super) fn score_of(units: ErrorUnits, totals: &ErrorTotals, t: u32, n: usize) -> Score {
    let (sum, sum_sq, max) = units.values(totals);
    Score {
        e_sum: sum,
        e_max: max,
        rms: (sum_sq / n as f64).sqrt(),
        t: t as usize,
    }
}
