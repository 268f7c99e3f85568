//! How a grid is cut into tiles that share their border rows and columns.

use super::TilingError;
use crate::heightfield::Heightfield;
use serde::{Deserialize, Serialize};

/// The default tile size in grid points per side (see [`TilePlan::new`]).
///
/// 1025 = 2¹⁰ + 1 points: a tile of that size is one the untiled method already handles well
/// (about a minute for the memetic method on one core, well under a gigabyte), so a grid up to
/// 1025×1025 keeps its untiled front, while a 2048² grid gives 4 tiles (2 per core on this
/// machine's two) and a 3601² one 16, enough for every core to stay busy to the end.
pub const DEFAULT_TILE: usize = 1025;

/// The smallest tile size [`TilePlan::new`] accepts. A tile needs room inside its fixed border
/// for the optimizer to choose anything: below 33 points a side the borders and corners are
/// most of the tile, and the number of tiles (each with its own run) explodes.
pub(crate) const MIN_TILE: usize = 33;

/// One tile: a rectangle of grid points. Neighbouring tiles share the row or column on their
/// common side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tile {
    /// Position in [`TilePlan::tiles`], row by row.
    pub index: usize,
    /// Column of the tile's first grid point in the whole grid.
    pub x0: usize,
    /// Row of the tile's first grid point in the whole grid.
    pub y0: usize,
    /// Columns (points per row), at least 2.
    pub w: usize,
    /// Rows, at least 2.
    pub h: usize,
}

impl Tile {
    /// The whole-grid index of the tile's grid point `local` (a tile-local index y·w + x).
    pub fn to_grid(&self, local: u32, grid_width: usize) -> u32 {
        let (x, y) = (local as usize % self.w, local as usize / self.w);
        ((self.y0 + y) * grid_width + self.x0 + x) as u32
    }
}

/// A W×H grid cut into tiles of at most `tile` points a side that share their border rows and
/// columns, as evenly as possible.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct TilePlan {
    width: usize,
    height: usize,
    tile: usize,
    /// Column starts of the tile columns, then W − 1 (so tile column c spans
    /// `xs[c] ..= xs[c + 1]`).
    xs: Vec<usize>,
    /// The same for rows.
    ys: Vec<usize>,
}

/// Cuts `0 ..= n − 1` into the fewest spans of at most `tile` points that share their ends, as
/// evenly as possible (spans differ by at most one cell).
fn cuts(n: usize, tile: usize) -> Vec<usize> {
    let cells = n - 1;
    let per = tile - 1;
    let count = cells.div_ceil(per).max(1);
    let (base, extra) = (cells / count, cells % count);
    let mut at = vec![0];
    for k in 0..count {
        let next = at[k] + base + usize::from(k < extra);
        at.push(next);
    }
    at
}

/// Checks a tile size on its own, before a grid is read: under `MIN_TILE` is refused.
pub fn check_tile(tile: usize) -> Result<(), TilingError> {
    if tile < MIN_TILE {
        return Err(TilingError::TileTooSmall {
            tile,
            min: MIN_TILE,
        });
    }
    Ok(())
}

impl TilePlan {
    /// The plan of a `width`×`height` grid in tiles of at most `tile` points a side (the grid
    /// itself when it fits in one tile). Fails before any work on a tile under `MIN_TILE`
    /// or a grid under 2×2.
    ///
    /// ```
    /// use paretomesh::tiling::{TilePlan, TilingError};
    /// let plan = TilePlan::new(100, 60, 50).unwrap();
    /// let tiles = plan.tiles();
    /// assert_eq!(tiles.len(), 3 * 2);
    /// // Neighbours share a column: the first tile ends where the second starts.
    /// assert_eq!(tiles[0].x0 + tiles[0].w - 1, tiles[1].x0);
    /// assert!(matches!(
    ///     TilePlan::new(100, 60, 8),
    ///     Err(TilingError::TileTooSmall { tile: 8, .. })
    /// ));
    /// ```
    pub fn new(width: usize, height: usize, tile: usize) -> Result<TilePlan, TilingError> {
        if tile < MIN_TILE {
            return Err(TilingError::TileTooSmall {
                tile,
                min: MIN_TILE,
            });
        }
        if width < 2 || height < 2 {
            return Err(TilingError::GridTooSmall { width, height });
        }
        Ok(TilePlan {
            width,
            height,
            tile,
            xs: cuts(width, tile),
            ys: cuts(height, tile),
        })
    }

