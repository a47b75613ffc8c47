//! `fpc`: the command-line face of the fpc library. Glue only: parse flags,
//! validate them into library types, call the library, print or write
//! (through the shared utilities of the `fpc_cli` library: output, report,
//! provenance, status).
#![warn(clippy::print_stdout, clippy::print_stderr, clippy::dbg_macro)]

use clap::{Parser, Subcommand};
use fpc_cli::{interrupt, output, provenance, render, report, status};

mod calibrate;
mod compare;
mod design;
mod finger;
mod kernels;
mod models;
mod paper;
mod serve;
mod solve;
mod sweep;

/// Fluidic prestressed composite fingers and grippers: the chained composite model.
#[derive(Parser, Debug)]
#[command(name = "fpc", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Fit parameters to measurements (MANIFEST.toml, --fit eps0,kappa,...) with errors and an identifiability verdict; writes calibration.json and a calibrated scene per specimen.
    Calibrate(calibrate::Args),
    /// The model against measurements, no fitting (MANIFEST.toml of specimens and CSV tests); writes compare.csv, compare.json, figures (--format).
    Compare(compare::Args),
    /// The finger and gripper to build for a set of objects (REQUIREMENTS.toml); writes design.json, scenes, design.svg (--format: png, pdf).
    Design(design::Args),
    /// Solve one finger of the default actuator (eps0, pressure, tip force, model, N or auto).
    Finger(finger::Args),
    /// Print the generated element kernels and their operation counts.
    Kernels(kernels::Args),
    /// List the element models: name, spec file, unknowns.
    Models(models::Args),
    /// The live page for designers: a local web server (127.0.0.1 unless --bind) with sliders, drawings and curves.
    Serve(serve::Args),
    /// Solve the finger or gripper grasp of a TOML scene file; write solution.json, shape.csv, shape.svg (--format: png, pdf).
    Solve(solve::Args),
    /// Run the paper's eight studies; write CSV tables, SVG figures (also PNG, PDF with --format), summary.json and index.html.
    Paper(paper::Args),
    /// A grid over scene parameters, solved in parallel with warm starts; writes sweep.csv and sweep.json.
    Sweep(sweep::Args),
}

fn main() {
    fpc_cli::main(|cli: Cli| match cli.command {
        Command::Calibrate(a) => calibrate::run(&a),
        Command::Compare(a) => compare::run(&a),
        Command::Design(a) => design::run(&a),
        Command::Finger(a) => finger::run(&a),
        Command::Kernels(a) => kernels::run(&a),
        Command::Models(a) => models::run(&a),
        Command::Serve(a) => serve::run(&a),
        Command::Solve(a) => solve::run(&a),
        Command::Paper(a) => paper::run(&a),
        Command::Sweep(a) => sweep::run(&a),
    })
}
