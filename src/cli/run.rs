//! `paretomesh run GRID [--algo ALGO] [...] --out front.json [--triangles] [--csv front.csv]
//! [import options]`:
//! runs one optimizer to the end, shows progress on stderr, writes front.json (and the front as
//! CSV, see [`paretomesh::export::front_csv`]).
//!
//! The methods and the parameters each reads come from [`paretomesh::catalogue`].

use super::input::InputArgs;
use clap::{Args, ValueEnum};
use paretomesh::baselines::InsertionRule;
use paretomesh::catalogue::{Algorithm, Built, Config, Param, Params};
use paretomesh::evaluator::Evaluator;
use paretomesh::evolution::CrossoverKind;
use paretomesh::export::front_csv;
use paretomesh::front::Front;
use paretomesh::front_file::FrontFile;
use paretomesh::front_file::{GridInfo, ImportRecord, RunHeader};
use paretomesh::heightfield::Heightfield;
use paretomesh::import::GridWindows;
use paretomesh::measure::ErrorMeasure;
use paretomesh::optimizer::Progress;
use paretomesh::tiling::{
    DEFAULT_TILE, TilePlan, TileSource, TiledFront, TiledFrontFile, TilingError, check_tile,
    run_tiled_with_progress, tile_config,
};
use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

/// The greedy-insertion rules, as the command line spells them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum RuleArg {
    /// Insert the point of largest vertical error (classic).
    MaxError,
    /// Insert the point whose insertion reduces E_sum the most.
    SumReduction,
    /// Insert the max-error point of the triangle with the largest error sum.
    WorstTriangle,
}

/// The crossover operators, as the command line spells them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum CrossoverArg {
    /// Orthogonal-array crossover over spatial blocks.
    Oax,
    /// Uniform crossover.
    Uniform,
    /// Two-point crossover in row-major order.
    TwoPoint,
}

/// Options of `paretomesh run`.
#[derive(Args, Debug)]
pub(super) struct RunArgs {
    /// The grid file and how to import it.
    #[command(flatten)]
    input: InputArgs,
    /// The algorithm.
    #[arg(long, value_enum, default_value = "memetic")]
    algo: Algorithm,
    /// The error the front minimises beside T: sum (Σ|z − z̃|, the paper's), rms or max (the
    /// vertical error bound). NSGA-II and the weighted-sum GA take sum only.
    #[arg(long, value_enum, default_value = "sum")]
    error: ErrorMeasure,
    /// Population size [default: 100 for the GAs, 24 for memetic].
    #[arg(long)]
    pop: Option<usize>,
    /// GAs: generations (per weight, for the weighted-sum GA) [default: 50].
    #[arg(long)]
    gens: Option<usize>,
    /// Crossover probability [default: 0.8 for the GAs, 0.3 for memetic].
    #[arg(long)]
    pc: Option<f64>,
    /// GAs: bit-flip probability per free gene [default: 1/L, L = grid points − 4].
    #[arg(long)]
    pm: Option<f64>,
    /// GAs: crossover operator [default: oax].
    #[arg(long, value_enum)]
    crossover: Option<CrossoverArg>,
    /// GAs: number of OAX factors (spatial blocks) [default: 7].
    #[arg(long)]
    factors: Option<usize>,
    /// Seed of the random generator.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Stop after about this many evaluations (shared equally between the weights of the
    /// weighted-sum GA).
    #[arg(long)]
    evals: Option<u64>,
    /// NSGA-II: seed this fraction (0 to 1) of the initial population from a greedy-insertion
    /// run, whose insertions count as evaluations [default: 0, as in the paper].
    #[arg(long, default_value_t = 0.0)]
    greedy_seed: f64,
    /// Greedy insertion: which point to insert next [default: max-error].
    #[arg(long, value_enum)]
    rule: Option<RuleArg>,
    /// Greedy insertion: stop once E_max ≤ this fraction of the z range (e.g. 0.01)
    /// [default: insert every point, or stop after --evals insertions].
    #[arg(long)]
    max_error_fraction: Option<f64>,
    /// Greedy insertion: stop once E_max ≤ X, in the surface's own z units (hmm's -e).
    #[arg(long, value_name = "X")]
    max_vertical_error: Option<f64>,
    /// Where to write front.json.
    #[arg(long)]
    out: PathBuf,
    /// Also write the front as CSV here (T, E_sum, E_max, kept points per member).
    #[arg(long)]
    csv: Option<PathBuf>,
    /// List every member's triangles in front.json too (by default a member lists its kept
    /// grid indices, which determine its triangles). Untiled runs only.
    #[arg(long)]
    triangles: bool,
    /// Tile size in grid points a side: a larger grid is cut into tiles that share their
    /// borders, each optimised on its own (--evals then counts per tile), and one whole-grid
    /// front is assembled [default: 1025].
    #[arg(long, value_name = "N")]
    tile: Option<usize>,
    /// Threads the tiles run on (the front does not depend on it) [default: every core].
    #[arg(long, value_name = "N")]
    threads: Option<usize>,
}

