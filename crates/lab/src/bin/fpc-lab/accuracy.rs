//! `fpc-lab accuracy`: the accuracy-time front of the standard tip-loaded
//! finger over every element model, partition kind and extrapolation
//! ([`fpc_lab::accuracy`]). Writes accuracy.csv (one row per
//! configuration), accuracy.json (the whole study) and accuracy.svg (error
//! against time, log-log, with the Pareto front; `--format` adds or
//! replaces it with accuracy.png and accuracy.pdf), and prints the
//! references, the observed orders, every configuration and the fastest
//! configuration per tolerance (or the JSON document with `--json`).

use std::io::Write as _;
use std::path::PathBuf;
use std::time::Duration;

use fpc::plan::PartitionKind;
use fpc::report::{Corner, Figure, Panel, PlotAxis, RefLine, Series, SeriesKind};
use fpc::ModelId;
use fpc_lab::{accuracy_study, AccuracyRow, AccuracyStudy, Convergence, FrontPoint, StudyConfig};

/// Flags of `fpc-lab accuracy`. The budget takes `allow_hyphen_values` (see
/// the `fpc` binary's `finger` flags): `-1` is a value for the parser to reject.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Directory for accuracy.csv, accuracy.json and accuracy.svg (created
    /// if missing).
    #[arg(long, value_name = "DIR", default_value = "accuracy-out")]
    out: PathBuf,
    /// Least wall-clock time spent timing each configuration, in
    /// milliseconds, shared by its 7 rounds (and at least 7 runs per round;
    /// a configuration's time is its fastest round's median).
    #[arg(long, default_value_t = 30, allow_hyphen_values = true)]
    budget_ms: u64,
    /// Print the whole study as one JSON document instead of tables.
    #[arg(long)]
    json: bool,
    /// The reduced configuration list, 2 rounds, 3 runs (tests, previews).
    #[arg(long, hide = true)]
    quick: bool,
    #[command(flatten)]
    format: fpc_cli::render::formats::FormatArgs,
}

/// One row of accuracy.csv: flat, units in the column names.
#[derive(serde::Serialize)]
struct CsvRow<'a> {
    label: &'a str,
    model: &'static str,
    partition: &'static str,
    start: usize,
    levels: usize,
    extrapolate: bool,
    elements: usize,
    elements_per_level: String,
    iterations_per_level: String,
    tip_x_mm: f64,
    tip_z_mm: f64,
    error_vs_ccm_mm: f64,
    error_vs_own_mm: f64,
    estimated_error_mm: Option<f64>,
    time_us: f64,
    runs: usize,
    time_over_n8: f64,
    pareto: bool,
}

fn joined(v: &[usize]) -> String {
    v.iter().map(usize::to_string).collect::<Vec<_>>().join(";")
}

/// accuracy.csv: one row per configuration.
pub fn csv(study: &AccuracyStudy) -> anyhow::Result<Vec<u8>> {
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    for r in &study.rows {
        w.serialize(CsvRow {
            label: &r.label,
            model: r.plan.model.name(),
            partition: r.plan.partition.name(),
            start: r.plan.start,
            levels: r.plan.levels,
            extrapolate: r.plan.extrapolate,
            elements: r.elements,
            elements_per_level: joined(&r.elements_per_level),
            iterations_per_level: joined(&r.iterations),
            tip_x_mm: r.tip[0],
            tip_z_mm: r.tip[1],
            error_vs_ccm_mm: r.error_vs_ccm_mm,
            error_vs_own_mm: r.error_vs_own_mm,
            estimated_error_mm: r.estimated_error_mm,
            time_us: r.time_us,
            runs: r.runs,
            time_over_n8: r.time_over_n8,
            pareto: r.pareto,
        })?;
    }
    Ok(w.into_inner().map_err(|e| e.into_error())?)
}

/// A family of rows: one model, one partition kind, with or without
/// extrapolation.
fn family(r: &AccuracyRow) -> (ModelId, PartitionKind, bool) {
    (r.plan.model, r.plan.partition, r.plan.extrapolate)
}

/// The colour key of a family (the model is told by the marker).
fn family_key(partition: PartitionKind, extrapolate: bool) -> &'static str {
    match (partition, extrapolate) {
        (PartitionKind::Equal, _) => "equal",
        (PartitionKind::Material, false) => "material",
        (PartitionKind::Material, true) => "material+richardson",
    }
}

