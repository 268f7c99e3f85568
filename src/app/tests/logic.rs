//! The browser app's logic, natively: plot layout and hit-testing, the 3-D view's geometry and
//! camera, loading, time-budgeted stepping, share links, the curated examples and the teaching
//! view.

const GRID: &[u8] = include_bytes!("../../../tests/data/volcano_33x33.f32");
const SIDECAR: &[u8] = include_bytes!("../../../tests/data/volcano_33x33.json");

mod plot_hit_testing {
    use crate::app::plot::{Layout, PlotPoint, hit_test, ticks};

    fn pt(t: f64, e: f64) -> PlotPoint {
        PlotPoint { t, e }
    }

    #[test]
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

    #[test]
    fn a_click_selects_the_nearest_point_within_the_radius_only() {
        let points = [pt(2.0, 900.0), pt(40.0, 120.0), pt(300.0, 3.5)];
        let layout = Layout::fit(400.0, 300.0, &points);
        let (x, y) = layout.to_pixel(points[1]);
        assert_eq!(hit_test(&layout, &points, x + 3.0, y - 2.0, 8.0), Some(1));
        // 20 px away from every point: no hit.
        assert_eq!(hit_test(&layout, &points, x + 20.0, y + 20.0, 8.0), None);
        assert_eq!(hit_test(&layout, &[], x, y, 8.0), None);
    }

    #[test]
    fn coincident_points_resolve_to_the_lower_index() {
        // Two members drawn on the same pixel: the answer must not depend on float noise.
        let points = [pt(10.0, 5.0), pt(10.0, 5.0)];
        let layout = Layout::fit(200.0, 200.0, &points);
        let (x, y) = layout.to_pixel(points[0]);
        assert_eq!(hit_test(&layout, &points, x, y, 4.0), Some(0));
    }

    #[test]
    fn a_single_point_or_no_point_still_maps_to_finite_pixels() {
        for points in [vec![pt(2.0, 0.0)], vec![]] {
            let layout = Layout::fit(300.0, 200.0, &points);
            let (x, y) = layout.to_pixel(pt(2.0, 0.0));
            assert!(x.is_finite() && y.is_finite());
        }
    }

    #[test]
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

    #[test]
    fn axis_titles_never_overlap_their_tick_labels() {
        // E from a 2048² grid's corner-only mesh (a billion) down to small errors, linear and
        // log, on small and wide canvases: every E tick label ends before the plotting area
        // and starts after the E title's band; the T labels end above the T title.
        use crate::app::plot::{
            E_TITLE_LEFT, TICK_FONT_PX, TICK_GAP, TITLE_LINE, format_value, label_width,
        };
        for top in [3.5, 950.0, 12_345.0, 1.0e6, 1.0e9, 1.234_567e9, 4.2e12] {
            for log in [false, true] {
                for (w, h) in [(320.0, 200.0), (900.0, 400.0)] {
                    let points = [pt(2.0, top), pt(4000.0, top / 1000.0), pt(8_000_000.0, 0.0)];
                    let layout = Layout::fit_scaled(w, h, &points, log);
                    let (l, _, _, b) = layout.area();
                    let ticks = layout.e_ticks();
                    assert!(!ticks.is_empty());
                    for v in ticks {
                        let text = format_value(v);
                        let left = l - TICK_GAP - label_width(&text);
                        assert!(
                            left >= E_TITLE_LEFT + TITLE_LINE,
                            "E = {top}, log {log}: label {text:?} starts at {left}"
                        );
                    }
                    // T labels hang below the area; the T title sits on the canvas's bottom.
                    assert!(b + TICK_GAP + TICK_FONT_PX + 2.0 <= h - 2.0 - TITLE_LINE);
                }
            }
        }
        assert_eq!(format_value(1.0e9), "1G");
        assert_eq!(format_value(1.25e6), "1.25M");
        assert_eq!(format_value(1000.0e6), "1G");
        assert_eq!(format_value(12_500.0), "12.5k");
    }

    #[test]
    fn the_e_axis_shows_sum_mean_or_max_and_hover_gives_all_three() {
        use crate::app::plot::{EAxis, hover_text};
        use crate::evaluator::Score;
        let score = Score {
            e_sum: 2500.0,
            e_max: 3.25,
            rms: f64::NAN,
            t: 40,
        };
        assert_eq!(EAxis::from_key("sum").unwrap().value(&score, 100), 2500.0);
        assert_eq!(EAxis::from_key("mean").unwrap().value(&score, 100), 25.0);
        assert_eq!(EAxis::from_key("max").unwrap().value(&score, 100), 3.25);
        assert_eq!(EAxis::from_key("median"), None);
        assert!(EAxis::Max.title("m", false).starts_with("E_max"));
        assert!(EAxis::Mean.title("", true).contains("(z units, log scale)"));
        assert_eq!(
            hover_text(&score, 100, "m"),
            "T = 40 · E_sum = 2500 · mean = 25 m · E_max = 3.25 m"
        );
    }

