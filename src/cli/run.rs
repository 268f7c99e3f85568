//! `paretomesh run GRID --algo ALGO [...] --out front.json [--csv front.csv] [import options]`:
//! runs one optimizer to the end, shows progress on stderr, writes front.json (and the front as
//! CSV, see [`paretomesh::export::csv`]).
//!
//! Adding an algorithm = one variant of [`Algo`] and one arm in [`build`] (the variant's
//! command-line name is the `algorithm` field of front.json).

use super::input::InputArgs;
use clap::{Args, ValueEnum};
use paretomesh::baselines::{
    DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams, GreedyStop, InsertionRule,
};
use paretomesh::evaluator::Evaluator;
use paretomesh::evolution::{CrossoverKind, GaParams, Nsga2, WeightedSum, WeightedSumParams};
use paretomesh::export::csv::front_csv;
use paretomesh::front::Front;
use paretomesh::heightfield::Heightfield;
use paretomesh::optimizer::{Optimizer, Progress};
use paretomesh::run_file::RunFile;
use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

/// The algorithms `run` knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Algo {
    /// NSGA-II with orthogonal-array crossover.
    Nsga2,
    /// Weighted-sum GA, one run per weight 0, 0.1, …, 1.
    Weighted,
    /// Greedy insertion (Garland & Heckbert 1995) from the corners; one run records a front.
    Greedy,
    /// Edge decimation from the full grid to 5 %, 10 %, …, 50 % fewer triangles.
    Decimation,
}

/// The greedy-insertion rules, as the command line spells them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RuleArg {
    /// Insert the point of largest vertical error (classic).
    MaxError,
    /// Insert the point whose insertion reduces E_sum the most.
    SumReduction,
}

impl Algo {
    /// The name on the command line, which front.json repeats.
    fn name(self) -> String {
        self.to_possible_value()
            .expect("every algorithm has a command-line name")
            .get_name()
            .to_string()
    }
}

/// The crossover operators, as the command line spells them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CrossoverArg {
    /// Orthogonal-array crossover over spatial blocks.
    Oax,
    /// Uniform crossover.
    Uniform,
    /// Two-point crossover in row-major order.
    TwoPoint,
}

