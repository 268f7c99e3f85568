//! The web layer in a real headless browser (wasm-bindgen-test, Chromium).
#![cfg(target_arch = "wasm32")]

use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

const GRID: &[u8] = include_bytes!("data/volcano_33x33.f32");
const SIDECAR: &[u8] = include_bytes!("data/volcano_33x33.json");

#[wasm_bindgen_test]
fn the_core_evaluates_in_the_browser_like_natively() {
    // The same kept set scored natively in tests/evaluator.rs' sense: corners only is 2 triangles.
    let value = paretomesh::web::evaluate_raw(GRID, SIDECAR, &[]).unwrap();
    let t = js_sys::Reflect::get(&value, &"T".into())
        .unwrap()
        .as_f64()
        .unwrap();
    assert_eq!(t, 2.0);
    let e = js_sys::Reflect::get(&value, &"E_sum".into())
        .unwrap()
        .as_f64()
        .unwrap();
    let native = {
        let hf = paretomesh::heightfield::raw::parse(GRID, SIDECAR, "t").unwrap();
        paretomesh::evaluator::Evaluator::new(std::sync::Arc::new(hf))
            .score(&[])
            .unwrap()
            .e_sum
    };
    assert_eq!(e, native);
    assert!(e > 0.0);
}

#[wasm_bindgen_test]
fn bad_input_is_an_error_not_a_panic() {
    let err = paretomesh::web::evaluate_raw(&GRID[..100], SIDECAR, &[]);
    assert!(err.is_err());
}

mod plot_hit_testing {
    use paretomesh::web::plot::{Layout, PlotPoint, hit_test, ticks};
    use wasm_bindgen_test::wasm_bindgen_test;

    fn pt(t: f64, e: f64) -> PlotPoint {
        PlotPoint { t, e }
    }

    #[wasm_bindgen_test]
    fn every_fitted_point_lies_inside_the_plotting_area() {
        // A front from few triangles and large error to many triangles and small error.
        let points = [pt(2.0, 900.0), pt(40.0, 120.0), pt(300.0, 3.5)];
        let layout = Layout::fit(400.0, 300.0, &points);
        let (l, t, r, b) = layout.area();
        for p in points {
            let (x, y) = layout.to_pixel(p);
            assert!(x >= l && x <= r && y >= t && y <= b, "{p:?} at ({x}, {y})");
        }
        // More triangles is further right; more error is higher up (smaller y).
        assert!(layout.to_pixel(points[0]).0 < layout.to_pixel(points[2]).0);
        assert!(layout.to_pixel(points[0]).1 < layout.to_pixel(points[2]).1);
    }

    #[wasm_bindgen_test]
    fn a_click_selects_the_nearest_point_within_the_radius_only() {
        let points = [pt(2.0, 900.0), pt(40.0, 120.0), pt(300.0, 3.5)];
        let layout = Layout::fit(400.0, 300.0, &points);
        let (x, y) = layout.to_pixel(points[1]);
        assert_eq!(hit_test(&layout, &points, x + 3.0, y - 2.0, 8.0), Some(1));
        // 20 px away from every point: no hit.
        assert_eq!(hit_test(&layout, &points, x + 20.0, y + 20.0, 8.0), None);
        assert_eq!(hit_test(&layout, &[], x, y, 8.0), None);
    }

    #[wasm_bindgen_test]
    fn coincident_points_resolve_to_the_lower_index() {
        // Two members drawn on the same pixel: the answer must not depend on float noise.
        let points = [pt(10.0, 5.0), pt(10.0, 5.0)];
        let layout = Layout::fit(200.0, 200.0, &points);
        let (x, y) = layout.to_pixel(points[0]);
        assert_eq!(hit_test(&layout, &points, x, y, 4.0), Some(0));
    }

    #[wasm_bindgen_test]
    fn a_single_point_or_no_point_still_maps_to_finite_pixels() {
        for points in [vec![pt(2.0, 0.0)], vec![]] {
            let layout = Layout::fit(300.0, 200.0, &points);
            let (x, y) = layout.to_pixel(pt(2.0, 0.0));
            assert!(x.is_finite() && y.is_finite());
        }
    }