    #[test]
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

mod views {
    use crate::app::geometry::{ViewMapping, flat_mesh, wireframe};
    use crate::app::state::shown_mesh;
    use crate::evaluator::Evaluator;
    use crate::heightfield::Heightfield;
    use crate::import::raw;
    use std::sync::Arc;

    fn volcano() -> Arc<Heightfield> {
        Arc::new(raw::parse(super::GRID, super::SIDECAR, "volcano_33x33").unwrap())
    }

    // Kept points spread over the 33×33 grid (interior points of a few rows and columns).
    const KEPT: [u32; 6] = [34, 200, 530, 545, 800, 1000];

    #[test]
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

    #[test]
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
}

mod camera_and_loading {
    use crate::app::camera::{MAX_PITCH, MIN_DISTANCE, OrbitCamera};
    use crate::app::loader;
    use crate::import::{ImportOptions, Projection, Surface};

    #[test]
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

    #[test]
    fn panning_moves_the_target_and_keeps_the_distance() {
        let mut c = OrbitCamera::default();
        let d = c.distance;
        c.pan(50.0, 0.0, 500.0);
        assert_ne!(c.target, [0.0; 3]);
        assert_eq!(c.distance, d);
    }

    #[test]
    fn the_builtin_surface_is_a_real_grid_with_its_source_note() {
        let hf = loader::builtin();
        assert_eq!((hf.width(), hf.height()), (65, 65));
        assert!(hf.source().contains("jacksboro"));
        let (lo, hi) = hf.z_range();
        assert!(hi > lo);
    }

    #[test]
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

    #[test]
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
        assert_eq!(
            loader::options("spherical", 0, 0),
            Err("unknown projection “spherical”".to_string())
        );
        assert_eq!(
            loader::options("planar", 64, 0),
            Err("give both grid width and height, or neither".to_string())
        );
        assert_eq!(loader::surface("outer").unwrap(), Surface::Outer);
        assert_eq!(loader::surface("single").unwrap(), Surface::Single);
        assert!(loader::surface("inner").unwrap_err().contains("inner"));
    }

    /// A closed box around the origin with a second box 5 % inside it: a thick shell, which
    /// folds over itself in every projection.
    fn thick_box_stl() -> Vec<u8> {
        let mut s = String::from("solid shell\n");
        for scale in [1.0, 0.95] {
            let c = |x: f64, y: f64, z: f64| [x * scale, y * scale, z * scale * 0.5];
            let faces = [
                [
                    c(-1., -1., -1.),
                    c(1., -1., -1.),
                    c(1., 1., -1.),
                    c(-1., 1., -1.),
                ],
                [
                    c(-1., -1., 1.),
                    c(1., -1., 1.),
                    c(1., 1., 1.),
                    c(-1., 1., 1.),
                ],
                [
                    c(-1., -1., -1.),
                    c(1., -1., -1.),
                    c(1., -1., 1.),
                    c(-1., -1., 1.),
                ],
                [
                    c(-1., 1., -1.),
                    c(1., 1., -1.),
                    c(1., 1., 1.),
                    c(-1., 1., 1.),
                ],
                [
                    c(-1., -1., -1.),
                    c(-1., 1., -1.),
                    c(-1., 1., 1.),
                    c(-1., -1., 1.),
                ],
                [
                    c(1., -1., -1.),
                    c(1., 1., -1.),
                    c(1., 1., 1.),
                    c(1., -1., 1.),
                ],
            ];
            for q in faces {
                for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
                    s.push_str("facet normal 0 0 0\n outer loop\n");
                    for v in t {
                        s.push_str(&format!("  vertex {} {} {}\n", v[0], v[1], v[2]));
                    }
                    s.push_str(" endloop\nendfacet\n");
                }
            }
        }
        s.push_str("endsolid shell\n");
        s.into_bytes()
    }

    #[test]
    fn a_folding_mesh_is_reported_as_such_and_loads_as_its_outer_surface() {
        let stl = thick_box_stl();
        let e = loader::parse_file("shell.stl", &stl, None, &ImportOptions::default()).unwrap_err();
        assert!(e.folds, "{e:?}");
        assert!(
            e.message.starts_with("shell.stl") && e.message.contains("folds"),
            "{e:?}"
        );
        let outer = ImportOptions {
            surface: Surface::Outer,
            ..ImportOptions::default()
        };
        let hf = loader::parse_file("shell.stl", &stl, None, &outer).unwrap();
        assert!(hf.source().contains("outer surface"), "{}", hf.source());
        // Other failures are not offered the outer surface.
        let e = loader::parse_file("notes.txt", b"hello", None, &outer).unwrap_err();
        assert!(!e.folds);
    }

    #[test]
    fn a_geotiffs_georeferencing_is_summarised_for_the_dialog() {
        let tif = include_bytes!("../../../tests/data/volcano_87x61_int16_lzw_nodata.tif");
        let name = "volcano_87x61_int16_lzw_nodata.tif";
        let hf = loader::parse(name, tif, None, &ImportOptions::default()).unwrap();
        let text = loader::georeference_summary(&hf).unwrap();
        assert!(text.contains("pixel size 10 × 10 map units"), "{text}");
        assert!(text.contains("map (2667400, 6478710)"), "{text}");
        assert!(text.contains("nodata -9999: 14 cells filled"), "{text}");
        // No georeferencing tags: said so; a grid from another format has no summary.
        let plain = include_bytes!("../../../tests/data/volcano_87x61_uint16_packbits.tif");
        let hf = loader::parse("p.tif", plain, None, &ImportOptions::default()).unwrap();
        let text = loader::georeference_summary(&hf).unwrap();
        assert!(
            text.contains("no pixel scale") && text.contains("no nodata"),
            "{text}"
        );
        let ply = include_bytes!("../../../tests/data/volcano_87x61.ply");
        let hf = loader::parse("v.ply", ply, None, &ImportOptions::default()).unwrap();
        assert_eq!(loader::georeference_summary(&hf), None);
    }

    #[test]
    fn an_oversized_grid_size_is_refused_with_the_limit_in_the_message() {
        let ply = include_bytes!("../../../tests/data/bunny_33x33.ply");
        let o = loader::options("planar", 4097, 4097).unwrap();
        let e = loader::parse("bunny.ply", ply, None, &o).unwrap_err();
        assert!(e.contains("16.8 M points") && e.contains("limit"), "{e}");
    }

    #[test]
    fn a_grid_ply_loads_as_is_and_needs_no_dialog() {
        let ply = include_bytes!("../../../tests/data/volcano_87x61.ply");
        let hf = loader::parse("volcano_87x61.ply", ply, None, &ImportOptions::default()).unwrap();
        assert_eq!((hf.width(), hf.height()), (87, 61));
        assert!(!hf.resampled());
    }
}

