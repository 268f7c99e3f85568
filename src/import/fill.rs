//! The nodata fill of one window of a grid, with the whole grid's bits but without the whole
//! grid: [`fill_window`] reads the window with a margin around it, fills that, and widens the
//! margin until every missing cell of the window is provably filled as
//! [`fill_nearest`](super::resample::fill_nearest) fills it on the whole grid.
//!
//! Why a margin is enough: the whole-grid fill is a breadth-first search from the valid cells
//! (queued in index order), so a missing cell j at 4-neighbour distance d from the nearest
//! valid cell takes its value from a chain of cells that all lie within distance d of j, and
//! which of them wins depends only on their distances and on the index order of valid cells
//! within distance d of j. A window reaching at least d cells past j on every side (or to the
//! grid's edge) holds all of them with the same distances and the same relative order, so the
//! search on the window gives j the same value. The window's own search never finds a cell
//! nearer than it is in the whole grid, so "every missing cell of the rectangle is at window
//! distance ≤ margin" proves the condition.

use super::error::ImportError;
use std::collections::VecDeque;

/// The first margin tried, in cells; each retry quadruples it.
const FIRST_MARGIN: usize = 16;

/// [`fill_nearest`](super::resample::fill_nearest) that also returns each cell's search depth:
/// 0 for a valid cell, the 4-neighbour distance to the cell it copied for a filled one,
/// `u32::MAX` for a cell never reached (a grid with no valid cell). The queue order, and so
/// every filled value, is `fill_nearest`'s.
pub(super) fn fill_with_depth(z: &mut [f64], width: usize, height: usize) -> Vec<u32> {
    let mut depth: Vec<u32> = z
        .iter()
        .map(|v| if v.is_nan() { u32::MAX } else { 0 })
        .collect();
    spread_nearest(z, width, height, |to, from| depth[to] = depth[from] + 1);
    depth
}

/// The breadth-first search of [`fill_nearest`](super::resample::fill_nearest): every NaN
/// point takes the value of the point it is reached from, and `copied(to, from)` is told of
/// each copy in the search's order.
pub(super) fn spread_nearest(
    z: &mut [f64],
    width: usize,
    height: usize,
    mut copied: impl FnMut(usize, usize),
) {
    let neighbours = |i: usize| {
        let (x, y) = (i % width, i / width);
        [
            (y > 0).then(|| i - width),
            (x > 0).then(|| i - 1),
            (x + 1 < width).then(|| i + 1),
            (y + 1 < height).then(|| i + width),
        ]
    };
    // Breadth-first from every valid point in index order; a valid point with no missing
    // neighbour would fill nothing, so only the border of the missing regions is queued (the
    // same order and result, with memory for the border instead of the whole grid).
    let mut queue: VecDeque<usize> = (0..z.len())
        .filter(|&i| !z[i].is_nan() && neighbours(i).into_iter().flatten().any(|j| z[j].is_nan()))
        .collect();
    while let Some(i) = queue.pop_front() {
        for j in neighbours(i).into_iter().flatten() {
            if z[j].is_nan() {
                z[j] = z[i];
                copied(j, i);
                queue.push_back(j);
            }
        }
    }
}

/// A rectangle of a grid: columns `x0 .. x0 + w`, rows `y0 .. y0 + h`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Window {
    /// First column.
    pub(super) x0: usize,
    /// First row.
    pub(super) y0: usize,
    /// Columns.
    pub(super) w: usize,
    /// Rows.
    pub(super) h: usize,
}