    #[wasm_bindgen_test]
    fn a_log_axis_keeps_decades_apart_and_draws_zero_error_at_the_bottom() {
        // Errors over four decades plus the full mesh (E = 0).
        let points = [
            pt(2.0, 10000.0),
            pt(20.0, 100.0),
            pt(200.0, 1.0),
            pt(400.0, 0.0),
        ];
        let layout = Layout::fit_scaled(400.0, 300.0, &points, true);
        let y: Vec<f64> = points.iter().map(|p| layout.to_pixel(*p).1).collect();
        // Equal ratios are equal distances.
        assert!(((y[1] - y[0]) - (y[2] - y[1])).abs() < 1e-9, "{y:?}");
        assert!(y[3] > y[2] && y[3].is_finite());
        let (_, top, _, bottom) = layout.area();
        assert!(y.iter().all(|&v| v >= top && v <= bottom));
        assert_eq!(layout.e_ticks(), vec![1.0, 10.0, 100.0, 1000.0, 10000.0]);
        // Hit-testing works on the log axis too.
        let (x, yy) = layout.to_pixel(points[1]);
        assert_eq!(hit_test(&layout, &points, x, yy, 4.0), Some(1));
    }

    #[wasm_bindgen_test]
    fn ticks_are_round_numbers_inside_the_range() {
        assert_eq!(ticks(0.0, 10.0, 5), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        let t = ticks(13.0, 987.0, 6);
        assert!(
            t.iter()
                .all(|v| (13.0..=987.0).contains(v) && v % 100.0 == 0.0),
            "{t:?}"
        );
    }
}

mod views_and_exports {
    use paretomesh::evaluator::Evaluator;
    use paretomesh::heightfield::{Heightfield, Placement, raw};
    use paretomesh::web::app::shown_mesh;
    use paretomesh::web::export::{WorldMesh, front_csv};
    use paretomesh::web::render::geometry::{ViewMapping, flat_mesh, wireframe};
    use std::sync::Arc;
    use wasm_bindgen_test::wasm_bindgen_test;

    fn volcano() -> Arc<Heightfield> {
        Arc::new(raw::parse(super::GRID, super::SIDECAR, "volcano_33x33").unwrap())
    }

    // Kept points spread over the 33×33 grid (interior points of a few rows and columns).
    const KEPT: [u32; 6] = [34, 200, 530, 545, 800, 1000];

    #[wasm_bindgen_test]
    fn per_point_errors_add_up_to_the_evaluators_error() {
        let hf = volcano();
        let mesh = shown_mesh(&hf, &KEPT).unwrap();
        let sum: f64 = mesh.point_error.iter().sum();
        let e = Evaluator::new(hf.clone()).score(&KEPT).unwrap().e_sum;
        assert!((sum - e).abs() <= 1e-9 * e, "{sum} vs {e}");
        assert_eq!(mesh.e_sum, e);
        // Kept points (corners included) have no error.
        for &k in mesh.kept.iter() {
            assert_eq!(mesh.point_error[k as usize], 0.0);
        }
        assert_eq!(mesh.kept.len(), KEPT.len() + 4);
    }

    #[wasm_bindgen_test]
    fn the_wireframe_draws_each_edge_once() {
        // A triangulation of a convex region with V points and T triangles has V + T − 1 edges.
        let hf = volcano();
        let mesh = shown_mesh(&hf, &KEPT).unwrap();
        let map = ViewMapping::new(&hf);
        let lines = wireframe(&hf, &map, &mesh.triangles, [0.0; 4]);
        assert_eq!(
            lines.indices.len() / 2,
            mesh.kept.len() + mesh.triangles.len() - 1
        );
        let fill = flat_mesh(&hf, &map, &mesh.triangles, [1.0; 4]);
        assert_eq!(fill.vertices.len(), 3 * mesh.triangles.len());
    }

