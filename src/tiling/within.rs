//! One mesh within a max error X over tiles, the tiles run in parallel (native builds only).
//!
//! Every border line keeps the shortest prefix of its 1-D ranking (`border`) whose largest
//! error is at most X: a function of the line's profile and X alone, so both tiles that share
//! a line keep the same points on it and the mesh has no cracks. Each tile then runs greedy
//! insertion of its worst point from its start and those border points until its E_max ≤ X,
//! and bounded-error decimation with its border vertices fixed. The tile's errors on a border
//! line are the 2-D triangles' interpolation, which can differ from the line's 1-D one by a
//! rounding; where that makes a tile insert a border point, the line's prefix grows to hold it
//! and both of its tiles run again, until no tile adds one. Each round is a pure function of
//! the prefixes, so the mesh has the same bits for any number of threads.

use super::assemble::{TiledFront, assemble};
use super::border::{Side, TileBorders, level_count, ranked};
use super::tile_front::{TileCandidate, TileFront, unowned_error, unowned_square_error};
use super::{TilePlan, TilingError};
use crate::baselines::MaxErrorMesh;
use crate::baselines::max_error_mesh::tile_mesh_within;
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::sync::Arc;

/// A tiled mesh within a max error and how it was reached.
#[derive(Clone, Debug, PartialEq)]
pub struct TiledWithin {
    /// The mesh as a tiled front of one member (its tiles' border lines hold exactly the
    /// points the mesh keeps on them), so that `export` and the browser rebuild it as any
    /// tiled member.
    pub front: TiledFront,
    /// Points greedy insertion added over all tiles (in the last run of each tile).
    pub inserted: u64,
    /// Points the decimation removed over all tiles.
    pub removed: usize,
    /// Rounds of tile runs: 1 unless a tile added a border point (see the module doc).
    pub rounds: usize,
}

/// A border line of the whole grid: vertical or not, the column or row it lies on, and the
/// row or column it starts at (lines of the same tile row or column share their ends only).
type Line = (bool, usize, usize);

/// The lines of tile `index`'s sides, in [`Side::ALL`] order.
fn lines_of(plan: &TilePlan, index: usize) -> [Line; 4] {
    let t = plan.tile(index).expect("indices come from the plan");
    Side::ALL.map(|side| match side {
        Side::Top => (false, t.y0, t.x0),
        Side::Bottom => (false, t.y0 + t.h - 1, t.x0),
        Side::Left => (true, t.x0, t.y0),
        Side::Right => (true, t.x0 + t.w - 1, t.y0),
    })
}

/// The number of a line's ranked points to keep for its largest error to be at most `x`.
fn prefix_within(ranking: &[(u32, f64)], x: f64) -> usize {
    ranking
        .iter()
        .position(|&(_, e)| e <= x)
        .unwrap_or(ranking.len())
}

/// The mesh within `x` over the tiles of `plan` on `hf`, on `threads` threads (0 = every
/// core). `starts` gives each tile's points to start from (tile-local indices, in tile
/// order; points on a tile's border are ignored), or `None` to start from the corners and the
/// border points. Errors: the grid is not the plan's, `starts` has not one entry per tile,
/// or `x` is refused (negative, not finite, or under the grid's exactness floor).
pub fn tiled_mesh_within(
    hf: &Heightfield,
    plan: &TilePlan,
    starts: Option<&[Vec<u32>]>,
    x: f64,
    threads: usize,
) -> Result<TiledWithin, TilingError> {
    plan.check_grid(hf)?;
    if let Some(s) = starts
        && s.len() != plan.len()
    {
        return Err(TilingError::WrongTiles {
            expected: plan.len(),
            given: (0..s.len()).collect(),
        });
    }
    if !(x >= 0.0 && x.is_finite()) {
        return Err(bad(format!(
            "a max error of {x} is refused: give a finite number ≥ 0"
        )));
    }
    let floor = crate::baselines::exactness_floor(hf);
    if x > 0.0 && x < floor {
        return Err(bad(format!(
            "a max error of {x} is below the grid's exactness floor {floor:e}: give 0 for an exact mesh, or at least the floor"
        )));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| TilingError::Threads(e.to_string()))?;
    pool.install(|| run_rounds(hf, plan, starts, x))
}