/// The catalogue's parameters the command line sets (`None` where an option is not given).
fn params(args: &RunArgs) -> Params {
    Params {
        population: args.pop,
        generations: args.gens,
        crossover_probability: args.pc,
        mutation_probability: args.pm,
        crossover: args.crossover.map(|c| match c {
            CrossoverArg::Oax => CrossoverKind::Oax,
            CrossoverArg::Uniform => CrossoverKind::Uniform,
            CrossoverArg::TwoPoint => CrossoverKind::TwoPoint,
        }),
        factors: args.factors,
        max_evaluations: args.evals,
        // 0, the default, seeds nothing and is what every method runs with.
        greedy_seed_fraction: (args.greedy_seed != 0.0).then_some(args.greedy_seed),
        rule: args.rule.map(|r| match r {
            RuleArg::MaxError => InsertionRule::MaxError,
            RuleArg::SumReduction => InsertionRule::SumReduction,
            RuleArg::WorstTriangle => InsertionRule::WorstTriangle,
        }),
        max_error_fraction: args.max_error_fraction,
        max_vertical_error: args.max_vertical_error,
        without: None,
        error: args.error,
    }
}

/// The method-specific options given on the command line, with their names and parameters.
fn given_options(args: &RunArgs) -> Vec<(&'static str, Param)> {
    [
        ("--pop", Param::Population, args.pop.is_some()),
        ("--gens", Param::Generations, args.gens.is_some()),
        ("--pc", Param::CrossoverProbability, args.pc.is_some()),
        ("--pm", Param::MutationProbability, args.pm.is_some()),
        ("--crossover", Param::Crossover, args.crossover.is_some()),
        ("--factors", Param::Factors, args.factors.is_some()),
        ("--rule", Param::Rule, args.rule.is_some()),
        (
            "--max-error-fraction",
            Param::MaxErrorFraction,
            args.max_error_fraction.is_some(),
        ),
        ("--evals", Param::MaxEvaluations, args.evals.is_some()),
        (
            "--max-vertical-error",
            Param::MaxVerticalError,
            args.max_vertical_error.is_some(),
        ),
    ]
    .into_iter()
    .filter_map(|(name, param, given)| given.then_some((name, param)))
    .collect()
}

/// Refuses an option that the method would ignore, saying why (the catalogue's reason), so
/// that a run never silently differs from what its command line asks for.
fn refuse_foreign_options(args: &RunArgs) -> Result<(), String> {
    let algo = args.algo;
    for (option, param) in given_options(args) {
        if let Some(why) = algo.refusal(param) {
            return Err(format!(
                "{option} does not apply to --algo {}: {why}",
                algo.name()
            ));
        }
    }
    if args.greedy_seed != 0.0 && !algo.reads(Param::GreedySeedFraction) {
        return Err(format!(
            "--greedy-seed applies to NSGA-II only, not to {}",
            algo.name()
        ));
    }
    Ok(())
}

