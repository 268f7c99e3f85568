//! A terrain tile pyramid for web globes (3D Tiles 1.1): each quadtree level shows one whole-grid
//! member of a front, the coarsest level the fewest triangles, cut into the level's 2^L × 2^L
//! tiles that share their border edges exactly.
//!
//! [`plan`] picks a member per level, `quadtree::Level` cuts a level into tiles and shares the
//! member's kept points out to them (with `borders`' points on inner tile borders, so that a
//! border follows the surface within the member's E_max), `tileset::tile_content` triangulates
//! and encodes one tile, and `tileset::tileset_json` ties the tiles together. `build` does it
//! all in one thread (the app's download); the CLI spreads the tiles over every core through
//! [`build_with`], with the same result. The files are private; what callers need is
//! re-exported here.

pub(crate) mod borders;
pub(crate) mod budget;
pub(crate) mod budget_levels;
pub(crate) mod globe;
pub(crate) mod quadtree;
pub(crate) mod refine;
pub(crate) mod tile_mesh;
mod tiled_levels;
mod tileset;

pub use budget_levels::MapTiles;
pub(crate) use budget_levels::{budget_levels, ladder_of};
pub use globe::{Frame, MapSystem};
pub(crate) use quadtree::Tile;
// Terrain tiles and the budgeted levels pick their levels by it.
pub(crate) use tiled_levels::level_within;
pub use tiled_levels::tiled_levels;
pub(crate) use tileset::TileContent;

/// The parts a pyramid is made of, for the crate's tests (the `test-support` feature); not part
/// of the API.
#[cfg(feature = "test-support")]
#[doc(hidden)]
pub use {
    borders::with_border_points, globe::ecef, quadtree::Level, tile_mesh::TileMesh,
    tile_mesh::tile_mesh,
};

use crate::evaluator::Score;
use crate::heightfield::Heightfield;
use quadtree::max_level;
use serde_json::Value;
use std::fmt;
use tileset::{LevelNote, content_uri, tile_content, tileset_json};

/// Each level's triangle budget is this many times its parent's.
pub(crate) const GROWTH: usize = 4;

/// Why a pyramid cannot be made.
#[derive(Clone, Debug, PartialEq)]
pub enum PyramidError {
    /// The front has fewer than two members: there is no ladder of detail to build.
    TooFewMembers { members: usize },
    /// Zero levels were asked for.
    NoLevels,
    /// More levels than the front has distinct triangle counts.
    MoreLevelsThanMembers { levels: usize, distinct: usize },
    /// More levels than the grid can cut into tiles of two cells or more per side.
    TilesTooSmall {
        levels: usize,
        most: usize,
        width: usize,
        height: usize,
    },
}

impl fmt::Display for PyramidError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewMembers { members } => write!(
                f,
                "the front has {members} member; a pyramid needs at least two members of different detail"
            ),
            Self::NoLevels => write!(f, "a pyramid needs at least one level"),
            Self::MoreLevelsThanMembers { levels, distinct } => write!(
                f,
                "too many levels: {levels} levels need {levels} members of different triangle counts, and the front has {distinct}; ask for at most {distinct} levels"
            ),
            Self::TilesTooSmall {
                levels,
                most,
                width,
                height,
            } => write!(
                f,
                "too many levels: {levels} levels cut the {width}×{height} grid into {side}×{side} tiles, under two grid cells per side; this grid takes at most {most} levels",
                side = 1usize << (levels - 1)
            ),
        }
    }
}

impl std::error::Error for PyramidError {}

/// The most levels a `width` × `height` grid takes.
pub fn most_levels(width: usize, height: usize) -> usize {
    max_level(width, height) as usize + 1
}

