//! Points added on a level's inner tile borders. A tile holds only the member's kept points
//! inside it, so where few of them lie on a border line the tiles on both sides would span it
//! with long edges far from the surface. Along every inner border line, grid points are
//! inserted greedily (the worst first) until the line's kept points follow the surface within a
//! tolerance; the insertion reads only that line, so both tiles sharing it get the same points
//! and still meet without cracks.

use super::quadtree::Level;
use crate::heightfield::Heightfield;

/// `kept` (increasing grid indices) with the points that bring every inner border line of
/// `level` within `tolerance` of the surface: between two consecutive points on a line, no grid
/// point of the line is further than `tolerance` from the straight segment joining them.
/// Increasing, without repeats.
pub fn with_border_points(
    hf: &Heightfield,
    level: &Level,
    kept: &[u32],
    tolerance: f64,
) -> Vec<u32> {
    let (w, h) = (hf.width(), hf.height());
    let columns: Vec<usize> = (1..level.side())
        .map(|i| level.tile(i, 0).columns.0)
        .collect();
    let rows: Vec<usize> = (1..level.rows()).map(|i| level.tile(0, i).rows.0).collect();
    // Each inner line's positions along it (y for a column, x for a row) of its kept points.
    let mut on_columns = vec![Vec::new(); columns.len()];
    let mut on_rows = vec![Vec::new(); rows.len()];
    for &g in kept {
        let (x, y) = (g as usize % w, g as usize / w);
        if let Ok(i) = columns.binary_search(&x) {
            on_columns[i].push(y);
        }
        if let Ok(i) = rows.binary_search(&y) {
            on_rows[i].push(x);
        }
    }
    let z = hf.z();
    let mut out = kept.to_vec();
    for (&x, along) in columns.iter().zip(&on_columns) {
        let added = refine_line(along, h, tolerance, |y| z[y * w + x]);
        out.extend(added.into_iter().map(|y| (y * w + x) as u32));
    }
    for (&y, along) in rows.iter().zip(&on_rows) {
        let added = refine_line(along, w, tolerance, |x| z[y * w + x]);
        out.extend(added.into_iter().map(|x| (y * w + x) as u32));
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// The positions to add on a line of `length` grid points, heights `z`, whose kept positions
/// are `kept` (the two ends always count as kept): the worst point of an interval goes in while
/// it is further than `tolerance` from the interval's chord.
pub(super) fn refine_line(
    kept: &[usize],
    length: usize,
    tolerance: f64,
    z: impl Fn(usize) -> f64,
) -> Vec<usize> {
    let mut points: Vec<usize> = kept.to_vec();
    points.extend([0, length - 1]);
    points.sort_unstable();
    points.dedup();
    let mut added = Vec::new();
    let mut stack: Vec<(usize, usize)> = points.windows(2).map(|p| (p[0], p[1])).collect();
    while let Some((a, b)) = stack.pop() {
        let (za, zb) = (z(a), z(b));
        let mut worst = (tolerance, None);
        for p in a + 1..b {
            let chord = za + (zb - za) * (p - a) as f64 / (b - a) as f64;
            let gap = (z(p) - chord).abs();
            if gap > worst.0 {
                worst = (gap, Some(p));
            }
        }
        if let Some(p) = worst.1 {
            added.push(p);
            stack.push((a, p));
            stack.push((p, b));
        }
    }
    added
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_refined_line_follows_the_surface_within_the_tolerance() {
        let z: Vec<f64> = (0..200).map(|i| ((i as f64) * 0.17).sin() * 10.0).collect();
        for tolerance in [0.0, 0.5, 3.0] {
            let mut points = refine_line(&[50], z.len(), tolerance, |i| z[i]);
            points.extend([0, 50, 199]);
            points.sort_unstable();
            for pair in points.windows(2) {
                let (a, b) = (pair[0], pair[1]);
                for p in a..=b {
                    let chord = z[a] + (z[b] - z[a]) * (p - a) as f64 / (b - a) as f64;
                    assert!((z[p] - chord).abs() <= tolerance + 1e-12);
                }
            }
        }
        // A line already within the tolerance gets nothing.
        assert!(refine_line(&[], 50, 25.0, |i| z[i]).is_empty());
    }
}