/// The method the command line asks for, with every parameter it runs with.
fn config(args: &RunArgs) -> Result<Config, String> {
    refuse_foreign_options(args)?;
    args.algo.configure(&params(args))
}

/// The smallest error (in the front's measure) among solutions with at most `t` triangles.
fn best_e_within(front: &Front, t: usize) -> Option<f64> {
    front.within(t).map(|s| front.measure().of(s))
}

/// One status line: generation, evaluations, front size, best E at a few triangle counts.
fn status(p: &Progress, generations: u64, front: &Front, full_triangles: usize) -> String {
    let mut line = if generations > 0 {
        format!("gen {}/{}", p.generation, generations)
    } else {
        format!("gen {}", p.generation)
    };
    line.push_str(&format!("  evals {}  front {}", p.evaluations, front.len()));
    for percent in [1, 5, 25] {
        let t = (full_triangles * percent / 100).max(2);
        if let Some(e) = best_e_within(front, t) {
            line.push_str(&format!("  E(T≤{t}) {e:.4e}"));
        }
    }
    line
}

pub(super) fn run(args: &RunArgs) -> Result<(), String> {
    check_tile(args.tile.unwrap_or(DEFAULT_TILE)).map_err(|e| format!("--tile: {e}"))?;
    if args.threads == Some(0) {
        return Err("--threads must be at least 1".to_string());
    }
    let within = config(args).is_ok_and(|c| super::run_within::makes_one_mesh(&c));
    let tile = args.tile.unwrap_or(if within {
        super::run_within::WITHIN_TILE
    } else {
        DEFAULT_TILE
    });
    // A tiled run of a file read by windows holds only the tiles in flight (one mesh within a
    // max error is made from the grid whole: its border lines cross every tile).
    if let Some(windows) = if within { None } else { args.input.windows()? } {
        let plan =
            TilePlan::new(windows.width(), windows.height(), tile).map_err(|e| e.to_string())?;
        if !plan.is_single() {
            let windows = windows.scan().map_err(|e| e.to_string())?;
            return run_tiled_grid(args, &windows, &plan);
        }
    }
    let hf = Arc::new(args.input.load()?);
    let plan = TilePlan::new(hf.width(), hf.height(), tile).map_err(|e| e.to_string())?;
    if !plan.is_single() {
        if within {
            return run_within_grid(args, &hf, &plan);
        }
        return run_tiled_grid(args, &*hf, &plan);
    }
    let config = config(args)?;
    let Built {
        mut optimizer,
        generations,
        budget,
    } = config.clone().build(hf.clone(), args.seed)?;
    let terminal = std::io::stderr().is_terminal();
    let full = hf.full_triangles();
    // Without a known number of generations, report every tenth of the budget instead.
    let report_every = (generations / 10).max(1);
    let budget_step = budget.map_or(u64::MAX, |b| (b / 10).max(1));
    let mut last_budget_report = 0;
    let mut last_reported = u64::MAX;
    let started = Instant::now();
    loop {
        let p = optimizer.step(250);
        if terminal {
            let by_generation = p.generation as f64 / generations.max(1) as f64;
            let by_cap = budget.map_or(0.0, |cap| p.evaluations as f64 / cap.max(1) as f64);
            let fraction = if p.done {
                1.0
            } else {
                by_generation.max(by_cap).min(1.0)
            };
            let filled = (fraction * 30.0).round() as usize;
            eprint!(
                "\r[{}{}] {}\x1b[K",
                "#".repeat(filled),
                ".".repeat(30 - filled),
                status(&p, generations, optimizer.front(), full)
            );
        } else if generations == 0 {
            if p.evaluations / budget_step != last_budget_report || p.done {
                eprintln!("{}", status(&p, generations, optimizer.front(), full));
                last_budget_report = p.evaluations / budget_step;
            }
        } else if p.generation != last_reported && (p.generation % report_every == 0 || p.done) {
            eprintln!("{}", status(&p, generations, optimizer.front(), full));
            last_reported = p.generation;
        }
        if p.done {
            break;
        }
    }
    let millis = started.elapsed().as_millis() as u64;
    let p = optimizer.progress();
    if terminal {
        eprintln!();
    }
    eprintln!(
        "done: {} evaluations in {} ms ({:.0} evaluations/s), front of {} solutions",
        p.evaluations,
        millis,
        p.evaluations as f64 / (millis.max(1) as f64 / 1000.0),
        optimizer.front().len()
    );
    // Re-triangulating the front and writing it are timed apart from the run.
    let writing = Instant::now();
    let mut evaluator = Evaluator::new(hf);
    let mut file = FrontFile::new(
        &mut evaluator,
        &config,
        args.seed,
        p.evaluations,
        millis,
        optimizer.front(),
    )
    .map_err(|e| e.to_string())?
    .with_import(&args.input.import.options());
    if args.triangles {
        file.add_triangles(&mut evaluator)
            .map_err(|e| e.to_string())?;
    }
    write(&args.out, |w| {
        serde_json::to_writer(w, &file).map_err(std::io::Error::other)
    })?;
    if let Some(csv) = &args.csv {
        let rows = front_csv(file.front.iter().map(|m| &m.solution));
        write(csv, |w| w.write_all(rows.as_bytes()))?;
    }
    let bytes = std::fs::metadata(&args.out).map_or(0, |m| m.len());
    eprintln!(
        "wrote {} ({:.1} MB, {}) in {} ms",
        args.out.display(),
        bytes as f64 / 1e6,
        if args.triangles {
            "kept points and triangles of every member"
        } else {
            "kept points of every member"
        },
        writing.elapsed().as_millis()
    );
    Ok(())
}