/// The member (index into `members`) each of `levels` levels shows, the root's first.
///
/// The finest level shows the member of least E_sum. Each coarser level's budget is the finest
/// member's T divided by `GROWTH` per level up; it shows the member of least E_sum within its
/// budget among those with fewer triangles than the level below, keeping enough members with
/// fewer triangles still for the levels above it (when none fits the budget, the fewest
/// triangles it may take). Triangle counts therefore fall strictly towards the root.
pub fn plan(
    members: &[Score],
    levels: usize,
    width: usize,
    height: usize,
) -> Result<Vec<usize>, PyramidError> {
    if members.len() < 2 {
        return Err(PyramidError::TooFewMembers {
            members: members.len(),
        });
    }
    if levels == 0 {
        return Err(PyramidError::NoLevels);
    }
    let most = most_levels(width, height);
    if levels > most {
        return Err(PyramidError::TilesTooSmall {
            levels,
            most,
            width,
            height,
        });
    }
    let mut counts: Vec<usize> = members.iter().map(|m| m.t).collect();
    counts.sort_unstable();
    counts.dedup();
    if levels > counts.len() {
        return Err(PyramidError::MoreLevelsThanMembers {
            levels,
            distinct: counts.len(),
        });
    }
    let better = |&i: &usize, &j: &usize| {
        let (a, b): (&Score, &Score) = (&members[i], &members[j]);
        a.e_sum
            .total_cmp(&b.e_sum)
            .then(a.t.cmp(&b.t))
            .then(i.cmp(&j))
    };
    let finest = (0..members.len()).min_by(better).expect("two members");
    let mut picks = vec![finest; levels];
    for level in (0..levels.saturating_sub(1)).rev() {
        let above_finer = members[picks[level + 1]].t;
        // The level needs `level` distinct counts below its own for the levels above.
        let least = counts[level];
        let budget = members[finest].t / GROWTH.pow((levels - 1 - level) as u32);
        let allowed: Vec<usize> = (0..members.len())
            .filter(|&i| members[i].t < above_finer && members[i].t >= least)
            .collect();
        let within = allowed.iter().copied().filter(|&i| members[i].t <= budget);
        picks[level] = match within.min_by(better) {
            Some(i) => i,
            None => allowed
                .iter()
                .copied()
                .filter(|&i| members[i].t == least)
                .min_by(better)
                .expect("counts[level] is below the finer level's count"),
        };
    }
    Ok(picks)
}

/// Levels when none are asked for, fewer when the grid or the front has fewer.
pub const DEFAULT_LEVELS: usize = 4;

/// The levels a pyramid of a front of `members` on a `width` × `height` grid gets when none are
/// asked for: `DEFAULT_LEVELS`, or fewer when the grid or the front's distinct triangle
/// counts allow fewer.
pub fn default_levels(members: &[Score], width: usize, height: usize) -> usize {
    let mut ts: Vec<usize> = members.iter().map(|s| s.t).collect();
    ts.sort_unstable();
    ts.dedup();
    DEFAULT_LEVELS
        .min(most_levels(width, height))
        .min(ts.len().max(1))
}

/// A whole pyramid in memory: each level's tiles (row by row) and tileset.json.
#[derive(Clone, Debug)]
pub struct Pyramid {
    /// Level 0 (the root) first.
    pub levels: Vec<Vec<TileContent>>,
    /// The member each level shows, the root's first.
    pub picks: Vec<usize>,
    /// Why the pyramid stays in the input's own coordinates, when the grid has a map system
    /// that cannot be placed on the globe.
    pub why_local: Option<String>,
    /// The tileset.
    pub tileset: Value,
}

impl Pyramid {
    /// The pyramid's files as (path relative to the pyramid's folder, bytes): tileset.json
    /// first, then every tile's glb, level by level.
    pub fn into_files(self) -> Vec<(String, Vec<u8>)> {
        let text = serde_json::to_string_pretty(&self.tileset).expect("a JSON value serialises");
        let mut files = vec![("tileset.json".to_owned(), text.into_bytes())];
        for content in self.levels.into_iter().flatten() {
            files.push((content_uri(&content.tile), content.glb));
        }
        files
    }
}

/// The frame's description for tileset.json.
pub(crate) fn frame_note(frame: &Frame, why_local: Option<&str>) -> String {
    match (frame, why_local) {
        (Frame::Globe { system, .. }, _) => {
            format!("east-north-up metres at the grid's centre on WGS84, from {system}")
        }
        (Frame::Local, Some(why)) => format!("the input's own coordinates: {why}"),
        (Frame::Local, None) => "the input's own coordinates (not georeferenced)".into(),
    }
}

/// One level's tiles and each tile's share of the kept points, to be turned into contents with
/// `tile_content`; a [`build_with`] caller chooses how (in one thread or spread over cores).
pub struct LevelWork<'a> {
    /// The grid.
    pub hf: &'a Heightfield,
    /// Where the tiles are placed.
    pub frame: &'a Frame,
    /// The level's tiles, row by row.
    pub tiles: Vec<Tile>,
    /// Each tile's kept points, border points included.
    pub shares: Vec<Vec<u32>>,
    /// The bound each tile's mesh is refined to meet (its worst off-border points added), if any.
    pub bound: Option<f64>,
}

