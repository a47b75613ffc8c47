//! `fpc`: the command-line face of the fpc library. Glue only: parse flags,
//! validate them into library types, call the library, print or write.

use clap::{Parser, Subcommand};

mod accuracy;
mod finger;
mod kernels;
mod output;
mod paper;
mod solve;
mod stress;
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
    /// Run time against error over N and the Newton tolerance (writes CSV and SVG).
    Accuracy(accuracy::Args),
    /// Solve one finger of the default actuator (eps0, pressure, tip force).
    Finger(finger::Args),
    /// Print the generated element kernels and their operation counts.
    Kernels(kernels::Args),
    /// Solve the finger or gripper grasp of a TOML scene file; write solution.json, shape.csv, shape.svg.
    Solve(solve::Args),
    /// Median solve times of the standard cases, measured in-process.
    Timing(timing::Args),
    /// Run the paper's eight studies; write CSV tables, SVG figures, summary.json and index.html.
    Paper(paper::Args),
    /// Seeded random extreme-but-legal scenes, solved and checked independently.
    Stress(stress::Args),
}

fn main() {
    let cli = Cli::try_parse().unwrap_or_else(|e| exit_on_usage_error(e));
    let result = match cli.command {
        Command::Accuracy(a) => accuracy::run(&a),
        Command::Finger(a) => finger::run(&a),
        Command::Kernels(a) => kernels::run(&a),
        Command::Solve(a) => solve::run(&a),
        Command::Timing(a) => timing::run(&a),
        Command::Paper(a) => paper::run(&a),
        Command::Stress(a) => stress::run(&a),
    };
    if let Err(e) = result {
        eprintln!("fpc: error: {e:#}");
        std::process::exit(exit_code(&e));
    }
}

/// Help and version go to stdout (status 0) as clap prints them; a usage
/// error (unknown flag, missing or malformed value) is rejected input: one
/// line on stderr in the form of every other error, and status 2.
fn exit_on_usage_error(e: clap::Error) -> ! {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        e.exit()
    }
    eprintln!("fpc: error: {}", usage_error_line(&e.to_string()));
    std::process::exit(2)
}

/// clap's message and tips on one line, without the usage block.
fn usage_error_line(text: &str) -> String {
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

/// 2 for rejected input, 1 for anything else (a failed solve, I/O).
fn exit_code(e: &anyhow::Error) -> i32 {
    let input = e.chain().any(|c| {
        c.downcast_ref::<fpc::InputError>().is_some()
            || matches!(
                c.downcast_ref::<fpc::SolveError>(),
                Some(fpc::SolveError::Input(_))
            )
    });
    if input {
        2
    } else {
        1
    }
}