/// A tiled run: every tile on the thread pool, each cut from `hf` as it starts, then the
/// whole-grid front, written as a [`TiledFrontFile`]. `hf` is the grid in memory or its
/// file's windows; the front has the same bits.
fn run_tiled_grid<S: TileSource + Described>(
    args: &RunArgs,
    hf: &S,
    plan: &TilePlan,
) -> Result<(), String> {
    let (width, height) = hf.size();
    if args.triangles {
        return Err(format!(
            "--triangles lists triangles of untiled runs only: this {}×{} grid is cut into {} tiles of at most {} points a side (export rebuilds any member's mesh, or give a larger --tile)",
            width,
            height,
            plan.len(),
            plan.tile_size()
        ));
    }
    // As every tile runs it; the tiling checks it on the first tile before any tile runs.
    let config = tile_config(plan, &config(args)?);
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    eprintln!(
        "{width}×{height} grid in {} tiles ({}×{}) of at most {} points a side, on {threads} threads",
        plan.len(),
        plan.columns(),
        plan.rows(),
        plan.tile_size()
    );
    let started = Instant::now();
    let finished = std::sync::atomic::AtomicUsize::new(0);
    let progress = super::progress::Progress::new("tiles run");
    let report = |_index: usize| {
        let n = finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        progress.report(n, plan.len());
    };
    let tiled = run_tiled_with_progress(hf, plan, &config, args.seed, threads, &report).map_err(
        |e| match e {
            // The method's own message, as an untiled run gives it.
            TilingError::BadParams { reason, .. } => reason,
            other => other.to_string(),
        },
    )?;
    let millis = started.elapsed().as_millis() as u64;
    let full = 2 * (width as u64 - 1) * (height as u64 - 1);
    let mut line = format!(
        "done: {} evaluations in {millis} ms, whole-grid front of {} members",
        tiled.evaluations(),
        tiled.members.len()
    );
    for per_mille in [1, 10, 50] {
        let t = (full * per_mille / 1000).max(2);
        if let Some(m) = tiled.within(t) {
            let e = match tiled.measure() {
                ErrorMeasure::Sum => m.e_sum,
                ErrorMeasure::Rms => m.rms.unwrap_or(f64::NAN),
                ErrorMeasure::Max => m.e_max,
            };
            line.push_str(&format!("  E(T≤{t}) {e:.4e}"));
        }
    }
    eprintln!("{line}");
    write_tiled(args, hf, &config, threads, tiled, millis)
}

