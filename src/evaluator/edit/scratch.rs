//! The buffers an edit reuses between calls, and when a removal goes region by region.

use crate::evaluator::mesh::canonical_triangulation::Triangulation;

/// Scratch buffers of an edit, kept by the evaluator between calls.
#[derive(Clone, Debug, Default)]
pub(crate) struct EditScratch {
    pub(super) stack: Vec<u32>,
    /// Slots written by this edit (repeats allowed).
    pub(super) touched: Vec<u32>,
    /// Slots emptied by removals, to be filled by compaction.
    pub(super) dead: Vec<u32>,
    pub(super) dirty: Vec<bool>,
    /// The dirty slots, increasing.
    pub(super) dirty_slots: Vec<u32>,
    pub(super) boundary: Vec<u32>,
    pub(super) outer: Vec<u32>,
    pub(super) star: Vec<u32>,
    pub(super) fill: Vec<[u32; 3]>,
    /// Diagonals of a hole's fill seen from one side: (from, to) boundary positions, half-edge.
    pub(super) diagonals: Vec<(usize, usize, u32)>,
    /// [`MeshState::remove_region`]: per slot, is it in a removed vertex's star?
    pub(super) in_region: Vec<bool>,
    /// The slots of the region, in the order found.
    pub(super) region: Vec<u32>,
    /// Per grid point: is it already among `region_points`?
    pub(super) listed: Vec<bool>,
    /// The kept points of the region's closure, plus the grid corners.
    pub(super) region_points: Vec<u32>,
    /// Their canonical triangulation.
    pub(super) sub: Triangulation,
    /// Per grid point, a half-edge of `sub` leaving it.
    pub(super) leaving: Vec<u32>,
    /// Per half-edge of `sub`: the mesh's half-edge across the region's boundary, or
    /// [`INSIDE`] for an edge that is not on it.
    pub(super) across: Vec<u32>,
    /// Per triangle of `sub`: its slot in the mesh once taken, or `NONE`.
    pub(super) taken: Vec<u32>,
    /// The triangles of `sub` inside the region.
    pub(super) inside: Vec<u32>,
}

/// [`EditScratch::across`] of a half-edge that is not on the region's boundary.
pub(super) const INSIDE: u32 = u32::MAX - 1;

/// An edit removes its points region by region (`MeshState::remove_region`) when it removes
/// at least this many.
pub(super) const REGION_MIN_REMOVALS: usize = 16;

/// ... and when the region's remaining kept points number at most this many per removed point.
/// Why: a region pays per removal (stars, flood, relinking) and per point it triangulates again,
/// so it beats removing the points one hole at a time only while it holds few points per removal.
pub(super) const REGION_POINTS_PER_REMOVAL: usize = 1;