mod app_stepping {
    use crate::app::algorithms::{Algorithm, Params, build};
    use crate::app::state::{App, Reproduction, RunConfig, Surface};
    use crate::import::raw;
    use std::sync::Arc;

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

    /// Ticks `app` with `budget_ms` per frame on `clock` until it stops running; returns the
    /// number of frames (at most 100 000: a run that would take more fails).
    fn tick_until_idle(app: &mut App, budget_ms: f64, clock: &mut impl FnMut() -> f64) -> usize {
        let mut frames = 0;
        while app.is_running() {
            app.tick(budget_ms, clock);
            frames += 1;
            assert!(frames < 100_000, "the run must stop");
        }
        frames
    }

    #[test]
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

    #[test]
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

    #[test]
    fn a_slow_call_keeps_the_next_frames_from_starting_a_call_late() {
        // Calls take 1 ms, but the fourth takes 6 ms (a large mesh's fresh build, say). The
        // frame after it expects 3 ms of a call (the 6 ms, faded once) and stops when that
        // would not fit in its 8 ms, at six calls instead of eight; as the memory of the slow
        // call fades, frames fill their budget again.
        let mut app = app();
        app.run().unwrap();
        let (mut now, mut readings) = (0.0, 0);
        let mut clock = move || {
            readings += 1;
            // Reading 1 starts the first frame; reading k + 1 ends call k of it.
            now += if readings == 5 {
                6.0
            } else if readings == 1 {
                0.0
            } else {
                1.0
            };
            now
        };
        assert_eq!(
            app.tick(8.0, &mut clock).steps,
            4,
            "stopped after the slow call"
        );
        assert_eq!(app.tick(8.0, &mut clock).steps, 6);
        let later: Vec<u32> = (0..5).map(|_| app.tick(8.0, &mut clock).steps).collect();
        assert_eq!(later.last(), Some(&8), "{later:?}");
    }

    #[test]
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

    #[test]
    fn a_paused_app_does_no_work() {
        let mut app = app();
        app.run().unwrap();
        app.pause();
        let report = app.tick(8.0, &mut ticking_clock());
        assert_eq!((report.steps, report.evaluations), (0, 0));
        assert_eq!(app.status().evaluations, 0);
    }

    #[test]
    fn slicing_into_frames_reaches_the_front_of_one_uninterrupted_run() {
        let mut app = app();
        app.run().unwrap();
        let frames = tick_until_idle(&mut app, 8.0, &mut ticking_clock());
        assert!(frames > 1, "the run took several frames");
        assert!(app.status().done);
        let c = config();
        let mut whole = build(c.algorithm, &c.params, app.surface().heightfield.clone()).unwrap();
        whole.run_to_end();
        assert_eq!(app.front().unwrap(), whole.front());
        assert_eq!(app.status().evaluations, whole.progress().evaluations);
    }

