//! The quadtree's tiles on the grid: level L cuts the grid into 2^L × 2^L tiles along grid
//! lines, neighbours sharing their border line, each level's lines including its parent's.

/// Grid-line positions cutting `points` grid points into `tiles` runs that share their end
/// points: `tiles + 1` increasing positions from 0 to `points − 1`. Position i is
/// ⌊i·(points − 1) / tiles⌋, so level L + 1's even positions are level L's.
pub(super) fn cuts(points: usize, tiles: usize) -> Vec<usize> {
    (0..=tiles).map(|i| i * (points - 1) / tiles).collect()
}

/// One tile: its level, column and row in the level's 2^L × 2^L tiles, and its grid window
/// (inclusive, so a tile's border points are also its neighbour's).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Quadtree level, 0 for the root.
    pub level: u32,
    /// Column of the tile (along grid x).
    pub x: usize,
    /// Row of the tile (along grid y).
    pub y: usize,
    /// First and last grid column of the tile.
    pub columns: (usize, usize),
    /// First and last grid row of the tile.
    pub rows: (usize, usize),
}

impl Tile {
    /// The tile's width and height in grid points.
    pub(crate) fn size(&self) -> (usize, usize) {
        (
            self.columns.1 - self.columns.0 + 1,
            self.rows.1 - self.rows.0 + 1,
        )
    }

    /// True when grid point (`x`, `y`) is in the tile (its border included).
    pub(crate) fn contains(&self, x: usize, y: usize) -> bool {
        (self.columns.0..=self.columns.1).contains(&x) && (self.rows.0..=self.rows.1).contains(&y)
    }
}

/// The tiles of one quadtree level of a `width` × `height` grid, row by row.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Level {
    level: u32,
    width: usize,
    column_cuts: Vec<usize>,
    row_cuts: Vec<usize>,
}

impl Level {
    /// Level `level` (2^level tiles per side) of a `width` × `height` grid. Its tiles have at
    /// least two grid cells per side when `level` ≤ [`max_level`].
    pub fn new(width: usize, height: usize, level: u32) -> Self {
        let tiles = 1usize << level;
        Self {
            level,
            width,
            column_cuts: cuts(width, tiles),
            row_cuts: cuts(height, tiles),
        }
    }

    /// A level cut along the given grid lines (each list increasing from 0 to the grid's last
    /// point): a block of several quadtree roots, as a terrain scheme's tiles over a DEM.
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn from_cuts(
        level: u32,
        width: usize,
        column_cuts: Vec<usize>,
        row_cuts: Vec<usize>,
    ) -> Self {
        Self {
            level,
            width,
            column_cuts,
            row_cuts,
        }
    }

    /// Tiles per side, 2^level (for a block, the tiles along x).
    pub fn side(&self) -> usize {
        self.column_cuts.len() - 1
    }

    /// Tiles along y.
    pub(crate) fn rows(&self) -> usize {
        self.row_cuts.len() - 1
    }

    /// The tile at column `x`, row `y`.
    pub(crate) fn tile(&self, x: usize, y: usize) -> Tile {
        Tile {
            level: self.level,
            x,
            y,
            columns: (self.column_cuts[x], self.column_cuts[x + 1]),
            rows: (self.row_cuts[y], self.row_cuts[y + 1]),
        }
    }

    /// Every tile, row by row (index y·side + x).
    pub fn tiles(&self) -> Vec<Tile> {
        let side = self.side();
        (0..side * self.rows())
            .map(|i| self.tile(i % side, i / side))
            .collect()
    }

    /// For each tile (row by row), the grid indices of `kept` (increasing) that lie in it,
    /// border included, with the tile's four corners added; each list increasing. A point on a
    /// border line goes to every tile that shares the line.
    pub fn share_out(&self, kept: &[u32]) -> Vec<Vec<u32>> {
        let side = self.side();
        let mut lists = vec![Vec::new(); side * self.rows()];
        let spans = |cuts: &[usize], v: usize| -> (usize, usize) {
            // The last tile whose first line is at or before v, and the one before it when v
            // is on that line.
            let last = cuts[..cuts.len() - 1].partition_point(|&c| c <= v) - 1;
            let first = if last > 0 && cuts[last] == v {
                last - 1
            } else {
                last
            };
            (first, last)
        };
        for &g in kept {
            let (x, y) = (g as usize % self.width, g as usize / self.width);
            let (x0, x1) = spans(&self.column_cuts, x);
            let (y0, y1) = spans(&self.row_cuts, y);
            for ty in y0..=y1 {
                for tx in x0..=x1 {
                    lists[ty * side + tx].push(g);
                }
            }
        }
        for (i, list) in lists.iter_mut().enumerate() {
            let tile = self.tile(i % side, i / side);
            for y in [tile.rows.0, tile.rows.1] {
                for x in [tile.columns.0, tile.columns.1] {
                    list.push((y * self.width + x) as u32);
                }
            }
            list.sort_unstable();
            list.dedup();
        }
        lists
    }
}

/// The deepest level whose tiles keep at least two grid cells per side on a `width` × `height`
/// grid.
pub(super) fn max_level(width: usize, height: usize) -> u32 {
    let cells = width.min(height).saturating_sub(1);
    let mut level = 0;
    while (cells >> (level + 1)) >= 2 {
        level += 1;
    }
    level
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_levels_cuts_contain_its_parents() {
        for points in [3, 33, 87, 100, 3601] {
            for level in 1..=max_level(points, points) {
                let parent = Level::new(points, points, level - 1);
                let child = Level::new(points, points, level);
                let even: Vec<usize> = child.column_cuts.iter().step_by(2).copied().collect();
                assert_eq!(even, parent.column_cuts, "{points} points, level {level}");
            }
        }
    }

    #[test]
    fn the_deepest_level_keeps_two_cells_per_tile_side() {
        for (w, h) in [
            (3, 3),
            (5, 9),
            (33, 33),
            (87, 61),
            (3601, 3601),
            (2048, 2048),
        ] {
            let level = Level::new(w, h, max_level(w, h));
            assert!(level.tiles().iter().all(|t| {
                let (tw, th) = t.size();
                tw >= 3 && th >= 3
            }));
            let deeper = Level::new(w, h, max_level(w, h) + 1);
            assert!(
                deeper
                    .tiles()
                    .iter()
                    .any(|t| t.size().0 < 3 || t.size().1 < 3)
            );
        }
    }

    #[test]
    fn shared_out_points_are_those_in_each_tile_plus_its_corners() {
        let (w, h) = (17, 11);
        let kept: Vec<u32> = (0..(w * h) as u32).filter(|g| g % 7 == 0).collect();
        let level = Level::new(w, h, 2);
        let lists = level.share_out(&kept);
        for (i, tile) in level.tiles().iter().enumerate() {
            let mut want: Vec<u32> = kept
                .iter()
                .copied()
                .filter(|&g| tile.contains(g as usize % w, g as usize / w))
                .collect();
            for y in [tile.rows.0, tile.rows.1] {
                for x in [tile.columns.0, tile.columns.1] {
                    want.push((y * w + x) as u32);
                }
            }
            want.sort_unstable();
            want.dedup();
            assert_eq!(lists[i], want, "tile {tile:?}");
        }
    }
}
