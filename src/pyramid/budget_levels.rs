//! A pyramid's tile meshes under a triangle budget ([`super::budget`] spends it).
//!
//! Each tile's ladder is its mesh at each bound of a ladder of error bounds, the coarsest
//! first: the whole-grid kept set chosen for that bound, cut to the tile, refined until the
//! tile meets the bound. A tile's shared edges do not take the kept set's points: each edge's
//! points come from the edge alone, by Douglas–Peucker splitting to a tolerance, whose points
//! at a tolerance hold all its points at any larger one. The edge between two tiles takes the
//! smaller of their bounds, so both tiles have the same points on it (no cracks) and each tile
//! still meets its own bound.

use super::budget::{Allocation, Rung, allocate, total};
use super::quadtree::Level;
use super::refine::refine_share_best;
use super::tile_mesh::TileMesh;
use crate::heightfield::Heightfield;
use crate::tiling::TiledFront;

/// One rung of the ladder: a bound and the whole-grid kept set (increasing grid indices) whose
/// run tiles meet it.
pub(crate) struct LadderRung {
    /// The bound.
    pub bound: f64,
    /// The kept set.
    pub kept: Vec<u32>,
}

/// Runs `f(i)` for every `i` in `0..n` (in one thread or spread over cores), in order.
pub type MapTiles<'a> = &'a (
        dyn Fn(
    usize,
    &(dyn Fn(usize) -> Result<(Vec<u32>, TileMesh), String> + Sync),
) -> Result<Vec<(Vec<u32>, TileMesh)>, String>
            + Sync
    );

/// A level's tile meshes under the budget: each tile's kept set (its refinement included) and
/// mesh, row by row.
pub type LevelMeshes = Vec<(Vec<u32>, TileMesh)>;

/// The positions to keep on an edge of `length` grid points of heights `z` (its two ends
/// always kept) so that no point is further than `tolerance` from the polyline: Douglas–Peucker
/// splitting at the furthest point. Increasing.
fn edge_points(length: usize, tolerance: f64, z: impl Fn(usize) -> f64) -> Vec<usize> {
    let mut out = super::borders::refine_line(&[], length, tolerance, z);
    out.extend([0, length - 1]);
    out.sort_unstable();
    out.dedup();
    out
}

