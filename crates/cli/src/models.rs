//! `fpc models`: the element models generated from `energy-spec/`.

use std::io::Write;

use fpc::ModelId;

/// Flags of `fpc models`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print one JSON array instead of a table.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct Row {
    name: &'static str,
    default: bool,
    spec: &'static str,
    unknowns: &'static [&'static str],
    local: Vec<&'static str>,
    description: &'static str,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let rows: Vec<Row> = ModelId::ALL
        .iter()
        .map(|&m| {
            let i = m.info();
            Row {
                name: i.name,
                default: m == ModelId::default(),
                spec: i.spec,
                unknowns: i.unknowns,
                local: i.local.iter().map(|&k| i.unknowns[k]).collect(),
                description: i.description,
            }
        })
        .collect();
    let mut out = crate::output::stdout();
    if args.json {
        writeln!(out, "{}", serde_json::to_string(&rows)?)?;
        return Ok(());
    }
    writeln!(
        out,
        "model    unknowns  spec                    unknown names (local)"
    )?;
    for r in &rows {
        writeln!(
            out,
            "{:<8} {:>8}  {:<23} {} ({}){}",
            r.name,
            r.unknowns.len(),
            r.spec,
            r.unknowns.join(", "),
            r.local.join(", "),
            if r.default { "  [default]" } else { "" }
        )?;
        // the spec's first paragraph, on one line
        let first: Vec<&str> = r
            .description
            .lines()
            .take_while(|l| !l.trim().is_empty())
            .map(str::trim)
            .collect();
        writeln!(out, "         {}", first.join(" "))?;
    }
    Ok(())
}