impl LevelWork<'_> {
    /// The content of tile `i`.
    pub fn content(&self, i: usize) -> Result<TileContent, String> {
        match self.bound {
            None => tile_content(self.hf, self.frame, &self.tiles[i], &self.shares[i]),
            Some(bound) => {
                let (share, _) =
                    refine::refine_share_best(self.hf, &self.tiles[i], &self.shares[i], bound)?;
                tile_content(self.hf, self.frame, &self.tiles[i], &share)
            }
        }
    }
}

/// Builds the pyramid of `hf`'s front (each member's score and kept set) showing member
/// `picks[L]` at level L, with `contents` turning each level's work into its tiles' contents
/// in tile order. Members' kept indices must lie within the grid.
pub fn build_with(
    hf: &Heightfield,
    scores: &[Score],
    kept: &[&[u32]],
    picks: &[usize],
    contents: impl Fn(&LevelWork) -> Result<Vec<TileContent>, String>,
) -> Result<Pyramid, String> {
    build_levels(hf, scores, kept, picks, None, contents)
}

/// [`build_with`] for levels chosen from a tiled front (level L shows member L), each tile's
/// mesh refined until it meets its level's bound `bounds[L]`: cut from a whole-grid mesh, a
/// tile's own triangulation may otherwise miss the bound its run tiles met.
pub fn build_refined(
    hf: &Heightfield,
    scores: &[Score],
    kept: &[&[u32]],
    bounds: &[f64],
    contents: impl Fn(&LevelWork) -> Result<Vec<TileContent>, String>,
) -> Result<Pyramid, String> {
    let picks: Vec<usize> = (0..scores.len()).collect();
    build_levels(hf, scores, kept, &picks, Some(bounds), contents)
}

fn build_levels(
    hf: &Heightfield,
    scores: &[Score],
    kept: &[&[u32]],
    picks: &[usize],
    bounds: Option<&[f64]>,
    contents: impl Fn(&LevelWork) -> Result<Vec<TileContent>, String>,
) -> Result<Pyramid, String> {
    let (frame, why_local) = Frame::of(hf);
    let mut out = Vec::with_capacity(picks.len());
    for (depth, &member) in picks.iter().enumerate() {
        let level = quadtree::Level::new(hf.width(), hf.height(), depth as u32);
        let bound = bounds.map(|b| b[depth]);
        let tolerance = bound.unwrap_or(scores[member].e_max);
        let with_borders = borders::with_border_points(hf, &level, kept[member], tolerance);
        let work = LevelWork {
            hf,
            frame: &frame,
            shares: level.share_out(&with_borders),
            tiles: level.tiles(),
            bound,
        };
        out.push(contents(&work)?);
    }
    let tileset = tileset_json(
        &out,
        &notes(scores, picks),
        &frame,
        &frame_note(&frame, why_local.as_deref()),
        hf.z_range(),
    );
    Ok(Pyramid {
        levels: out,
        picks: picks.to_vec(),
        why_local,
        tileset,
    })
}

/// The pyramid of `levels` levels from a tiled `front` on `hf` that spends at most `budget`
/// triangles over all its tiles where the error falls most (`budget`), down to the bound
/// `finest`; `map` makes the tiles' meshes (in one thread or over cores) and `contents` turns
/// each level's tiles into contents, as in [`build_with`].
pub fn build_budget(
    hf: &Heightfield,
    front: &crate::tiling::TiledFront,
    levels: usize,
    finest: f64,
    budget: u64,
    map: MapTiles,
    contents: impl Fn(&LevelWork) -> Result<Vec<TileContent>, String>,
) -> Result<Pyramid, String> {
    let (frame, why_local) = Frame::of(hf);
    let cuts: Vec<quadtree::Level> = (0..levels as u32)
        .map(|d| quadtree::Level::new(hf.width(), hf.height(), d))
        .collect();
    let ladder = ladder_of(front, hf, levels, finest)?;
    let meshes = budget_levels(hf, &cuts, &ladder, budget, map)?;
    let mut out = Vec::with_capacity(levels);
    let mut notes = Vec::with_capacity(levels);
    for (depth, (level, list)) in cuts.iter().zip(meshes).enumerate() {
        notes.push(LevelNote {
            member: depth,
            t: list.iter().map(|m| m.1.triangles.len()).sum(),
            e_sum: None,
            e_max: list.iter().map(|m| m.1.e_max).fold(0.0, f64::max),
        });
        // Each tile's kept set triangulates to the mesh the budget chose.
        let work = LevelWork {
            hf,
            frame: &frame,
            tiles: level.tiles(),
            shares: list.into_iter().map(|m| m.0).collect(),
            bound: None,
        };
        out.push(contents(&work)?);
    }
    let tileset = tileset_json(
        &out,
        &notes,
        &frame,
        &frame_note(&frame, why_local.as_deref()),
        hf.z_range(),
    );
    Ok(Pyramid {
        levels: out,
        picks: (0..levels).collect(),
        why_local,
        tileset,
    })
}