/// Tile `i` of `level`'s share: the kept points of `in_tile` (its share of a whole-grid kept
/// set) off its shared edges, its corners, and on each shared edge the edge's own points at
/// `edge_tolerance(neighbour)` (the neighbour's tile index across the edge).
fn tile_share(
    hf: &Heightfield,
    level: &Level,
    i: usize,
    in_tile: &[u32],
    edge_tolerance: impl Fn(usize) -> f64,
) -> Vec<u32> {
    let (w, side, rows) = (hf.width(), level.side(), level.rows());
    let tile = level.tile(i % side, i / side);
    let (x0, x1) = tile.columns;
    let (y0, y1) = tile.rows;
    let (tx, ty) = (tile.x, tile.y);
    let shared = [tx > 0, tx + 1 < side, ty > 0, ty + 1 < rows]; // west, east, north, south
    let on_shared = |g: u32| {
        let (x, y) = (g as usize % w, g as usize / w);
        (shared[0] && x == x0)
            || (shared[1] && x == x1)
            || (shared[2] && y == y0)
            || (shared[3] && y == y1)
    };
    let mut out: Vec<u32> = in_tile.iter().copied().filter(|&g| !on_shared(g)).collect();
    for y in [y0, y1] {
        for x in [x0, x1] {
            out.push((y * w + x) as u32);
        }
    }
    let z = hf.z();
    let column = |x: usize, neighbour: usize| {
        let tol = edge_tolerance(neighbour);
        edge_points(y1 - y0 + 1, tol, |k| z[(y0 + k) * w + x])
            .into_iter()
            .map(move |k| ((y0 + k) * w + x) as u32)
    };
    let row = |y: usize, neighbour: usize| {
        let tol = edge_tolerance(neighbour);
        edge_points(x1 - x0 + 1, tol, |k| z[y * w + x0 + k])
            .into_iter()
            .map(move |k| (y * w + x0 + k) as u32)
    };
    if shared[0] {
        out.extend(column(x0, i - 1));
    }
    if shared[1] {
        out.extend(column(x1, i + 1));
    }
    if shared[2] {
        out.extend(row(y0, i - side));
    }
    if shared[3] {
        out.extend(row(y1, i + side));
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// The meshes of every tile of `level` when tile `i` meets `ladder[rungs[i]]`'s bound.
fn level_meshes(
    hf: &Heightfield,
    level: &Level,
    ladder: &[LadderRung],
    rungs: &[usize],
    map: MapTiles,
) -> Result<LevelMeshes, String> {
    let tiles = level.tiles();
    // Each rung's kept set shared out once, for the tiles that take it.
    let mut shares: Vec<Option<Vec<Vec<u32>>>> = (0..ladder.len()).map(|_| None).collect();
    for &k in rungs {
        if shares[k].is_none() {
            shares[k] = Some(level.share_out(&ladder[k].kept));
        }
    }
    let bound = |i: usize| ladder[rungs[i]].bound;
    map(tiles.len(), &|i| {
        let own = shares[rungs[i]].as_ref().expect("shared out above");
        let share = tile_share(hf, level, i, &own[i], |n| bound(i).min(bound(n)));
        refine_share_best(hf, &tiles[i], &share, bound(i))
    })
}

/// Every tile's ladder on `level`: its mesh at each rung with its edges at its own bound.
fn ladders_of(
    hf: &Heightfield,
    level: &Level,
    ladder: &[LadderRung],
    map: MapTiles,
) -> Result<Vec<Vec<Rung>>, String> {
    let count = level.side() * level.rows();
    let mut out = vec![Vec::with_capacity(ladder.len()); count];
    for k in 0..ladder.len() {
        for (tile, (_, mesh)) in level_meshes(hf, level, ladder, &vec![k; count], map)?
            .into_iter()
            .enumerate()
        {
            out[tile].push(Rung {
                t: mesh.triangles.len() as u64,
                e: mesh.e_max,
            });
        }
    }
    Ok(out)
}

/// The tiles' meshes of `levels` (the root's first) that spend at most `budget` triangles
/// where the pyramid's error falls most ([`super::budget::allocate`]), each level's geometric
/// error falling with depth and neighbours sharing their edge points. `ladder` is ordered from
/// the largest bound. The allocation is made on each tile's meshes with its edges at its own
/// bound; an edge shared with a finer neighbour takes more points, so when the final meshes
/// pass the budget or stop falling, the walk's last steps are undone until they do not.
pub(crate) fn budget_levels(
    hf: &Heightfield,
    levels: &[Level],
    ladder: &[LadderRung],
    budget: u64,
    map: MapTiles,
) -> Result<Vec<LevelMeshes>, String> {
    if ladder.is_empty() {
        return Err("no mesh meets any bound of the ladder".into());
    }
    let ladders: Vec<Vec<Vec<Rung>>> = levels
        .iter()
        .map(|level| ladders_of(hf, level, ladder, map))
        .collect::<Result<_, _>>()?;
    let allocation: Allocation = allocate(&ladders, budget)?;
    let mut n = allocation.steps.len();
    loop {
        let rungs = allocation.after(n);
        let meshes: Vec<LevelMeshes> = levels
            .iter()
            .zip(&rungs)
            .map(|(level, r)| level_meshes(hf, level, ladder, r, map))
            .collect::<Result<_, _>>()?;
        let actual: u64 = meshes
            .iter()
            .flatten()
            .map(|m| m.1.triangles.len() as u64)
            .sum();
        let errors: Vec<f64> = meshes
            .iter()
            .map(|l| l.iter().map(|m| m.1.e_max).fold(0.0, f64::max))
            .collect();
        let falls = errors.windows(2).all(|p| p[1] < p[0]);
        if actual <= budget && falls {
            return Ok(meshes);
        }
        if n == 0 {
            return Err(format!(
                "--max-triangles {budget} is too few: the coarsest pyramid whose errors fall with depth takes {actual} triangles with its tiles' shared edges"
            ));
        }
        // Back to the last state whose planned total leaves room for this overshoot.
        let over = actual.saturating_sub(total(&ladders, &rungs));
        let planned = |m: usize| total(&ladders, &allocation.after(m));
        let mut m = n - 1;
        while m > 0 && planned(m) + over > budget {
            m -= 1;
        }
        n = m;
    }
}

/// The ladder of a pyramid of `levels` levels: from 2^`levels` times its finest bound down to
/// that bound (`finest`, or the least the front allows when that is larger), each bound √2
/// below the one before. At each bound, the whole-grid kept set of fewest triangles from
/// `front` whose run tiles meet it ([`super::level_within`]).
pub(crate) fn ladder_of(
    front: &TiledFront,
    hf: &Heightfield,
    levels: usize,
    finest: f64,
) -> Result<Vec<LadderRung>, String> {
    let finest = finest.max(super::tiled_levels::least_bound(front));
    let coarsest = finest * f64::powi(2.0, levels as i32);
    let mut out = Vec::new();
    let mut bound = coarsest;
    while bound >= finest * (1.0 - 1e-9) {
        match super::level_within(front, hf, bound)? {
            Some(level) => out.push(LadderRung {
                bound,
                kept: level.kept,
            }),
            None => break,
        }
        bound /= std::f64::consts::SQRT_2;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn serial(
        n: usize,
        f: &(dyn Fn(usize) -> Result<(Vec<u32>, TileMesh), String> + Sync),
    ) -> Result<LevelMeshes, String> {
        (0..n).map(f).collect()
    }

    #[test]
    fn a_budget_is_kept_errors_fall_with_depth_and_edges_meet() {
        let (w, h) = (65, 65);
        let (hf, front) = super::super::tiled_levels::tests::front(w, h);
        let ladder = ladder_of(&front, &hf, 3, 0.5).unwrap();
        assert!(ladder.len() > 6);
        let levels: Vec<Level> = (0..3).map(|d| Level::new(w, h, d)).collect();
        let mut spent = Vec::new();
        for budget in [800, 2000, 6000] {
            let meshes = budget_levels(&hf, &levels, &ladder, budget, &serial).unwrap();
            let t: u64 = meshes
                .iter()
                .flatten()
                .map(|m| m.1.triangles.len() as u64)
                .sum();
            assert!(t <= budget, "{t} > {budget}");
            spent.push(t);
            let errors: Vec<f64> = meshes
                .iter()
                .map(|l| l.iter().map(|m| m.1.e_max).fold(0.0, f64::max))
                .collect();
            assert!(errors.windows(2).all(|p| p[1] < p[0]), "{errors:?}");
            // Cracks: neighbours have the same vertices on their shared edge.
            for (level, tiles) in levels.iter().zip(&meshes) {
                let side = level.side();
                for i in 0..tiles.len() {
                    let a = level.tile(i % side, i / side);
                    let on = |m: &TileMesh, f: &dyn Fn(usize, usize) -> bool| -> Vec<u32> {
                        m.vertices
                            .iter()
                            .copied()
                            .filter(|&g| f(g as usize % w, g as usize / w))
                            .collect()
                    };
                    if a.x + 1 < side {
                        let x = a.columns.1;
                        let edge =
                            |gx: usize, gy: usize| gx == x && gy >= a.rows.0 && gy <= a.rows.1;
                        assert_eq!(on(&tiles[i].1, &edge), on(&tiles[i + 1].1, &edge));
                    }
                    if a.y + 1 < level.rows() {
                        let y = a.rows.1;
                        let edge = |gx: usize, gy: usize| {
                            gy == y && gx >= a.columns.0 && gx <= a.columns.1
                        };
                        assert_eq!(on(&tiles[i].1, &edge), on(&tiles[i + side].1, &edge));
                    }
                }
            }
        }
        // A larger budget is spent: more triangles, not fewer.
        assert!(
            spent.windows(2).all(|p| p[0] <= p[1]) && spent[2] > spent[0],
            "{spent:?}"
        );
        // Too small a budget is named.
        let e = budget_levels(&hf, &levels, &ladder, 10, &serial).unwrap_err();
        assert!(e.contains("too few"), "{e}");
    }

    #[test]
    fn edge_points_nest_and_follow_the_edge_within_the_tolerance() {
        let z: Vec<f64> = (0..129)
            .map(|i| ((i as f64) * 0.21).sin() * 9.0 + (i as f64 * 0.05).cos() * 4.0)
            .collect();
        let mut previous: Option<Vec<usize>> = None;
        for tolerance in [8.0, 4.0, 1.0, 0.25, 0.0] {
            let points = edge_points(z.len(), tolerance, |i| z[i]);
            for pair in points.windows(2) {
                let (a, b) = (pair[0], pair[1]);
                for p in a..=b {
                    let chord = z[a] + (z[b] - z[a]) * (p - a) as f64 / (b - a) as f64;
                    assert!((z[p] - chord).abs() <= tolerance + 1e-12);
                }
            }
            if let Some(coarser) = previous {
                assert!(coarser.iter().all(|p| points.contains(p)), "nested");
            }
            previous = Some(points);
        }
    }
}
