//! One tile's front: its optimizer's members with the fixed border points of each border level
//! put in, scored exactly.

use super::algorithm::build_tile;
use super::border::{Side, TileBorders, level_count};
use super::{TilePlan, TilingError};
use crate::catalogue::{Config, Running};
use crate::evaluator::{Evaluator, MeshState};
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// At most this many of a tile optimizer's members are kept, spread evenly over log T: the
/// whole-grid front combines the tiles' members, so it stays fine-grained with far fewer per
/// tile than the tile's own front holds.
pub(crate) const MEMBERS_PER_TILE: usize = 64;

/// Each member is scored at the border levels within this many levels of its own border
/// density (see [`run_tile`]).
pub(super) const LEVEL_REACH: usize = 2;

/// A member of a tile's front at one border level, scored exactly.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TileCandidate {
    /// Which of [`TileFront::members`] it is.
    pub member: u32,
    /// Its border level.
    pub level: u8,
    /// The tile mesh's own E_sum.
    pub e_tile: f64,
    /// Its share of the whole-grid E_sum: `e_tile` less the errors of its left and top border
    /// lines when it shares them with a neighbour (which counts them), so shares add up.
    pub e_share: f64,
    /// The tile mesh's E_max.
    pub e_max: f64,
    /// The tile mesh's triangles.
    pub t: u64,
    /// Its share of the whole grid's Σ (z − z̃)², as `e_share` is of E_sum; recorded by runs
    /// in `rms` or `max` only, so a `sum` run's file is as before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sq_share: Option<f64>,
}

impl TileCandidate {
    /// Its error in `measure` as the whole-grid allocation adds (sum, rms: the shares) or
    /// bounds (max) it.
    pub(crate) fn error_in(&self, measure: ErrorMeasure) -> f64 {
        match measure {
            ErrorMeasure::Sum => self.e_share,
            ErrorMeasure::Rms => self.sq_share.unwrap_or(f64::NAN),
            ErrorMeasure::Max => self.e_max,
        }
    }
}

/// The front of one tile: small, serialisable, and the same bits wherever it is computed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TileFront {
    /// The tile's index in its plan.
    pub index: usize,
    /// Its border lines' rankings, which fix its border points at every level.
    pub borders: TileBorders,
    /// The members' kept points off the border (tile-local indices, increasing). Written as
    /// `PackedSet`s, each whole or as a diff with the member
    /// before it; plain index arrays (older files) are read too.
    #[serde(with = "packed_members")]
    pub members: Vec<Vec<u32>>,
    /// Every member at each border level it was scored at, non-dominated per level.
    pub candidates: Vec<TileCandidate>,
    /// Evaluations the tile's optimizer spent.
    pub evaluations: u64,
    /// The error measure the tile's run minimised (its parameters' `error`); written only
    /// when not `sum`.
    #[serde(default, skip_serializing_if = "ErrorMeasure::is_sum")]
    pub measure: ErrorMeasure,
}

impl TileFront {
    /// The tile-local kept set of candidate `c`: its member's points and its level's border
    /// points (corners are always kept and not listed).
    pub(crate) fn kept(&self, c: &TileCandidate) -> Vec<u32> {
        let mut kept = self.members[c.member as usize].clone();
        kept.extend(self.borders.kept(c.level as usize));
        kept.sort_unstable();
        kept
    }
}

/// The error of tile `index`'s shared border lines that its left and top neighbours count
/// (its own z values `z`, border `level`): what its E share leaves out.
pub(crate) fn unowned_error(
    plan: &TilePlan,
    index: usize,
    borders: &TileBorders,
    z: &[f64],
    level: usize,
) -> f64 {
    unowned_with(plan, index, |side| borders.side_error(side, level, z))
}

/// [`unowned_error`] in squared errors.
pub(super) fn unowned_square_error(
    plan: &TilePlan,
    index: usize,
    borders: &TileBorders,
    z: &[f64],
    level: usize,
) -> f64 {
    unowned_with(plan, index, |side| {
        borders.side_square_error(side, level, z)
    })
}

fn unowned_with(plan: &TilePlan, index: usize, side_error: impl Fn(Side) -> f64) -> f64 {
    let left = plan
        .has_left_neighbour(index)
        .then(|| side_error(Side::Left));
    let top = plan.has_top_neighbour(index).then(|| side_error(Side::Top));
    left.unwrap_or(0.0) + top.unwrap_or(0.0)
}