/// Builds the pyramid of `levels` levels of `hf`'s front, given as each member's score and
/// kept set, in one thread.
pub(crate) fn build(
    hf: &Heightfield,
    scores: &[Score],
    kept: &[&[u32]],
    levels: usize,
) -> Result<Pyramid, String> {
    let picks = plan(scores, levels, hf.width(), hf.height()).map_err(|e| e.to_string())?;
    if let Some((member, &bad)) = picks.iter().find_map(|&m| {
        kept[m]
            .iter()
            .find(|&&g| g as usize >= hf.len())
            .map(|g| (m, g))
    }) {
        return Err(format!(
            "member {member} keeps grid index {bad}, past the grid's {} points",
            hf.len()
        ));
    }
    build_with(hf, scores, kept, &picks, |work| {
        (0..work.tiles.len()).map(|i| work.content(i)).collect()
    })
}

/// Each level's member as tileset.json records it.
pub(crate) fn notes(scores: &[Score], picks: &[usize]) -> Vec<LevelNote> {
    picks
        .iter()
        .map(|&member| LevelNote {
            member,
            t: scores[member].t,
            e_sum: Some(scores[member].e_sum),
            e_max: scores[member].e_max,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::front::Solution;

    fn scores(list: &[(f64, usize)]) -> Vec<Score> {
        list.iter()
            .map(|&(e, t)| Solution::recorded(e, e / 10.0, t, vec![]).score)
            .collect()
    }

    #[test]
    fn levels_take_falling_triangle_counts_near_their_budgets() {
        // T from 2 to 4096; the finest level is the most accurate member.
        let members = scores(&[
            (900.0, 2),
            (500.0, 16),
            (300.0, 60),
            (200.0, 250),
            (100.0, 1000),
            (50.0, 4096),
            (60.0, 3000),
        ]);
        let picks = plan(&members, 4, 257, 257).unwrap();
        let ts: Vec<usize> = picks.iter().map(|&i| members[i].t).collect();
        // Budgets 64, 256, 1024, 4096.
        assert_eq!(ts, vec![60, 250, 1000, 4096]);
    }

    #[test]
    fn a_sparse_front_still_gives_each_level_its_own_member() {
        let members = scores(&[(900.0, 2), (10.0, 5000), (20.0, 4900)]);
        let picks = plan(&members, 3, 257, 257).unwrap();
        let ts: Vec<usize> = picks.iter().map(|&i| members[i].t).collect();
        assert_eq!(ts, vec![2, 4900, 5000]);
    }

    #[test]
    fn bad_requests_are_named() {
        let one = scores(&[(1.0, 2)]);
        assert_eq!(
            plan(&one, 2, 33, 33),
            Err(PyramidError::TooFewMembers { members: 1 })
        );
        let two = scores(&[(2.0, 2), (1.0, 8), (1.5, 8)]);
        assert_eq!(
            plan(&two, 3, 33, 33),
            Err(PyramidError::MoreLevelsThanMembers {
                levels: 3,
                distinct: 2
            })
        );
        assert_eq!(plan(&two, 0, 33, 33), Err(PyramidError::NoLevels));
        let many = scores(
            &(1..40)
                .map(|t| (100.0 / t as f64, t * 2))
                .collect::<Vec<_>>(),
        );
        let err = plan(&many, 6, 33, 33).unwrap_err();
        assert_eq!(
            err,
            PyramidError::TilesTooSmall {
                levels: 6,
                most: 5,
                width: 33,
                height: 33
            }
        );
        assert!(err.to_string().contains("at most 5 levels"), "{err}");
    }
}
