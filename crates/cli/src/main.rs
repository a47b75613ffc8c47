//! `fpc`: the command-line face of the fpc library. Glue only: parse flags,
//! validate them into library types, call the library, print or write.

use clap::{Parser, Subcommand};

mod kernels;

/// Fluidic prestressed composite fingers and grippers: the chained composite model.
#[derive(Parser, Debug)]
#[command(name = "fpc", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print the generated element kernels and their operation counts.
    Kernels(kernels::Args),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Kernels(a) => kernels::run(&a),
    };
    if let Err(e) = result {
        eprintln!("fpc: {e:#}");
        std::process::exit(1);
    }
}