/// The border level whose interior points per line are nearest (in log scale) to `per_line`.
fn nearest_level(per_line: f64, levels: usize) -> usize {
    if per_line < 0.5 {
        return 0;
    }
    ((per_line.log2() + 1.0).round().max(0.0) as usize).min(levels - 1)
}

/// Up to `count` positions of `ts` (increasing), spread evenly over log T, first and last
/// included.
fn spread(ts: &[usize], count: usize) -> Vec<usize> {
    if ts.len() <= count {
        return (0..ts.len()).collect();
    }
    let (lo, hi) = (
        (ts[0].max(1) as f64).ln(),
        (ts[ts.len() - 1].max(1) as f64).ln(),
    );
    let mut out: Vec<usize> = Vec::with_capacity(count);
    for k in 0..count {
        let target = lo + (hi - lo) * k as f64 / (count - 1) as f64;
        let at = ts.partition_point(|&t| (t.max(1) as f64).ln() < target);
        let at = at.min(ts.len() - 1);
        if out.last() != Some(&at) {
            out.push(at);
        }
    }
    out
}

/// Runs `config` ([`tile_config`](super::tile_config) of it) on tile `index` of `plan`, whose
/// own grid is `tile_hf` (cut by [`TilePlan::cut`] or read by window), and scores its members
/// with the tile's fixed border points. A pure function of its inputs: a tile run in any
/// thread or process gives the same bits. The tile's seed is derived from `seed` and `index`.
///
/// Each kept member (at most `MEMBERS_PER_TILE`) loses its points on the tile's border and is
/// scored at the border levels within `LEVEL_REACH` of the level nearest its own number of
/// points per border line, each level's border points added by editing the previous level's
/// mesh.
pub fn run_tile(
    tile_hf: &Heightfield,
    plan: &TilePlan,
    index: usize,
    config: &Config,
    seed: u64,
) -> Result<TileFront, TilingError> {
    run_tile_keeping(tile_hf, plan, index, config, seed, MEMBERS_PER_TILE)
}

/// [`run_tile`] keeping at most `keep` of the optimizer's members (at least 2) instead of
/// `MEMBERS_PER_TILE`: scoring a member visits every point of the tile, so a quick look at a
/// tile's front keeps fewer.
pub(crate) fn run_tile_keeping(
    tile_hf: &Heightfield,
    plan: &TilePlan,
    index: usize,
    config: &Config,
    seed: u64,
    keep: usize,
) -> Result<TileFront, TilingError> {
    let hf = Arc::new(tile_hf.clone());
    let optimizer = build_tile(hf.clone(), plan, index, config, seed)?;
    run_built_tile(hf, optimizer, plan, index, keep)
}

