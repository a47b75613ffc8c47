//! `fpc stress`: seeded random scenes with extreme but legal inputs, each
//! solved and checked independently (`fpc_lab::stress`).

use std::io::Write;
use std::time::Duration;

use fpc_lab::{StressCase, StressConfig, StressReport};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Value};

/// Flags of `fpc stress`. Numeric flags take `allow_hyphen_values` (see
/// `finger::Args`): `-1` or `-inf` is a value for the parser to reject.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Seed of the case generator.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    seed: u64,
    /// Number of cases.
    #[arg(long, default_value_t = 200, allow_hyphen_values = true)]
    cases: usize,
    /// Wall-clock budget in seconds; no case starts after it is spent.
    #[arg(long = "budget-s", default_value_t = 60.0, allow_hyphen_values = true)]
    budget_s: f64,
    /// Largest element count drawn (from 1, 2, 3, 4, 8, 16, 32, 64, 128).
    #[arg(
        long = "max-elements",
        default_value_t = 128,
        allow_hyphen_values = true
    )]
    max_elements: usize,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    if !(args.budget_s.is_finite() && args.budget_s > 0.0) {
        return Err(fpc::InputError::NotPositive {
            field: "--budget-s".into(),
            value: args.budget_s,
        }
        .into());
    }
    let budget = Duration::try_from_secs_f64(args.budget_s).unwrap_or(Duration::MAX);
    let config = StressConfig {
        max_elements: args.max_elements.max(1),
        ..StressConfig::new(args.seed, args.cases, budget)
    };
    // draws on stderr, and not at all when stderr is not a terminal
    let bar = ProgressBar::new(args.cases as u64);
    let style = ProgressStyle::with_template("{spinner} [{elapsed}] [{bar:24}] {pos}/{len} cases")
        .map(|s| s.progress_chars("=> "))
        .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar.enable_steady_tick(Duration::from_millis(120));
    // the bar is hidden when stderr is not a terminal: then one line per tenth
    let plain = !crate::report::is_terminal();
    let report = fpc_lab::stress_with(&config, |done, total| {
        bar.set_position(done as u64);
        if plain && (done * 10 / total.max(1) > (done - 1) * 10 / total.max(1)) {
            crate::report::plain(&format!("fpc stress: {done}/{total} cases"));
        }
    });
    bar.finish_and_clear();

    let mut out = crate::output::stdout();
    if args.json {
        writeln!(out, "{}", serde_json::to_string(&to_json(&report))?)?;
    } else {
        summary(&mut out, &report)?;
    }
    out.flush()?;
    if report.bugs() > 0 {
        anyhow::bail!(
            "{} panic(s) and {} silently wrong answer(s) in {} cases (seed {})",
            report.panics(),
            report.silently_wrong(),
            report.cases_run(),
            args.seed
        );
    }
    Ok(())
}