    #[wasm_bindgen_test]
    fn exports_use_the_inputs_own_coordinates() {
        // A 3×2 grid with spacing (2, 5) and origin (10, 20): point 5 is (x=2, y=1).
        let hf = Heightfield::new(3, 2, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
            .unwrap()
            .with_geometry([10.0, 20.0], [2.0, 5.0])
            .unwrap();
        // Kept: point 1 and the four corners (0, 2, 3, 5) = 5 vertices.
        let mesh = shown_mesh(&Arc::new(hf.clone()), &[1]).unwrap();
        let world = WorldMesh::new(&hf, &mesh.kept, &mesh.triangles).unwrap();
        assert_eq!(world.vertices.last(), Some(&[14.0, 25.0, 5.0]));
        let ply = world.to_ply("test");
        assert!(ply.contains("element vertex 5\n"));
        assert!(ply.contains(&format!("element face {}\n", mesh.triangles.len())));
        assert!(ply.contains("\n14 25 5\n"));
        let obj = world.to_obj("test");
        assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 5);
        assert!(
            obj.lines()
                .filter(|l| l.starts_with("f "))
                .all(|l| !l.contains(" 0"))
        );
        let stl = world.to_stl("solid-looking header");
        assert_eq!(stl.len(), 84 + 50 * mesh.triangles.len());
        assert_ne!(&stl[..5], b"solid");
    }

    #[wasm_bindgen_test]
    fn a_cylindrical_unwrap_exports_back_onto_the_cylinder() {
        // θ along x, ζ along y, ρ = z = 2 everywhere: every exported vertex is 2 from the axis.
        let hf = Heightfield::new(4, 3, vec![2.0; 12])
            .unwrap()
            .with_geometry([0.0, 0.0], [1.0, 1.0])
            .unwrap()
            .with_placement(Placement::Cylindrical {
                origin: [0.0; 3],
                axis: [0.0, 0.0, 1.0],
                reference: [1.0, 0.0, 0.0],
            });
        let mesh = shown_mesh(&Arc::new(hf.clone()), &[5, 6]).unwrap();
        let world = WorldMesh::new(&hf, &mesh.kept, &mesh.triangles).unwrap();
        for v in &world.vertices {
            assert!(
                ((v[0] * v[0] + v[1] * v[1]).sqrt() - 2.0).abs() < 1e-12,
                "{v:?}"
            );
        }
    }

    #[wasm_bindgen_test]
    fn exported_meshes_parse_back_with_the_projects_importers() {
        use paretomesh::heightfield::{obj, ply, stl};
        // volcano_33x33 has spacing 1 and origin 0, so grid and world coordinates agree.
        let hf = volcano();
        let mesh = shown_mesh(&hf, &KEPT).unwrap();
        let world = WorldMesh::new(&hf, &mesh.kept, &mesh.triangles).unwrap();
        // The importers may renumber vertices (e.g. in order of first use), so compare positions:
        // the vertex sets, and each triangle as its corner positions in order (rotation-normalised,
        // so the orientation must survive).
        let sorted = |mut v: Vec<[f64; 3]>| {
            v.sort_by(|a, b| a.partial_cmp(b).unwrap());
            v
        };
        let shapes = |vs: &[[f64; 3]], ts: &[[u32; 3]]| {
            let mut out: Vec<[[f64; 3]; 3]> = ts
                .iter()
                .map(|t| {
                    let p = t.map(|i| vs[i as usize]);
                    let k = (0..3)
                        .min_by(|&a, &b| p[a].partial_cmp(&p[b]).unwrap())
                        .unwrap();
                    [p[k], p[(k + 1) % 3], p[(k + 2) % 3]]
                })
                .collect();
            out.sort_by(|a, b| a.partial_cmp(b).unwrap());
            out
        };
        let expected = shapes(&world.vertices, &world.triangles);
        let from_ply = ply::parse(world.to_ply("round trip").as_bytes()).unwrap();
        assert_eq!(
            sorted(from_ply.vertices.clone()),
            sorted(world.vertices.clone())
        );
        assert_eq!(shapes(&from_ply.vertices, &from_ply.triangles), expected);
        let from_obj = obj::parse(world.to_obj("round trip").as_bytes()).unwrap();
        assert_eq!(
            sorted(from_obj.vertices.clone()),
            sorted(world.vertices.clone())
        );
        assert_eq!(shapes(&from_obj.vertices, &from_obj.triangles), expected);
        // STL stores f32 corners: the same triangles up to f32 rounding (heights here are f32s
        // already and x, y small integers, so the rounding is exact).
        let from_stl = stl::parse(&world.to_stl("round trip")).unwrap();
        assert_eq!(shapes(&from_stl.vertices, &from_stl.triangles), expected);
        // The exported PLY scores like the selection on the original grid.
        let index_of = |p: [f64; 3]| hf.index(p[0] as usize, p[1] as usize);
        let grid_tris: Vec<[u32; 3]> = from_ply
            .triangles
            .iter()
            .map(|t| t.map(|i| index_of(from_ply.vertices[i as usize])))
            .collect();
        let e = Evaluator::new(hf.clone())
            .score_triangulation(&grid_tris)
            .unwrap()
            .e_sum;
        assert_eq!(e, mesh.e_sum);
    }
    #[wasm_bindgen_test]
    fn a_triangle_on_a_point_that_is_not_kept_is_an_error() {
        let hf = Heightfield::new(2, 2, vec![0.0; 4]).unwrap();
        assert!(WorldMesh::new(&hf, &[0, 1, 3], &[[0, 1, 2]]).is_err());
    }

