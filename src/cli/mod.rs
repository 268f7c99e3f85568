//! Command-line parsing and dispatch. Each subcommand lives in its own file.

mod eval;
mod info;
mod input;
mod run;

use clap::{Parser, Subcommand};

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
        #[command(flatten)]
        input: input::InputArgs,
    },
    /// Triangulate a kept set and print its error as JSON.
    Eval {
        #[command(flatten)]
        input: input::InputArgs,
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
        Command::Info { input } => info::run(&input),
        Command::Eval { input, keep } => eval::run(&input, &keep),
        Command::Run(args) => run::run(&args),
    }
}