/// A finite number, or JSON null.
fn num(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

fn opt(v: Option<f64>) -> Value {
    v.map_or(Value::Null, num)
}

fn case_json(c: &StressCase) -> Value {
    let i = &c.inputs;
    let g = &i.geometry;
    let ch = &i.channel;
    let (reason, element, solver_residual, detail) = match &c.outcome {
        fpc_lab::StressOutcome::Failed {
            reason,
            element,
            relative_residual,
        } => (
            json!(fpc_lab::reason_name(*reason)),
            json!(element),
            num(*relative_residual),
            Value::Null,
        ),
        fpc_lab::StressOutcome::Rejected { error } => {
            (Value::Null, Value::Null, Value::Null, json!(error))
        }
        fpc_lab::StressOutcome::SilentlyWrong { what } => {
            (Value::Null, Value::Null, Value::Null, json!(what))
        }
        fpc_lab::StressOutcome::Panicked { message } => {
            (Value::Null, Value::Null, Value::Null, json!(message))
        }
        fpc_lab::StressOutcome::Converged => (Value::Null, Value::Null, Value::Null, Value::Null),
    };
    json!({
        "index": c.index,
        "outcome": c.outcome.label(),
        "reason": reason,
        "element": element,
        "solver_residual": solver_residual,
        "detail": detail,
        "inputs": {
            "eps0": num(i.eps0),
            "pressure_kpa": num(i.pressure_kpa),
            "fx_n": num(i.fx),
            "fz_n": num(i.fz),
            "elements": i.elements,
            "length_ratio": num(i.length_ratio),
            "lengths_mm": i.lengths.iter().map(|&l| num(l)).collect::<Vec<_>>(),
            "thickness_scale": num(i.thickness_scale),
            "lamina_factors": i.lamina_factors.iter().map(|&f| num(f)).collect::<Vec<_>>(),
            "h_mm": num(g.h),
            "h1_mm": num(g.h1),
            "h2_mm": num(g.h2),
            "h3_mm": num(g.h3),
            "h3a_mm": num(ch.h3a),
            "h3b_mm": num(ch.h3b),
            "ribs": i.ribs,
        },
        "rejected_draws": c.rejected_draws,
        "iterations": c.iterations,
        "continuation_steps": c.continuation_steps,
        "residual": opt(c.residual),
        "min_eig": opt(c.min_eig),
        "conditioning": opt(c.conditioning),
        "max_rotation_rad": opt(c.max_rotation),
        "seconds": num(c.seconds),
    })
}

fn to_json(r: &StressReport) -> Value {
    let failures: Vec<Value> = r.failures().map(case_json).collect();
    json!({
        "seed": r.config.seed,
        "cases_requested": r.config.cases,
        "cases_run": r.cases_run(),
        "stopped_early": r.stopped_early(),
        "budget_s": num(r.config.budget.as_secs_f64()),
        "elapsed_s": num(r.elapsed.as_secs_f64()),
        "max_elements": r.config.max_elements,
        "converged": r.converged(),
        "failed": r.failed(),
        "failed_by_reason": r.failed_by_reason(),
        "rejected": r.rejected(),
        "rejected_draws": r.rejected_draws(),
        "rejected_draws_by_field": r.rejections_by_field(),
        "panics": r.panics(),
        "silently_wrong": r.silently_wrong(),
        "unstable": r.unstable(),
        "beyond_validity": r.beyond_validity(),
        "convergence_rate": opt(r.convergence_rate()),
        "largest_residual": opt(r.largest_residual().and_then(|c| c.residual)),
        "largest_residual_case": r.largest_residual().map(|c| c.index),
        "worst_conditioning": opt(r.worst_conditioning().and_then(|c| c.conditioning)),
        "worst_conditioning_case": r.worst_conditioning().map(|c| c.index),
        "by_elements": r
            .by_elements()
            .iter()
            .map(|(n, (legal, conv))| (n.to_string(), json!({ "legal": legal, "converged": conv })))
            .collect::<serde_json::Map<String, Value>>(),
        "failures": failures,
    })
}

fn summary(out: &mut impl Write, r: &StressReport) -> std::io::Result<()> {
    let cfg = &r.config;
    writeln!(
        out,
        "fpc stress: seed {}, {} of {} cases in {:.1} s (budget {:.0} s{}), N up to {}",
        cfg.seed,
        r.cases_run(),
        cfg.cases,
        r.elapsed.as_secs_f64(),
        cfg.budget.as_secs_f64(),
        if r.stopped_early() {
            ", stopped early"
        } else {
            ""
        },
        cfg.max_elements
    )?;
    writeln!(out)?;
    writeln!(out, "  {:<34} {:>6}", "outcome", "cases")?;
    writeln!(out, "  {:<34} {:>6}", "converged (checked)", r.converged())?;
    writeln!(out, "  {:<34} {:>6}", "failed to converge", r.failed())?;
    for (reason, n) in r.failed_by_reason() {
        writeln!(out, "  {:<34} {:>6}", format!("  {reason}"), n)?;
    }
    writeln!(
        out,
        "  {:<34} {:>6}   ({} rejected draws redrawn)",
        "rejected input",
        r.rejected(),
        r.rejected_draws()
    )?;
    for (field, n) in r.rejections_by_field() {
        writeln!(out, "  {:<34} {:>6}", format!("  redrawn: {field}"), n)?;
    }
    writeln!(out, "  {:<34} {:>6}", "PANICS", r.panics())?;
    writeln!(out, "  {:<34} {:>6}", "SILENTLY WRONG", r.silently_wrong())?;
    writeln!(out)?;
    match r.convergence_rate() {
        Some(rate) => writeln!(
            out,
            "  convergence rate (legal inputs)   {:.1} % ({} of {})",
            100.0 * rate,
            r.converged(),
            r.legal()
        )?,
        None => writeln!(out, "  convergence rate (legal inputs)   n/a")?,
    }
    if let Some(c) = r.largest_residual() {
        writeln!(
            out,
            "  largest recomputed residual       {:.3e} (case {}, limit {:.0e})",
            c.residual.unwrap_or(f64::NAN),
            c.index,
            fpc_lab::RESIDUAL_LIMIT
        )?;
    }
    if let Some(c) = r.worst_conditioning() {
        writeln!(
            out,
            "  worst conditioning lmin/G         {:.3e} (case {}, lmin/stiffness {:.3e})",
            c.conditioning.unwrap_or(f64::NAN),
            c.index,
            c.min_eig.unwrap_or(f64::NAN)
        )?;
    }
    writeln!(out, "  unstable equilibria (lmin < 0)    {}", r.unstable())?;
    let by_n: Vec<String> = r
        .by_elements()
        .iter()
        .map(|(n, (legal, conv))| format!("N={n} {conv}/{legal}"))
        .collect();
    writeln!(
        out,
        "  converged by N                    {}",
        by_n.join(", ")
    )?;
    writeln!(
        out,
        "  element rotated > 90 deg          {} (converged, outside the model's kinematics)",
        r.beyond_validity()
    )?;
    let failures: Vec<&StressCase> = r.failures().collect();
    if !failures.is_empty() {
        writeln!(out)?;
        writeln!(out, "failures:")?;
        for c in failures {
            writeln!(
                out,
                "  case {:>4}: {} | {} | {:.2} s",
                c.index, c.outcome, c.inputs, c.seconds
            )?;
        }
    }
    Ok(())
}