/// Options of `paretomesh run`.
#[derive(Args, Debug)]
pub struct RunArgs {
    /// The grid file and how to import it.
    #[command(flatten)]
    input: InputArgs,
    /// The algorithm.
    #[arg(long, value_enum)]
    algo: Algo,
    /// Population size.
    #[arg(long, default_value_t = GaParams::default().population)]
    pop: usize,
    /// Generations (per weight, for the weighted-sum GA).
    #[arg(long, default_value_t = GaParams::default().generations)]
    gens: usize,
    /// Crossover probability.
    #[arg(long, default_value_t = GaParams::default().crossover_probability)]
    pc: f64,
    /// Bit-flip probability per free gene [default: 1/L, L = grid points − 4].
    #[arg(long)]
    pm: Option<f64>,
    /// Crossover operator.
    #[arg(long, value_enum, default_value = "oax")]
    crossover: CrossoverArg,
    /// Number of OAX factors (spatial blocks).
    #[arg(long, default_value_t = GaParams::default().factors)]
    factors: usize,
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
    /// Greedy insertion: which point to insert next.
    #[arg(long, value_enum, default_value = "max-error")]
    rule: RuleArg,
    /// Greedy insertion: stop once E_max ≤ this fraction of the z range (e.g. 0.01)
    /// [default: insert every point, or stop after --evals insertions].
    #[arg(long)]
    max_error_fraction: Option<f64>,
    /// Where to write front.json.
    #[arg(long)]
    out: PathBuf,
    /// Also write the front as CSV here (T, E_sum, E_max, kept points per member).
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// A ready-to-run optimizer, its parameters as JSON and how many generations it will run.
struct Built {
    optimizer: Box<dyn Optimizer>,
    params: serde_json::Value,
    generations: u64,
}

fn ga_params(args: &RunArgs) -> GaParams {
    GaParams {
        population: args.pop,
        generations: args.gens,
        crossover_probability: args.pc,
        mutation_probability: args.pm,
        crossover: match args.crossover {
            CrossoverArg::Oax => CrossoverKind::Oax,
            CrossoverArg::Uniform => CrossoverKind::Uniform,
            CrossoverArg::TwoPoint => CrossoverKind::TwoPoint,
        },
        factors: args.factors,
        max_evaluations: args.evals,
        greedy_seed_fraction: args.greedy_seed,
    }
}

fn to_json<T: serde::Serialize>(params: &T) -> serde_json::Value {
    serde_json::to_value(params).expect("parameters are plain data")
}

fn build(args: &RunArgs, hf: Arc<Heightfield>) -> Result<Built, String> {
    if args.greedy_seed != 0.0 && matches!(args.algo, Algo::Greedy | Algo::Decimation) {
        return Err(format!(
            "--greedy-seed applies to NSGA-II only, not to {}",
            args.algo.name()
        ));
    }
    Ok(match args.algo {
        Algo::Nsga2 => {
            let p = ga_params(args);
            Built {
                params: to_json(&p),
                generations: p.generations as u64,
                optimizer: Box::new(Nsga2::new(hf, p, args.seed).map_err(|e| e.to_string())?),
            }
        }
        Algo::Weighted => {
            let p = WeightedSumParams {
                ga: ga_params(args),
                ..WeightedSumParams::default()
            };
            Built {
                params: to_json(&p),
                generations: (p.ga.generations * p.weights.len()) as u64,
                optimizer: Box::new(WeightedSum::new(hf, p, args.seed).map_err(|e| e.to_string())?),
            }
        }
        Algo::Greedy => {
            let stop = match (args.max_error_fraction, args.evals) {
                (Some(_), Some(_)) => {
                    return Err(
                        "greedy insertion stops on --max-error-fraction or on --evals, not both"
                            .to_string(),
                    );
                }
                (Some(f), None) => GreedyStop::MaxErrorFraction(f),
                // One evaluation is one insertion, after the four corners.
                (None, Some(n)) => GreedyStop::Points(
                    4usize.saturating_add(usize::try_from(n).unwrap_or(usize::MAX)),
                ),
                (None, None) => GreedyStop::AllPoints,
            };
            let p = GreedyParams {
                rule: match args.rule {
                    RuleArg::MaxError => InsertionRule::MaxError,
                    RuleArg::SumReduction => InsertionRule::SumReduction,
                },
                stop,
                ..GreedyParams::default()
            };
            Built {
                params: to_json(&p),
                generations: p.records as u64,
                optimizer: Box::new(GreedyInsertion::new(hf, p).map_err(|e| e.to_string())?),
            }
        }
        Algo::Decimation => {
            if args.evals.is_some() {
                return Err(
                    "edge decimation runs to its last reduction: --evals does not apply"
                        .to_string(),
                );
            }
            let p = DecimationParams::default();
            Built {
                params: to_json(&p),
                generations: p.reductions.len() as u64,
                optimizer: Box::new(EdgeDecimation::new(hf, p).map_err(|e| e.to_string())?),
            }
        }
    })
}

/// The smallest E on `front` among solutions with at most `t` triangles.
fn best_e_within(front: &Front, t: usize) -> Option<f64> {
    let members = front.solutions();
    let at = members.partition_point(|s| s.t <= t);
    (at > 0).then(|| members[at - 1].e_sum)
}

/// One status line: generation, evaluations, front size, best E at a few triangle counts.
fn status(p: &Progress, generations: u64, front: &Front, full_triangles: usize) -> String {
    let mut line = format!(
        "gen {}/{}  evals {}  front {}",
        p.generation,
        generations,
        p.evaluations,
        front.len()
    );
    for percent in [1, 5, 25] {
        let t = (full_triangles * percent / 100).max(2);
        if let Some(e) = best_e_within(front, t) {
            line.push_str(&format!("  E(T≤{t}) {e:.4e}"));
        }
    }
    line
}

pub fn run(args: &RunArgs) -> Result<(), String> {
    let hf = Arc::new(args.input.load()?);
    let Built {
        mut optimizer,
        params,
        generations,
    } = build(args, hf.clone())?;
    let terminal = std::io::stderr().is_terminal();
    let full = hf.full_triangles();
    let report_every = (generations / 10).max(1);
    let mut last_reported = u64::MAX;
    let started = Instant::now();
    loop {
        let p = optimizer.step(250);
        if terminal {
            let by_generation = p.generation as f64 / generations.max(1) as f64;
            let by_cap = args
                .evals
                .map_or(0.0, |cap| p.evaluations as f64 / cap.max(1) as f64);
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
    let file = RunFile::new(
        &mut evaluator,
        &args.algo.name(),
        params,
        args.seed,
        p.evaluations,
        millis,
        optimizer.front(),
    )
    .map_err(|e| e.to_string())?;
    write(&args.out, |w| {
        serde_json::to_writer(w, &file).map_err(std::io::Error::other)
    })?;
    if let Some(csv) = &args.csv {
        let rows = front_csv(file.front.iter().map(|m| &m.solution));
        write(csv, |w| w.write_all(rows.as_bytes()))?;
    }
    let bytes = std::fs::metadata(&args.out).map_or(0, |m| m.len());
    eprintln!(
        "wrote {} ({:.1} MB, with every member's triangles) in {} ms",
        args.out.display(),
        bytes as f64 / 1e6,
        writing.elapsed().as_millis()
    );
    Ok(())
}

/// Writes a file through a buffer, with the path in the error message. The buffer is large
/// because a paper run's front.json is tens of megabytes, which the default 8 KB buffer writes
/// in many more system calls.
fn write(
    path: &PathBuf,
    body: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<(), String> {
    let file = std::fs::File::create(path)
        .map_err(|e| format!("cannot create {}: {e}", path.display()))?;
    let mut w = std::io::BufWriter::with_capacity(1 << 18, file);
    body(&mut w)
        .and_then(|()| w.flush())
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}