/// One mesh within a max error over `plan`'s tiles (see `run_within`), written as a tiled
/// front of that one member.
fn run_within_grid(args: &RunArgs, hf: &Heightfield, plan: &TilePlan) -> Result<(), String> {
    let config = tile_config(plan, &config(args)?);
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let x = super::run_within::bound_of(&config, hf)
        .ok_or_else(|| "a run within a max error needs a max-error stop".to_string())?;
    let started = Instant::now();
    let tiled = super::run_within::make(hf, plan, x, threads)?;
    let millis = started.elapsed().as_millis() as u64;
    write_tiled(args, hf, &config, threads, tiled, millis)
}

/// Writes a tiled run's front (and CSV); the run took `millis`.
fn write_tiled<S: TileSource + Described>(
    args: &RunArgs,
    hf: &S,
    config: &Config,
    threads: usize,
    tiled: TiledFront,
    millis: u64,
) -> Result<(), String> {
    let (width, height) = hf.size();
    let writing = Instant::now();
    let grid = GridInfo {
        width,
        height,
        source: hf.note().to_string(),
        import: Some(ImportRecord::of(&args.input.import.options())),
    };
    let file = TiledFrontFile {
        header: RunHeader::new(grid, config, args.seed, tiled.evaluations(), millis),
        threads,
        tiled,
    };
    write(&args.out, |w| {
        serde_json::to_writer(w, &file).map_err(std::io::Error::other)
    })?;
    if let Some(csv) = &args.csv {
        let mut rows = String::from("T,E_sum,E_max\n");
        for m in &file.tiled.members {
            rows.push_str(&format!("{},{},{}\n", m.t, m.e_sum, m.e_max));
        }
        write(csv, |w| w.write_all(rows.as_bytes()))?;
    }
    let bytes = std::fs::metadata(&args.out).map_or(0, |m| m.len());
    eprintln!(
        "wrote {} ({:.1} MB, per-tile kept sets and each member's choice per tile) in {} ms",
        args.out.display(),
        bytes as f64 / 1e6,
        writing.elapsed().as_millis()
    );
    Ok(())
}

/// A grid's source note, from the grid in memory or its windows.
trait Described {
    fn note(&self) -> &str;
}

impl Described for Heightfield {
    fn note(&self) -> &str {
        self.source()
    }
}

impl Described for GridWindows {
    fn note(&self) -> &str {
        self.source()
    }
}

/// Writes a file through a buffer, with the path in the error message. The buffer is large
/// because a paper run's front.json is tens of megabytes, which the default 8 KB buffer writes
/// in many more system calls. The file is written beside `path` under a temporary name and
/// renamed into place once complete, so an interrupted run never leaves a partial file at
/// `path`.
fn write(
    path: &PathBuf,
    body: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<(), String> {
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    let temporary = path.with_file_name(format!(".{name}.{}.partial", std::process::id()));
    let file = std::fs::File::create(&temporary)
        .map_err(|e| format!("cannot create {}: {e}", temporary.display()))?;
    let mut w = std::io::BufWriter::with_capacity(1 << 18, file);
    let written = body(&mut w)
        .and_then(|()| w.flush())
        .and_then(|()| std::fs::rename(&temporary, path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        format!("cannot write {}: {e}", path.display())
    })
}
