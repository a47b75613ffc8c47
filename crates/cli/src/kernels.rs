//! `fpc kernels`: show what build.rs generated from the energy spec.

use std::io::Write;

/// Flags of `fpc kernels`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print only the operation counts (before and after common-subexpression binding).
    #[arg(long)]
    report: bool,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    if !args.report {
        writeln!(out, "{}", fpc::kernels::SOURCE)?;
    }
    writeln!(out, "// Operation counts per generated function:")?;
    for line in fpc::kernels::REPORT.lines() {
        writeln!(out, "// {line}")?;
    }
    Ok(())
}
