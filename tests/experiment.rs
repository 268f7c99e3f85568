//! `paretomesh experiment` end to end on small grids with tiny budgets: every output file, the
//! report's numbers against an independent recomputation from results.json with the metrics
//! module, the figure's structure, `paretomesh report` reproducing both from results.json,
//! determinism across thread counts, equal and per-weight budgets, outside tools' fronts
//! (front.json, PLY/OBJ directories, JSON mesh lists) re-scored beside the methods, and bad
//! input.

use paretomesh::evaluator::Evaluator;
use paretomesh::experiment::{Budget, Dataset, DatasetResults, Method, Results, Settings, run_all};
use paretomesh::import;
use paretomesh::metrics::{self, Normalization, Point};
use std::path::{Path, PathBuf};
use std::process::Output;
use std::sync::Arc;

mod common;
use common::cli::{data, paretomesh, scratch};

/// A 17×17 grid: every other row and column of volcano_33x33 (a real surface, small enough for
/// a debug-build experiment), with a sidecar that names its unit.
fn volcano_17x17(dir: &Path) -> PathBuf {
    let bytes = std::fs::read(data("volcano_33x33.f32")).unwrap();
    let z: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let mut out = Vec::new();
    for y in (0..33).step_by(2) {
        for x in (0..33).step_by(2) {
            out.extend_from_slice(&z[y * 33 + x].to_le_bytes());
        }
    }
    let path = dir.join("volcano_17x17.f32");
    std::fs::write(&path, out).unwrap();
    std::fs::write(
        dir.join("volcano_17x17.json"),
        r#"{"width":17,"height":17,"units":"m","source":"volcano_33x33, every other point"}"#,
    )
    .unwrap();
    path
}

/// Runs the tiny experiment (the paper's per-weight budgets) into `out` with `threads` workers.
fn tiny_experiment(grid: &Path, out: &Path, threads: &str) -> Output {
    paretomesh(&[
        "experiment",
        grid.to_str().unwrap(),
        "--budget",
        "per-weight",
        "--runs",
        "3",
        "--weighted-runs",
        "2",
        "--pop",
        "8",
        "--gens",
        "3",
        "--seed",
        "5",
        "--threads",
        threads,
        "--out",
        out.to_str().unwrap(),
    ])
}

/// The table rows (cells trimmed, outer pipes dropped) between `heading` and the next `## `,
/// without header and separator rows (a row is a header when its first cell is in `headers`).
fn rows(report: &str, heading: &str, headers: &[&str]) -> Vec<Vec<String>> {
    let start = report
        .find(heading)
        .unwrap_or_else(|| panic!("no {heading}"));
    let rest = &report[start + heading.len()..];
    let end = rest.find("\n## ").unwrap_or(rest.len());
    rest[..end]
        .lines()
        .filter(|l| l.starts_with('|') && !l.starts_with("|---"))
        .map(|l| {
            l.trim_matches('|')
                .split(" | ")
                .map(|c| c.trim().to_string())
                .collect::<Vec<_>>()
        })
        .filter(|r| !headers.contains(&r[0].as_str()))
        .collect()
}

/// Parses `mean ± std` (std `n/a` → None).
fn summary(cell: &str) -> (f64, Option<f64>) {
    let (m, s) = cell.split_once(" ± ").unwrap_or_else(|| panic!("{cell:?}"));
    (m.parse().unwrap(), s.parse().ok())
}

fn mean_std(v: &[f64]) -> (f64, Option<f64>) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let std = (v.len() > 1)
        .then(|| (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt());
    (mean, std)
}

/// A 4-decimal cell against the recomputed value.
fn assert_4dp(cell: (f64, Option<f64>), want: (f64, Option<f64>), what: &str) {
    assert!(
        (cell.0 - want.0).abs() <= 0.5e-4 + 1e-12,
        "{what}: report {cell:?}, recomputed {want:?}"
    );
    match (cell.1, want.1) {
        (Some(a), Some(b)) => assert!((a - b).abs() <= 0.5e-4 + 1e-12, "{what}: {a} vs {b}"),
        (None, None) => {}
        _ => panic!("{what}: report {cell:?}, recomputed {want:?}"),
    }
}