/// The figure: error against time, both logarithmic, one series per
/// family (the CCM with filled markers, other models with crosses), the
/// Pareto front dashed, the tolerances and t8 as grey reference lines.
pub fn figure(study: &AccuracyStudy) -> Figure {
    let mut p = Panel::new(
        format!(
            "tip-loaded finger, eps0 = {}: error vs the CCM's N → ∞ tip ({} build)",
            study.eps0, study.build
        ),
        PlotAxis::new("time per solve", "us").log(),
        PlotAxis::new("tip error", "mm").log(),
    );
    p.legend = Corner::UpperRight;
    let mut families: Vec<(ModelId, PartitionKind, bool)> = Vec::new();
    for r in &study.rows {
        if !families.contains(&family(r)) {
            families.push(family(r));
        }
    }
    for f @ (model, partition, extrapolate) in families {
        let mut rows: Vec<&AccuracyRow> = study.rows.iter().filter(|r| family(r) == f).collect();
        rows.sort_by_key(|r| r.elements);
        let points: Vec<[f64; 2]> = rows
            .iter()
            .map(|r| [r.time_us, r.error_vs_ccm_mm])
            .collect();
        let key = family_key(partition, extrapolate);
        let label = format!(
            "{} {}{}",
            model.name(),
            partition.name(),
            if extrapolate { " + Richardson" } else { "" }
        );
        if model == ModelId::default() {
            p.series
                .push(Series::new(key, SeriesKind::LinePoints, points).label(label));
        } else {
            p.series
                .push(Series::new(key, SeriesKind::Line, points.clone()));
            p.series
                .push(Series::new(key, SeriesKind::Cross, points).label(label));
        }
    }
    let front: Vec<[f64; 2]> = study
        .front
        .iter()
        .map(|f| [f.time_us, f.error_vs_ccm_mm])
        .collect();
    p.series
        .push(Series::new("reference", SeriesKind::Dashed, front).label("Pareto front"));
    let tolerances: Vec<String> = study
        .fastest
        .iter()
        .map(|f| f.tolerance_mm.to_string())
        .collect();
    for (i, f) in study.fastest.iter().enumerate() {
        p.hlines.push(RefLine {
            at: f.tolerance_mm,
            label: if i == 0 {
                format!("tolerances {} mm", tolerances.join(", "))
            } else {
                String::new()
            },
        });
    }
    p.vlines.push(RefLine {
        at: study.n8.time_us,
        label: "t8: N = 8 equal, cold".into(),
    });
    Figure::row("The accuracy-time front", [1000, 680], vec![p])
}

/// `x` in scientific notation, `–` when not finite.
fn sci(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        "–".into()
    }
}

