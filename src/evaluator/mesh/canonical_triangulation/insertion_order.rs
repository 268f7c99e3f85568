//! The order in which a point set is inserted.

use crate::evaluator::exact::predicates::Lattice;

/// The order in which [`Triangulation::insert_all`] inserts a point set: groups of points, each
/// inserted in turn, alternately forwards and backwards.
///
/// In three rounds of rows (every fourth row, then the rows halfway between, then the rest).
/// Why: one sweep up the grid keeps inserting points just above a front whose triangles fan
/// out to the box's top corners, and each insertion then flips much of that fan; the rounds
/// fill in between rows already there, so each point takes fewer flips and in-circle tests
/// (for slightly longer walks).
///
/// Within a round, a dense set goes row by row (a group per row). A sparse one goes by bands of
/// `c` rows (`c` a power of two, chosen so that a `c`×`c` cell holds about four points) and
/// within a band cell by cell (a group per band), so the next point is about one cell away
/// rather than a whole row's gap: at 2 % kept a row's points are ≈ 50 columns apart, and the
/// walk between them crosses many thin triangles; bands halve the walk steps there. Denser
/// sets gain nothing from bands, so sets denser than about one point per 8×8 cell (c < 8,
/// about 12 % kept) keep the rows. The bands come from a counting sort, stable, so a cell's
/// points stay in row order.
#[derive(Clone, Debug, Default)]
pub(crate) struct InsertionOrder {
    /// The points in insertion order (unused when the groups index `kept` itself).
    points: Vec<u32>,
    /// Each group as a range of the points.
    groups: Vec<(u32, u32)>,
    /// Row-by-row scratch: each row as a range of `kept` and its round.
    rows: Vec<(u32, u32, u8)>,
    /// Counting-sort scratch: a count, then an offset, per key.
    counts: Vec<u32>,
    /// Counting-sort scratch: each point's key.
    keys: Vec<u32>,
}

impl InsertionOrder {
    /// Cells hold about this many points (see the type's docs).
    const POINTS_PER_CELL: f64 = 4.0;
    /// Bands of fewer rows than this (denser sets) go row by row.
    const MIN_BAND: u32 = 3;

    /// The round of row `y`.
    #[inline]
    pub(super) fn round_of(y: i64) -> usize {
        match y & 3 {
            0 => 0,
            2 => 1,
            _ => 2,
        }
    }

    /// Plans the insertion of `kept` (increasing grid indices, repeats allowed), whose bounding
    /// box is `[x0, y0, x1, y1]`: the sequence of points and the ranges of its groups, in
    /// insertion order.
    pub(crate) fn plan<'a>(
        &'a mut self,
        lattice: Lattice,
        kept: &'a [u32],
        [x0, y0, x1, y1]: [i64; 4],
    ) -> (&'a [u32], &'a [(u32, u32)]) {
        self.groups.clear();
        let area = ((x1 - x0 + 1) * (y1 - y0 + 1)) as f64;
        let cell = (Self::POINTS_PER_CELL * area / kept.len().max(1) as f64).sqrt();
        let band = cell.max(1.0).log2().round() as u32;
        if band < Self::MIN_BAND {
            // Row by row: the rows are runs of one y in `kept`.
            self.rows.clear();
            let mut start = 0;
            while start < kept.len() {
                let y = lattice.point(kept[start])[1];
                let mut end = start + 1;
                while end < kept.len() && lattice.point(kept[end])[1] == y {
                    end += 1;
                }
                self.rows
                    .push((start as u32, end as u32, Self::round_of(y) as u8));
                start = end;
            }
            for round in 0..3 {
                let rows = self.rows.iter().filter(|r| r.2 == round);
                self.groups
                    .extend(rows.map(|&(start, end, _)| (start, end)));
            }
            return (kept, &self.groups);
        }
        // By bands and cells: key = (round, band, cell column), sorted by counting.
        let band = band.min(30);
        let columns = ((x1 - x0) >> band) as usize + 1;
        let bands = ((y1 - y0) >> band) as usize + 1;
        let keys = 3 * bands * columns;
        self.counts.clear();
        self.counts.resize(keys + 1, 0);
        self.keys.clear();
        for &p in kept {
            let [x, y] = lattice.point(p);
            let key = (Self::round_of(y) * bands + ((y - y0) >> band) as usize) * columns
                + ((x - x0) >> band) as usize;
            self.keys.push(key as u32);
            self.counts[key + 1] += 1;
        }
        for k in 1..=keys {
            self.counts[k] += self.counts[k - 1];
        }
        self.points.clear();
        self.points.resize(kept.len(), 0);
        for (&p, &key) in kept.iter().zip(&self.keys) {
            let slot = &mut self.counts[key as usize];
            self.points[*slot as usize] = p;
            *slot += 1;
        }
        // Now `counts[k]` is where key k's points end; a group is one (round, band).
        let mut begin = 0;
        for g in 0..3 * bands {
            let end = self.counts[(g + 1) * columns - 1];
            if end > begin {
                self.groups.push((begin, end));
            }
            begin = end;
        }
        (&self.points, &self.groups)
    }
}
