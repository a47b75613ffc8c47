//! `fpc-lab`: experiments on the fpc library, kept out of the user's `fpc`
//! binary: the seeded numerical stress test, the accuracy-time front and
//! in-process solve timings (optionally against an external peer). Glue
//! over the `fpc_lab` library, with the `fpc` binary's output, report,
//! provenance and exit codes (`fpc_cli`).
#![warn(clippy::print_stdout, clippy::print_stderr, clippy::dbg_macro)]

use clap::{Parser, Subcommand};
use fpc_cli::{output, provenance, report};

mod accuracy;
mod stress;
mod timing;

/// Experiments on the fpc library: stress test, accuracy-time front, timings.
#[derive(Parser, Debug)]
#[command(name = "fpc-lab", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run time against tip error over element models, partitions and extrapolation (CSV, JSON, SVG).
    Accuracy(accuracy::Args),
    /// Seeded random extreme-but-legal scenes, solved and checked independently.
    Stress(stress::Args),
    /// Median solve times of the standard cases, measured in-process (and against a peer).
    Timing(timing::Args),
}

fn main() {
    fpc_cli::main(|cli: Cli| match cli.command {
        Command::Accuracy(a) => accuracy::run(&a),
        Command::Stress(a) => stress::run(&a),
        Command::Timing(a) => timing::run(&a),
    })
}
