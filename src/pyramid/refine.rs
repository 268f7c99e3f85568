//! A tile's kept points refined until its mesh meets an error bound: a level's whole-grid kept
//! set cut into tiles is triangulated again in each tile, which can leave a tile's error above
//! the bound its run tiles met. Each round inserts, in every triangle with a grid point further
//! than the bound from it, that triangle's worst point off the tile's shared border lines (so
//! both tiles of a border keep the same points on it and still meet without cracks; the grid's
//! own edges are no one else's and take points too).

use super::quadtree::Tile;
use super::tile_mesh::{TileMesh, tile_mesh};
use crate::heightfield::Heightfield;

/// Rounds of insertion at most; each round at least one point per offending triangle goes in.
const MAX_ROUNDS: usize = 200;

/// `share` (increasing grid indices in `tile`, its corners included) with the inner points
/// that bring the tile's mesh within `bound`, and that mesh.
pub(crate) fn refine_share(
    hf: &Heightfield,
    tile: &Tile,
    share: &[u32],
    bound: f64,
) -> Result<(Vec<u32>, TileMesh), String> {
    let mut kept = share.to_vec();
    let w = hf.width();
    let z = hf.z();
    for _ in 0..MAX_ROUNDS {
        let mesh = tile_mesh(hf, tile, &kept)?;
        if mesh.e_max <= bound {
            return Ok((kept, mesh));
        }
        let mut added = Vec::new();
        for t in &mesh.triangles {
            let p = t.map(|i| {
                let g = mesh.vertices[i as usize] as usize;
                (g % w, g / w, z[g])
            });
            if let Some(g) = worst_inner_point(tile, (w, hf.height()), z, p, bound) {
                added.push(g);
            }
        }
        if added.is_empty() {
            return Ok((kept, mesh));
        }
        kept.extend(added);
        kept.sort_unstable();
        kept.dedup();
    }
    let mesh = tile_mesh(hf, tile, &kept)?;
    Ok((kept, mesh))
}

/// The fewer-triangle of two meshes of `tile` that both meet `bound` where they can: `share`
/// refined ([`refine_share`]), and `share`'s points on the tile's shared border lines alone
/// (with its corners) refined from scratch, a per-tile greedy insertion. Both keep the same
/// border points, so the tile still meets its neighbours without cracks; the second wins where
/// the whole-grid kept set is denser in the tile than its bound needs.
pub fn refine_share_best(
    hf: &Heightfield,
    tile: &Tile,
    share: &[u32],
    bound: f64,
) -> Result<(Vec<u32>, TileMesh), String> {
    let cut = refine_share(hf, tile, share, bound)?;
    let w = hf.width();
    let (x0, x1) = tile.columns;
    let (y0, y1) = tile.rows;
    let shared = |g: &u32| {
        let (x, y) = (*g as usize % w, *g as usize / w);
        (x == x0 && x0 > 0)
            || (x == x1 && x1 < w - 1)
            || (y == y0 && y0 > 0)
            || (y == y1 && y1 < hf.height() - 1)
            || ((x == x0 || x == x1) && (y == y0 || y == y1))
    };
    let border: Vec<u32> = share.iter().copied().filter(shared).collect();
    let fresh = refine_share(hf, tile, &border, bound)?;
    let better = |a: &TileMesh, b: &TileMesh| {
        (a.e_max <= bound || a.e_max <= b.e_max) && a.triangles.len() < b.triangles.len()
    };
    Ok(if better(&fresh.1, &cut.1) { fresh } else { cut })
}

/// The grid index of the point of triangle `p` (grid x, y and z of its corners) furthest from
/// its plane, off the tile's shared border lines, when that is further than `bound`.
fn worst_inner_point(
    tile: &Tile,
    (w, h): (usize, usize),
    z: &[f64],
    p: [(usize, usize, f64); 3],
    bound: f64,
) -> Option<u32> {
    let [(x0, y0, z0), (x1, y1, z1), (x2, y2, z2)] = p;
    let (ax, ay) = (x0 as f64, y0 as f64);
    let (bx, by) = (x1 as f64 - ax, y1 as f64 - ay);
    let (cx, cy) = (x2 as f64 - ax, y2 as f64 - ay);
    let det = bx * cy - by * cx;
    if det == 0.0 {
        return None;
    }
    // A line shared with a neighbour is off limits; the grid's own edges are not.
    let low = |first: usize| if first == 0 { 0 } else { first + 1 };
    let high = |last: usize, n: usize| if last == n - 1 { last } else { last - 1 };
    let xmin = x0.min(x1).min(x2).max(low(tile.columns.0));
    let xmax = x0.max(x1).max(x2).min(high(tile.columns.1, w));
    let ymin = y0.min(y1).min(y2).max(low(tile.rows.0));
    let ymax = y0.max(y1).max(y2).min(high(tile.rows.1, h));
    let mut worst = (bound, None);
    for y in ymin..=ymax {
        for x in xmin..=xmax {
            let (px, py) = (x as f64 - ax, y as f64 - ay);
            let s = (px * cy - py * cx) / det;
            let t = (bx * py - by * px) / det;
            if s < -1e-12 || t < -1e-12 || s + t > 1.0 + 1e-12 {
                continue;
            }
            let g = y * w + x;
            let error = (z[g] - (z0 + s * (z1 - z0) + t * (z2 - z0))).abs();
            if error > worst.0 {
                worst = (error, Some(g as u32));
            }
        }
    }
    worst.1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pyramid::borders::with_border_points;
    use crate::pyramid::quadtree::Level;

    #[test]
    fn a_refined_tile_meets_the_bound_and_keeps_its_border() {
        let (w, h) = (65, 65);
        let z: Vec<f64> = (0..w * h)
            .map(|i| ((i % w) as f64 * 0.4).sin() * 20.0 + ((i / w) as f64 * 0.23).cos() * 9.0)
            .collect();
        let hf = Heightfield::new(w, h, z).unwrap();
        let level = Level::new(w, h, 1);
        for bound in [8.0, 1.0] {
            // Border lines within the bound first, as a level's meshes have them.
            let shares = level.share_out(&with_border_points(&hf, &level, &[], bound));
            for (tile, share) in level.tiles().iter().zip(&shares) {
                let (kept, mesh) = refine_share(&hf, tile, share, bound).unwrap();
                let (best_kept, best) = refine_share_best(&hf, tile, share, bound).unwrap();
                assert!(best.e_max <= bound && best.triangles.len() <= mesh.triangles.len());
                let border_of = |list: &[u32]| {
                    list.iter()
                        .copied()
                        .filter(|&g| (g as usize % w) == 32 || (g as usize / w) == 32)
                        .collect::<Vec<_>>()
                };
                assert_eq!(border_of(&best_kept), border_of(share));
                assert!(mesh.e_max <= bound, "{} > {bound}", mesh.e_max);
                // The lines shared with the other tiles of the level.
                let on_border = |g: u32| (g as usize % w) == 32 || (g as usize / w) == 32;
                let border = |list: &[u32]| {
                    list.iter()
                        .copied()
                        .filter(|&g| on_border(g))
                        .collect::<Vec<_>>()
                };
                assert_eq!(border(&kept), border(share));
            }
        }
    }
}