/// The filled heights of `window` of a `width`×`height` grid whose raw cells (NaN where
/// missing) `read` gives for any window, row-major: bit for bit what filling the whole grid
/// and cutting the window out gives. Reads the window alone when it has no missing cell, else
/// wider windows until the proof in the module note holds (at worst the whole grid). A grid
/// with no valid cell at all is an error.
pub(super) fn fill_window(
    (width, height): (usize, usize),
    window: Window,
    mut read: impl FnMut(Window) -> Result<Vec<f64>, ImportError>,
) -> Result<Vec<f64>, ImportError> {
    let mut z = read(window)?;
    if !z.iter().any(|v| v.is_nan()) {
        return Ok(z);
    }
    let mut margin = FIRST_MARGIN;
    loop {
        let x0 = window.x0.saturating_sub(margin);
        let y0 = window.y0.saturating_sub(margin);
        let x1 = (window.x0 + window.w + margin).min(width);
        let y1 = (window.y0 + window.h + margin).min(height);
        let wide = Window {
            x0,
            y0,
            w: x1 - x0,
            h: y1 - y0,
        };
        let whole = wide.w == width && wide.h == height;
        let mut raw = read(wide)?;
        let depth = fill_with_depth(&mut raw, wide.w, wide.h);
        let (dx, dy) = (window.x0 - x0, window.y0 - y0);
        let proven = (0..window.h).all(|r| {
            depth[(dy + r) * wide.w + dx..][..window.w]
                .iter()
                .all(|&d| d as usize <= margin || (whole && d != u32::MAX))
        });
        if proven {
            z.clear();
            for r in 0..window.h {
                z.extend_from_slice(&raw[(dy + r) * wide.w + dx..][..window.w]);
            }
            return Ok(z);
        }
        if whole {
            return Err(ImportError::Malformed {
                format: "grid",
                message:
                    "every cell is nodata (or not a finite number); there is no height to read"
                        .into(),
            });
        }
        margin = margin.saturating_mul(4);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::import::fill_nearest;

    /// A grid of `w`×`h` with missing cells where `missing(x, y)`; heights distinct per cell.
    fn grid(w: usize, h: usize, missing: impl Fn(usize, usize) -> bool) -> Vec<f64> {
        (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                if missing(x, y) {
                    f64::NAN
                } else {
                    (i as f64 * 0.37).sin() * 100.0 + i as f64
                }
            })
            .collect()
    }

    fn cut(z: &[f64], width: usize, win: Window) -> Vec<f64> {
        (0..win.h)
            .flat_map(|r| z[(win.y0 + r) * width + win.x0..][..win.w].to_vec())
            .collect()
    }

    /// Every window of a tiling of the grid, filled alone, equals the whole grid's fill.
    fn check(w: usize, h: usize, raw: &[f64], tile: usize) {
        let mut whole = raw.to_vec();
        fill_nearest(&mut whole, w, h);
        let mut reads = 0;
        for y0 in (0..h - 1).step_by(tile - 1) {
            for x0 in (0..w - 1).step_by(tile - 1) {
                let win = Window {
                    x0,
                    y0,
                    w: tile.min(w - x0),
                    h: tile.min(h - y0),
                };
                let got = fill_window((w, h), win, |r| {
                    reads += 1;
                    Ok(cut(raw, w, r))
                })
                .unwrap();
                let want = cut(&whole, w, win);
                assert_eq!(
                    got.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    want.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    "window at ({x0}, {y0})"
                );
            }
        }
        assert!(reads > 0);
    }

    #[test]
    fn depth_fill_is_fill_nearest() {
        let (w, h) = (37, 23);
        let raw = grid(w, h, |x, y| (x * 7 + y * 3) % 5 == 0 || (x > 10 && x < 20));
        let (mut a, mut b) = (raw.clone(), raw);
        fill_nearest(&mut a, w, h);
        let depth = fill_with_depth(&mut b, w, h);
        assert_eq!(
            a.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            b.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        // Row 0 misses columns 10 ..= 20 (the band and the pattern's 10 and 20): column 15 is
        // 6 steps from the valid columns 9 and 21.
        assert_eq!(depth[15], 6);
        assert_eq!(depth[0], 1);
    }

    #[test]
    fn scattered_holes_fill_as_the_whole_grid() {
        let (w, h) = (90, 70);
        let raw = grid(w, h, |x, y| (x * 31 + y * 17) % 11 < 3);
        check(w, h, &raw, 33);
    }

    #[test]
    fn a_lake_wider_than_the_margin_fills_as_the_whole_grid() {
        // A disc of missing cells 60 across, ties everywhere on its rim; and a missing band
        // along the grid's edge.
        let (w, h) = (150, 120);
        let raw = grid(w, h, |x, y| {
            let (dx, dy) = (x as f64 - 70.0, y as f64 - 55.0);
            dx * dx + dy * dy < 900.0 || y < 4 || (x > 140 && y > 100)
        });
        check(w, h, &raw, 33);
        check(w, h, &raw, 50);
    }

    #[test]
    fn most_of_the_grid_missing_fills_as_the_whole_grid() {
        let (w, h) = (100, 80);
        let raw = grid(w, h, |x, y| !((x, y) == (97, 3) || (x, y) == (2, 77)));
        check(w, h, &raw, 33);
    }

    #[test]
    fn a_grid_with_no_valid_cell_is_an_error() {
        let (w, h) = (40, 40);
        let err = fill_window(
            (w, h),
            Window {
                x0: 0,
                y0: 0,
                w: 20,
                h: 20,
            },
            |r| Ok(vec![f64::NAN; r.w * r.h]),
        )
        .unwrap_err();
        assert!(err.to_string().contains("every cell is nodata"), "{err}");
    }
}
