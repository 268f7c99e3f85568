//! A tiled member grown to a triangle budget by exact steps: the worst point of the whole
//! mesh is inserted, one at a time, into the tile that holds it, and into its neighbour too
//! when it lies on their shared border line, so the tiles keep the same points on every line
//! (no cracks). Each tile's mesh stays the canonical Delaunay triangulation of its points, as
//! a tiled member's is.

use super::assemble::TiledFront;
use super::{TilePlan, TilingError};
use crate::baselines::{GreedyInsertion, GreedyParams};
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use crate::refine::budget_floor;
use std::sync::Arc;

/// A tiled member grown to a budget.
#[derive(Clone, Debug, PartialEq)]
pub struct TiledGrown {
    /// Whole-grid triangles (counter-clockwise), tile by tile.
    pub triangles: Vec<[u32; 3]>,
    /// Points inserted (each counted once, also when two tiles took it).
    pub insertions: usize,
    /// Of those, points on a border line two tiles share.
    pub on_shared_lines: usize,
}

/// Grows member `member` of `front` (made on `hf`) by inserting the worst point of the whole
/// mesh (largest vertical error, ties to the smaller grid index) until it has at least
/// [`budget_floor`]`(max_t)` triangles, never more than `max_t`: an interior point or one on a
/// shared line adds two, one on the grid's border one, so it stops early only when the next
/// point would pass `max_t` or every point is kept. Errors: the grid is not the front's.
pub fn grow_tiled_member(
    hf: &Heightfield,
    front: &TiledFront,
    member: usize,
    max_t: usize,
) -> Result<TiledGrown, TilingError> {
    let plan = &front.plan;
    plan.check_grid(hf)?;
    let parts = front.parts(member)?;
    let mut runs = Vec::with_capacity(parts.len());
    for part in &parts {
        let tile_hf = Arc::new(plan.cut(hf, part.tile)?);
        let run = GreedyInsertion::from_kept(tile_hf, GreedyParams::default(), &part.kept)
            .map_err(|e| TilingError::Evaluate(e.to_string()))?;
        runs.push(run);
    }
    let width = hf.width();
    let floor = budget_floor(max_t);
    let mut total: usize = runs.iter().map(|r| r.triangle_count()).sum();
    let (mut insertions, mut on_shared_lines) = (0, 0);
    while total < floor {
        // The worst point over all tiles, as a whole-grid index.
        let best = runs
            .iter()
            .enumerate()
            .filter_map(|(i, r)| {
                let (e, p) = r.worst()?;
                let tile = plan.tile(i).expect("one run per tile");
                Some((e, tile.to_grid(p, width), i))
            })
            .reduce(|a, b| {
                if b.0 > a.0 || (b.0 == a.0 && b.1 < a.1) {
                    b
                } else {
                    a
                }
            });
        let Some((_, g, owner)) = best else {
            break;
        };
        let holders = tiles_holding(plan, g);
        let (x, y) = (g as usize % width, g as usize / width);
        let on_grid_border = x == 0 || y == 0 || x + 1 == width || y + 1 == hf.height();
        let grows = if on_grid_border { 1 } else { 2 };
        if total + grows > max_t {
            break;
        }
        for &i in &holders {
            let before = runs[i].triangle_count();
            let run = &mut runs[i];
            if i == owner {
                run.unit();
            } else {
                let tile = plan.tile(i).expect("a plan's tile");
                let local = ((y - tile.y0) * tile.w + (x - tile.x0)) as u32;
                run.insert_at(local);
            }
            total += runs[i].triangle_count() - before;
        }
        insertions += 1;
        on_shared_lines += usize::from(holders.len() > 1);
    }
    let mut triangles = Vec::new();
    for (i, run) in runs.iter().enumerate() {
        let tile = plan.tile(i).expect("one run per tile");
        triangles.extend(
            run.triangles()
                .into_iter()
                .map(|t| t.map(|v| tile.to_grid(v, width))),
        );
    }
    Ok(TiledGrown {
        triangles,
        insertions,
        on_shared_lines,
    })
}

/// The tiles whose rectangles hold whole-grid point `g` (two on a shared line, four at a tile
/// corner, which is always kept), by index.
fn tiles_holding(plan: &TilePlan, g: u32) -> Vec<usize> {
    let (x, y) = (g as usize % plan.width(), g as usize / plan.width());
    plan.tiles()
        .iter()
        .filter(|t| (t.x0..t.x0 + t.w).contains(&x) && (t.y0..t.y0 + t.h).contains(&y))
        .map(|t| t.index)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalogue::Config;
    use crate::evaluator::Evaluator;
    use crate::tiling::{assemble, run_tile};
    use std::path::Path;

    #[test]
    fn a_grown_member_is_crack_free_within_the_budget_and_keeps_its_points() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/volcano_87x61.f32");
        let hf = crate::import::load(&path).unwrap();
        let plan = TilePlan::new(hf.width(), hf.height(), 33).unwrap();
        let config = Config::Greedy(GreedyParams {
            records: 8,
            ..GreedyParams::default()
        });
        let fronts = (0..plan.len())
            .map(|i| run_tile(&plan.cut(&hf, i).unwrap(), &plan, i, &config, 1).unwrap())
            .collect();
        let front = assemble(&plan, fronts).unwrap();
        let mut evaluator = Evaluator::new(Arc::new(hf.clone()));
        let mut grew_on_lines = false;
        for member in [0, front.members.len() / 3, front.members.len() / 2] {
            let from = front.members[member].t as usize;
            let start = front.mesh(&hf, member).unwrap();
            for max_t in [from, from + 1, from * 3 / 2, from * 4] {
                let grown = grow_tiled_member(&hf, &front, member, max_t).unwrap();
                // A whole triangulation (the evaluator refuses cracks and overlaps).
                let score = evaluator.score_triangulation(&grown.triangles).unwrap();
                assert!(score.t <= max_t, "{} > {max_t}", score.t);
                assert!(score.t >= budget_floor(max_t) || score.t + 1 == max_t || from >= max_t);
                let mut kept: Vec<u32> = grown.triangles.iter().flatten().copied().collect();
                kept.sort_unstable();
                kept.dedup();
                assert!(start.kept.iter().all(|i| kept.binary_search(i).is_ok()));
                assert_eq!(kept.len(), start.kept.len() + grown.insertions);
                grew_on_lines |= grown.on_shared_lines > 0;
            }
        }
        assert!(grew_on_lines, "some growth crossed a shared line");
    }
}
