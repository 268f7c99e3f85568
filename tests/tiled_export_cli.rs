//! `export --max-vertical-error` and `--max-triangles` on tiled fronts, and `run --algo greedy
//! --max-vertical-error` over tiles: every mesh read back is a whole triangulation of the grid
//! (no cracks) scored afresh within its bound or budget, the same for any thread count, and bad
//! requests get a message and no file.

use paretomesh::evaluator::{Evaluator, Score};
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use paretomesh::refine::budget_floor;
use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

mod common;
use common::cli::{data, paretomesh, scratch, text};

/// The grid, cut into 3×2 tiles of at most 33 points a side.
const GRID: &str = "tests/data/volcano_87x61.f32";

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn grid() -> Heightfield {
    import::load(&data("volcano_87x61.f32")).unwrap()
}

/// A tiled front of greedy insertion's sweep on [`GRID`] (one run for the test binary).
fn front() -> &'static Path {
    static FRONT: OnceLock<PathBuf> = OnceLock::new();
    FRONT.get_or_init(|| {
        let out = scratch("tiled-front").join("front.json");
        let run = paretomesh(&[
            "run",
            GRID,
            "--algo",
            "greedy",
            "--tile",
            "33",
            "--seed",
            "3",
            "--out",
            s(&out),
        ]);
        assert!(run.status.success(), "{}", text(&run.stderr));
        out
    })
}

/// (T, E_max) of every member of a tiled front.json.
fn members(front: &Path) -> Vec<(u64, f64)> {
    let json: Value = serde_json::from_slice(&std::fs::read(front).unwrap()).unwrap();
    json["tiled"]["members"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| (m["T"].as_u64().unwrap(), m["E_max"].as_f64().unwrap()))
        .collect()
}

/// The grid-index triangles of a PLY `export` wrote on `hf`, scored afresh as a whole
/// triangulation (the evaluator refuses cracks, T-junctions and overlaps).
fn read_back(hf: &Heightfield, ply: &Path) -> Score {
    let index: HashMap<[u64; 3], u32> = (0..hf.len() as u32)
        .map(|i| (hf.to_world(i, hf.z()[i as usize]).map(f64::to_bits), i))
        .collect();
    let body = std::fs::read_to_string(ply).unwrap();
    let mut lines = body.lines();
    let mut vertices = 0;
    for line in lines.by_ref() {
        if let Some(n) = line.strip_prefix("element vertex ") {
            vertices = n.parse().unwrap();
        } else if line == "end_header" {
            break;
        }
    }
    let numbers =
        |l: &str| -> Vec<f64> { l.split_whitespace().map(|w| w.parse().unwrap()).collect() };
    let grid: Vec<u32> = (&mut lines)
        .take(vertices)
        .map(|l| index[&<[f64; 3]>::try_from(numbers(l)).unwrap().map(f64::to_bits)])
        .collect();
    let triangles: Vec<[u32; 3]> = lines
        .map(|l| {
            let n = numbers(l);
            [1, 2, 3].map(|k| grid[n[k] as usize])
        })
        .collect();
    Evaluator::new(Arc::new(hf.clone()))
        .score_triangulation(&triangles)
        .unwrap()
}

fn export(front: &Path, rule: &[&str], out: &Path) -> Result<String, String> {
    let mut args = vec!["export", s(front)];
    args.extend_from_slice(rule);
    args.extend_from_slice(&["--grid", GRID, "--out", s(out)]);
    let result = paretomesh(&args);
    let stderr = text(&result.stderr);
    if result.status.success() {
        Ok(stderr)
    } else {
        Err(stderr)
    }
}