/// A data set's numbers recomputed with the metrics module alone, independently of the report.
struct Recomputed {
    /// Per method, its runs' normalised fronts.
    runs: Vec<Vec<Vec<Point>>>,
    /// Per method, its runs merged into one front.
    merged: Vec<Vec<Point>>,
    /// Every method's merged front merged: the reference front of the HVRs.
    reference: Vec<Point>,
    /// Per method, each run's HVR against `reference`.
    hvr: Vec<Vec<f64>>,
}

fn recompute(d: &DatasetResults, paper: &Normalization, reference_point: [f64; 2]) -> Recomputed {
    let runs: Vec<Vec<Vec<Point>>> = d
        .methods
        .iter()
        .map(|m| m.runs.iter().map(|r| paper.solutions(&r.front)).collect())
        .collect();
    let merged: Vec<Vec<Point>> = runs
        .iter()
        .map(|r| metrics::merge(r.iter().map(Vec::as_slice)).unwrap())
        .collect();
    let reference = metrics::merge(merged.iter().map(Vec::as_slice)).unwrap();
    let hvr = runs
        .iter()
        .map(|r| {
            r.iter()
                .map(|f| metrics::hypervolume_ratio(f, &reference, reference_point).unwrap())
                .collect()
        })
        .collect();
    Recomputed {
        runs,
        merged,
        reference,
        hvr,
    }
}

