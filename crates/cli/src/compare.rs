//! `fpc compare MANIFEST`: the model against measurements, with no
//! fitting (`fpc::compare`; docs/measurements.md). Prints the chi-square
//! per test and in all, and writes `compare.csv` (a row per measured
//! quantity), `compare.json` (every prediction with its residuals and the
//! model's validity verdict) and the figures `compare_radius` and
//! `compare_force` (`--format`).
//!
//! A run in which rows were measured but the model predicted none (every
//! solve failed) writes its files, whose `note`s and `failure`s say why
//! for each row, and then fails (status 1) with one line naming the first
//! row and its reason: a summary of no residuals would read as success.

use std::io::Write as _;
use std::path::PathBuf;

use fpc::measure::{figures, table, Comparison, Manifest, FIGURE_STEMS};
use fpc::num::Num;
use serde::Serialize;

/// Flags of `fpc compare`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The measurement manifest (TOML; docs/measurements.md, examples in
    /// examples/calibration/).
    manifest: PathBuf,
    /// Output directory (default `<stem>-compare`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print compare.json's object instead of the summary.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    format: crate::render::formats::FormatArgs,
}

#[derive(Serialize)]
struct Report<'a> {
    #[serde(flatten)]
    comparison: &'a Comparison,
    /// The figure files written.
    figures: Vec<String>,
    provenance: crate::provenance::Provenance,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    // every file is read and checked before anything is computed
    let manifest =
        Manifest::load(&args.manifest).map_err(|e| crate::status::rejected(e.to_string()))?;
    let (_, out) =
        crate::output::stem_and_dir(&args.manifest, args.out.as_deref(), "manifest", "compare");
    crate::output::prepare_dir(&out)?;
    let c = fpc::compare(&manifest)?;
    crate::output::write_atomic(&out, "compare.csv", &crate::render::csv::csv(&table(&c))?)?;
    let mut written = Vec::new();
    let drawn = figures(&c);
    for (stem, fig) in &drawn {
        let svg = crate::paper::render::svg(fig)?;
        written.extend(args.format.write(&out, stem, &svg)?);
    }
    // an earlier run's figure of a kind of test this manifest lacks
    for stem in FIGURE_STEMS {
        if !drawn.iter().any(|(s, _)| *s == stem) {
            crate::render::formats::remove_figure(&out, stem, &[])?;
        }
    }
    let report = Report {
        comparison: &c,
        figures: written,
        provenance: crate::provenance::Provenance::now(),
    };
    let json = serde_json::to_string_pretty(&report)? + "\n";
    crate::output::write_atomic(&out, "compare.json", json.as_bytes())?;
    if let Some(why) = nothing_predicted(&c) {
        anyhow::bail!(
            "{why}; every row's reason is in {}",
            out.join("compare.csv").display()
        );
    }
    let mut w = crate::output::stdout();
    if args.json {
        writeln!(w, "{}", serde_json::to_string(&report)?)?;
        return Ok(());
    }
    for s in &c.specimens {
        for t in &s.tests {
            writeln!(
                w,
                "{:<12} {:<8} {:<40} chi2 {:>12.4} over {:>3} {}{}{}",
                s.name,
                t.kind.name(),
                t.file,
                Num(t.chi_square),
                t.points,
                noun(t.points, "residual"),
                counted(t.failed, "without a prediction"),
                counted(t.outside_model, "outside the model"),
            )?;
        }
    }
    writeln!(
        w,
        "total        chi2 {:.4} over {} {} (per residual {:.4}){}{}",
        Num(c.chi_square),
        c.points,
        noun(c.points, "residual"),
        Num(if c.points > 0 {
            c.chi_square / c.points as f64
        } else {
            0.0
        }),
        counted(c.failed, rows(c.failed, "without a prediction")),
        counted(
            c.outside_model,
            rows(c.outside_model, "predicted outside the model")
        ),
    )?;
    let mut files = vec!["compare.csv".to_string(), "compare.json".to_string()];
    files.extend(report.figures);
    writeln!(w, "wrote        {}: {}", out.display(), files.join(", "))?;
    Ok(())
}

/// Why a comparison that has rows but not one prediction failed (the
/// first row's file, line and reason); `None` when any row was predicted
/// or there was no row to predict.
fn nothing_predicted(c: &Comparison) -> Option<String> {
    let mut rows = c
        .specimens
        .iter()
        .flat_map(|s| &s.tests)
        .flat_map(|t| t.predictions.iter().map(move |p| (&t.file, p)));
    let (file, first) = rows.clone().next()?;
    if rows.any(|(_, p)| p.failure.is_none()) {
        return None;
    }
    Some(format!(
        "the model predicted none of the {} measured {}: {file}:{}: {}",
        c.failed,
        noun(c.failed, "row"),
        first.line,
        first.failure.as_deref().unwrap_or("no prediction")
    ))
}

/// `row what` for one row, `rows what` for any other count.
fn rows(n: usize, what: &str) -> String {
    format!("{} {what}", noun(n, "row"))
}

/// `noun`, or its plural (with an `s`) unless `n` is 1.
fn noun(n: usize, noun: &str) -> String {
    if n == 1 {
        noun.to_string()
    } else {
        format!("{noun}s")
    }
}

/// `; N what` when N > 0.
fn counted(n: usize, what: impl std::fmt::Display) -> String {
    if n == 0 {
        String::new()
    } else {
        format!("; {n} {what}")
    }
}
