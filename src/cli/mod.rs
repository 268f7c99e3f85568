//! Command-line parsing and dispatch. Each subcommand lives in its own file.

mod eval;
mod info;
mod run;

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Simplify height fields by evolutionary multi-objective optimisation.
#[derive(Parser, Debug)]
#[command(name = "paretomesh", version, about)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print the size, the z range and how the grid was made.
    Info {
        /// Input: .f32 (with its .json sidecar), PNG, PLY, OBJ or STL.
        grid: PathBuf,
    },
    /// Triangulate a kept set and print its error as JSON.
    Eval {
        /// Input: .f32 (with its .json sidecar), PNG, PLY, OBJ or STL.
        grid: PathBuf,
        /// JSON array of kept grid indices (y·W + x), or `-` for standard input.
        #[arg(long)]
        keep: String,
    },
    /// Run an optimizer and write its front as front.json (and CSV).
    Run(run::RunArgs),
}

/// Runs a parsed command line; the error is a message for the user.
pub fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Command::Info { grid } => info::run(&grid),
        Command::Eval { grid, keep } => eval::run(&grid, &keep),
        Command::Run(args) => run::run(&args),
    }
}
