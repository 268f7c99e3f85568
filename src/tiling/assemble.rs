//! The whole-grid front of a tiled run, assembled from its tiles' fronts.

use super::allocation::{TileOption, allocate};
use super::border::level_count;
use super::tile_front::TileFront;
use super::{TilePlan, TilingError};
use crate::front::dominates;
use serde::{Deserialize, Serialize};

/// One whole-grid member: a border level and one candidate per tile at that level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TiledMember {
    /// E_sum of the assembled mesh, each grid point counted once.
    #[serde(rename = "E_sum")]
    pub e_sum: f64,
    /// E_max of the assembled mesh.
    #[serde(rename = "E_max")]
    pub e_max: f64,
    /// Triangles of the assembled mesh.
    #[serde(rename = "T")]
    pub t: u64,
    /// The border level every tile uses.
    pub level: u8,
    /// Per tile, the index of its candidate in [`TileFront::candidates`].
    pub choice: Vec<u32>,
}

/// The whole-grid front of a tiled run: the plan, every tile's front and the members, each
/// naming one candidate per tile. Its mesh is the union of the chosen tile meshes (see
/// [`TiledFront::mesh`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TiledFront {
    /// How the grid was cut.
    pub plan: TilePlan,
    /// The tiles' fronts, by tile index.
    pub tiles: Vec<TileFront>,
    /// The non-dominated whole-grid members, by increasing T.
    pub members: Vec<TiledMember>,
}

impl TiledFront {
    /// Evaluations spent by every tile's optimizer.
    pub fn evaluations(&self) -> u64 {
        self.tiles.iter().map(|t| t.evaluations).sum()
    }

    /// The member of least error within `t` triangles, if any.
    pub fn within(&self, t: u64) -> Option<&TiledMember> {
        self.members.iter().rev().find(|m| m.t <= t)
    }
}

/// The whole-grid front of `plan` from its tiles' fronts (in any order, one per tile): for each
/// border level, every tile's candidates at that level are allocated (see `allocation.rs`), and
/// the non-dominated allocations of all levels are the members. Their E_sum, E_max and T are
/// those of the assembled mesh: shared border lines are counted once (each candidate's E
/// share leaves out the lines its neighbour counts), triangles add up, and E_max is the largest
/// tile's.
pub fn assemble(plan: &TilePlan, mut tiles: Vec<TileFront>) -> Result<TiledFront, TilingError> {
    tiles.sort_by_key(|t| t.index);
    let indices: Vec<usize> = tiles.iter().map(|t| t.index).collect();
    if indices != (0..plan.len()).collect::<Vec<_>>() {
        return Err(TilingError::WrongTiles {
            expected: plan.len(),
            given: indices,
        });
    }
    for t in &tiles {
        let tile = plan.tile(t.index).expect("indices were checked");
        if (t.borders.w, t.borders.h) != (tile.w, tile.h) {
            return Err(TilingError::GridMismatch {
                plan: (tile.w, tile.h),
                grid: (t.borders.w, t.borders.h),
            });
        }
    }
    let mut members: Vec<TiledMember> = Vec::new();
    for level in 0..level_count(plan.tile_size()) {
        // Per tile, its candidates at this level: their positions and their options.
        let picks: Vec<Vec<usize>> = tiles
            .iter()
            .map(|t| {
                (0..t.candidates.len())
                    .filter(|&c| t.candidates[c].level as usize == level)
                    .collect()
            })
            .collect();
        let options: Vec<Vec<TileOption>> = tiles
            .iter()
            .zip(&picks)
            .map(|(t, p)| {
                p.iter()
                    .map(|&c| {
                        let c = &t.candidates[c];
                        TileOption {
                            e: c.e_share,
                            e_max: c.e_max,
                            t: c.t,
                        }
                    })
                    .collect()
            })
            .collect();
        for a in allocate(&options) {
            members.push(TiledMember {
                e_sum: a.e,
                e_max: a.e_max,
                t: a.t,
                level: level as u8,
                choice: a
                    .choice
                    .iter()
                    .zip(&picks)
                    .map(|(&o, p)| p[o] as u32)
                    .collect(),
            });
        }
    }
    Ok(TiledFront {
        plan: plan.clone(),
        tiles,
        members: non_dominated(members),
    })
}

/// The members no other dominates in (E_sum, T), by increasing T; of equal ones, the first
/// (lowest level) stays.
fn non_dominated(mut members: Vec<TiledMember>) -> Vec<TiledMember> {
    members.sort_by(|a, b| {
        a.t.cmp(&b.t)
            .then(a.e_sum.total_cmp(&b.e_sum))
            .then(a.level.cmp(&b.level))
    });
    let mut out: Vec<TiledMember> = Vec::with_capacity(members.len());
    for m in members {
        let o = [m.e_sum, m.t as f64];
        if out
            .last()
            .is_none_or(|l| !(dominates([l.e_sum, l.t as f64], o) || [l.e_sum, l.t as f64] == o))
        {
            out.push(m);
        }
    }
    out
}