    #[wasm_bindgen_test]
    fn the_front_csv_has_one_row_per_member() {
        use paretomesh::front::{Front, Solution};
        let mut f = Front::default();
        f.offer(Solution {
            e_sum: 9.0,
            e_max: 3.0,
            t: 2,
            kept: vec![0, 1, 2, 3],
        });
        f.offer(Solution {
            e_sum: 1.5,
            e_max: 1.0,
            t: 4,
            kept: vec![0, 1, 2, 3, 4],
        });
        assert_eq!(front_csv(&f), "T,E_sum,E_max,kept\n2,9,3,4\n4,1.5,1,5\n");
    }
}

mod camera_and_loading {
    use paretomesh::heightfield::{ImportOptions, Projection};
    use paretomesh::web::loader;
    use paretomesh::web::render::camera::{MAX_PITCH, MIN_DISTANCE, OrbitCamera};
    use wasm_bindgen_test::wasm_bindgen_test;

    #[wasm_bindgen_test]
    fn orbiting_and_zooming_stay_within_limits() {
        let mut c = OrbitCamera::default();
        c.orbit(0.0, 1e6);
        assert_eq!(c.pitch, MAX_PITCH);
        c.zoom(1e-9);
        assert_eq!(c.distance, MIN_DISTANCE);
        c.zoom(f32::NAN);
        assert_eq!(c.distance, MIN_DISTANCE);
        let m = c.view_projection(1.5);
        assert!(m.to_cols_array().iter().all(|v| v.is_finite()));
    }

    #[wasm_bindgen_test]
    fn panning_moves_the_target_and_keeps_the_distance() {
        let mut c = OrbitCamera::default();
        let d = c.distance;
        c.pan(50.0, 0.0, 500.0);
        assert_ne!(c.target, [0.0; 3]);
        assert_eq!(c.distance, d);
    }

    #[wasm_bindgen_test]
    fn the_builtin_surface_is_a_real_grid_with_its_source_note() {
        let hf = loader::builtin();
        assert_eq!((hf.width(), hf.height()), (65, 65));
        assert!(hf.source().contains("jacksboro"));
        let (lo, hi) = hf.z_range();
        assert!(hi > lo);
    }

