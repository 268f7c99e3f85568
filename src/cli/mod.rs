//! Command-line parsing and dispatch. Each subcommand lives in its own file.

mod eval;
mod experiment;
mod export;
mod export_max_error;
mod front_reader;
mod info;
mod input;
mod progress;
mod run;
mod run_within;
mod tiles;

use clap::{Parser, Subcommand};

/// Simplify height fields by evolutionary multi-objective optimisation.
#[derive(Parser, Debug)]
#[command(name = "paretomesh", version, about)]
pub(crate) struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print the size, the z range and how the grid was made.
    Info {
        #[command(flatten)]
        input: input::InputArgs,
    },
    /// Triangulate a kept set (or take given triangles) and print its error as JSON.
    #[command(group(clap::ArgGroup::new("mesh").required(true).args(["keep", "triangles"])))]
    Eval {
        #[command(flatten)]
        input: input::InputArgs,
        /// JSON array of kept grid indices (y·W + x), or `-` for standard input.
        #[arg(long)]
        keep: Option<String>,
        /// JSON array of triangles [[a, b, c], …] over grid indices, or `-` for standard
        /// input: scores that triangulation as it is (another tool's mesh), without its triangles
        /// in the output.
        #[arg(long)]
        triangles: Option<String>,
    },
    /// Run an optimizer and write its front as front.json (and CSV).
    Run(run::RunArgs),
    /// Write one member of a front.json as a mesh (PLY, OBJ, STL, binary glTF or 3MF), or a
    /// printable solid, in the input's own coordinates.
    Export(export::ExportArgs),
    /// Write a terrain tileset of a front.json or a DEM: a 3D Tiles pyramid (tileset.json and
    /// one binary glTF per tile) or quantized-mesh-1.0 terrain (layer.json and .terrain tiles).
    Tiles(tiles::TilesArgs),
    /// Run the paper's experiment on one or more grids: every method, the indicators and the
    /// Wilcoxon tests; writes report.md, fronts-<name>.svg and results.json.
    Experiment(experiment::ExperimentArgs),
    /// Recompute report.md and the figures of an experiment from its results.json.
    Report(experiment::ReportArgs),
    /// List the catalogue's methods, one a line: name, budget kind and error measures (for
    /// scripts).
    #[command(hide = true)]
    Algorithms,
}

/// Runs a parsed command line; the error is a message for the user.
pub(crate) fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Command::Info { input } => info::run(&input),
        Command::Eval {
            input,
            keep,
            triangles,
        } => match (keep, triangles) {
            (Some(keep), _) => eval::run(&input, &keep),
            (None, Some(triangles)) => eval::run_triangles(&input, &triangles),
            (None, None) => unreachable!("clap requires --keep or --triangles"),
        },
        Command::Run(args) => run::run(&args),
        Command::Export(args) => export::run(&args),
        Command::Tiles(args) => tiles::run(&args),
        Command::Experiment(args) => experiment::run(&args),
        Command::Report(args) => experiment::report(&args),
        Command::Algorithms => {
            for a in paretomesh::catalogue::Algorithm::ALL {
                let measures: Vec<&str> = a.spec().measures.iter().map(|m| m.name()).collect();
                println!(
                    "{} {} {}",
                    a.name(),
                    a.spec().budget.name(),
                    measures.join(",")
                );
            }
            Ok(())
        }
    }
}
