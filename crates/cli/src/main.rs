//! `fpc`: the command-line face of the fpc library. Glue only: parse flags,
//! validate them into library types, call the library, print or write.
//!
//! Output goes through two doors: `output::stdout()` for results (a failed
//! write is an error, status 1) and `report` for every line on stderr
//! (bounded, escaped). `print!`-style macros and direct handles are
//! refused by clippy (the lints below and clippy.toml).
#![warn(clippy::print_stdout, clippy::print_stderr, clippy::dbg_macro)]

use std::io::Write as _;

use clap::{Parser, Subcommand};

mod accuracy;
mod design;
mod finger;
mod kernels;
mod models;
mod output;
mod paper;
mod provenance;
mod report;
mod solve;
mod status;
mod stress;
mod sweep;
mod timing;

/// Fluidic prestressed composite fingers and grippers: the chained composite model.
#[derive(Parser, Debug)]
#[command(name = "fpc", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run time against tip error over element models, partitions and extrapolation (CSV, JSON, SVG).
    Accuracy(accuracy::Args),
    /// The finger and gripper to build for a set of objects (REQUIREMENTS.toml); writes design.json, scenes, design.svg.
    Design(design::Args),
    /// Solve one finger of the default actuator (eps0, pressure, tip force, model, N or auto).
    Finger(finger::Args),
    /// Print the generated element kernels and their operation counts.
    Kernels(kernels::Args),
    /// List the element models: name, spec file, unknowns.
    Models(models::Args),
    /// Solve the finger or gripper grasp of a TOML scene file; write solution.json, shape.csv, shape.svg.
    Solve(solve::Args),
    /// Median solve times of the standard cases, measured in-process.
    Timing(timing::Args),
    /// Run the paper's eight studies; write CSV tables, SVG figures, summary.json and index.html.
    Paper(paper::Args),
    /// Seeded random extreme-but-legal scenes, solved and checked independently.
    Stress(stress::Args),
    /// A grid over scene parameters, solved in parallel with warm starts; writes sweep.csv and sweep.json.
    Sweep(sweep::Args),
}

fn main() {
    let result = run();
    if let Err(e) = &result {
        report::error(e);
    }
    std::process::exit(status::exit_code(&result));
}

fn run() -> anyhow::Result<()> {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage(e),
    };
    match cli.command {
        Command::Accuracy(a) => accuracy::run(&a),
        Command::Design(a) => design::run(&a),
        Command::Finger(a) => finger::run(&a),
        Command::Kernels(a) => kernels::run(&a),
        Command::Models(a) => models::run(&a),
        Command::Solve(a) => solve::run(&a),
        Command::Timing(a) => timing::run(&a),
        Command::Paper(a) => paper::run(&a),
        Command::Stress(a) => stress::run(&a),
        Command::Sweep(a) => sweep::run(&a),
    }?;
    // what is still buffered: a failure here is a failure to write output
    output::stdout().flush()?;
    Ok(())
}

/// Help and version go to stdout (status 0) as clap prints them; `fpc`
/// alone prints the help on stderr and is rejected. A usage error (unknown
/// flag, missing or malformed value) is rejected input: one line in the
/// form of every other error.
fn usage(e: clap::Error) -> anyhow::Result<()> {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            output::usable()?;
            e.print()
                .map_err(|e| anyhow::anyhow!("cannot write to standard output: {e}"))
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            Err(status::rejected("a subcommand is required (see above)"))
        }
        _ => {
            // clap quotes the offending argument: one holding a newline
            // would break up its message, so the message is rendered again
            // from the arguments with their control characters escaped
            let escaped = std::env::args_os().map(|a| match a.to_str() {
                Some(s) => report::sanitize(s).into_owned().into(),
                None => a,
            });
            let text = match Cli::try_parse_from(escaped) {
                Err(again) if again.kind() == e.kind() => again.render().to_string(),
                _ => e.render().to_string(),
            };
            Err(status::rejected(usage_error_line(&text)))
        }
    }
}

/// clap's message and tips on one line, without the usage block.
fn usage_error_line(text: &str) -> String {
    // the usage block and the pointer to --help come after the message
    // (which quotes no newline: the arguments were escaped)
    let body = text.split("\nUsage:").next().unwrap_or(text);
    let body = body.split("\nFor more information").next().unwrap_or(body);
    let mut line = String::new();
    for part in body.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if !line.is_empty() {
            line.push_str(if line.ends_with(':') { " " } else { "; " });
        }
        line.push_str(part);
    }
    let line = line.strip_prefix("error: ").unwrap_or(&line);
    format!("{line} (see --help)")
}
