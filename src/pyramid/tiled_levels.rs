//! A pyramid's levels from a tiled front: for each level's error bound, every run tile takes
//! the candidate of fewest triangles whose E_max meets the bound, at the one border level
//! (shared by all tiles, so their meshes still meet without cracks) where the tiles' sum of
//! triangles is smallest. The bounds halve from level to level, as a globe's screen-space
//! error halves with each level's halved tile size.

use crate::evaluator::Score;
use crate::front::Solution;
use crate::heightfield::Heightfield;
use crate::tiling::{TilePart, TiledFront, mesh_of_parts};

/// One level's whole-grid mesh chosen from a tiled front.
#[derive(Clone, Debug, PartialEq)]
pub struct TiledLevel {
    /// The bound every run tile's E_max meets.
    pub bound: f64,
    /// Its score on the whole grid (E_sum, E_max, T of the union of the tile meshes).
    pub score: Score,
    /// Its kept grid indices, increasing.
    pub kept: Vec<u32>,
}

/// The tile parts of fewest triangles whose every tile meets `bound` (E_max ≤ `bound`), with
/// their triangle count, or `None` when no border level lets every tile meet it.
pub(super) fn parts_within(front: &TiledFront, bound: f64) -> Option<(Vec<TilePart>, u64)> {
    let levels: Vec<u8> = {
        let mut l: Vec<u8> = front
            .tiles
            .iter()
            .flat_map(|t| t.candidates.iter().map(|c| c.level))
            .collect();
        l.sort_unstable();
        l.dedup();
        l
    };
    let mut best: Option<(u64, u8, Vec<usize>)> = None;
    for level in levels {
        let mut choice = Vec::with_capacity(front.tiles.len());
        let mut total = 0u64;
        let feasible = front.tiles.iter().all(|tile| {
            let pick = tile
                .candidates
                .iter()
                .enumerate()
                .filter(|(_, c)| c.level == level && c.e_max <= bound)
                .min_by(|a, b| a.1.t.cmp(&b.1.t).then(a.1.e_share.total_cmp(&b.1.e_share)));
            pick.map(|(i, c)| {
                choice.push(i);
                total += c.t;
            })
            .is_some()
        });
        if feasible && best.as_ref().is_none_or(|b| total < b.0) {
            best = Some((total, level, choice));
        }
    }
    let (total, level, choice) = best?;
    let parts = front
        .tiles
        .iter()
        .zip(choice)
        .map(|(tile, c)| TilePart {
            tile: tile.index,
            level,
            borders: tile.borders.clone(),
            kept: tile.kept(&tile.candidates[c]),
        })
        .collect();
    Some((parts, total))
}

/// The least bound any choice of a tiled front meets: at each border level, the largest over
/// tiles of the tile's least E_max, the smallest of these over levels.
pub(super) fn least_bound(front: &TiledFront) -> f64 {
    let mut levels: Vec<u8> = front
        .tiles
        .iter()
        .flat_map(|t| t.candidates.iter().map(|c| c.level))
        .collect();
    levels.sort_unstable();
    levels.dedup();
    levels
        .iter()
        .filter_map(|&level| {
            front
                .tiles
                .iter()
                .map(|t| {
                    t.candidates
                        .iter()
                        .filter(|c| c.level == level)
                        .map(|c| c.e_max)
                        .reduce(f64::min)
                })
                .try_fold(0.0f64, |worst, e| e.map(|e| worst.max(e)))
        })
        .fold(f64::INFINITY, f64::min)
}

/// The whole-grid mesh of fewest triangles from `front` on `hf` whose every run tile meets
/// `bound`; `None` when none does.
pub(crate) fn level_within(
    front: &TiledFront,
    hf: &Heightfield,
    bound: f64,
) -> Result<Option<TiledLevel>, String> {
    let Some((parts, _)) = parts_within(front, bound) else {
        return Ok(None);
    };
    let mesh = mesh_of_parts(&front.plan, hf, &parts).map_err(|e| e.to_string())?;
    let score = Solution::recorded(mesh.e_sum, mesh.e_max, mesh.triangles.len(), vec![]).score;
    Ok(Some(TiledLevel {
        bound,
        score,
        kept: mesh.kept,
    }))
}