/// [`tiled_mesh_within`] from member `member` of the tiled front `front` made on `hf`: each
/// tile starts from the member's interior points in it, its border lines from their prefixes
/// for `x` (not the member's border level), so the mesh is the member refined where it is
/// above `x` and decimated where it is within.
pub fn tiled_member_within(
    hf: &Heightfield,
    front: &TiledFront,
    member: usize,
    x: f64,
    threads: usize,
) -> Result<TiledWithin, TilingError> {
    let starts: Vec<Vec<u32>> = front.parts(member)?.into_iter().map(|p| p.kept).collect();
    tiled_mesh_within(hf, &front.plan, Some(&starts), x, threads)
}

fn bad(reason: String) -> TilingError {
    TilingError::BadParams {
        algorithm: crate::catalogue::Algorithm::Greedy,
        reason,
    }
}

/// One tile as the rounds see it.
struct TileWork {
    hf: Arc<Heightfield>,
    /// Its sides' rankings with errors, in [`Side::ALL`] order.
    ranking: [Vec<(u32, f64)>; 4],
    lines: [Line; 4],
    /// Its interior start points.
    start: Vec<u32>,
    made: Option<MaxErrorMesh>,
}

fn run_rounds(
    hf: &Heightfield,
    plan: &TilePlan,
    starts: Option<&[Vec<u32>]>,
    x: f64,
) -> Result<TiledWithin, TilingError> {
    let mut work: Vec<TileWork> = (0..plan.len())
        .into_par_iter()
        .map(|index| {
            let tile_hf = Arc::new(plan.cut(hf, index)?);
            let (w, h) = (tile_hf.width(), tile_hf.height());
            let z = tile_hf.z();
            let ranking = Side::ALL.map(|side| {
                let profile: Vec<f64> = (0..side.length(w, h))
                    .map(|p| z[side.local_index(p, w, h) as usize])
                    .collect();
                ranked(&profile)
            });
            let on_border = |i: u32| {
                let (px, py) = (i as usize % w, i as usize / w);
                px == 0 || py == 0 || px + 1 == w || py + 1 == h
            };
            let start = starts.map_or_else(Vec::new, |s| {
                s[index]
                    .iter()
                    .copied()
                    .filter(|&i| (i as usize) < w * h && !on_border(i))
                    .collect()
            });
            Ok(TileWork {
                hf: tile_hf,
                ranking,
                lines: lines_of(plan, index),
                start,
                made: None,
            })
        })
        .collect::<Result<_, TilingError>>()?;
    let mut prefix: BTreeMap<Line, usize> = BTreeMap::new();
    for t in &work {
        for (k, line) in t.lines.iter().enumerate() {
            prefix.insert(*line, prefix_within(&t.ranking[k], x));
        }
    }
    let mut rounds = 0;
    loop {
        rounds += 1;
        work.par_iter_mut()
            .filter(|t| t.made.is_none())
            .try_for_each(|t| -> Result<(), TilingError> {
                let (w, h) = (t.hf.width(), t.hf.height());
                let mut start = t.start.clone();
                for (k, side) in Side::ALL.iter().enumerate() {
                    let keep = prefix[&t.lines[k]];
                    start.extend(
                        t.ranking[k][..keep]
                            .iter()
                            .map(|&(p, _)| side.local_index(p as usize, w, h)),
                    );
                }
                let made =
                    tile_mesh_within(t.hf.clone(), &start, x).map_err(|e| bad(e.to_string()))?;
                t.made = Some(made);
                Ok(())
            })?;
        // Border points a tile added beyond its lines' prefixes: each prefix grows to hold
        // its line's, and the tiles on a grown line run again.
        let mut grown: BTreeMap<Line, usize> = BTreeMap::new();
        for t in &work {
            let made = t.made.as_ref().expect("every tile ran");
            let (w, h) = (t.hf.width(), t.hf.height());
            for (k, side) in Side::ALL.iter().enumerate() {
                let keep = prefix[&t.lines[k]];
                for (rank, &(p, _)) in t.ranking[k].iter().enumerate().skip(keep) {
                    let local = side.local_index(p as usize, w, h);
                    if made.kept.binary_search(&local).is_ok() {
                        let g = grown.entry(t.lines[k]).or_insert(keep);
                        *g = (*g).max(rank + 1);
                    }
                }
            }
        }
        if grown.is_empty() {
            break;
        }
        for (line, keep) in &grown {
            prefix.insert(*line, *keep);
        }
        for t in &mut work {
            if t.lines.iter().any(|l| grown.contains_key(l)) {
                t.made = None;
            }
        }
    }
    let level = level_count(plan.tile_size()) - 1;
    let mut inserted = 0;
    let mut removed = 0;
    let mut fronts = Vec::with_capacity(work.len());
    for (index, t) in work.into_iter().enumerate() {
        let made = t.made.expect("every tile ran");
        inserted += made.inserted;
        removed += made.removed;
        let (w, h) = (t.hf.width(), t.hf.height());
        let borders = TileBorders {
            w,
            h,
            order: std::array::from_fn(|k| {
                t.ranking[k][..prefix[&t.lines[k]]]
                    .iter()
                    .map(|&(p, _)| p)
                    .collect()
            }),
        };
        let interior: Vec<u32> = made
            .kept
            .iter()
            .copied()
            .filter(|&i| !borders.on_border(i))
            .collect();
        let z = t.hf.z();
        let score = made.score;
        let points = t.hf.len() as f64;
        let candidate = TileCandidate {
            member: 0,
            level: level as u8,
            e_tile: score.e_sum,
            e_share: score.e_sum - unowned_error(plan, index, &borders, z, level),
            e_max: score.e_max,
            t: score.t as u64,
            sq_share: Some(
                score.rms * score.rms * points
                    - unowned_square_error(plan, index, &borders, z, level),
            ),
        };
        fronts.push(TileFront {
            index,
            borders,
            members: vec![interior],
            candidates: vec![candidate],
            evaluations: made.inserted,
            measure: ErrorMeasure::Max,
        });
    }
    let front = assemble(plan, fronts)?;
    debug_assert_eq!(front.members.len(), 1);
    Ok(TiledWithin {
        front,
        inserted,
        removed,
        rounds,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluator::Evaluator;
    use std::path::Path;

    fn fixture(name: &str) -> Heightfield {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(format!("{name}.f32"));
        crate::import::load(&path).unwrap()
    }

    /// The member's whole-grid triangles, scored afresh by the evaluator (which refuses a
    /// triangulation with a crack, a T-junction or an overlap).
    fn fresh(hf: &Heightfield, made: &TiledWithin) -> crate::evaluator::Score {
        let mesh = made.front.mesh(hf, 0).unwrap();
        Evaluator::new(Arc::new(hf.clone()))
            .score_triangulation(&mesh.triangles)
            .unwrap()
    }

    #[test]
    fn the_tiled_mesh_is_crack_free_and_within_the_bound_by_a_fresh_score() {
        for (name, tile) in [
            ("volcano_87x61", 33),
            ("jacksboro_65x65", 33),
            ("camera_65x65", 40),
        ] {
            let hf = fixture(name);
            let plan = TilePlan::new(hf.width(), hf.height(), tile).unwrap();
            assert!(plan.len() > 1);
            let (lo, hi) = hf.z_range();
            for fraction in [0.0, 0.005, 0.02, 0.1] {
                let x = fraction * (hi - lo);
                let made = tiled_mesh_within(&hf, &plan, None, x, 2).unwrap();
                let m = &made.front.members[0];
                let score = fresh(&hf, &made);
                assert!(score.e_max <= x, "{name} at {x}: E_max {}", score.e_max);
                assert_eq!(score.t as u64, m.t, "{name} at {x}");
                assert_eq!(score.e_max, m.e_max, "{name} at {x}");
                assert!((score.e_sum - m.e_sum).abs() <= 1e-9 * score.e_sum.max(1.0));
                if x == 0.0 {
                    assert_eq!(score.e_sum, 0.0);
                }
            }
        }
    }

    #[test]
    fn the_tiled_mesh_is_the_same_for_any_thread_count() {
        let hf = fixture("volcano_87x61");
        let plan = TilePlan::new(hf.width(), hf.height(), 33).unwrap();
        let x = 0.01 * (hf.z_range().1 - hf.z_range().0);
        let one = tiled_mesh_within(&hf, &plan, None, x, 1).unwrap();
        for threads in [2, 3] {
            assert_eq!(
                tiled_mesh_within(&hf, &plan, None, x, threads).unwrap(),
                one
            );
        }
    }

    #[test]
    fn from_a_start_the_mesh_keeps_the_bound_and_drops_border_starts() {
        let hf = fixture("jacksboro_65x65");
        let plan = TilePlan::new(hf.width(), hf.height(), 33).unwrap();
        let x = 0.02 * (hf.z_range().1 - hf.z_range().0);
        // Every tile starts from every other point, border points included: decimation takes
        // the interior ones away, and the border ones are the lines' own.
        let starts: Vec<Vec<u32>> = plan
            .tiles()
            .iter()
            .map(|t| (0..(t.w * t.h) as u32).step_by(2).collect())
            .collect();
        let made = tiled_mesh_within(&hf, &plan, Some(&starts), x, 2).unwrap();
        let score = fresh(&hf, &made);
        assert!(score.e_max <= x);
        let plain = tiled_mesh_within(&hf, &plan, None, x, 2).unwrap();
        // Both meshes hold the same border points: the lines' prefixes depend on x alone.
        let border = |m: &TiledWithin| -> Vec<Vec<u32>> {
            m.front
                .tiles
                .iter()
                .map(|t| t.borders.kept(t.candidates[0].level as usize))
                .collect()
        };
        assert_eq!(border(&made), border(&plain));
        assert!(made.removed > 0);
    }

    #[test]
    fn a_line_keeps_the_shortest_prefix_within_the_bound() {
        let profile = [0.0, 3.0, 0.0, 1.0, 0.0, 0.0, 2.0, 0.0];
        let ranking = ranked(&profile);
        for x in [0.0, 0.5, 1.0, 1.5, 2.5, 3.0, 4.0] {
            let k = prefix_within(&ranking, x);
            let mut kept = vec![false; profile.len()];
            kept[0] = true;
            kept[profile.len() - 1] = true;
            let worst = |kept: &[bool]| {
                let mut e: f64 = 0.0;
                let mut a = 0;
                for b in 1..profile.len() {
                    if kept[b] {
                        for i in a + 1..b {
                            let t = (i - a) as f64 / (b - a) as f64;
                            e = e.max(
                                (profile[i] - (profile[a] + (profile[b] - profile[a]) * t)).abs(),
                            );
                        }
                        a = b;
                    }
                }
                e
            };
            for (j, &(p, e)) in ranking.iter().enumerate() {
                assert_eq!(e, worst(&kept), "the error before entry {j}");
                if j == k {
                    break;
                }
                kept[p as usize] = true;
            }
            assert!(worst(&kept) <= x, "x = {x}");
        }
    }

    #[test]
    fn bad_bounds_are_refused() {
        let hf = fixture("volcano_87x61");
        let plan = TilePlan::new(hf.width(), hf.height(), 33).unwrap();
        for x in [-1.0, f64::NAN, f64::INFINITY, 1e-30] {
            let e = tiled_mesh_within(&hf, &plan, None, x, 1).unwrap_err();
            assert!(matches!(e, TilingError::BadParams { .. }), "{x}: {e}");
        }
        let e = tiled_mesh_within(&hf, &plan, Some(&[vec![]]), 1.0, 1).unwrap_err();
        assert!(matches!(e, TilingError::WrongTiles { .. }));
    }
}
