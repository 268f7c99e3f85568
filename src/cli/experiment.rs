//! `paretomesh experiment GRID... [--runs 10] [--weighted-runs 1] [--seed S] [--pop 100 --gens 50]
//! [--methods nsga2,weighted,decimation,greedy] [--reference E,T] [--threads N] --out DIR`:
//! the paper's protocol on every input, on every core, then report.md, fronts-<name>.svg and
//! results.json in DIR. And `paretomesh report RESULTS --out DIR`: the report and figures again
//! from a results.json alone.

use super::input::InputArgs;
use clap::Args;
use paretomesh::experiment::{
    self, Analysis, Dataset, Method, Results, RunRecord, RunTiming, Settings, Timings,
};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// The options of `paretomesh experiment`.
#[derive(Args, Debug)]
pub struct ExperimentArgs {
    /// The first input grid, and the import options applied to every input.
    #[command(flatten)]
    input: InputArgs,
    /// More input grids (each is one data set of the tables).
    #[arg(value_name = "GRID")]
    more: Vec<PathBuf>,
    /// Runs of NSGA-II (deterministic methods run once).
    #[arg(long, default_value_t = 10)]
    runs: usize,
    /// Runs of the weighted-sum GA, each a sweep over its 11 weights (the paper: one sweep).
    #[arg(long, default_value_t = 1)]
    weighted_runs: usize,
    /// Run k of a stochastic method uses seed SEED + k.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// GA population (NSGA-II and each weighted-sum GA run).
    #[arg(long, default_value_t = 100)]
    pop: usize,
    /// GA generations.
    #[arg(long, default_value_t = 50)]
    gens: usize,
    /// Comma-separated methods to compare, in table order.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "nsga2,weighted,decimation,greedy"
    )]
    methods: Vec<String>,
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

/// The options of `paretomesh report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
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

/// Longest first: the weighted-sum sweep (11 GA runs), NSGA-II, then the classical methods.
fn expected_cost_rank(method: Method) -> u8 {
    match method {
        Method::Weighted => 0,
        Method::Nsga2 => 1,
        Method::Greedy => 2,
        Method::Decimation => 3,
    }
}

/// `paretomesh experiment`: runs the protocol on every input, then writes the report, the
/// figures and results.json.
pub fn run(args: &ExperimentArgs) -> Result<(), String> {
    let start = Instant::now();
    let settings = settings(args)?;
    let datasets = load_datasets(args)?;
    // Bad parameters fail now, not after the other runs.
    experiment::check_methods(&settings, &datasets[0]).map_err(|e| e.to_string())?;

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

/// The protocol's settings from the options, validated.
fn settings(args: &ExperimentArgs) -> Result<Settings, String> {
    let settings = Settings {
        methods: args
            .methods
            .iter()
            .map(|m| Method::parse(m))
            .collect::<Result<_, _>>()?,
        runs: args.runs,
        weighted_runs: args.weighted_runs,
        seed: args.seed,
        population: args.pop,
        generations: args.gens,
        reference_point: args
            .reference
            .unwrap_or(paretomesh::metrics::DEFAULT_REFERENCE_POINT),
    };
    settings.validate().map_err(|e| e.to_string())?;
    Ok(settings)
}

/// Every input grid as a data set, each loaded with the first one's import options; their
/// names must differ.
fn load_datasets(args: &ExperimentArgs) -> Result<Vec<Dataset>, String> {
    let mut datasets: Vec<Dataset> = Vec::new();
    for path in std::iter::once(&args.input.grid).chain(&args.more) {
        let input = InputArgs {
            grid: path.clone(),
            projection: args.input.projection,
            grid_size: args.input.grid_size,
            surface: args.input.surface,
            terrain_rgb: args.input.terrain_rgb,
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

/// Runs every job on `pool`, reporting each on stderr as it ends, and returns their records
/// and timings in plan order; the first failed job's error otherwise.
fn run_jobs(
    pool: &rayon::ThreadPool,
    jobs: &[experiment::Job],
    datasets: &[Dataset],
    settings: &Settings,
) -> Result<(Vec<RunRecord>, Vec<RunTiming>), String> {
    let done = AtomicUsize::new(0);
    // Longest jobs first (a weighted-sum sweep costs about 11 NSGA-II runs), handed out one at a
    // time to whichever thread is free, so the last jobs to finish are short. Each job is a pure
    // function of its seed and the records go back to plan order, so neither the schedule nor
    // the thread count changes the results.
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&i| expected_cost_rank(jobs[i].method));
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
pub fn report(args: &ReportArgs) -> Result<(), String> {
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
