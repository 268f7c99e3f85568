//! The tiling's promises: exact whole-grid scores, crack-free meshes, the same bits for any
//! thread count, and allocations as good as brute force on the hull.

use super::allocation::allocate;
use super::border::{Side, TileBorders, insertion_order, line_error};
use super::test_fixtures::{every_choice, random_options, sums, terrain, tiled};
use super::*;
use crate::catalogue::{Algorithm, Config};
use crate::evaluator::exact::paper_e::brute_force;
use crate::heightfield::Heightfield;
use std::collections::HashMap;

fn greedy() -> Config {
    Config::from_json(Algorithm::Greedy, &serde_json::json!({"records": 24})).unwrap()
}

fn memetic(max_evaluations: u64) -> Config {
    Config::from_json(
        Algorithm::Memetic,
        &serde_json::json!({ "max_evaluations": max_evaluations }),
    )
    .unwrap()
}

#[test]
fn tiles_cover_the_grid_and_share_their_borders() {
    for (w, h, tile) in [(100, 60, 50), (65, 65, 33), (1000, 37, 200), (40, 40, 40)] {
        let plan = TilePlan::new(w, h, tile).unwrap();
        let mut covered = vec![0u32; w * h];
        for t in plan.tiles() {
            assert!(t.w <= tile && t.h <= tile && t.w >= 2 && t.h >= 2);
            for y in t.y0..t.y0 + t.h {
                for x in t.x0..t.x0 + t.w {
                    covered[y * w + x] += 1;
                }
            }
        }
        // Every point is in a tile; only shared rows and columns are in more than one.
        assert!(covered.iter().all(|&c| c >= 1));
        let xs: Vec<usize> = plan
            .tiles()
            .iter()
            .map(|t| t.x0)
            .filter(|&x| x > 0)
            .collect();
        for (i, &c) in covered.iter().enumerate() {
            let (x, y) = (i % w, i / w);
            let on_cut_column = xs.contains(&x);
            let on_cut_row = plan.tiles().iter().any(|t| t.y0 == y && y > 0);
            assert_eq!(c > 1, on_cut_column || on_cut_row, "point ({x}, {y})");
        }
    }
    assert!(TilePlan::new(64, 64, 64).unwrap().is_single());
}

#[test]
fn a_too_small_tile_is_refused_by_name() {
    let err = TilePlan::new(4000, 4000, 16).unwrap_err();
    assert_eq!(
        err,
        TilingError::TileTooSmall {
            tile: 16,
            min: MIN_TILE
        }
    );
    assert!(err.to_string().contains("too small"));
    assert!(TilePlan::new(4000, 4000, MIN_TILE).is_ok());
}

#[test]
fn border_ranking_is_greedy_insertion_on_the_profile() {
    let profile = [0.0, 1.0, 0.0, 0.0, 5.0, 0.0, 0.0];
    let order = insertion_order(&profile);
    // The spike first, then the worst point of the slope up to it (3, 3.75 below the chord),
    // and every interior point once.
    assert_eq!(order[..2], [4, 3]);
    let mut sorted = order.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, vec![1, 2, 3, 4, 5]);
    let bump = [0.0, 1.0, 0.0];
    assert_eq!(line_error(&bump, &[true, false, true]), 1.0);
    assert_eq!(line_error(&bump, &[true, true, true]), 0.0);
    // Kept at 0, 4 and 6: 0.25 + 2.5 + 3.75 on the slope up, 2.5 on the way down.
    let kept = [true, false, false, false, true, false, true];
    assert_eq!(line_error(&profile, &kept), 9.0);
}