    #[test]
    fn arrow_keys_move_the_selection_along_the_front_and_stop_at_its_ends() {
        let mut app = app();
        app.run().unwrap();
        tick_until_idle(&mut app, 50.0, &mut ticking_clock());
        let n = app.front().unwrap().len();
        assert!(n >= 3, "front of {n}");
        // The finished run selected its knee; start from no selection.
        app.select_front_index(None);
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

    #[test]
    fn bad_parameters_are_refused_with_a_message() {
        let mut app = app();
        let mut c = config();
        c.params.crossover_probability = 1.5;
        app.set_config(c);
        let e = app.run().unwrap_err();
        assert!(e.contains("crossover probability"), "{e}");
        assert!(!app.is_running());
    }

    #[test]
    fn reproducing_stops_at_the_generation_and_selects_the_index() {
        // Re-running to generation 3 of a 6-generation run must stop there, paused, with the
        // front of a run that only has 3 generations (later ones do not change earlier ones).
        let mut app = app();
        app.reproduce(Reproduction {
            generations: 3,
            selected: Some(2),
        })
        .unwrap();
        let mut clock = ticking_clock();
        tick_until_idle(&mut app, 8.0, &mut clock);
        assert_eq!(app.reproduction(), None);
        assert_eq!(app.status().generation, 3);
        assert!(!app.status().done, "stopped before the run's own end");
        let c = config();
        let short = Params {
            generations: 3,
            ..c.params.clone()
        };
        let mut whole = build(c.algorithm, &short, app.surface().heightfield.clone()).unwrap();
        whole.run_to_end();
        assert_eq!(app.front().unwrap(), whole.front());
        assert_eq!(app.selected_front_index(), Some(2));
        assert_eq!(app.selected().unwrap(), &whole.front().solutions()[2]);
        // Run resumes to the end like any paused run.
        app.run().unwrap();
        tick_until_idle(&mut app, 8.0, &mut clock);
        assert!(app.status().done);
    }

    #[test]
    fn a_selection_past_the_front_or_zero_generations_selects_nothing() {
        let mut app = app();
        app.reproduce(Reproduction {
            generations: 0,
            selected: Some(0),
        })
        .unwrap();
        assert!(!app.is_running(), "0 generations: nothing runs");
        app.reproduce(Reproduction {
            generations: 1,
            selected: Some(1_000_000),
        })
        .unwrap();
        tick_until_idle(&mut app, 8.0, &mut ticking_clock());
        assert_eq!(app.status().generation, 1);
        assert_eq!(app.selected(), None);
    }

    /// The knee of `app`'s front, computed by brute force: each objective scaled to [0, 1]
    /// over the front, the member nearest (0, 0).
    fn expected_knee(app: &App) -> usize {
        let members = app.front().unwrap().solutions();
        let span = |f: &dyn Fn(usize) -> f64| {
            let values: Vec<f64> = (0..members.len()).map(f).collect();
            let lo = values.iter().cloned().fold(f64::INFINITY, f64::min);
            let hi = values.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            (lo, hi - lo)
        };
        let (e0, de) = span(&|i| members[i].e_sum);
        let (t0, dt) = span(&|i| members[i].t as f64);
        let distance = |i: usize| {
            let e = (members[i].e_sum - e0) / de;
            let t = (members[i].t as f64 - t0) / dt;
            (e * e + t * t).sqrt()
        };
        (0..members.len())
            .min_by(|&i, &j| distance(i).total_cmp(&distance(j)))
            .unwrap()
    }

    /// The paper's trade-off pick of `app`'s front, computed from the metric itself.
    fn expected_trade_off(app: &App) -> usize {
        let points: Vec<_> = app
            .front()
            .unwrap()
            .solutions()
            .iter()
            .map(|s| s.objectives())
            .collect();
        crate::metrics::trade_off_pick(&points, config().params.seed)
            .unwrap()
            .index
    }

    #[test]
    fn the_trade_off_pick_is_one_call_away() {
        let mut app = app();
        while !app.step_once().unwrap().done {}
        assert!(app.select_by(crate::pick::Pick::TradeOff));
        assert_eq!(app.selected_front_index(), Some(expected_trade_off(&app)));
        assert!(app.select_by(crate::pick::Pick::Knee));
        assert_eq!(app.selected_front_index(), Some(expected_knee(&app)));
    }

    #[test]
    fn a_finished_run_selects_its_knee() {
        let mut app = app();
        app.run().unwrap();
        let mut clock = ticking_clock();
        app.tick(8.0, &mut clock);
        assert!(!app.status().done);
        assert_eq!(
            app.selected(),
            None,
            "nothing is selected while the run goes on"
        );
        tick_until_idle(&mut app, 8.0, &mut clock);
        assert!(app.status().done);
        let n = app.front().unwrap().len();
        let pick = expected_knee(&app);
        assert!(
            n >= 3 && pick > 0 && pick < n - 1,
            "a middle member: {pick} of {n}"
        );
        assert_eq!(app.selected_front_index(), Some(pick));
        assert_eq!(
            app.shown_kept(),
            app.front().unwrap().solutions()[pick].kept
        );
    }

    #[test]
    fn a_run_finished_by_stepping_selects_its_knee() {
        let mut app = app();
        while !app.step_once().unwrap().done {}
        assert_eq!(app.selected_front_index(), Some(expected_knee(&app)));
    }

    #[test]
    fn a_selection_made_before_the_end_stays() {
        let mut app = app();
        app.run().unwrap();
        let mut clock = ticking_clock();
        while app.front().is_none_or(|f| f.len() < 2) {
            app.tick(8.0, &mut clock);
        }
        app.select_front_index(Some(0));
        let chosen = app.selected().unwrap().clone();
        tick_until_idle(&mut app, 8.0, &mut clock);
        assert!(app.status().done);
        assert_eq!(app.selected(), Some(&chosen));
        assert!(!app.select_if_unselected(app.front().unwrap().solutions()[1].clone()));
        assert_eq!(app.selected(), Some(&chosen));
    }

    #[test]
    fn a_shared_runs_selection_wins_at_the_end() {
        // Re-running a shared run to its last generation ends the run; the link's index stays.
        let mut app = app();
        app.reproduce(Reproduction {
            generations: config().params.generations as u64,
            selected: Some(0),
        })
        .unwrap();
        tick_until_idle(&mut app, 8.0, &mut ticking_clock());
        assert!(app.status().done);
        assert_ne!(expected_knee(&app), 0, "the test must tell them apart");
        assert_eq!(app.selected_front_index(), Some(0));
    }

    #[test]
    fn the_default_algorithm_is_memetic_with_the_clis_parameters() {
        let default = RunConfig::default();
        assert_eq!(default.algorithm, Algorithm::Memetic);
        assert_eq!(Algorithm::DEFAULT, Algorithm::Memetic, "first in the menu");
        assert_eq!(Algorithm::from_name("memetic"), Some(Algorithm::Memetic));
        // front.json records what `paretomesh run` without --algo records.
        assert_eq!(
            crate::app::algorithms::params_json(Algorithm::Memetic, &default.params),
            serde_json::to_value(crate::evolution::MemeticParams::default()).unwrap()
        );
        // It runs in the app like any other algorithm.
        let mut a = app();
        a.set_config(RunConfig {
            algorithm: Algorithm::Memetic,
            ..config()
        });
        a.run().unwrap();
        a.tick(30.0, &mut ticking_clock());
        assert!(a.status().evaluations > 0);
    }

    #[test]
    fn every_algorithm_in_the_menu_runs() {
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

mod curated_examples {
    use crate::app::examples::examples;
    use crate::app::loader::{BUILTINS, Builtin};
    use crate::app::share::{SharedSurface, decode, encode};

    const README: &str = include_str!("../../../README.md");

    #[test]
    fn every_builtin_surface_loads_with_its_name_and_source() {
        for b in BUILTINS {
            let hf = b.heightfield();
            assert!(hf.len() >= 33 * 33, "{}", b.name);
            assert!(hf.source().contains(b.name), "{}: {}", b.name, hf.source());
            assert_eq!(Builtin::named(b.name).unwrap().name, b.name);
        }
        assert!(Builtin::named("jacksboro").is_none(), "names match exactly");
    }

    #[test]
    fn the_examples_are_valid_links_on_builtin_surfaces_covering_three_kinds() {
        let examples = examples();
        assert!(examples.len() >= 3);
        let mut surfaces = Vec::new();
        for e in &examples {
            let fragment = encode(&e.link);
            assert_eq!(decode(&fragment).unwrap(), e.link, "{}", e.title);
            let SharedSurface::Builtin(name) = &e.link.surface else {
                panic!("{}: examples use built-in surfaces", e.title);
            };
            surfaces.push(name.clone());
        }
        // A terrain, a face-like relief and a range scan: three kinds of surface.
        for wanted in ["jacksboro_65x65", "camera_65x65", "bunny_65x65"] {
            assert!(surfaces.iter().any(|s| s == wanted), "{wanted}");
        }
    }

    #[test]
    fn the_readme_lists_exactly_the_pages_examples() {
        // The README's links are copies; a changed example (or codec) must be re-copied.
        let in_readme: Vec<&str> = README
            .split("#v1.")
            .skip(1)
            .map(|rest| rest.split([')', ' ', '>', '\n']).next().unwrap())
            .collect();
        let expected: Vec<String> = examples()
            .iter()
            .map(|e| encode(&e.link)["v1.".len()..].to_string())
            .collect();
        assert_eq!(
            in_readme, expected,
            "README links differ from src/app/examples.rs"
        );
        for e in examples() {
            assert!(
                README.contains(e.title),
                "README names the example {}",
                e.title
            );
        }
    }
}

mod teaching_view {
    use crate::app::oax_panel;
    use crate::app::plot::Shape;
    use crate::app::teaching::{Step, Stepper, scene};
    use crate::evolution::trace::Phase;
    use crate::evolution::{CrossoverKind, GaParams, Nsga2};
    use crate::import::raw;
    use crate::optimizer::Optimizer;
    use std::sync::Arc;

    fn run_to(generation: u64) -> Nsga2 {
        let hf = Arc::new(raw::parse(super::GRID, super::SIDECAR, "volcano_33x33").unwrap());
        let params = GaParams {
            population: 12,
            generations: 5,
            ..GaParams::default()
        };
        let mut run = Nsga2::new(hf, params, 2).unwrap();
        run.step_until(u64::MAX, generation);
        run
    }

    #[test]
    fn next_phase_walks_every_phase_then_asks_for_the_next_generation() {
        let mut s = Stepper::default();
        // Nothing traced yet: the first generation must be made first.
        assert_eq!(
            s.next_phase(0, None),
            Step::Run {
                generation: 1,
                then: Phase::Selection
            }
        );
        assert_eq!(s.arrived(0), None, "not there yet");
        assert_eq!(s.arrived(1), Some(Phase::Selection));
        let mut seen = vec![Phase::Selection];
        for _ in 1..Phase::ALL.len() {
            match s.next_phase(1, Some(1)) {
                Step::Show(p) => seen.push(p),
                other => panic!("expected a phase, got {other:?}"),
            }
        }
        assert_eq!(seen, Phase::ALL.to_vec());
        assert_eq!(
            s.next_phase(1, Some(1)),
            Step::Run {
                generation: 2,
                then: Phase::Selection
            },
            "after survival comes the next generation"
        );
        assert_eq!(
            s.next_generation(1),
            Step::Run {
                generation: 2,
                then: Phase::Survival
            }
        );
        assert_eq!(s.arrived(2), Some(Phase::Survival));
        // A trace of another generation than the run's (the user ran on): start over from it.
        assert!(matches!(
            s.next_phase(3, Some(2)),
            Step::Run { generation: 4, .. }
        ));
    }

    #[test]
    fn every_phase_has_marks_for_its_individuals_and_a_caption() {
        let run = run_to(2);
        let trace = run.last_generation().unwrap();
        let mu = trace.parents.len();
        for phase in Phase::ALL {
            let s = scene(trace, phase, CrossoverKind::Oax, 0.8);
            assert!(s.caption.contains(phase.explanation()), "{phase:?}");
            assert!(s.caption.starts_with("Generation 2"), "{}", s.caption);
            assert!(!s.legend.is_empty(), "{phase:?}");
            assert!(s.marks.iter().all(|m| !m.label.is_empty()));
            let expected = match phase {
                Phase::Selection => mu,
                Phase::Crossover | Phase::Mutation => {
                    mu + trace
                        .matings
                        .iter()
                        .filter(|m| m.crossed)
                        .map(|m| m.before_mutation.iter().flatten().count())
                        .sum::<usize>()
                }
                Phase::Evaluation => mu + trace.offspring.len(),
                Phase::Sorting | Phase::Crowding | Phase::Survival => 2 * mu,
            };
            assert_eq!(s.marks.len(), expected, "{phase:?}");
        }
        // Survival: exactly the dropped half is crossed out.
        let s = scene(trace, Phase::Survival, CrossoverKind::Oax, 0.8);
        let crosses = s.marks.iter().filter(|m| m.shape == Shape::Cross).count();
        assert_eq!(crosses, 2 * mu - trace.survivors.len());
        // Selection: the rings count the picks.
        let s = scene(trace, Phase::Selection, CrossoverKind::Oax, 0.8);
        let rings: f64 = s.marks.iter().map(|m| m.ring).sum();
        assert_eq!(rings as usize, 2 * trace.matings.len());
    }

    #[test]
    fn the_oax_panel_lists_the_array_the_effects_and_every_mesh() {
        let run = run_to(1);
        let record = run.last_crossover().expect("OAX ran in generation 1");
        let html = oax_panel::html(record);
        let rows = record.rows.len();
        // Two parents, the M rows and the best-levels child, each with a thumbnail.
        assert_eq!(html.matches("data-mesh=").count(), rows + 3);
        assert_eq!(oax_panel::meshes(record).len(), rows + 3);
        assert_eq!(
            html.matches(" ★</th>").count(),
            2 - usize::from(record.chosen[0] == record.chosen[1])
        );
        assert!(html.contains("Σ F at A") && html.contains("Σ F at B"));
        // Each factor has exactly one best level marked.
        assert_eq!(
            html.matches("class=\"chosen\"").count(),
            record.blocks.len()
        );
        // A thumbnail's mesh is the row's chromosome with its objectives.
        let third = &oax_panel::meshes(record)[2];
        assert_eq!(third.t, record.rows[0].objectives.t);
        assert_eq!(third.kept, record.rows[0].genes.indices());
    }
}

mod glb_export {
    use crate::app::geometry::error_colour;
    use crate::app::glb_export::{mesh_glb, vertex_error_colours};
    use crate::app::state::shown_mesh;
    use crate::import::raw;
    use std::sync::Arc;

    /// Vertex colours of a .glb, when it has them.
    type Colours = Option<Vec<[u8; 4]>>;

    /// Positions (with the node's translation added back), triangle count and colours of a
    /// .glb, read with the `gltf` crate.
    fn read_back(bytes: &[u8]) -> (Vec<[f64; 3]>, usize, Colours) {
        let file = gltf::Gltf::from_slice(bytes).expect("a valid .glb");
        let primitive = file.meshes().next().unwrap().primitives().next().unwrap();
        let blob = file.blob.as_deref();
        let reader = primitive.reader(|b| match b.source() {
            gltf::buffer::Source::Bin => blob,
            _ => None,
        });
        let shift = file.nodes().next().unwrap().transform().decomposed().0;
        let positions: Vec<[f64; 3]> = reader
            .read_positions()
            .unwrap()
            .map(|p| std::array::from_fn(|k| p[k] as f64 + shift[k] as f64))
            .collect();
        let triangles = reader.read_indices().unwrap().into_u32().count() / 3;
        let colours = reader.read_colors(0).map(|c| c.into_rgba_u8().collect());
        (positions, triangles, colours)
    }

    #[test]
    fn the_shown_mesh_reads_back_with_the_error_map_as_vertex_colours() {
        let hf = Arc::new(raw::parse(super::GRID, super::SIDECAR, "volcano_33x33").unwrap());
        // The corners, the centre and a few points: a coarse mesh with a visible error.
        let kept = vec![
            0,
            32,
            16 * 33 + 16,
            5 * 33 + 20,
            25 * 33 + 8,
            32 * 33,
            33 * 33 - 1,
        ];
        let mesh = shown_mesh(&hf, &kept).unwrap();
        let (positions, triangles, colours) = read_back(&mesh_glb(&hf, &mesh, false).unwrap());
        assert_eq!(positions.len(), mesh.kept.len());
        assert_eq!(triangles, mesh.triangles.len());
        assert!(colours.is_none(), "no error map shown, no colours");
        for (p, &g) in positions.iter().zip(&mesh.kept) {
            let want = hf.to_world(g, hf.z()[g as usize]);
            for k in 0..3 {
                assert!(
                    (p[k] - want[k]).abs() < 1e-3,
                    "vertex {g}: {p:?} vs {want:?}"
                );
            }
        }

        let (_, _, colours) = read_back(&mesh_glb(&hf, &mesh, true).unwrap());
        let colours = colours.expect("the error map as COLOR_0");
        assert_eq!(colours, vertex_error_colours(&hf, &mesh));
        // Different parts of a coarse mesh of a volcano are wrong by different amounts, and
        // none is off the ramp's top: the largest mean is below the largest point error.
        let distinct: std::collections::HashSet<_> = colours.iter().collect();
        assert!(distinct.len() > 2, "{colours:?}");
        let top = error_colour(1.0).map(|c| (c * 255.0).round() as u8);
        assert!(colours.iter().all(|c| *c != top), "{colours:?}");
        let bottom = error_colour(0.0).map(|c| (c * 255.0).round() as u8);
        // The full mesh is exact: every vertex takes the bottom of the ramp.
        let all: Vec<u32> = (0..hf.len() as u32).collect();
        let exact = shown_mesh(&hf, &all).unwrap();
        assert!(
            vertex_error_colours(&hf, &exact)
                .iter()
                .all(|c| *c == bottom)
        );
    }
}

mod parameter_fields {
    use crate::app::algorithms::{Algorithm, Field, Params, build};
    use crate::app::compare;
    use crate::evaluator::Score;
    use crate::evolution::CrossoverKind;
    use crate::import::raw;
    use std::sync::Arc;

    fn base() -> Params {
        Params {
            population: 10,
            generations: 4,
            seed: 3,
            ..Params::default()
        }
    }

    /// `params` with `field` set to another valid value.
    fn changed(params: &Params, field: Field) -> Params {
        let mut p = params.clone();
        match field {
            Field::Population => p.population = 14,
            Field::Generations => p.generations = 6,
            Field::Crossover => p.crossover = CrossoverKind::Uniform,
            Field::CrossoverProbability => p.crossover_probability = 0.3,
            Field::MutationProbability => p.mutation_probability = Some(0.2),
            Field::Seed => p.seed = 99,
        }
        p
    }

    /// Evaluations spent and the front (scores and kept sets) of `algorithm` with `params` on
    /// the 33×33 volcano: the two GAs run to their end, the others for a fixed budget (the
    /// memetic method's past its deterministic greedy seeding).
    fn outcome(algorithm: Algorithm, params: &Params) -> (u64, Vec<(Score, Vec<u32>)>) {
        let hf = Arc::new(raw::parse(super::GRID, super::SIDECAR, "volcano_33x33").unwrap());
        let mut run = build(algorithm, params, hf).unwrap();
        let progress = match algorithm {
            Algorithm::Nsga2 | Algorithm::Weighted => run.run_to_end(),
            Algorithm::Memetic => run.step(6000),
            _ => run.step(1500),
        };
        let front = run
            .front()
            .solutions()
            .iter()
            .map(|s| (s.score, s.kept.clone()))
            .collect();
        (progress.evaluations, front)
    }

    #[test]
    fn the_form_shows_a_field_exactly_when_it_changes_the_run() {
        for algorithm in Algorithm::ALL {
            let before = outcome(algorithm, &base());
            for field in Field::ALL {
                let after = outcome(algorithm, &changed(&base(), field));
                assert_eq!(
                    crate::app::algorithms::uses(algorithm, field),
                    after != before,
                    "{algorithm:?} and {field:?}: shown = {}",
                    crate::app::algorithms::uses(algorithm, field)
                );
            }
        }
    }

    #[test]
    fn the_memetic_method_reads_only_the_seed_and_the_classical_methods_none() {
        let used = |a: Algorithm| -> Vec<Field> {
            Field::ALL
                .into_iter()
                .filter(|&f| crate::app::algorithms::uses(a, f))
                .collect()
        };
        assert_eq!(used(Algorithm::Memetic), vec![Field::Seed]);
        assert_eq!(used(Algorithm::Greedy), Vec::<Field>::new());
        assert_eq!(used(Algorithm::Decimation), Vec::<Field>::new());
        assert_eq!(used(Algorithm::Nsga2), Field::ALL.to_vec());
    }

    #[test]
    fn compare_mode_reads_every_field_since_it_runs_the_two_gas() {
        for field in Field::ALL {
            assert!(compare::reads(field), "{field:?}");
        }
    }
}

mod worker_handoff {
    use crate::app::handoff::SurfaceParts;
    use crate::app::loader;
    use crate::export::WorldMesh;
    use crate::heightfield::Heightfield;
    use crate::import::ImportOptions;

    fn parse(name: &str, options: &ImportOptions) -> Heightfield {
        let bytes =
            std::fs::read(format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap();
        loader::parse_file(name, &bytes, None, options).unwrap()
    }

    fn round_trip(hf: &Heightfield) -> Heightfield {
        SurfaceParts::of(hf).into_heightfield().unwrap()
    }

    #[test]
    fn a_geotiff_crosses_with_its_georeference_and_exports_in_map_coordinates() {
        let hf = parse(
            "volcano_87x61_int16_lzw_nodata.tif",
            &ImportOptions::default(),
        );
        let geo = hf.georeference().expect("a georeferenced DEM").clone();
        let page = round_trip(&hf);
        assert_eq!(page, hf);
        assert_eq!(page.georeference(), Some(&geo));
        assert_eq!(
            loader::georeference_summary(&page),
            loader::georeference_summary(&hf)
        );
        // Corner (0, 0) is the south-west sample centre in map units: the tie point's corner
        // (2667400, 6478710) plus half a 10 m pixel east, and 60.5 pixels south.
        let corners = hf.corners();
        let mesh =
            WorldMesh::new(&page, &corners, &[[corners[0], corners[1], corners[2]]]).unwrap();
        assert_eq!(mesh.vertices[0][..2], [2_667_405.0, 6_478_105.0]);
        assert_eq!(
            mesh.vertices,
            WorldMesh::new(&hf, &corners, &[[corners[0], corners[1], corners[2]]])
                .unwrap()
                .vertices
        );
    }

    #[test]
    fn every_grid_kind_crosses_unchanged() {
        let resampled = ImportOptions {
            grid_size: Some((40, 30)),
            ..ImportOptions::default()
        };
        for hf in [
            parse(
                "jacksboro_65x65_float32_tiled_deflate.tif",
                &ImportOptions::default(),
            ),
            parse("volcano_87x61_uint16_packbits.tif", &resampled),
            parse("camera_33x33_float64.tif", &ImportOptions::default()),
            parse("volcano_87x61.ply", &ImportOptions::default()),
            parse("bunny_33x33.ply", &ImportOptions::default()),
            loader::builtin(),
        ] {
            assert_eq!(round_trip(&hf), hf, "{}", hf.source());
        }
    }

    #[test]
    fn broken_parts_are_refused_with_a_message() {
        let mut parts = SurfaceParts::of(&loader::builtin());
        parts.placement_kind = "spherical".into();
        assert_eq!(
            parts.clone().into_heightfield().unwrap_err(),
            "parsed surface: unknown placement spherical"
        );
        parts.placement_kind = "planar".into();
        parts.placement_values = vec![0.0; 11];
        assert_eq!(
            parts.clone().into_heightfield().unwrap_err(),
            "parsed surface: placement has too few values"
        );
        parts.placement_kind = "grid".into();
        parts.z.pop();
        let (w, h) = (parts.width, parts.height);
        assert_eq!(
            parts.into_heightfield().unwrap_err(),
            crate::heightfield::HeightfieldError::WrongLength {
                expected: w * h,
                found: w * h - 1
            }
            .to_string()
        );
    }
}