/// [`run_tile_keeping`] with the tile's optimizer already built on its grid `hf` (by
/// [`build_tile`]).
pub(crate) fn run_built_tile(
    hf: Arc<Heightfield>,
    mut optimizer: Box<dyn Running>,
    plan: &TilePlan,
    index: usize,
    keep: usize,
) -> Result<TileFront, TilingError> {
    let tile = plan.tile(index).ok_or(TilingError::NoSuchTile {
        index,
        tiles: plan.len(),
    })?;
    let progress = optimizer.run_to_end();
    // The measure the method ran in, which its Config's `error` chose.
    let measure = optimizer.front().measure();
    let (w, h) = (tile.w, tile.h);
    let borders = TileBorders::new(w, h, hf.z());
    let levels = level_count(plan.tile_size());
    let unowned: Vec<f64> = (0..levels)
        .map(|level| unowned_error(plan, index, &borders, hf.z(), level))
        .collect();
    // Squared shares only where a measure reads them, so a sum run does no extra work.
    let unowned_sq: Vec<f64> = if measure.is_sum() {
        Vec::new()
    } else {
        (0..levels)
            .map(|level| unowned_square_error(plan, index, &borders, hf.z(), level))
            .collect()
    };
    let points = hf.len() as f64;
    let solutions = optimizer.front().solutions();
    let ts: Vec<usize> = solutions.iter().map(|s| s.t).collect();
    let mut evaluator = Evaluator::new(hf.clone());
    let mut state = MeshState::default();
    let border_sets: Vec<Vec<u32>> = (0..levels).map(|l| borders.kept(l)).collect();
    let mut members = Vec::new();
    let mut candidates = Vec::new();
    for at in spread(&ts, keep.max(2)) {
        let kept = &solutions[at].kept;
        let on_border = kept.iter().filter(|&&i| borders.on_border(i)).count();
        let corners = 4;
        let per_line = on_border.saturating_sub(corners) as f64 / 4.0;
        let centre = nearest_level(per_line, levels);
        let (first, last) = (
            centre.saturating_sub(LEVEL_REACH),
            (centre + LEVEL_REACH).min(levels - 1),
        );
        let interior: Vec<u32> = kept
            .iter()
            .copied()
            .filter(|&i| !borders.on_border(i))
            .collect();
        let member = members.len() as u32;
        let mut start = interior.clone();
        start.extend_from_slice(&border_sets[first]);
        start.sort_unstable();
        let mut score = evaluator
            .score_into(&start, &mut state)
            .map_err(|e| TilingError::Evaluate(e.to_string()))?;
        for level in first..=last {
            if level > first {
                let added: Vec<u32> = border_sets[level]
                    .iter()
                    .copied()
                    .filter(|i| border_sets[level - 1].binary_search(i).is_err())
                    .collect();
                score = evaluator
                    .edit(&mut state, &[], &added)
                    .map_err(|e| TilingError::Evaluate(e.to_string()))?;
            }
            candidates.push(TileCandidate {
                member,
                level: level as u8,
                e_tile: score.e_sum,
                e_share: score.e_sum - unowned[level],
                e_max: score.e_max,
                t: score.t as u64,
                sq_share: (!measure.is_sum())
                    .then(|| score.rms * score.rms * points - unowned_sq[level]),
            });
        }
        members.push(interior);
    }
    let candidates = non_dominated_per_level(candidates, measure);
    // Members no candidate names are dropped, and the candidates renumbered.
    let mut used = vec![u32::MAX; members.len()];
    let mut kept_members = Vec::new();
    let mut out = Vec::with_capacity(candidates.len());
    for mut c in candidates {
        let m = c.member as usize;
        if used[m] == u32::MAX {
            used[m] = kept_members.len() as u32;
            kept_members.push(std::mem::take(&mut members[m]));
        }
        c.member = used[m];
        out.push(c);
    }
    Ok(TileFront {
        index,
        borders,
        members: kept_members,
        candidates: out,
        evaluations: progress.evaluations,
        measure,
    })
}

/// [`TileFront::members`] as front.json holds them.
mod packed_members {
    use crate::kept_codec::{PackedSet, pack_list};
    use serde::de::Error as _;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// A member as read: packed (see [`PackedSet`]) or a plain index array.
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Read {
        Plain(Vec<u32>),
        Packed(PackedSet),
    }

    pub(super) fn serialize<S: Serializer>(members: &[Vec<u32>], s: S) -> Result<S::Ok, S::Error> {
        pack_list(members).serialize(s)
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<u32>>, D::Error> {
        let read = Vec::<Read>::deserialize(d)?;
        let mut out: Vec<Vec<u32>> = Vec::with_capacity(read.len());
        for (i, r) in read.into_iter().enumerate() {
            let kept = match r {
                Read::Plain(kept) => kept,
                Read::Packed(p) => p
                    .unpack(out.last().map(Vec::as_slice), &format!("tile member {i}"))
                    .map_err(D::Error::custom)?,
            };
            out.push(kept);
        }
        Ok(out)
    }
}

/// The candidates no other of the same level dominates in (their error in `measure`, T), by
/// level then T.
fn non_dominated_per_level(
    mut candidates: Vec<TileCandidate>,
    measure: ErrorMeasure,
) -> Vec<TileCandidate> {
    let e = |c: &TileCandidate| c.error_in(measure);
    candidates.sort_by(|a, b| {
        a.level
            .cmp(&b.level)
            .then(a.t.cmp(&b.t))
            .then(e(a).total_cmp(&e(b)))
            .then(a.member.cmp(&b.member))
    });
    let mut out: Vec<TileCandidate> = Vec::with_capacity(candidates.len());
    for c in candidates {
        match out.last() {
            Some(last) if last.level == c.level && e(&c) >= e(last) => {}
            _ => out.push(c),
        }
    }
    out
}