    #[wasm_bindgen_test]
    fn bad_files_get_messages_a_user_understands() {
        let default = ImportOptions::default();
        let no_sidecar = loader::parse("dem.f32", super::GRID, None, &default).unwrap_err();
        assert!(no_sidecar.contains("sidecar"), "{no_sidecar}");
        let truncated = loader::parse(
            "dem.f32",
            &super::GRID[..10],
            Some(super::SIDECAR),
            &default,
        )
        .unwrap_err();
        assert!(
            truncated.contains("dem.f32") && truncated.contains("truncated"),
            "{truncated}"
        );
        let unknown = loader::parse("notes.txt", b"hello", None, &default).unwrap_err();
        assert!(unknown.contains("unknown file type"), "{unknown}");
        let corrupt = loader::parse(
            "broken.ply",
            b"ply\nformat ascii 1.0\nelement vertex 99\nend_header\n1 2\n",
            None,
            &default,
        )
        .unwrap_err();
        assert!(corrupt.contains("broken.ply"), "{corrupt}");
    }

    #[wasm_bindgen_test]
    fn the_import_dialogs_options_are_checked() {
        assert_eq!(
            loader::options("auto", 0, 0).unwrap(),
            ImportOptions::default()
        );
        let o = loader::options("cylindrical", 64, 32).unwrap();
        assert_eq!(
            (o.projection, o.grid_size),
            (Projection::Cylindrical, Some((64, 32)))
        );
        assert!(loader::options("spherical", 0, 0).is_err());
        assert!(loader::options("planar", 64, 0).is_err());
    }

    #[wasm_bindgen_test]
    fn an_oversized_grid_size_is_refused_with_the_limit_in_the_message() {
        let ply = include_bytes!("data/bunny_33x33.ply");
        let o = loader::options("planar", 4096, 4096).unwrap();
        let e = loader::parse("bunny.ply", ply, None, &o).unwrap_err();
        assert!(e.contains("16.8 M points") && e.contains("limit"), "{e}");
    }

    #[wasm_bindgen_test]
    fn a_grid_ply_loads_as_is_and_needs_no_dialog() {
        let ply = include_bytes!("data/volcano_87x61.ply");
        let hf = loader::parse("volcano_87x61.ply", ply, None, &ImportOptions::default()).unwrap();
        assert_eq!((hf.width(), hf.height()), (87, 61));
        assert!(!hf.resampled());
    }
}

mod app_stepping {
    use paretomesh::heightfield::raw;
    use paretomesh::web::algorithms::{Algorithm, Params, build};
    use paretomesh::web::app::{App, RunConfig, Surface};
    use std::sync::Arc;
    use wasm_bindgen_test::wasm_bindgen_test;

    // A small, quick NSGA-II run on the 33×33 volcano.
    fn config() -> RunConfig {
        RunConfig {
            algorithm: Algorithm::Nsga2,
            params: Params {
                population: 12,
                generations: 6,
                seed: 7,
                ..Params::default()
            },
            budget_ms: 8.0,
        }
    }

    fn app() -> App {
        let hf = raw::parse(super::GRID, super::SIDECAR, "volcano_33x33").unwrap();
        App::new(
            Surface {
                name: "volcano_33x33".into(),
                heightfield: Arc::new(hf),
            },
            config(),
        )
    }

    /// A clock that advances 1 ms per reading, so what a tick does is exact and repeatable.
    fn ticking_clock() -> impl FnMut() -> f64 {
        let mut now = 0.0;
        move || {
            now += 1.0;
            now
        }
    }

    #[wasm_bindgen_test]
    fn a_tick_steps_until_its_budget_is_spent() {
        let mut app = app();
        app.run().unwrap();
        let mut clock = ticking_clock();
        let report = app.tick(8.0, &mut clock);
        // One reading at the start and one after each step: after the 8th step, 8 ms are gone
        // (a 9th step of the 1 ms each step took so far would not fit).
        assert_eq!(report.steps, 8);
        assert!(report.evaluations >= 8, "{report:?}");
        assert_eq!(app.status().evaluations, report.evaluations);
        // A smaller budget does fewer steps.
        let report = app.tick(3.0, &mut clock);
        assert_eq!(report.steps, 3);
    }

    #[wasm_bindgen_test]
    fn a_tick_does_not_start_a_step_that_would_not_fit_in_its_budget() {
        // Every step takes 5 ms on this clock: after the first, 5 of the 8 ms are gone and a
        // second 5 ms step would end at 10 ms, so the frame stops at one step. A 12 ms budget
        // fits two.
        let mut app = app();
        app.run().unwrap();
        let mut now = 0.0;
        let mut slow_clock = || {
            now += 5.0;
            now
        };
        assert_eq!(app.tick(8.0, &mut slow_clock).steps, 1);
        assert_eq!(app.tick(12.0, &mut slow_clock).steps, 2);
    }

