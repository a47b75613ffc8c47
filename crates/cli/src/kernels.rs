//! `fpc kernels`: show what build.rs generated from an element model's spec.

use std::io::Write;

/// Flags of `fpc kernels`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print only the operation counts (before and after common-subexpression binding).
    #[arg(long)]
    report: bool,
    /// The element model (`fpc models` lists them).
    #[arg(long, default_value_t = fpc::ModelId::default().name().to_string())]
    model: String,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let model = fpc::ModelId::parse(fpc::Field::key("--model"), &args.model)?;
    let (source, report) = model.generated();
    let mut out = crate::output::stdout();
    if !args.report {
        writeln!(out, "{source}")?;
    }
    writeln!(out, "// Operation counts per generated function:")?;
    for line in report.lines() {
        writeln!(out, "// {line}")?;
    }
    Ok(())
}