/// Every member of `front` rebuilt, checked against a brute-force score of its triangles on the
/// whole grid, and checked for cracks.
fn check_members(hf: &Heightfield, front: &TiledFront) {
    assert!(!front.members.is_empty());
    for (k, m) in front.members.iter().enumerate() {
        let mesh = front.mesh(hf, k).unwrap();
        assert_eq!(mesh.triangles.len() as u64, m.t, "member {k}: T");
        let (e_sum, e_max, _, missing) = brute_force(hf, &mesh.kept, &mesh.triangles);
        assert_eq!(missing, 0, "member {k}: points in no triangle");
        let tolerance = 1e-9 * e_sum.max(1.0);
        assert!(
            (e_sum - m.e_sum).abs() <= tolerance,
            "member {k}: E_sum {} vs brute force {e_sum}",
            m.e_sum
        );
        assert!(
            (e_max - m.e_max).abs() <= 1e-9 * e_max.max(1.0),
            "member {k}: E_max"
        );
        check_crack_free(hf, &mesh);
    }
}

/// Every edge inside the grid is shared by exactly two triangles and every edge on the grid's
/// boundary belongs to one (so no T-junction and no gap); the triangles cover the grid's area.
fn check_crack_free(hf: &Heightfield, mesh: &TiledMesh) {
    let (w, h) = (hf.width() as i64, hf.height() as i64);
    let p = |i: u32| (i as i64 % w, i as i64 / w);
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    let mut area2 = 0i64;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(p);
        area2 += ((b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)).abs();
        for (u, v) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *edges.entry((u.min(v), u.max(v))).or_default() += 1;
        }
    }
    assert_eq!(area2, 2 * (w - 1) * (h - 1), "the triangles tile the grid");
    for (&(u, v), &count) in &edges {
        let ((ux, uy), (vx, vy)) = (p(u), p(v));
        let on_boundary =
            (ux == vx && (ux == 0 || ux == w - 1)) || (uy == vy && (uy == 0 || uy == h - 1));
        assert_eq!(count, if on_boundary { 1 } else { 2 }, "edge {u}–{v}");
    }
}

#[test]
fn assembled_members_are_exact_and_crack_free() {
    let hf = terrain(70, 52, 3);
    let front = tiled(&hf, 33, &greedy());
    assert!(front.plan.len() >= 4);
    check_members(&hf, &front);
}