fn orders(c: &Convergence) -> String {
    let list = |v: &[f64]| -> String {
        v.iter()
            .map(|x| {
                if x.is_finite() {
                    format!("{x:.2}")
                } else {
                    "–".into()
                }
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    format!(
        "{} {}->{}: {} (X {}; Z {})",
        c.partition.name(),
        c.elements.first().copied().unwrap_or(0),
        c.elements.last().copied().unwrap_or(0),
        list(&c.orders),
        list(&c.orders_x),
        list(&c.orders_z)
    )
}

/// The tables on stdout.
fn print_tables(study: &AccuracyStudy, out: &mut impl std::io::Write) -> std::io::Result<()> {
    writeln!(
        out,
        "fpc-lab accuracy ({} build): tip-loaded finger, eps0 = {}, Fx = {} N, Fz = {} N, tip-only, rtol {:e}",
        study.build, study.eps0, study.tip_force_n[0], study.tip_force_n[1], study.rtol
    )?;
    let families: Vec<String> = study
        .ccm_reference()
        .families
        .iter()
        .map(|f| {
            format!(
                "{} -> {} elements",
                f.elements.first().copied().unwrap_or(0),
                f.elements.last().copied().unwrap_or(0)
            )
        })
        .collect();
    writeln!(
        out,
        "references: material partition, {}, every level to rtol {:e}, terms h to h^4 removed from the five finest levels of each family; the midpoint, uncertainty the larger of the families' and their gap",
        families.join(" and "),
        fpc_lab::accuracy::REFERENCE_RTOL
    )?;
    for r in &study.references {
        writeln!(
            out,
            "  {:<5} tip ({:.8}, {:.8}) mm  uncertainty {} mm (families {} mm apart{})  refiner: estimate {} mm, {} mm from the reference",
            r.model.name(),
            r.tip[0],
            r.tip[1],
            sci(r.uncertainty_mm),
            sci(r.family_gap_mm),
            if r.families_agree { "" } else { ", DISAGREEING" },
            r.refiner_estimate_mm.map_or("–".into(), sci),
            sci(r.refiner_offset_mm)
        )?;
    }
    writeln!(out, "observed orders (log2 of successive change ratios):")?;
    for r in &study.references {
        writeln!(
            out,
            "  {:<5} {}; {}",
            r.model.name(),
            orders(&r.material),
            orders(&r.equal)
        )?;
    }
    for g in &study.gaps {
        writeln!(
            out,
            "model gap: {} vs {} {} mm (uncertainty {} mm)",
            g.model.name(),
            g.against.name(),
            sci(g.gap_mm),
            sci(g.uncertainty_mm)
        )?;
    }
    let (lo, hi) = study
        .n8
        .batches_us
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &t| {
            (lo.min(t), hi.max(t))
        });
    writeln!(
        out,
        "t8 ({}, cold, {} iterations): {:.2} us, the fastest of {} batch medians (their median {:.2} us, range {:.2} - {:.2} us; median of those paired with the rows' fastest rounds {:.2} us)",
        study.n8.label,
        study.n8.iterations,
        study.n8.time_us,
        study.n8.batches_us.len(),
        study.n8.all_batches_median_us,
        lo,
        hi,
        study.n8.paired_median_us,
    )?;
    writeln!(
        out,
        "every time: the fastest of {} rounds' medians, each round at least {} runs; noise check: the {} row / t8 = {}",
        study.config.rounds,
        study.config.min_runs,
        study.n8.label,
        study
            .n8
            .same_row_ratio
            .map_or("–".into(), |x| format!("{x:.3}"))
    )?;
    writeln!(
        out,
        "{:<32} {:>8} {:>14} {:>11} {:>8} {:>10} {:>10} {:>10} pareto",
        "configuration",
        "elements",
        "iterations",
        "time (us)",
        "t / t8",
        "vs ccm",
        "vs own",
        "estimate"
    )?;
    for r in &study.rows {
        writeln!(
            out,
            "{:<32} {:>8} {:>14} {:>11.2} {:>8.3} {:>10} {:>10} {:>10} {}",
            r.label,
            r.elements,
            joined(&r.iterations),
            r.time_us,
            r.time_over_n8,
            sci(r.error_vs_ccm_mm),
            sci(r.error_vs_own_mm),
            r.estimated_error_mm.map_or("–".into(), sci),
            if r.pareto { "*" } else { "" }
        )?;
    }
    writeln!(
        out,
        "(errors in mm, vs the CCM's and the model's own reference)"
    )?;
    let point = |b: &FrontPoint| {
        format!(
            "{} ({:.2} us, {:.2} x t8, error {} mm)",
            b.label,
            b.time_us,
            b.time_over_n8,
            sci(b.error_vs_ccm_mm)
        )
    };
    for f in &study.fastest {
        let fastest = f.fastest.as_ref().map_or("no configuration".into(), point);
        let estimated = f
            .fastest_estimated
            .as_ref()
            .map_or("no configuration".into(), point);
        let library = f.library.as_ref().map_or("failed".into(), |l| {
            format!(
                "{} ({:.2} us, {:.2} x t8, error {} mm{}{})",
                l.label,
                l.time_us,
                l.time_over_n8,
                sci(l.error_vs_ccm_mm),
                if l.meets { "" } else { ", NOT within" },
                f.library_over_fastest
                    .map_or(String::new(), |x| format!(", {x:.2} x the fastest"))
            )
        });
        writeln!(
            out,
            "fastest within {} mm: {fastest}; with its estimate within too: {estimated}; the library picks {library}",
            f.tolerance_mm
        )?;
    }
    Ok(())
}

/// How far the N = 8 row's time may be from t8 (relative) before the run
/// is reported as noisy.
const NOISY: f64 = 0.05;

pub fn run(args: &Args) -> anyhow::Result<()> {
    let config = if args.quick {
        StudyConfig::quick()
    } else {
        StudyConfig::full()
    }
    .with_budget(Duration::from_millis(args.budget_ms));
    crate::output::prepare_dir(&args.out)?;
    let study = accuracy_study(&config, |done, total| {
        crate::report::progress(&format!("fpc-lab accuracy: {done}/{total} steps"));
    });
    crate::report::end_progress();
    let study = study?;
    if let Some(r) = study.n8.same_row_ratio.filter(|r| (r - 1.0).abs() > NOISY) {
        crate::report::warning(&format!(
            "timing noise: the {} row took {r:.2} x t8, the same configuration measured the same way; the time ratios of this run are unreliable (run again on a quieter machine)",
            study.n8.label
        ));
    }
    let json = serde_json::to_string_pretty(&study)?;
    let svg = fpc_cli::render::svg::svg(&figure(&study))?;
    let figures = args.format.render("accuracy", &svg)?;
    crate::output::write_atomic(&args.out, "accuracy.csv", &csv(&study)?)?;
    crate::output::write_atomic(&args.out, "accuracy.json", format!("{json}\n").as_bytes())?;
    for (name, bytes) in &figures {
        crate::output::write_atomic(&args.out, name, bytes)?;
    }
    let mut out = crate::output::stdout();
    if args.json {
        writeln!(out, "{json}")?;
    } else {
        print_tables(&study, &mut out)?;
        let names: Vec<&str> = figures.iter().map(|(n, _)| n.as_str()).collect();
        writeln!(
            out,
            "wrote accuracy.csv, accuracy.json and {} in {}",
            names.join(", "),
            args.out.display()
        )?;
    }
    Ok(())
}