#[test]
fn tiny_experiment_writes_consistent_tables_figure_and_results() {
    let dir = scratch("e2e");
    let grid = volcano_17x17(&dir);
    let out = dir.join("out");
    let o = tiny_experiment(&grid, &out, "2");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let json = std::fs::read_to_string(out.join("results.json")).unwrap();
    let svg = std::fs::read_to_string(out.join("fronts-volcano_17x17.svg")).unwrap();
    let results = Results::from_json(&json).unwrap();
    let labels: Vec<&str> = Method::standard().iter().map(|m| m.label()).collect();

    // results.json: the protocol's run counts and seeds, and real solutions.
    assert_eq!(results.datasets.len(), 1);
    let d = &results.datasets[0];
    assert_eq!(
        (d.grid.width, d.grid.height, d.e_units.as_str()),
        (17, 17, "m")
    );
    let hf = Arc::new(import::load(&grid).unwrap());
    let mut evaluator = Evaluator::new(hf.clone());
    let paper = Normalization::from_evaluator(&mut evaluator).unwrap();
    assert_eq!(
        (d.normalization.e_scale, d.normalization.t_scale),
        (paper.e_scale(), paper.t_scale())
    );
    assert_eq!(paper.t_scale(), 512.0); // 2·16·16
    let methods: Vec<Method> = d.methods.iter().map(|m| m.method).collect();
    assert_eq!(methods, Method::standard());
    for m in &d.methods {
        let seeds: Vec<_> = m.runs.iter().map(|r| r.seed).collect();
        if m.method.is_stochastic() {
            let want = match m.method {
                Method::WEIGHTED => vec![Some(5), Some(6)],
                _ => vec![Some(5), Some(6), Some(7)],
            };
            assert_eq!(seeds, want, "{}", m.method);
            if m.method == Method::MEMETIC {
                // Its own population; NSGA-II's 8 × 3 generations as evaluations.
                assert_eq!(m.params["population"], 24);
                assert_eq!(m.params["max_evaluations"], 84);
            } else {
                assert_eq!(m.params["population"], 8);
                assert_eq!(m.params["generations"], 3);
            }
        } else {
            assert_eq!(seeds, vec![None], "{}", m.method);
        }
        for r in &m.runs {
            assert!(!r.front.is_empty());
            for s in &r.front {
                let fresh = evaluator.score(&s.kept).unwrap();
                assert_eq!(fresh.t, s.t);
                assert!((fresh.e_sum - s.e_sum).abs() <= 1e-9 * s.e_sum.max(1.0));
            }
        }
    }

    // Independent recomputation with the metrics module.
    let reference_point = results.settings.reference_point;
    let Recomputed {
        runs,
        merged,
        reference,
        hvr,
    } = recompute(d, &paper, reference_point);

    // Table II: per-run HVR, then the merged fronts' HVR.
    let t2 = rows(&report, "## Table II.", &["Data set"]);
    assert_eq!(t2.len(), 2);
    assert_eq!(t2[0][0], "volcano_17x17");
    for k in 0..5 {
        assert_4dp(summary(&t2[0][k + 1]), mean_std(&hvr[k]), "HVR");
        let merged_hvr =
            metrics::hypervolume_ratio(&merged[k], &reference, reference_point).unwrap();
        let cell: f64 = t2[1][k + 1].parse().unwrap();
        assert!((cell - merged_hvr).abs() <= 0.5e-4 + 1e-12, "merged HVR");
    }

    // Table III: every ordered pair.
    let t3 = rows(&report, "## Table III.", &["A"]);
    assert_eq!(t3.len(), 20);
    for row in &t3 {
        let a = labels.iter().position(|l| *l == row[0]).unwrap();
        let b = labels.iter().position(|l| *l == row[1]).unwrap();
        let (mut eps, mut cov) = (vec![], vec![]);
        for fa in &runs[a] {
            for fb in &runs[b] {
                eps.push(metrics::additive_epsilon(fa, fb).unwrap());
                cov.push(metrics::coverage(fa, fb).unwrap());
            }
        }
        assert_4dp(summary(&row[2]), mean_std(&eps), "epsilon");
        assert_4dp(summary(&row[3]), mean_std(&cov), "coverage");
    }

    // Table IV: picks from the merged fronts, in the grid's units.
    let t4 = rows(&report, "## Table IV.", &["Data set"]);
    assert_eq!(t4.len(), 5);
    for (k, row) in t4.iter().enumerate() {
        assert_eq!(row[1], labels[k]);
        let picks = [
            metrics::best_error_pick(&merged[k]).unwrap(),
            metrics::fewest_triangles_pick(&merged[k]).unwrap(),
            metrics::trade_off_pick(&merged[k], results.settings.seed)
                .unwrap()
                .index,
        ];
        for (j, &i) in picks.iter().enumerate() {
            let [e, t] = paper.invert(merged[k][i]);
            let cell_e: f64 = row[2 + 2 * j].parse().unwrap();
            let cell_t: f64 = row[3 + 2 * j].parse().unwrap();
            assert!((cell_e - e).abs() <= 1e-5 * e.max(1.0), "{row:?}: E {e}");
            assert_eq!(cell_t, t.round(), "{row:?}");
        }
    }

    // Table V: averaged dominance probability and the rank-sum mark on per-run HVRs.
    let t5 = rows(&report, "## Table V.", &["P(row ≺ column)"]);
    assert_eq!(t5.len(), 5);
    for (a, row) in t5.iter().enumerate() {
        assert_eq!(row[0], labels[a]);
        for b in 0..5 {
            let cell = &row[b + 1];
            if a == b {
                assert_eq!(cell, "—");
                continue;
            }
            let mut dom = vec![];
            for fa in &runs[a] {
                for fb in &runs[b] {
                    dom.push(metrics::dominance_probability(fa, fb).unwrap());
                }
            }
            let mut parts = cell.split_whitespace();
            let p: f64 = parts.next().unwrap().parse().unwrap();
            assert!((p - mean_std(&dom).0).abs() <= 0.5e-4 + 1e-12, "{cell}");
            let mark = parts.next().unwrap();
            if hvr[a].len() > 1 && hvr[b].len() > 1 {
                let t = metrics::rank_sum_test(&hvr[a], &hvr[b]).unwrap();
                let want = match t.verdict(0.05) {
                    std::cmp::Ordering::Greater => "+",
                    std::cmp::Ordering::Less => "−",
                    std::cmp::Ordering::Equal => "=",
                };
                assert_eq!(mark, want, "{cell}");
                assert!(cell.contains(&format!("(p = {:.2e})", t.p_value)), "{cell}");
            } else {
                assert_eq!(mark, "n/a", "{cell}");
            }
        }
    }
    assert!(report.contains("Wall time: "));

    // The figure: well-formed XML, one front group and one legend entry per method, with the
    // merged front's points, and axis labels with units.
    let doc = roxmltree::Document::parse(&svg).expect("the figure is well-formed XML");
    let class = |n: &roxmltree::Node, c: &str| n.attribute("class") == Some(c);
    let fronts: Vec<_> = doc.descendants().filter(|n| class(n, "front")).collect();
    assert_eq!(fronts.len(), 5);
    for (k, g) in fronts.iter().enumerate() {
        assert_eq!(
            g.attribute("data-method"),
            Some(Method::standard()[k].name())
        );
        let polyline = g.children().find(|c| c.has_tag_name("polyline")).unwrap();
        let points = polyline.attribute("points").unwrap().split(' ').count();
        assert_eq!(points, merged[k].len());
        assert_eq!(
            g.children().filter(|c| c.has_tag_name("circle")).count(),
            merged[k].len()
        );
    }
    let legend: Vec<String> = doc
        .descendants()
        .filter(|n| class(n, "legend-entry"))
        .map(|n| n.descendants().filter_map(|t| t.text()).collect::<String>())
        .collect();
    assert_eq!(legend.len(), 5);
    for (k, entry) in legend.iter().enumerate() {
        assert!(entry.starts_with(labels[k]), "{entry}");
    }
    let axis: Vec<&str> = doc
        .descendants()
        .filter(|n| class(n, "axis-label"))
        .filter_map(|n| n.text())
        .collect();
    assert_eq!(axis, vec!["T (triangles)", "E = Σ|z − z̃| (m)"]);

    // `paretomesh report` recomputes the same report and figure from results.json alone.
    let again = dir.join("again");
    let r = paretomesh(&[
        "report",
        out.join("results.json").to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(
        std::fs::read_to_string(again.join("report.md")).unwrap(),
        report
    );
    assert_eq!(
        std::fs::read_to_string(again.join("fronts-volcano_17x17.svg")).unwrap(),
        svg
    );
}

/// results.json up to its timings, which are the only part allowed to differ.
fn without_timings(json: &str) -> &str {
    let at = json.find("\"timings\"").expect("results.json has timings");
    &json[..at]
}

#[test]
fn same_seed_gives_identical_results_on_one_or_two_threads() {
    let dir = scratch("determinism");
    let grid = volcano_17x17(&dir);
    let (one, two) = (dir.join("one"), dir.join("two"));
    assert!(tiny_experiment(&grid, &one, "1").status.success());
    assert!(tiny_experiment(&grid, &two, "2").status.success());
    let read = |d: &Path, f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    let (a, b) = (read(&one, "results.json"), read(&two, "results.json"));
    assert_eq!(without_timings(&a), without_timings(&b));
    assert!(a.contains("\"threads\":1") && b.contains("\"threads\":2"));
    // The report differs only in its command line (--threads, --out) and wall-time line; the
    // figure not at all.
    let strip = |r: String| {
        r.lines()
            .filter(|l| !l.starts_with("- Wall time:") && !l.starts_with("paretomesh experiment"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(
        strip(read(&one, "report.md")),
        strip(read(&two, "report.md"))
    );
    assert_eq!(
        read(&one, "fronts-volcano_17x17.svg"),
        read(&two, "fronts-volcano_17x17.svg")
    );

    // The library's sequential driver gives the same results as the CLI's parallel one.
    let settings = Settings {
        runs: 3,
        weighted_runs: 2,
        seed: 5,
        population: 8,
        generations: 3,
        budget: Budget::PerWeight,
        ..Settings::default()
    };
    let dataset = Dataset::new("volcano_17x17", import::load(&grid).unwrap(), "m").unwrap();
    let sequential = run_all(&[dataset], &settings).unwrap();
    let mut parallel = Results::from_json(&a).unwrap();
    parallel.timings = None;
    parallel.command = None;
    assert_eq!(sequential, parallel);
}

#[test]
fn bad_options_are_refused_with_a_message() {
    let dir = scratch("bad");
    let grid = volcano_17x17(&dir);
    let g = grid.to_str().unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let cases: [(&[&str], &str); 11] = [
        (
            &["--methods", "nsga2,simplex"],
            "unknown method \"simplex\"",
        ),
        (&["--runs", "0"], "runs must be at least 1"),
        (&["--weighted-runs", "0"], "runs must be at least 1"),
        (&["--methods", "greedy,greedy"], "listed twice"),
        (&["--reference", "1.1"], "reference point must look like"),
        (&["--pop", "1"], "population"),
        (&["--gens", "3"], "--gens sets the per-weight budget"),
        (
            &["--budget", "per-weight", "--evals", "99"],
            "--evals sets the equal budget",
        ),
        (&["--evals", "5"], "at least 11 are needed"),
        (
            &["--external", "a=x.json,b=y.json", "--external", "a=z.json"],
            "once per grid",
        ),
        (&["--external", "greedy=x.json"], "has a method's name"),
    ];
    for (extra, message) in cases {
        let mut args = vec!["experiment", g, "--out", o];
        args.extend_from_slice(extra);
        let r = paretomesh(&args);
        assert!(!r.status.success(), "{extra:?} was accepted");
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(err.contains(message), "{extra:?}: {err}");
    }
    // The same file twice would write one figure over the other.
    let r = paretomesh(&["experiment", g, g, "--out", o]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("two inputs are named"));
    assert!(!out.join("report.md").exists());
}

/// Reads an output file of an experiment.
fn read(dir: &Path, file: &str) -> String {
    std::fs::read_to_string(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// An upper bound on what one run may spend past its budget: it stops at the first mating
/// boundary at or after it, and one mating scores at most the 8 rows of the orthogonal array
/// (L8 for the default 7 factors), the best-levels child and the two mutated offspring.
const MATING_OVERSHOOT: u64 = 11;

#[test]
fn equal_budgets_give_every_ga_run_the_same_evaluations() {
    let dir = scratch("equal");
    let out = dir.join("out");
    let grid = data("jacksboro_33x33.f32");
    // 341 = 11 × 31: each weight of the weighted-sum GA gets 31 evaluations, none left over.
    let o = paretomesh(&[
        "experiment",
        grid.to_str().unwrap(),
        "--methods",
        "nsga2,weighted,greedy",
        "--runs",
        "2",
        "--pop",
        "10",
        "--evals",
        "341",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let results = Results::from_json(&read(&out, "results.json")).unwrap();
    assert_eq!(results.settings.budget, Budget::Equal { evaluations: 341 });
    let d = &results.datasets[0];
    for m in &d.methods {
        for r in &m.runs {
            let range = match m.method {
                Method::NSGA2 => 341..341 + MATING_OVERSHOOT,
                Method::WEIGHTED => 341..341 + 11 * MATING_OVERSHOOT,
                _ => continue,
            };
            assert!(
                range.contains(&r.evaluations),
                "{} run {} spent {}",
                m.method,
                r.run,
                r.evaluations
            );
        }
        if m.method.is_ga() {
            assert_eq!(m.params["max_evaluations"], 341);
            assert_eq!(m.params["population"], 10);
        }
    }
    let report = read(&out, "report.md");
    assert!(report.contains("## Protocol"), "{report}");
    assert!(report.contains(
        "each weight's GA run gets ⌊341 / 11⌋ = 31 evaluations, and the remaining 0 are not spent"
    ));
    let runs = rows(&report, "## Runs", &["Data set"]);
    let budgets: Vec<(&str, &str)> = runs
        .iter()
        .map(|r| (r[1].as_str(), r[3].as_str()))
        .collect();
    assert_eq!(
        budgets,
        vec![
            ("NSGA-II", "341"),
            ("Weighted-sum GA", "341 = 11 weights × 31 (+ 0 unspent)"),
            ("Greedy insertion", "own stopping rule"),
        ]
    );
    // The command that made the report heads it.
    assert!(
        report.contains("\n```sh\nparetomesh experiment "),
        "{report}"
    );
}

/// Writes a PLY with x, y, z vertices and triangles.
fn write_ply(path: &Path, vertices: &[[f64; 3]], triangles: &[[usize; 3]]) {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        vertices.len(),
        triangles.len()
    );
    for v in vertices {
        s.push_str(&format!("{} {} {}\n", v[0], v[1], v[2]));
    }
    for t in triangles {
        s.push_str(&format!("3 {} {} {}\n", t[0], t[1], t[2]));
    }
    std::fs::write(path, s).unwrap();
}

/// Writes an OBJ with vertices and 1-based faces.
fn write_obj(path: &Path, vertices: &[[f64; 3]], triangles: &[[usize; 3]]) {
    let mut s = String::from("# hand-written\n");
    for v in vertices {
        s.push_str(&format!("v {} {} {}\n", v[0], v[1], v[2]));
    }
    for t in triangles {
        s.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    std::fs::write(path, s).unwrap();
}

#[test]
fn outside_fronts_are_rescored_and_reported_beside_the_methods() {
    let dir = scratch("external");
    let grid = data("volcano_33x33.f32");
    let g = grid.to_str().unwrap();
    let hf = Arc::new(import::load(&grid).unwrap());
    let mut evaluator = Evaluator::new(hf.clone());

    // A real front.json: a short NSGA-II run.
    let front_json = dir.join("front.json");
    let r = paretomesh(&[
        "run",
        g,
        "--algo",
        "nsga2",
        "--pop",
        "8",
        "--gens",
        "3",
        "--seed",
        "3",
        "--out",
        front_json.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&front_json).unwrap()).unwrap();
    let members = run["front"].as_array().unwrap();

    // A directory of hand-written meshes over the 33×33 grid (x = column, y = row): the two
    // triangles of the corners, the four of the corners and the centre, one with an off-grid
    // vertex and one with a hole; other files are ignored.
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    let corners = [
        [0.0, 0.0, 1.0],
        [32.0, 0.0, 2.0],
        [0.0, 32.0, 3.0],
        [32.0, 32.0, 4.0],
    ];
    write_ply(
        &meshes.join("a-corners.ply"),
        &corners,
        &[[0, 1, 3], [0, 3, 2]],
    );
    let mut centre = corners.to_vec();
    centre.push([16.0, 16.0, 0.0]);
    let fan = [[0, 1, 4], [1, 3, 4], [3, 2, 4], [2, 0, 4]];
    write_obj(&meshes.join("b-centre.obj"), &centre, &fan);
    centre[4] = [16.5, 16.0, 0.0];
    write_ply(&meshes.join("c-offgrid.ply"), &centre, &fan);
    write_obj(&meshes.join("d-hole.obj"), &corners, &[[0, 1, 3]]);
    std::fs::write(meshes.join("notes.txt"), "not a mesh").unwrap();

    // A JSON list over grid indices (y·33 + x): the corners with their two triangles, the
    // corners and the centre left to the project's triangulation, and one out of range.
    let list = dir.join("list.json");
    std::fs::write(
        &list,
        r#"[{"vertices":[0,32,1056,1088],"triangles":[[0,1,3],[0,3,2]]},
            {"vertices":[0,32,1056,1088,544]},
            {"vertices":[0,32,1056,5000]}]"#,
    )
    .unwrap();

    let out = dir.join("out");
    let external = format!(
        "run={},hand={},list={}",
        front_json.display(),
        meshes.display(),
        list.display()
    );
    let o = paretomesh(&[
        "experiment",
        g,
        "--methods",
        "greedy",
        "--external",
        &external,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let results = Results::from_json(&read(&out, "results.json")).unwrap();
    let x = &results.datasets[0].external;
    let names: Vec<&str> = x.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(names, vec!["run", "hand", "list"]);

    // The run's front.json comes back with the run's own numbers: Delaunay meshes, re-scored.
    assert_eq!(
        (x[0].meshes, x[0].rejected.len(), x[0].not_delaunay),
        (members.len(), 0, 0)
    );
    assert_eq!(x[0].front.len(), members.len());
    for (s, m) in x[0].front.iter().zip(members) {
        assert_eq!(s.t as u64, m["T"].as_u64().unwrap());
        let e = m["E_sum"].as_f64().unwrap();
        assert!(
            (s.e_sum - e).abs() <= 1e-9 * e.max(1.0),
            "{} vs {e}",
            s.e_sum
        );
    }

    // The hand-written meshes: two valid, scored on their own triangles; two refused.
    let corner_mesh = evaluator
        .score_triangulation(&[[0, 32, 1088], [0, 1088, 1056]])
        .unwrap();
    let centre_mesh = evaluator.score(&[0, 32, 544, 1056, 1088]).unwrap();
    let hand = &x[1];
    assert_eq!((hand.meshes, hand.valid()), (4, 2));
    let refused: Vec<(&str, &str)> = hand
        .rejected
        .iter()
        .map(|r| (r.mesh.as_str(), r.reason.as_str()))
        .collect();
    assert_eq!(refused[0].0, "c-offgrid.ply");
    assert!(
        refused[0]
            .1
            .contains("vertex 4 at (16.5, 16) is not on a grid point"),
        "{refused:?}"
    );
    assert_eq!(refused[1].0, "d-hole.obj");
    assert!(refused[1].1.contains("hole"), "{refused:?}");
    let points: Vec<(f64, usize)> = hand.front.iter().map(|s| (s.e_sum, s.t)).collect();
    let mut want = vec![(corner_mesh.e_sum, 2)];
    if centre_mesh.e_sum < corner_mesh.e_sum {
        want.push((centre_mesh.e_sum, 4));
    }
    assert_eq!(points, want);

    // The list: the same two meshes, the third refused.
    let listed = &x[2];
    assert_eq!((listed.meshes, listed.valid()), (3, 2));
    assert!(
        listed.rejected[0].reason.contains("out of range"),
        "{listed:?}"
    );
    assert_eq!(
        listed
            .front
            .iter()
            .map(|s| (s.e_sum, s.t))
            .collect::<Vec<_>>(),
        want
    );

    // Every table has a column or rows for them; an outside front is one sample: no tests.
    let report = read(&out, "report.md");
    let header = "| Data set | Greedy insertion | run | hand | list |";
    assert_eq!(report.matches(header).count(), 2, "{report}");
    assert_eq!(rows(&report, "## Table III.", &["A"]).len(), 12);
    let t4 = rows(&report, "## Table IV.", &["Data set"]);
    assert_eq!(
        t4.iter().map(|r| r[1].as_str()).collect::<Vec<_>>(),
        vec!["Greedy insertion", "run", "hand", "list"]
    );
    let t5 = rows(&report, "## Table V.", &["P(row ≺ column)"]);
    for row in &t5 {
        for c in &row[1..] {
            assert!(c == "—" || c.ends_with(" n/a"), "{row:?}");
        }
    }
    let outside = rows(&report, "## Outside fronts", &["Data set"]);
    assert_eq!(
        outside[1][3..8],
        ["4", "2", "2", "0", &hand.front.len().to_string()]
    );
    assert!(report.contains("- c-offgrid.ply: vertex 4 at (16.5, 16) is not on a grid point"));
    assert!(report.contains("counts as a single run"));

    // The figure: one group per front, the outside ones marked.
    let svg = read(&out, "fronts-volcano_33x33.svg");
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let groups: Vec<_> = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("front"))
        .map(|n| {
            (
                n.attribute("data-method").unwrap(),
                n.attribute("data-external").is_some(),
            )
        })
        .collect();
    assert_eq!(
        groups,
        vec![
            ("greedy", false),
            ("run", true),
            ("hand", true),
            ("list", true)
        ]
    );

    // `paretomesh report` rebuilds the same report from results.json alone.
    let again = dir.join("again");
    let r = paretomesh(&[
        "report",
        out.join("results.json").to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(read(&again, "report.md"), report);

    // An outside front with no valid mesh stops the experiment before any run, with reasons.
    let bad = dir.join("bad");
    std::fs::create_dir_all(&bad).unwrap();
    std::fs::copy(meshes.join("c-offgrid.ply"), bad.join("c-offgrid.ply")).unwrap();
    let spec = format!("bad={}", bad.display());
    let o = paretomesh(&[
        "experiment",
        g,
        "--methods",
        "greedy",
        "--external",
        &spec,
        "--out",
        dir.join("none").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("no valid mesh") && err.contains("not on a grid point"),
        "{err}"
    );
}

#[test]
fn memetic_ablation_variants_run_at_the_same_budget_and_are_tested_against_the_full_method() {
    let dir = scratch("ablation");
    let out = dir.join("out");
    let grid = data("camera_33x33.f32");
    // 2 600 evaluations: the two greedy sweeps (2 × 1 089) and a few generations.
    let o = paretomesh(&[
        "experiment",
        grid.to_str().unwrap(),
        "--methods",
        "greedy",
        "--ablation",
        "memetic",
        "--runs",
        "3",
        "--evals",
        "2600",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let results = Results::from_json(&read(&out, "results.json")).unwrap();
    let d = &results.datasets[0];
    let methods: Vec<Method> = d.methods.iter().map(|m| m.method).collect();
    let mut want = vec![Method::GREEDY];
    want.extend(Method::MEMETIC.with_ablations());
    assert_eq!(methods, want);

    let hf = Arc::new(import::load(&grid).unwrap());
    let mut evaluator = Evaluator::new(hf.clone());
    let paper = Normalization::from_evaluator(&mut evaluator).unwrap();
    let switches = [
        "greedy_seeding",
        "guided_mutation",
        "neighbour_mating",
        "local_search",
    ];
    for m in d.methods.iter().filter(|m| m.method != Method::GREEDY) {
        assert_eq!(m.params["max_evaluations"], 2600, "{}", m.method);
        // The full method writes no switch; each variant writes the one it turns off.
        let off: Vec<&str> = switches
            .iter()
            .copied()
            .filter(|s| m.params.get(*s) == Some(&serde_json::Value::Bool(false)))
            .collect();
        assert_eq!(
            off.len(),
            usize::from(m.method != Method::MEMETIC),
            "{}",
            m.method
        );
        let seeds: Vec<_> = m.runs.iter().map(|r| r.seed).collect();
        assert_eq!(seeds, vec![Some(1), Some(2), Some(3)], "{}", m.method);
        for r in &m.runs {
            assert!(!r.front.is_empty(), "{}", m.method);
            // Every GA run stops within one unit of work of the budget (a move's trials, or a
            // local-search round, are the largest: under 100 evaluations).
            assert!(
                (2600..2700).contains(&r.evaluations),
                "{} spent {}",
                m.method,
                r.evaluations
            );
            for s in &r.front {
                let fresh = evaluator.score(&s.kept).unwrap();
                assert_eq!(fresh.t, s.t);
                assert!((fresh.e_sum - s.e_sum).abs() <= 1e-9 * s.e_sum.max(1.0));
            }
        }
    }
    // Greedy seeding puts both greedy fronts in the archive, so the full method's runs all
    // differ from the unseeded variant's.
    let full = &d.methods[1];
    let no_seed = &d.methods[2];
    assert_eq!(no_seed.method, Method::MEMETIC_NO_SEED);
    assert_ne!(full.runs[0].front, no_seed.runs[0].front);

    // The ablation table: each variant against the full method, p from the rank-sum test on
    // the per-run HVRs recomputed here.
    let report = read(&out, "report.md");
    for m in Method::MEMETIC.with_ablations().into_iter().skip(1) {
        let (_, removes) = m.spec().ablation.unwrap();
        assert!(report.contains(removes), "{m} is not explained:\n{report}");
    }
    let hvr = recompute(d, &paper, results.settings.reference_point).hvr;
    let table = rows(&report, "## Ablations", &["Data set"]);
    assert_eq!(table.len(), 4, "{report}");
    for (k, row) in table.iter().enumerate() {
        let variant = k + 2;
        assert_eq!(row[1], d.methods[variant].method.label());
        assert_4dp(summary(&row[2]), mean_std(&hvr[variant]), "variant HVR");
        assert_4dp(summary(&row[3]), mean_std(&hvr[1]), "full HVR");
        let t = metrics::rank_sum_test(&hvr[variant], &hvr[1]).unwrap();
        assert_eq!(row[5], format!("{:.2e}", t.p_value), "{row:?}");
        let mark = match t.verdict(0.05) {
            std::cmp::Ordering::Greater => "+",
            std::cmp::Ordering::Less => "−",
            std::cmp::Ordering::Equal => "=",
        };
        assert_eq!(row[6], mark, "{row:?}");
    }
    // The figure draws every variant.
    let svg = read(&out, "fronts-camera_33x33.svg");
    for m in &methods {
        assert!(
            svg.contains(&format!("data-method=\"{}\"", m.name())),
            "{m}"
        );
    }

    // --ablation of a method without variants is refused.
    let o = paretomesh(&[
        "experiment",
        grid.to_str().unwrap(),
        "--ablation",
        "nsga2",
        "--out",
        dir.join("refused").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("no ablation variants"));
}