#[test]
fn tile_members_are_written_packed_and_read_in_either_form() {
    let hf = terrain(70, 52, 3);
    let front = tiled(&hf, 33, &greedy());
    let written = serde_json::to_value(&front).unwrap();
    let mut diffs = 0;
    for tile in written["tiles"].as_array().unwrap() {
        for (i, m) in tile["members"].as_array().unwrap().iter().enumerate() {
            let m = m.as_object().unwrap();
            assert_eq!(m.len(), 1, "one form a member: {m:?}");
            assert!(i > 0 || m.contains_key("kept_packed"), "the first is whole");
            diffs += usize::from(m.contains_key("kept_diff"));
        }
    }
    assert!(diffs > 0, "neighbouring members are written as diffs");
    let read: TiledFront = serde_json::from_value(written.clone()).unwrap();
    assert_eq!(read, front);
    // The plain index arrays of older files read to the same front.
    let mut plain = written;
    for (tile, t) in plain["tiles"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .zip(&front.tiles)
    {
        tile["members"] = serde_json::to_value(&t.members).unwrap();
    }
    assert!(plain["tiles"][0]["members"][1].is_array());
    let read: TiledFront = serde_json::from_value(plain).unwrap();
    assert_eq!(read, front);
    let last = front.members.len() - 1;
    assert_eq!(
        read.mesh(&hf, last).unwrap(),
        front.mesh(&hf, last).unwrap()
    );
    // A diff with nothing before it is refused by name.
    let mut broken = serde_json::to_value(&front).unwrap();
    broken["tiles"][0]["members"][0] = serde_json::json!({"kept_diff": "AQ=="});
    let e = serde_json::from_value::<TiledFront>(broken).unwrap_err();
    assert!(e.to_string().contains("tile member 0"), "{e}");
}

#[test]
fn memetic_tiles_share_the_whole_grids_search_budget() {
    use crate::evolution::memetic::{MemeticParams, search_budget, seeding_budget};
    let plan = TilePlan::new(2048, 2048, 1025).unwrap();
    assert_eq!(plan.len(), 4);
    let share = search_budget(2048 * 2048).div_ceil(4);
    let given =
        Config::from_json(Algorithm::Memetic, &serde_json::json!({"population": 30})).unwrap();
    let tiled = tile_config(&plan, &given);
    let Config::Memetic(p) = &tiled else {
        panic!("memetic stays memetic: {tiled:?}");
    };
    assert_eq!((p.search_evaluations, p.population), (Some(share), 30));
    // Idempotent, so recording the tile parameters and running tiles with them agree.
    assert_eq!(tile_config(&plan, &tiled), tiled);
    // A budget given is kept, and other methods' parameters are left alone.
    assert_eq!(tile_config(&plan, &memetic(5000)), memetic(5000));
    assert_eq!(tile_config(&plan, &greedy()), greedy());
    // A tile's memetic budget is its own seeding and the share; one tile is the untiled run.
    let hf = terrain(40, 30, 1);
    assert_eq!(p.budget(&hf), seeding_budget(&hf) + share);
    let one = TilePlan::new(40, 30, 40).unwrap();
    let Config::Memetic(untiled) = tile_config(&one, &Algorithm::Memetic.defaults()) else {
        panic!("memetic stays memetic");
    };
    assert_eq!(untiled.budget(&hf), MemeticParams::default().budget(&hf));
}

#[test]
fn memetic_tiles_assemble_exact_members() {
    let hf = terrain(50, 40, 11);
    let front = tiled(&hf, 33, &memetic(1500));
    check_members(&hf, &front);
}

#[test]
fn shared_lines_keep_the_same_vertices_from_both_sides() {
    let hf = terrain(90, 70, 5);
    let plan = TilePlan::new(90, 70, 40).unwrap();
    let borders: Vec<TileBorders> = (0..plan.len())
        .map(|i| {
            let t = plan.cut(&hf, i).unwrap();
            TileBorders::new(t.width(), t.height(), t.z())
        })
        .collect();
    let columns = plan.columns();
    for i in 0..plan.len() {
        for level in 0..6 {
            if plan.has_left_neighbour(i) {
                assert_eq!(
                    borders[i].kept_on(Side::Left, level),
                    borders[i - 1].kept_on(Side::Right, level)
                );
            }
            if plan.has_top_neighbour(i) {
                assert_eq!(
                    borders[i].kept_on(Side::Top, level),
                    borders[i - columns].kept_on(Side::Bottom, level)
                );
            }
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn threads_do_not_change_the_bits() {
    let hf = terrain(80, 45, 9);
    let plan = TilePlan::new(80, 45, 33).unwrap();
    let config = memetic(800);
    let runs: Vec<String> = [1, 2, 3]
        .into_iter()
        .map(|threads| {
            let front = run_tiled(&hf, &plan, &config, 5, threads).unwrap();
            serde_json::to_string(&front).unwrap()
        })
        .collect();
    assert_eq!(runs[0], runs[1]);
    assert_eq!(runs[0], runs[2]);
    // Tile 0 runs the optimizer built to check the parameters: the same front as each tile
    // run on its own.
    let fronts = (0..plan.len())
        .map(|i| run_tile(&plan.cut(&hf, i).unwrap(), &plan, i, &config, 5).unwrap())
        .collect();
    let alone = assemble(&plan, fronts).unwrap();
    assert_eq!(serde_json::to_string(&alone).unwrap(), runs[0]);
    // A tile front survives serialisation (as it does on its way from a worker process).
    let front: TiledFront = serde_json::from_str(&runs[0]).unwrap();
    assert_eq!(serde_json::to_string(&front).unwrap(), runs[0]);
}

#[test]
fn a_tile_is_a_pure_function_of_its_inputs() {
    let hf = terrain(60, 60, 2);
    let plan = TilePlan::new(60, 60, 33).unwrap();
    let tile = plan.cut(&hf, 3).unwrap();
    let a = run_tile(&tile, &plan, 3, &memetic(600), 1).unwrap();
    let b = run_tile(&tile, &plan, 3, &memetic(600), 1).unwrap();
    assert_eq!(a, b);
    // Serialised and read back (as from a worker process), it is the same front.
    let shipped: TileFront = serde_json::from_str(&serde_json::to_string(&a).unwrap()).unwrap();
    assert_eq!(shipped, a);
}

#[test]
fn bad_parameters_and_grids_are_refused() {
    let hf = terrain(40, 40, 1);
    let plan = TilePlan::new(40, 40, 33).unwrap();
    let tile = plan.cut(&hf, 0).unwrap();
    let one = Config::from_json(Algorithm::Memetic, &serde_json::json!({"population": 1})).unwrap();
    let bad = run_tile(&tile, &plan, 0, &one, 1);
    assert!(
        matches!(&bad, Err(TilingError::BadParams { algorithm: Algorithm::Memetic, reason }) if reason.contains("population")),
        "{bad:?}"
    );
    #[cfg(not(target_arch = "wasm32"))]
    assert_eq!(
        run_tiled(&hf, &plan, &one, 1, 1).unwrap_err(),
        bad.unwrap_err()
    );
    let wrong = run_tile(&terrain(20, 20, 1), &plan, 0, &greedy(), 1);
    assert!(matches!(wrong, Err(TilingError::GridMismatch { .. })));
    let plan_front = tiled(&hf, 33, &greedy());
    assert!(matches!(
        assemble(&plan, plan_front.tiles[..1].to_vec()),
        Err(TilingError::WrongTiles { .. })
    ));
}

#[test]
fn allocation_finds_every_hull_point_of_brute_force_and_only_true_sums() {
    let mut rng = 42u64;
    for _ in 0..200 {
        let options = random_options(&mut rng);
        // Brute force: the least E at every total T.
        let mut best: HashMap<u64, f64> = HashMap::new();
        for (e, _, t) in every_choice(&options) {
            let slot = best.entry(t).or_insert(f64::INFINITY);
            *slot = slot.min(e);
        }
        let mut frontier: Vec<(u64, f64)> = best.into_iter().collect();
        frontier.sort_by_key(|p| p.0);
        let mut pareto: Vec<(u64, f64)> = Vec::new();
        for p in frontier {
            if pareto.last().is_none_or(|l| p.1 < l.1) {
                pareto.push(p);
            }
        }
        let found = allocate(&options);
        // Every allocation's sums are its choice's, and none is dominated by another.
        for a in &found {
            let (e, m, t) = sums(&options, &a.choice);
            assert_eq!((a.e, a.t, a.e_max), (e, t, m));
            assert!(
                pareto
                    .iter()
                    .all(|p| !(p.0 <= t && p.1 <= e && (p.0 < t || p.1 < e))
                        || found.iter().any(|b| b.t == t))
            );
        }
        for w in found.windows(2) {
            assert!(w[0].t < w[1].t && w[0].e > w[1].e);
        }
        // Every vertex of the brute-force front's lower convex hull is found, exactly.
        for (k, p) in pareto.iter().enumerate() {
            let on_hull = pareto.iter().enumerate().all(|(i, a)| {
                pareto.iter().enumerate().skip(i + 1).all(|(j, b)| {
                    if !(i < k && k < j) {
                        return true;
                    }
                    // p strictly below the chord a–b.
                    let chord = a.1 + (b.1 - a.1) * (p.0 - a.0) as f64 / (b.0 - a.0) as f64;
                    p.1 < chord
                })
            });
            if on_hull {
                assert!(
                    found.iter().any(|a| a.t == p.0 && a.e == p.1),
                    "hull point {p:?} missing from {:?}",
                    found.iter().map(|a| (a.t, a.e)).collect::<Vec<_>>()
                );
            }
        }
        // The first member is the cheapest allocation in T, the last the least error.
        assert_eq!(found[0].t, pareto[0].0);
        assert_eq!(found.last().unwrap().e, pareto.last().unwrap().1);
    }
}