/// `levels` whole-grid meshes from `front` on `hf`, the root's first: the finest meets the
/// least bound the front allows (`least_bound`) or `finest` when that is larger, and each
/// level above doubles its bound. Levels whose bound no choice meets take the finest choice.
/// Errors: the grid is not the front's.
pub fn tiled_levels(
    front: &TiledFront,
    hf: &Heightfield,
    levels: usize,
    finest: Option<f64>,
) -> Result<Vec<TiledLevel>, String> {
    let least = least_bound(front);
    let base = finest.map_or(least, |f| f.max(least));
    (0..levels)
        .map(|depth| {
            let bound = base * f64::powi(2.0, (levels - 1 - depth) as i32);
            level_within(front, hf, bound)?
                .ok_or_else(|| format!("no choice of the tiled front meets E_max ≤ {bound}"))
        })
        .collect()
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::tiling::{TilePlan, assemble, run_tile};

    /// A wavy `w`×`h` grid and its greedy front over tiles of 33 (64 records a tile).
    pub(in crate::pyramid) fn front(w: usize, h: usize) -> (Heightfield, TiledFront) {
        let z = (0..w * h)
            .map(|i| ((i % w) as f64 * 0.31).sin() * 5.0 + ((i / w) as f64 * 0.17).cos() * 3.0)
            .collect();
        let hf = Heightfield::new(w, h, z).unwrap();
        let plan = TilePlan::new(w, h, 33).unwrap();
        let config = crate::catalogue::Config::from_json(
            crate::catalogue::Algorithm::Greedy,
            &serde_json::json!({"records": 64}),
        )
        .unwrap();
        let fronts = (0..plan.len())
            .map(|i| run_tile(&plan.cut(&hf, i).unwrap(), &plan, i, &config, 1).unwrap())
            .collect();
        (hf, assemble(&plan, fronts).unwrap())
    }

    #[test]
    fn every_tile_meets_the_bound_with_the_fewest_triangles() {
        let (hf, front) = front(70, 50);
        let bound = 1.0;
        let (parts, t) = parts_within(&front, bound).unwrap();
        let mesh = mesh_of_parts(&front.plan, &hf, &parts).unwrap();
        assert!(mesh.e_max <= bound, "{} > {bound}", mesh.e_max);
        assert_eq!(mesh.triangles.len() as u64, t);
        // Brute force over border levels and each tile's candidates: none has fewer triangles.
        let levels: std::collections::BTreeSet<u8> = front
            .tiles
            .iter()
            .flat_map(|t| t.candidates.iter().map(|c| c.level))
            .collect();
        for level in levels {
            let per_tile: Option<u64> = front
                .tiles
                .iter()
                .map(|tile| {
                    tile.candidates
                        .iter()
                        .filter(|c| c.level == level && c.e_max <= bound)
                        .map(|c| c.t)
                        .min()
                })
                .sum();
            if let Some(total) = per_tile {
                assert!(total >= t);
            }
        }
        // Tighter bounds cost triangles; a bound under the least one is met by no choice.
        let least = least_bound(&front);
        assert!(parts_within(&front, least).is_some());
        assert!(parts_within(&front, least * 0.999 - 1e-12).is_none() || least == 0.0);
    }

    #[test]
    fn levels_halve_their_bounds_and_gain_triangles_with_depth() {
        let (hf, front) = front(70, 50);
        let levels = tiled_levels(&front, &hf, 3, Some(0.2)).unwrap();
        for pair in levels.windows(2) {
            assert_eq!(pair[0].bound, 2.0 * pair[1].bound);
            assert!(pair[0].score.t <= pair[1].score.t);
            assert!(pair[1].score.e_max <= pair[1].bound);
        }
    }
}
