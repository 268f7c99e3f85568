//! `paretomesh experiment GRID... [--budget equal|per-weight] [--evals 17400 | --gens 50]
//! [--pop 100] [--runs 10] [--weighted-runs N] [--seed S] [--methods nsga2,weighted,…]
//! [--external NAME=FILE[,NAME=FILE…]]… [--reference E,T] [--threads N] --out DIR`:
//! the protocol on every input, on every core, then report.md, fronts-<name>.svg and
//! results.json in DIR. And `paretomesh report RESULTS --out DIR`: the report and figures again
//! from a results.json alone.

use super::input::InputArgs;
use clap::{Args, ValueEnum};
use paretomesh::evaluator::Evaluator;
use paretomesh::experiment::{
    self, Analysis, Budget, DEFAULT_EQUAL_EVALUATIONS, Dataset, ExternalFront, Job, Method,
    Results, RunRecord, RunTiming, Settings, Timings, external,
};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// The options of `paretomesh experiment`.
#[derive(Args, Debug)]
pub(super) struct ExperimentArgs {
    /// The first input grid, and the import options applied to every input.
    #[command(flatten)]
    input: InputArgs,
    /// More input grids (each is one data set of the tables).
    #[arg(value_name = "GRID")]
    more: Vec<PathBuf>,
    /// Runs of NSGA-II and of each memetic method (deterministic methods run once).
    #[arg(long, default_value_t = 10)]
    runs: usize,
    /// Runs of the weighted-sum GA, each a sweep over its 11 weights [default: --runs with
    /// --budget equal, where a sweep costs one NSGA-II run; 1 with --budget per-weight, the
    /// paper's one sweep].
    #[arg(long)]
    weighted_runs: Option<usize>,
    /// Run k of a stochastic method uses seed SEED + k.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// GA budgets: `equal` gives every GA run the same evaluations (--evals; the weighted-sum
    /// GA splits them over its 11 weights), `per-weight` is the paper's population × generations
    /// per GA run, and so per weight.
    #[arg(long, value_enum, default_value_t = BudgetArg::Equal)]
    budget: BudgetArg,
    /// Evaluations of one GA run with `--budget equal`.
    #[arg(long, value_name = "N")]
    evals: Option<u64>,
    /// GA population (NSGA-II and each weighted-sum GA run).
    #[arg(long, default_value_t = 100)]
    pop: usize,
    /// GA generations with `--budget per-weight` [default: 50].
    #[arg(long)]
    gens: Option<usize>,
    /// Comma-separated methods to compare, in table order [default: nsga2, weighted,
    /// decimation, greedy, memetic]; the memetic ablation variants are memetic-no-seed,
    /// memetic-random-mutation, memetic-no-neighbour-mating and memetic-no-local-search.
    #[arg(long, value_delimiter = ',')]
    methods: Vec<String>,
    /// Adds METHOD and every ablation variant of it (each with one component switched off, at
    /// the same budget) after the methods compared.
    #[arg(long, value_name = "METHOD")]
    ablation: Option<String>,
    /// Fronts made by other tools, one option per grid in grid order, each NAME=FILE,…: FILE is
    /// a front.json, a JSON list of {vertices: [grid indices], triangles: [[a, b, c], …]}
    /// (indices into vertices), or a directory of PLY/OBJ meshes with vertices on grid points
    /// (x = column, y = row). Every grid needs the same names.
    #[arg(long, value_name = "NAME=FILE,...")]
    external: Vec<String>,
    /// Hypervolume reference point in normalised (E, T), e.g. 1.1,1.1.
    #[arg(long, value_name = "E,T", value_parser = parse_reference)]
    reference: Option<[f64; 2]>,
    /// Worker threads (default: RAYON_NUM_THREADS, else every core). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
}

/// `--budget`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum BudgetArg {
    /// The same evaluations for every GA run.
    Equal,
    /// The paper's: population × generations per GA run, so per weight of the weighted-sum GA.
    PerWeight,
}

/// The options of `paretomesh report`.
#[derive(Args, Debug)]
pub(super) struct ReportArgs {
    /// A results.json written by `paretomesh experiment`.
    results: PathBuf,
    /// Output directory for report.md and the figures (created if missing).
    #[arg(long)]
    out: PathBuf,
}

fn parse_reference(text: &str) -> Result<[f64; 2], String> {
    let bad = || format!("the reference point must look like 1.1,1.1, got {text:?}");
    let (e, t) = text.split_once(',').ok_or_else(bad)?;
    Ok([
        e.trim().parse().map_err(|_| bad())?,
        t.trim().parse().map_err(|_| bad())?,
    ])
}

