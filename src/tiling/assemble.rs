//! The whole-grid front of a tiled run, assembled from its tiles' fronts.

use super::allocation::{TileOption, allocate, allocate_max};
use super::border::level_count;
use super::tile_front::TileFront;
use super::{TilePlan, TilingError};
use crate::front::dominates;
use crate::measure::ErrorMeasure;
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
    /// RMS of the assembled mesh, from the tiles' squared-error shares; recorded by runs in
    /// `rms` or `max` only.
    #[serde(rename = "RMS", default, skip_serializing_if = "Option::is_none")]
    pub rms: Option<f64>,
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

    /// The error measure the members are non-dominated in (the tiles' runs').
    pub fn measure(&self) -> ErrorMeasure {
        self.tiles.first().map_or(ErrorMeasure::Sum, |t| t.measure)
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
///
/// The members are non-dominated in the tiles' error measure: for `sum` the allocation adds E
/// shares, for `rms` squared-error shares (RMS grows with their sum), and for `max` each
/// whole-grid member is, at a bound on E_max, the fewest total T with every tile's E_max
/// within it ([`allocate_max`]). Tiles run in different measures are refused.
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
    let measure = tiles.first().map_or(ErrorMeasure::Sum, |t| t.measure);
    if let Some(other) = tiles.iter().find(|t| t.measure != measure) {
        return Err(TilingError::BadParams {
            algorithm: "tiles".to_string(),
            reason: format!(
                "tile 0 was run in error measure {measure}, tile {} in {}",
                other.index, other.measure
            ),
        });
    }
    let points = (plan.width() * plan.height()) as f64;
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
                            e: match measure {
                                ErrorMeasure::Rms => c.error_in(measure),
                                ErrorMeasure::Sum | ErrorMeasure::Max => c.e_share,
                            },
                            e_max: c.e_max,
                            t: c.t,
                        }
                    })
                    .collect()
            })
            .collect();
        let allocations = match measure {
            ErrorMeasure::Max => allocate_max(&options),
            ErrorMeasure::Sum | ErrorMeasure::Rms => allocate(&options),
        };
        for a in allocations {
            let chosen = || {
                a.choice
                    .iter()
                    .zip(&picks)
                    .zip(&tiles)
                    .map(|((&o, p), t)| &t.candidates[p[o]])
            };
            // E_sum adds the shares in tile order, as the allocation adds its E.
            let e_sum = match measure {
                ErrorMeasure::Rms => chosen().fold(0.0, |e, c| e + c.e_share),
                ErrorMeasure::Sum | ErrorMeasure::Max => a.e,
            };
            let rms = (!measure.is_sum()).then(|| {
                let sq = chosen().fold(0.0, |e, c| e + c.sq_share.unwrap_or(f64::NAN));
                (sq.max(0.0) / points).sqrt()
            });
            members.push(TiledMember {
                e_sum,
                e_max: a.e_max,
                rms,
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
        members: non_dominated(members, measure),
    })
}

/// The members no other dominates in (their error in `measure`, T), by increasing T; of equal
/// ones, the first (lowest level) stays.
fn non_dominated(mut members: Vec<TiledMember>, measure: ErrorMeasure) -> Vec<TiledMember> {
    let e = |m: &TiledMember| match measure {
        ErrorMeasure::Sum => m.e_sum,
        ErrorMeasure::Rms => m.rms.unwrap_or(f64::NAN),
        ErrorMeasure::Max => m.e_max,
    };
    members.sort_by(|a, b| {
        a.t.cmp(&b.t)
            .then(e(a).total_cmp(&e(b)))
            .then(a.level.cmp(&b.level))
    });
    let mut out: Vec<TiledMember> = Vec::with_capacity(members.len());
    for m in members {
        let o = [e(&m), m.t as f64];
        if out
            .last()
            .is_none_or(|l| !(dominates([e(l), l.t as f64], o) || [e(l), l.t as f64] == o))
        {
            out.push(m);
        }
    }
    out
}