    #[wasm_bindgen_test]
    fn a_clock_too_coarse_to_see_a_step_does_not_let_a_tick_run_away() {
        // performance.now() is coarsened: steps can look instantaneous. The chunk then grows
        // by doubling only, so after k zero-time calls the next call spends at most 2^k
        // evaluations plus one unit, instead of the whole run.
        let mut app = app();
        app.run().unwrap();
        // The first six readings show no time passing, the seventh shows the budget gone.
        let mut readings = 0;
        let mut clock_then_jump = || {
            readings += 1;
            if readings > 6 { 100.0 } else { 0.0 }
        };
        let report = app.tick(8.0, &mut clock_then_jump);
        assert_eq!(report.steps, 6);
        // Chunks 1, 2, 4, 8, 16, 32 at most; NSGA-II's unit is one evaluation, so a call spends
        // exactly its chunk.
        assert!(report.evaluations <= 63, "{report:?}");
        assert!(!app.status().done);
    }

    #[wasm_bindgen_test]
    fn a_paused_app_does_no_work() {
        let mut app = app();
        app.run().unwrap();
        app.pause();
        let report = app.tick(8.0, &mut ticking_clock());
        assert_eq!((report.steps, report.evaluations), (0, 0));
        assert_eq!(app.status().evaluations, 0);
    }

    #[wasm_bindgen_test]
    fn slicing_into_frames_reaches_the_front_of_one_uninterrupted_run() {
        let mut app = app();
        app.run().unwrap();
        let mut clock = ticking_clock();
        let mut frames = 0;
        while app.is_running() {
            app.tick(8.0, &mut clock);
            frames += 1;
            assert!(frames < 100_000, "the run must finish");
        }
        assert!(frames > 1, "the run took several frames");
        assert!(app.status().done);
        let c = config();
        let mut whole = build(c.algorithm, &c.params, app.surface().heightfield.clone()).unwrap();
        whole.run_to_end();
        assert_eq!(app.front().unwrap(), whole.front());
        assert_eq!(app.status().evaluations, whole.progress().evaluations);
    }

    #[wasm_bindgen_test]
    fn arrow_keys_move_the_selection_along_the_front_and_stop_at_its_ends() {
        let mut app = app();
        app.run().unwrap();
        let mut clock = ticking_clock();
        while app.is_running() {
            app.tick(50.0, &mut clock);
        }
        let n = app.front().unwrap().len();
        assert!(n >= 3, "front of {n}");
        app.move_selection(1);
        assert_eq!(app.selected_front_index(), Some(0));
        app.move_selection(1);
        assert_eq!(app.selected_front_index(), Some(1));
        app.move_selection(-5);
        assert_eq!(app.selected_front_index(), Some(0));
        app.select_front_index(Some(n - 1));
        app.move_selection(1);
        assert_eq!(app.selected_front_index(), Some(n - 1));
        let selected = app.selected().unwrap().clone();
        assert_eq!(&selected, &app.front().unwrap().solutions()[n - 1]);
    }

    #[wasm_bindgen_test]
    fn bad_parameters_are_refused_with_a_message() {
        let mut app = app();
        let mut c = config();
        c.params.crossover_probability = 1.5;
        app.set_config(c);
        let e = app.run().unwrap_err();
        assert!(e.contains("crossover probability"), "{e}");
        assert!(!app.is_running());
    }

    #[wasm_bindgen_test]
    fn every_algorithm_in_the_menu_runs_in_the_browser() {
        for algorithm in Algorithm::ALL {
            let mut app = app();
            app.set_config(RunConfig {
                algorithm,
                ..config()
            });
            app.run().unwrap();
            app.tick(5.0, &mut ticking_clock());
            assert!(app.status().evaluations > 0, "{algorithm:?}");
        }
    }
}