/// The unit of z: the raw format's sidecar may say (`units`); other inputs do not.
fn e_units(path: &Path) -> String {
    let sidecar = path.with_extension("json");
    let is_raw = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("f32"));
    is_raw
        .then(|| std::fs::read(&sidecar).ok())
        .flatten()
        .and_then(|bytes| serde_json::from_slice::<serde_json::Value>(&bytes).ok())
        .and_then(|v| v.get("units")?.as_str().map(str::to_string))
        .unwrap_or_else(|| "height units".to_string())
}

/// A short name for tables and file names: the file name without its extension.
fn dataset_name(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// The budget the options ask for; `--evals` belongs to `equal` and `--gens` to `per-weight`,
/// so that neither is silently ignored.
fn budget(args: &ExperimentArgs) -> Result<(Budget, usize), String> {
    let paper_generations = Settings::default().generations;
    match args.budget {
        BudgetArg::Equal => {
            if args.gens.is_some() {
                return Err(
                    "--gens sets the per-weight budget; with --budget equal every GA run stops at --evals evaluations"
                        .to_string(),
                );
            }
            let evaluations = args.evals.unwrap_or(DEFAULT_EQUAL_EVALUATIONS);
            Ok((Budget::Equal { evaluations }, paper_generations))
        }
        BudgetArg::PerWeight => {
            if args.evals.is_some() {
                return Err(
                    "--evals sets the equal budget; with --budget per-weight every GA run has --pop individuals for --gens generations"
                        .to_string(),
                );
            }
            Ok((Budget::PerWeight, args.gens.unwrap_or(paper_generations)))
        }
    }
}

/// One `--external` value: its (name, file) pairs.
fn parse_external(text: &str) -> Result<Vec<(String, PathBuf)>, String> {
    text.split(',')
        .map(|part| {
            let (name, file) = part
                .split_once('=')
                .map(|(n, f)| (n.trim(), f.trim()))
                .filter(|(n, f)| !n.is_empty() && !f.is_empty())
                .ok_or_else(|| format!("--external wants NAME=FILE[,NAME=FILE…], got {part:?}"))?;
            if Method::parse(name).is_ok() {
                return Err(format!(
                    "the outside front {name:?} has a method's name; name it after its tool"
                ));
            }
            Ok((name.to_string(), PathBuf::from(file)))
        })
        .collect()
}

/// `--external` options: per grid, the (name, file) pairs.
fn external_specs(
    args: &ExperimentArgs,
    grids: usize,
) -> Result<Vec<Vec<(String, PathBuf)>>, String> {
    if args.external.is_empty() {
        return Ok(vec![Vec::new(); grids]);
    }
    if args.external.len() != grids {
        return Err(format!(
            "--external is given {} time(s) for {grids} grid(s): give it once per grid, in grid order",
            args.external.len()
        ));
    }
    let specs = args
        .external
        .iter()
        .map(|text| parse_external(text))
        .collect::<Result<Vec<_>, String>>()?;
    let names = |v: &Vec<(String, PathBuf)>| v.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
    let first = names(&specs[0]);
    for (i, n) in first.iter().enumerate() {
        if first[..i].contains(n) {
            return Err(format!("the outside front {n:?} is named twice"));
        }
    }
    if let Some(other) = specs.iter().map(names).find(|n| *n != first) {
        return Err(format!(
            "every --external needs the same names in the same order (the tables have one column per name): {first:?} and {other:?}"
        ));
    }
    Ok(specs)
}

/// Reads one outside front for `dataset` and re-scores it; an error when it cannot be read at
/// all or no mesh of it is valid.
fn read_external(name: &str, path: &Path, dataset: &Dataset) -> Result<ExternalFront, String> {
    let hf = &dataset.heightfield;
    let (w, h) = (hf.width(), hf.height());
    let at = |e: String| format!("--external {name}={}: {e}", path.display());
    let inputs = if path.is_dir() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(|e| at(format!("cannot read the directory: {e}")))?
            .filter_map(|entry| entry.ok().map(|e| e.path()))
            .filter(|p| {
                p.extension()
                    .is_some_and(|x| x.eq_ignore_ascii_case("ply") || x.eq_ignore_ascii_case("obj"))
            })
            .collect();
        files.sort();
        if files.is_empty() {
            return Err(at("the directory holds no .ply or .obj file".to_string()));
        }
        files
            .iter()
            .map(|f| {
                let label = f.file_name().map_or_else(
                    || f.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                match std::fs::read(f) {
                    Ok(bytes) => {
                        let ext = f
                            .extension()
                            .map(|x| x.to_string_lossy())
                            .unwrap_or_default();
                        external::from_mesh_file(label, &ext, &bytes, w, h)
                    }
                    Err(e) => experiment::MeshInput {
                        label,
                        mesh: Err(format!("cannot read the file: {e}")),
                    },
                }
            })
            .collect()
    } else {
        let bytes = std::fs::read(path).map_err(|e| at(format!("cannot read: {e}")))?;
        external::from_json(&bytes, w, h).map_err(at)?
    };
    let mut evaluator = Evaluator::new(hf.clone());
    let front = experiment::rescore(name, &path.display().to_string(), inputs, &mut evaluator);
    eprintln!(
        "{} {name}: {} mesh(es), {} valid, {} refused, {} on the front",
        dataset.name,
        front.meshes,
        front.valid(),
        front.rejected.len(),
        front.front.len()
    );
    if front.front.is_empty() {
        let why: Vec<String> = front
            .rejected
            .iter()
            .take(3)
            .map(|r| format!("{}: {}", r.mesh, r.reason))
            .collect();
        return Err(at(format!(
            "no valid mesh for {} (first refusals: {})",
            dataset.name,
            why.join("; ")
        )));
    }
    Ok(front)
}

/// The methods to compare: `--methods` (or the standard ones), then `--ablation`'s method and
/// its variants that are not listed yet.
fn methods(args: &ExperimentArgs) -> Result<Vec<Method>, String> {
    let mut methods: Vec<Method> = if args.methods.is_empty() {
        Method::standard()
    } else {
        args.methods
            .iter()
            .map(|m| Method::parse(m))
            .collect::<Result<_, _>>()?
    };
    if let Some(name) = &args.ablation {
        let full = Method::parse(name)?;
        let all = full.with_ablations();
        if all.len() < 2 {
            return Err(format!(
                "--ablation: {full} has no ablation variants (memetic has)"
            ));
        }
        for m in all {
            if !methods.contains(&m) {
                methods.push(m);
            }
        }
    }
    Ok(methods)
}

/// The command line as a shell would take it back (arguments with spaces or quotes quoted).
fn command_line() -> String {
    let quote = |a: String| {
        if !a.is_empty()
            && a.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_./=,:+".contains(c))
        {
            a
        } else {
            format!("'{}'", a.replace('\'', r"'\''"))
        }
    };
    std::iter::once("paretomesh".to_string())
        .chain(std::env::args().skip(1).map(quote))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs `paretomesh experiment`: every method's runs on every data set, in parallel, then the
/// report, the figures and results.json.
pub(super) fn run(args: &ExperimentArgs) -> Result<(), String> {
    let start = Instant::now();
    let settings = settings(args)?;
    settings.validate().map_err(|e| e.to_string())?;
    let datasets = load_datasets(args)?;

    let specs = external_specs(args, datasets.len())?;
    // Bad parameters and outside fronts fail now, not after the runs.
    experiment::check_methods(&settings, &datasets[0]).map_err(|e| e.to_string())?;
    let externals = datasets
        .iter()
        .zip(&specs)
        .map(|(d, spec)| {
            spec.iter()
                .map(|(name, path)| read_external(name, path, d))
                .collect::<Result<Vec<_>, String>>()
        })
        .collect::<Result<Vec<_>, String>>()?;

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .map_err(|e| format!("cannot start the worker threads: {e}"))?;
    let threads = pool.current_num_threads();
    let jobs = experiment::plan(datasets.len(), &settings);
    eprintln!(
        "experiment: {} data set(s), {} runs on {threads} thread(s)",
        datasets.len(),
        jobs.len()
    );
    let (records, run_timings) = run_jobs(&pool, &jobs, &datasets, &settings)?;
    let mut results = experiment::assemble(&settings, &datasets, &jobs, records, None)
        .map_err(|e| e.to_string())?;
    for (d, x) in results.datasets.iter_mut().zip(externals) {
        d.external = x;
    }
    results.command = Some(command_line());
    let analysis = Analysis::of(&results).map_err(|e| e.to_string())?;
    results.timings = Some(Timings {
        wall_seconds: start.elapsed().as_secs_f64(),
        threads,
        runs: run_timings,
    });

    let out = write_outputs(&args.out, &results, &analysis, true)?;
    println!(
        "wrote {out} (report.md, results.json, {} figure(s)) in {:.1} s",
        results.datasets.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The experiment's settings from the command line (not yet validated).
fn settings(args: &ExperimentArgs) -> Result<Settings, String> {
    let (budget, generations) = budget(args)?;
    Ok(Settings {
        methods: methods(args)?,
        runs: args.runs,
        weighted_runs: args.weighted_runs.unwrap_or(match budget {
            Budget::Equal { .. } => args.runs,
            Budget::PerWeight => 1,
        }),
        seed: args.seed,
        population: args.pop,
        generations,
        budget,
        reference_point: args
            .reference
            .unwrap_or(paretomesh::metrics::DEFAULT_REFERENCE_POINT),
    })
}

/// The data sets: the grid and the more grids, each loaded with the import options, with
/// distinct names.
fn load_datasets(args: &ExperimentArgs) -> Result<Vec<Dataset>, String> {
    let mut datasets: Vec<Dataset> = Vec::new();
    for path in std::iter::once(&args.input.grid).chain(&args.more) {
        let input = InputArgs {
            grid: path.clone(),
            import: args.input.import.clone(),
        };
        let hf = input
            .load()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        let name = dataset_name(path);
        if datasets.iter().any(|d| d.name == name) {
            return Err(format!(
                "two inputs are named {name:?}; the tables and figures need distinct file names"
            ));
        }
        datasets.push(Dataset::new(name, hf, e_units(path)).map_err(|e| format!("{e}"))?);
    }
    Ok(datasets)
}

/// Runs `jobs` on `pool`, and returns their records and wall times in plan order.
fn run_jobs(
    pool: &rayon::ThreadPool,
    jobs: &[Job],
    datasets: &[Dataset],
    settings: &Settings,
) -> Result<(Vec<RunRecord>, Vec<RunTiming>), String> {
    let done = AtomicUsize::new(0);
    // Longest jobs first, handed out one at a time to whichever thread is free, so the last jobs
    // to finish are short. Each job is a pure function of its seed and the records go back to
    // plan order, so neither the schedule nor the thread count changes the results.
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(jobs[i].method.spec().cost));
    let mut outcomes: Vec<_> = pool.install(|| {
        order
            .into_iter()
            .par_bridge()
            .map(|i| {
                let job = &jobs[i];
                let t0 = Instant::now();
                let dataset = &datasets[job.dataset];
                let record = experiment::run_job(job, dataset, settings);
                let millis = t0.elapsed().as_millis() as u64;
                let k = done.fetch_add(1, Ordering::Relaxed) + 1;
                if let Ok(r) = &record {
                    eprintln!(
                        "[{k}/{}] {} {} run {}: {} solutions, {} evaluations, {millis} ms",
                        jobs.len(),
                        dataset.name,
                        job.method,
                        job.run,
                        r.front.len(),
                        r.evaluations
                    );
                }
                (i, record.map(|r| (r, millis)))
            })
            .collect()
    });
    outcomes.sort_by_key(|(i, _)| *i);
    let mut records: Vec<RunRecord> = Vec::with_capacity(jobs.len());
    let mut run_timings = Vec::with_capacity(jobs.len());
    for (job, (_, outcome)) in jobs.iter().zip(outcomes) {
        let (record, millis) = outcome.map_err(|e| e.to_string())?;
        records.push(record);
        run_timings.push(RunTiming {
            dataset: datasets[job.dataset].name.clone(),
            method: job.method,
            run: job.run,
            millis,
        });
    }
    Ok((records, run_timings))
}

/// Writes report.md, the figures and (if `with_results`) results.json into `out`; returns
/// `out` for messages.
fn write_outputs(
    out: &Path,
    results: &Results,
    analysis: &Analysis,
    with_results: bool,
) -> Result<String, String> {
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let write = |name: &str, text: &str| {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    if with_results {
        write("results.json", &results.to_json())?;
    }
    write("report.md", &experiment::report_markdown(results, analysis))?;
    for (d, a) in results.datasets.iter().zip(&analysis.datasets) {
        write(
            &format!("fronts-{}.svg", d.name),
            &experiment::fronts_svg(d, a),
        )?;
    }
    Ok(out.display().to_string())
}

/// `paretomesh report`: recomputes every table and figure from a results.json.
pub(super) fn report(args: &ReportArgs) -> Result<(), String> {
    let text = std::fs::read_to_string(&args.results)
        .map_err(|e| format!("cannot read {}: {e}", args.results.display()))?;
    let results =
        Results::from_json(&text).map_err(|e| format!("{}: {e}", args.results.display()))?;
    let analysis = Analysis::of(&results).map_err(|e| e.to_string())?;
    let out = write_outputs(&args.out, &results, &analysis, false)?;
    println!(
        "wrote {out} (report.md, {} figure(s)) from {}",
        results.datasets.len(),
        args.results.display()
    );
    Ok(())
}