    /// The plan with the [`DEFAULT_TILE`] size.
    pub fn with_default_tile(width: usize, height: usize) -> Result<TilePlan, TilingError> {
        Self::new(width, height, DEFAULT_TILE)
    }

    /// W of the whole grid.
    pub(crate) fn width(&self) -> usize {
        self.width
    }

    /// H of the whole grid.
    pub(crate) fn height(&self) -> usize {
        self.height
    }

    /// The largest tile side asked for.
    pub fn tile_size(&self) -> usize {
        self.tile
    }

    /// Tile columns.
    pub fn columns(&self) -> usize {
        self.xs.len() - 1
    }

    /// Tile rows.
    pub fn rows(&self) -> usize {
        self.ys.len() - 1
    }

    /// Number of tiles.
    pub fn len(&self) -> usize {
        self.columns() * self.rows()
    }

    /// Never true: a plan has at least one tile.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// True when the whole grid is one tile (an untiled run).
    pub fn is_single(&self) -> bool {
        self.len() == 1
    }

    /// Tile `index` (row by row), if there is one.
    pub(crate) fn tile(&self, index: usize) -> Option<Tile> {
        let (c, r) = (index % self.columns(), index / self.columns());
        (r < self.rows()).then(|| Tile {
            index,
            x0: self.xs[c],
            y0: self.ys[r],
            w: self.xs[c + 1] - self.xs[c] + 1,
            h: self.ys[r + 1] - self.ys[r] + 1,
        })
    }

    /// Every tile, row by row.
    pub fn tiles(&self) -> Vec<Tile> {
        (0..self.len()).filter_map(|i| self.tile(i)).collect()
    }

    /// True when tile `index` shares its left column with another tile.
    pub(crate) fn has_left_neighbour(&self, index: usize) -> bool {
        !index.is_multiple_of(self.columns())
    }

    /// True when tile `index` shares its top row with another tile.
    pub(crate) fn has_top_neighbour(&self, index: usize) -> bool {
        index / self.columns() > 0
    }

    /// Checks that `hf` is the grid this plan cuts.
    pub(crate) fn check_grid(&self, hf: &Heightfield) -> Result<(), TilingError> {
        self.check_size((hf.width(), hf.height()))
    }

    /// Checks that a grid of `(W, H)` is the grid this plan cuts.
    pub(crate) fn check_size(&self, grid: (usize, usize)) -> Result<(), TilingError> {
        if grid != (self.width, self.height) {
            return Err(TilingError::GridMismatch {
                plan: (self.width, self.height),
                grid,
            });
        }
        Ok(())
    }

    /// Tile `index`'s own height field, cut out of the whole grid `hf`, with the whole grid's
    /// spacing and its origin moved to the tile's first point.
    pub fn cut(&self, hf: &Heightfield, index: usize) -> Result<Heightfield, TilingError> {
        self.check_grid(hf)?;
        let t = self.tile(index).ok_or(TilingError::NoSuchTile {
            index,
            tiles: self.len(),
        })?;
        let mut z = Vec::with_capacity(t.w * t.h);
        for y in t.y0..t.y0 + t.h {
            let row = y * self.width + t.x0;
            z.extend_from_slice(&hf.z()[row..row + t.w]);
        }
        self.tile_grid(t, z, hf.origin(), hf.spacing(), hf.source())
    }

    /// The height field of tile `t` with heights `z`, of a whole grid with `origin`, `spacing`
    /// and `source` note: what [`TilePlan::cut`] makes, wherever `z` came from.
    pub(crate) fn tile_grid(
        &self,
        t: Tile,
        z: Vec<f64>,
        [ox, oy]: [f64; 2],
        [dx, dy]: [f64; 2],
        source: &str,
    ) -> Result<Heightfield, TilingError> {
        let tile = Heightfield::new(t.w, t.h, z)
            .and_then(|h| h.with_geometry([ox + t.x0 as f64 * dx, oy + t.y0 as f64 * dy], [dx, dy]))
            .map_err(|e| TilingError::Grid(e.to_string()))?;
        Ok(tile.with_source(format!("tile {} of {source}", t.index)))
    }
}
