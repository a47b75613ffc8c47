//! `fpc`: the command-line face of the fpc library. Glue only: parse flags,
//! validate them into library types, call the library, print or write.

use clap::{Parser, Subcommand};

mod accuracy;
mod finger;
mod kernels;
mod output;
mod paper;
mod solve;
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
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Accuracy(a) => accuracy::run(&a),
        Command::Finger(a) => finger::run(&a),
        Command::Kernels(a) => kernels::run(&a),
        Command::Solve(a) => solve::run(&a),
        Command::Timing(a) => timing::run(&a),
        Command::Paper(a) => paper::run(&a),
    };
    if let Err(e) = result {
        eprintln!("fpc: error: {e:#}");
        std::process::exit(exit_code(&e));
    }
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
