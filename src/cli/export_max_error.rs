//! `export --max-vertical-error X`: the fewest triangles found with E_max ≤ X, from the front's
//! members and, on demand, from meshes made for X from the members nearest it (greedy
//! refinement of the member just above X, bounded-error decimation of the member just within
//! it). On a tiled front, those meshes are made per tile with shared border points
//! ([`tiled_member_within`]). Every mesh is scored afresh before it is written, and none with
//! E_max > X is.

use paretomesh::baselines::{exactness_floor, mesh_within};
use paretomesh::evaluator::{Evaluator, Score, canonical_set};
use paretomesh::front_file::FrontFile;
use paretomesh::heightfield::Heightfield;
use paretomesh::tiling::{TiledFront, tiled_member_within};
use std::sync::Arc;

/// Refuses a bound no mesh can have, before any file is read: NaN or negative.
pub(super) fn check_sign(x: f64) -> Result<(), String> {
    if x.is_nan() {
        return Err(
            "--max-vertical-error is not a number: give a vertical error of at least 0".to_string(),
        );
    }
    if x < 0.0 {
        return Err(format!(
            "--max-vertical-error {x} is negative: a vertical error is at least 0 (0 asks for an exact mesh)"
        ));
    }
    Ok(())
}

/// Refuses a bound above 0 but below the grid's exactness floor, where an error is the
/// interpolation's rounding rather than the surface's.
pub(super) fn check_floor(hf: &Heightfield, x: f64) -> Result<(), String> {
    let floor = exactness_floor(hf);
    if x > 0.0 && x < floor {
        return Err(format!(
            "--max-vertical-error {x} is below this grid's exactness floor {floor:e} (heights up to {:e} in magnitude are interpolated in f64, so smaller errors are rounding): give 0 for an exact mesh, or at least {floor:e}",
            max_abs(hf)
        ));
    }
    Ok(())
}

fn max_abs(hf: &Heightfield) -> f64 {
    let (lo, hi) = hf.z_range();
    lo.abs().max(hi.abs())
}

/// The mesh `export` writes for `--max-vertical-error x`: its triangles, its score and how it
/// was reached.
pub(super) struct Reached {
    pub triangles: Vec<[u32; 3]>,
    pub score: Score,
    pub how: String,
}

/// The fewest-triangle mesh within `x` among: the front's fewest-triangle member within `x`
/// (`picked`, if any), that member decimated to `x`, and the member just above `x` in E_max
/// with fewer triangles refined to `x` by greedy insertion and then decimated.
pub(super) fn reach(
    hf: Arc<Heightfield>,
    file: &FrontFile,
    picked: Option<usize>,
    x: f64,
) -> Result<Reached, String> {
    let members = &file.front;
    let limit = picked.map_or(usize::MAX, |k| members[k].solution.score.t);
    // The member with the most triangles under the picked one's that is above x: the nearest
    // starting point below it for refinement.
    let above = (0..members.len())
        .filter(|&k| {
            let s = &members[k].solution.score;
            s.e_max > x && s.t < limit
        })
        .max_by_key(|&k| (members[k].solution.score.t, std::cmp::Reverse(k)));
    let mut best: Option<(usize, Vec<u32>, String)> = picked.map(|k| {
        let s = &members[k].solution;
        (
            s.score.t,
            s.kept.clone(),
            format!("member {k} meets it as it is"),
        )
    });
    let mut consider = |start: usize, what: &str| -> Result<(), String> {
        let s = &members[start].solution;
        let made = mesh_within(hf.clone(), &s.kept, x).map_err(|e| e.to_string())?;
        let how = format!(
            "made for it from member {start} (T = {}, E_max = {}): {what}, {} points inserted by greedy insertion of the worst point, {} removed by bounded-error decimation",
            s.score.t, s.score.e_max, made.inserted, made.removed
        );
        if best.as_ref().is_none_or(|b| made.score.t < b.0) {
            best = Some((made.score.t, made.kept, how));
        }
        Ok(())
    };
    if let Some(k) = picked {
        consider(k, "the fewest-triangle member within the bound")?;
    }
    if let Some(k) = above {
        consider(k, "the nearest member above the bound")?;
    }
    let (_, kept, how) = best.ok_or("the front has no members")?;
    let evaluation = Evaluator::new(hf)
        .evaluate(&kept)
        .map_err(|e| e.to_string())?;
    if evaluation.score.e_max > x {
        return Err(format!(
            "internal error: the mesh made for --max-vertical-error {x} scores E_max {} afresh; nothing written",
            evaluation.score.e_max
        ));
    }
    Ok(Reached {
        triangles: canonical_set(&evaluation.triangles),
        score: evaluation.score,
        how,
    })
}

/// [`reach`] on a tiled front: the fewest-triangle mesh within `x` among the picked member
/// (if any), the meshes made for `x` per tile from it and from the member just above `x` with
/// fewer triangles, scored afresh as a whole-grid triangulation (which also refuses a crack).
pub fn reach_tiled(
    hf: Arc<Heightfield>,
    front: &TiledFront,
    picked: Option<usize>,
    x: f64,
) -> Result<Reached, String> {
    let members = &front.members;
    let limit = picked.map_or(u64::MAX, |k| members[k].t);
    let above = (0..members.len())
        .filter(|&k| members[k].e_max > x && members[k].t < limit)
        .max_by_key(|&k| (members[k].t, std::cmp::Reverse(k)));
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut best: Option<(u64, Option<TiledFront>, String)> =
        picked.map(|k| (members[k].t, None, format!("member {k} meets it as it is")));
    for (start, what) in [
        (picked, "the fewest-triangle member within the bound"),
        (above, "the nearest member above the bound"),
    ] {
        let Some(k) = start else { continue };
        let made = tiled_member_within(&hf, front, k, x, threads).map_err(|e| e.to_string())?;
        let t = made.front.members[0].t;
        if best.as_ref().is_none_or(|b| t < b.0) {
            let how = format!(
                "made for it from member {k} (T = {}, E_max = {}): {what}, per tile with shared border points ({} tiles), {} points inserted by greedy insertion of the worst point, {} removed by bounded-error decimation",
                members[k].t,
                members[k].e_max,
                front.plan.len(),
                made.inserted,
                made.removed
            );
            best = Some((t, Some(made.front), how));
        }
    }
    let (_, made, how) = best.ok_or("the front has no members")?;
    let mesh = match &made {
        Some(f) => f.mesh(&hf, 0),
        None => front.mesh(&hf, picked.expect("a member as it is was picked")),
    }
    .map_err(|e| e.to_string())?;
    let score = Evaluator::new(hf)
        .score_triangulation(&mesh.triangles)
        .map_err(|e| format!("internal error: the mesh made for --max-vertical-error {x} is not a whole triangulation ({e}); nothing written"))?;
    if score.e_max > x {
        return Err(format!(
            "internal error: the mesh made for --max-vertical-error {x} scores E_max {} afresh; nothing written",
            score.e_max
        ));
    }
    Ok(Reached {
        triangles: mesh.triangles,
        score,
        how,
    })
}