#[test]
fn a_max_vertical_error_is_met_per_tile_within_the_bound() {
    let front = front();
    let all = members(front);
    let hf = grid();
    let out = scratch("tiled-within").join("m.ply");
    let least = all.iter().map(|m| m.1).fold(f64::INFINITY, f64::min);
    let mut made = 0;
    for x in [
        all[all.len() / 4].1,
        all[all.len() / 2].1,
        least,
        least / 2.0,
    ] {
        let said = export(front, &["--max-vertical-error", &x.to_string()], &out).unwrap();
        let score = read_back(&hf, &out);
        assert!(score.e_max <= x, "{} > {x}", score.e_max);
        // Never more triangles than the fewest-triangle member within x.
        if let Some(fewest) = all.iter().filter(|m| m.1 <= x).map(|m| m.0).min() {
            assert!(score.t as u64 <= fewest, "{} > {fewest}", score.t);
        }
        assert!(said.contains(&format!("T = {}", score.t)), "{said}");
        made += usize::from(said.contains("per tile with shared border points"));
    }
    assert!(made >= 2, "meshes were made for the bound");
    // A bound below what the grid allows gets a message that says why, and no file.
    let o = scratch("tiled-within-bad").join("m.ply");
    for (x, why) in [
        ("-1", "is negative"),
        ("NaN", "is not a number"),
        ("1e-30", "below this grid's exactness floor"),
    ] {
        let e = export(front, &["--max-vertical-error", x], &o).unwrap_err();
        assert!(
            e.contains("--max-vertical-error") && e.contains(why),
            "{x}: {e}"
        );
        assert!(!o.exists());
    }
}

#[test]
fn a_triangle_budget_is_met_by_growing_a_tiled_member() {
    let front = front();
    let all = members(front);
    let hf = grid();
    let out = scratch("tiled-budget").join("m.ply");
    // Budgets in the widest gaps between members, and past the densest member.
    let mut gaps: Vec<(u64, u64)> = all.windows(2).map(|w| (w[0].0, w[1].0)).collect();
    gaps.sort_by_key(|&(a, b)| std::cmp::Reverse(b - a));
    let mut grown = 0;
    for n in gaps[..3]
        .iter()
        .map(|&(a, b)| (a + b) / 2)
        .chain([hf.full_triangles() as u64 - 7])
    {
        let said = export(front, &["--max-triangles", &n.to_string()], &out).unwrap();
        let score = read_back(&hf, &out);
        assert!(score.t as u64 <= n, "{} > {n}", score.t);
        assert!(
            score.t >= budget_floor(n as usize) || score.t as u64 + 1 == n,
            "{} < 0.99·{n}",
            score.t
        );
        if said.contains("grown by") {
            grown += 1;
            assert!(said.contains("border lines two tiles share"), "{said}");
        }
    }
    assert!(grown >= 2, "some budgets were met by growth");
    let o = scratch("tiled-budget-bad").join("m.ply");
    let e = export(front, &["--max-triangles", "1"], &o).unwrap_err();
    assert!(e.contains("--max-triangles must be at least 2"), "{e}");
    assert!(!o.exists());
}

#[test]
fn greedy_to_a_max_error_over_tiles_is_exact_and_the_same_for_any_thread_count() {
    let hf = grid();
    let (lo, hi) = hf.z_range();
    let dir = scratch("tiled-greedy");
    for fraction in [0.003, 0.03] {
        let x = (fraction * (hi - lo)).to_string();
        let mut tiled = Vec::new();
        for threads in ["1", "2"] {
            let out = dir.join(format!("front-{threads}.json"));
            let run = paretomesh(&[
                "run",
                GRID,
                "--algo",
                "greedy",
                "--max-vertical-error",
                &x,
                "--tile",
                "33",
                "--threads",
                threads,
                "--out",
                s(&out),
            ]);
            let stderr = text(&run.stderr);
            assert!(run.status.success(), "{stderr}");
            assert!(stderr.contains("one mesh within E_max"), "{stderr}");
            let json: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
            tiled.push(json["tiled"].clone());
            let ply = dir.join("m.ply");
            export(&out, &["--member", "0"], &ply).unwrap();
            let score = read_back(&hf, &ply);
            assert!(score.e_max <= x.parse::<f64>().unwrap());
            assert_eq!(
                score.t as u64,
                json["tiled"]["members"][0]["T"].as_u64().unwrap()
            );
        }
        assert_eq!(tiled[0], tiled[1], "the same front on 1 and 2 threads");
    }
}
