//! `fpc-lab stress`: seeded random scenes over a domain wider than the model's
//! validity, each solved, checked independently and classified inside or
//! outside the validity envelope (`fpc_lab::stress`).

use std::io::Write;
use std::sync::atomic::Ordering;
use std::time::Duration;

use fpc_lab::{StressCase, StressConfig, StressOutcome, StressReport, Tally};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Value};

/// Flags of `fpc-lab stress`. Numeric flags take `allow_hyphen_values` (see
/// the `fpc` binary's `finger` flags): `-1` or `-inf` is a value for the parser to reject.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Seed of the case generator.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    seed: u64,
    /// Number of cases (at most 1000000).
    #[arg(long, default_value_t = 200, allow_hyphen_values = true)]
    cases: usize,
    /// Wall-clock budget in seconds (at most 86400); no case starts after
    /// it is spent.
    #[arg(long = "budget-s", default_value_t = 60.0, allow_hyphen_values = true)]
    budget_s: f64,
    /// Largest fixed element count drawn (from 1, 2, 3, 4, 8, 16, 32, 64,
    /// 128, 256; from 1 to 1000); the automatic partition is drawn whatever
    /// it is.
    #[arg(
        long = "max-elements",
        default_value_t = 256,
        allow_hyphen_values = true
    )]
    max_elements: usize,
    /// Run only case INDEX of the seed (to reproduce it) and print it in full.
    #[arg(long = "case", allow_hyphen_values = true)]
    case: Option<usize>,
    /// With --json, list every case (not only the failures).
    #[arg(long = "all-cases")]
    all_cases: bool,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

/// The most cases of one run (the report holds every case).
const MAX_CASES: usize = 1_000_000;
/// The longest budget, in seconds (a day).
const MAX_BUDGET_S: f64 = 86_400.0;
/// The largest fixed element count.
const MAX_ELEMENTS: usize = 1000;

pub fn run(args: &Args) -> anyhow::Result<()> {
    // every bound checked before any allocation or case
    let out_of_range = |field: &'static str, value: f64, rule: String| -> anyhow::Error {
        fpc::InputError::OutOfRange {
            field: fpc::Field::key(field),
            value,
            rule,
        }
        .into()
    };
    if !(args.budget_s.is_finite() && args.budget_s > 0.0 && args.budget_s <= MAX_BUDGET_S) {
        return Err(out_of_range(
            "--budget-s",
            args.budget_s,
            format!("must lie in (0, {MAX_BUDGET_S}]"),
        ));
    }
    if !(1..=MAX_CASES).contains(&args.cases) {
        return Err(out_of_range(
            "--cases",
            args.cases as f64,
            format!("must lie in [1, {MAX_CASES}]"),
        ));
    }
    if !(1..=MAX_ELEMENTS).contains(&args.max_elements) {
        return Err(out_of_range(
            "--max-elements",
            args.max_elements as f64,
            format!("must lie in [1, {MAX_ELEMENTS}]"),
        ));
    }
    let max_elements = args.max_elements;
    if let Some(index) = args.case {
        let c = fpc_lab::stress_case(args.seed, index, max_elements);
        let mut out = crate::output::stdout();
        if args.json {
            writeln!(out, "{}", serde_json::to_string(&case_json(&c))?)?;
        } else {
            writeln!(
                out,
                "case {} of seed {} ({} envelope): {} [{}] | {} | {:.3} s",
                c.index,
                args.seed,
                if c.inside_envelope {
                    "inside the"
                } else {
                    "outside the"
                },
                c.outcome,
                c.findings.join(", "),
                c.inputs,
                c.seconds
            )?;
            writeln!(out, "{}", serde_json::to_string_pretty(&case_json(&c))?)?;
        }
        out.flush()?;
        if c.outcome.is_bug() {
            anyhow::bail!("case {index} of seed {}: {}", args.seed, c.outcome);
        }
        return Ok(());
    }
    let budget = Duration::try_from_secs_f64(args.budget_s).unwrap_or(Duration::MAX);
    let config = StressConfig {
        max_elements,
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
    // Ctrl-C ends the run after the case under way, which is kept
    let stop = fpc_cli::interrupt::arm("the cases run are reported");
    let stopped = || stop.as_ref().is_some_and(|f| f.load(Ordering::Relaxed));
    let report = fpc_lab::stress_with(&config, |done, total| {
        bar.set_position(done as u64);
        if plain && (done * 10 / total.max(1) > (done - 1) * 10 / total.max(1)) {
            crate::report::plain(&format!("fpc-lab stress: {done}/{total} cases"));
        }
        !stopped()
    });
    bar.finish_and_clear();

    let mut out = crate::output::stdout();
    if args.json {
        writeln!(
            out,
            "{}",
            serde_json::to_string(&to_json(&report, args.all_cases))?
        )?;
    } else {
        summary(&mut out, &report)?;
    }
    out.flush()?;
    if report.bugs() > 0 {
        anyhow::bail!(
            "{} panic(s), {} silently wrong answer(s) and {} wrong stability answer(s) in {} cases (seed {})",
            report.panics(),
            report.silently_wrong(),
            report.wrong_stability(),
            report.cases_run(),
            args.seed
        );
    }
    if stopped() && report.stopped_early() {
        return Err(fpc_cli::status::interrupted(format!(
            "stopped by Ctrl-C after {} of {} cases (reported above)",
            report.cases_run(),
            args.cases
        )));
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
        StressOutcome::Failed {
            reason,
            element,
            relative_residual,
        } => (
            json!(fpc_lab::reason_name(*reason)),
            json!(element),
            num(*relative_residual),
            Value::Null,
        ),
        StressOutcome::Rejected { error } => (Value::Null, Value::Null, Value::Null, json!(error)),
        StressOutcome::SilentlyWrong { what } => {
            (Value::Null, Value::Null, Value::Null, json!(what))
        }
        StressOutcome::WrongStability { .. } => (
            Value::Null,
            Value::Null,
            Value::Null,
            json!(c.outcome.to_string()),
        ),
        StressOutcome::Panicked { message } => {
            (Value::Null, Value::Null, Value::Null, json!(message))
        }
        StressOutcome::Converged => (Value::Null, Value::Null, Value::Null, Value::Null),
    };
    json!({
        "index": c.index,
        "outcome": c.outcome.label(),
        "inside_envelope": c.inside_envelope,
        "reason": reason,
        "element": element,
        "solver_residual": solver_residual,
        "detail": detail,
        "inputs": {
            "model": i.model.name(),
            "eps0": num(i.eps0),
            "pressure_kpa": num(i.pressure_kpa),
            "fx_n": num(i.fx),
            "fz_n": num(i.fz),
            "relative_load": num(i.relative_load),
            "load_strain": num(i.load_strain()),
            "curl": num(i.curl()),
            "force_scale_n": num(i.force_scale),
            "partition": if i.auto_partition { "auto" } else { "custom" },
            "elements": (!i.auto_partition).then_some(i.elements),
            "length_ratio": num(i.length_ratio),
            "lengths_mm": i.lengths.iter().map(|&l| num(l)).collect::<Vec<_>>(),
            "thickness_scale": num(i.thickness_scale),
            "jittered": i.jittered,
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
        "solved_elements": c.solved_elements,
        "refinements": c.refinements,
        "iterations": c.iterations,
        "continuation_steps": c.continuation_steps,
        "steps": c.steps,
        "residual": opt(c.residual),
        "negative_eigenvalues": c.negative_eigenvalues,
        "dense_negative": c.dense_negative.map(|(below, within)| json!({"below": below, "within": within})),
        "min_eig": opt(c.min_eig),
        "conditioning": opt(c.conditioning),
        "max_rotation_rad": opt(c.max_rotation),
        "findings": c.findings,
        "notes": c.notes,
        "missed_findings": c.missed_findings,
        "seconds": num(c.seconds),
    })
}

fn tally_json(t: &Tally) -> Value {
    json!({
        "cases": t.cases,
        "converged": t.converged,
        "warned": t.warned,
        "failed": t.failed,
        "failed_by_reason": t.failed_by_reason,
        "findings": t.findings,
        "unstable": t.unstable,
        "bugs": t.bugs,
        "convergence_rate": opt(t.convergence_rate()),
    })
}

fn envelope_json() -> Value {
    use fpc_lab::stress::envelope::*;
    json!({
        "definition": "auto partition or longest element <= max_element_fraction lx; no per-lamina jitter; eps0 <= max_eps0; P <= max_pressure_kpa; |eps0 - P / pressure_per_prestrain_kpa| lx / H <= max_curl; relative_load H / lx <= max_load_strain_over_eps0 eps0; H <= max_thickness_over_lx lx and H <= max_thickness_over_ly ly (the plate theory's limits)",
        "max_eps0": MAX_EPS0,
        "max_pressure_kpa": MAX_PRESSURE_KPA,
        "pressure_per_prestrain_kpa": PRESSURE_PER_PRESTRAIN_KPA,
        "max_curl": MAX_CURL,
        "max_load_strain_over_eps0": MAX_LOAD_STRAIN_OVER_EPS0,
        "max_element_fraction": MAX_ELEMENT_FRACTION,
        "max_thickness_over_lx": fpc::validity::THICKNESS_TO_LENGTH_LIMIT,
        "max_thickness_over_ly": fpc::validity::THICKNESS_TO_WIDTH_LIMIT,
        "lamina_jitter": false,
    })
}

fn to_json(r: &StressReport, all_cases: bool) -> Value {
    let failures: Vec<Value> = r.failures().map(case_json).collect();
    let inside_defects: Vec<Value> = r.inside_defects().map(case_json).collect();
    let mut v = json!({
        "seed": r.config.seed,
        "cases_requested": r.config.cases,
        "cases_run": r.cases_run(),
        "stopped_early": r.stopped_early(),
        "budget_s": num(r.config.budget.as_secs_f64()),
        "elapsed_s": num(r.elapsed.as_secs_f64()),
        "max_elements": r.config.max_elements,
        "step_distributions": step_distributions(r)
            .into_iter()
            .map(|(name, q)| (name.to_string(), json!(q)))
            .collect::<serde_json::Map<String, Value>>(),
        "converged": r.converged(),
        "failed": r.failed(),
        "failed_by_reason": r.failed_by_reason(),
        "rejected": r.rejected(),
        "rejected_draws": r.rejected_draws(),
        "rejected_draws_by_field": r.rejections_by_field(),
        "panics": r.panics(),
        "silently_wrong": r.silently_wrong(),
        "wrong_stability": r.wrong_stability(),
        "unstable_reported_stable": r.unstable_reported_stable(),
        "stability_checked": r.stability_checked(),
        "stability_unknown": r.stability_unknown(),
        "unstable": r.unstable(),
        "beyond_validity": r.beyond_validity(),
        "missed_findings": r.missed_findings(),
        "convergence_rate": opt(r.convergence_rate()),
        "largest_residual": opt(r.largest_residual().and_then(|c| c.residual)),
        "largest_residual_case": r.largest_residual().map(|c| c.index),
        "worst_conditioning": opt(r.worst_conditioning().and_then(|c| c.conditioning)),
        "worst_conditioning_case": r.worst_conditioning().map(|c| c.index),
        "envelope": envelope_json(),
        "inside_envelope": tally_json(&r.inside()),
        "outside_envelope": tally_json(&r.outside()),
        "by_elements": r
            .by_elements()
            .iter()
            .map(|(n, t)| {
                (
                    n.to_string(),
                    json!({
                        "legal": t.cases,
                        "converged": t.converged,
                        "warned": t.warned,
                        "failed": t.failed,
                    }),
                )
            })
            .collect::<serde_json::Map<String, Value>>(),
        "by_model": r
            .by_model()
            .iter()
            .map(|(m, t)| (m.to_string(), tally_json(t)))
            .collect::<serde_json::Map<String, Value>>(),
        "failures": failures,
        "inside_defects": inside_defects,
    });
    if all_cases {
        v["cases"] = Value::Array(r.cases.iter().map(case_json).collect());
    }
    v
}

/// The step counts' distributions over converged coupled solves, by
/// name: the coupled Newton steps (from the start and in continuation),
/// the start's element iterations, and the globalisation's counts.
fn step_distributions(r: &StressReport) -> Vec<(&'static str, Option<fpc_lab::Quantiles>)> {
    vec![
        (
            "coupled Newton steps",
            r.step_quantiles(|s| s.coupled + s.continuation),
        ),
        (
            "start (element) iterations",
            r.step_quantiles(|s| s.element),
        ),
        ("chord steps", r.step_quantiles(|s| s.chord)),
        ("shifted steps", r.step_quantiles(|s| s.shifted)),
        ("damped steps", r.step_quantiles(|s| s.damped)),
        ("grown steps", r.step_quantiles(|s| s.grown)),
        ("extended steps", r.step_quantiles(|s| s.extended)),
    ]
}

fn rate(t: &Tally) -> String {
    match t.convergence_rate() {
        Some(r) => format!("{:.2} %", 100.0 * r),
        None => "n/a".into(),
    }
}

fn tally_lines(out: &mut impl Write, name: &str, t: &Tally) -> std::io::Result<()> {
    writeln!(
        out,
        "  {name}: {} cases, {} converged ({}), {} of them with validity findings, {} failed, {} bugs",
        t.cases,
        t.converged,
        rate(t),
        t.warned,
        t.failed,
        t.bugs
    )?;
    for (reason, n) in &t.failed_by_reason {
        writeln!(out, "    failed: {reason:<28} {n:>6}")?;
    }
    for (kind, n) in &t.findings {
        writeln!(out, "    finding: {kind:<27} {n:>6}")?;
    }
    Ok(())
}

fn summary(out: &mut impl Write, r: &StressReport) -> std::io::Result<()> {
    let cfg = &r.config;
    writeln!(
        out,
        "fpc-lab stress: seed {}, {} of {} cases in {:.1} s (budget {:.0} s{}), fixed N up to {} or auto",
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
    writeln!(
        out,
        "  {:<34} {:>6}",
        "  with validity findings",
        r.beyond_validity()
    )?;
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
    writeln!(
        out,
        "  {:<34} {:>6}",
        "WRONG STABILITY",
        r.wrong_stability()
    )?;
    writeln!(
        out,
        "  {:<34} {:>6}",
        "  unstable reported stable",
        r.unstable_reported_stable()
    )?;
    writeln!(out)?;
    writeln!(out, "validity envelope (fpc_lab::inside_envelope):")?;
    tally_lines(out, "inside", &r.inside())?;
    tally_lines(out, "outside", &r.outside())?;
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
            "  worst conditioning lmin/G         {:.3e} (case {}, lmin/stiffness {:.3e}, N <= {})",
            c.conditioning.unwrap_or(f64::NAN),
            c.index,
            c.min_eig.unwrap_or(f64::NAN),
            fpc_lab::CONDITIONING_MAX_ELEMENTS
        )?;
    }
    writeln!(
        out,
        "  stability checked against dense   {} (N <= {})",
        r.stability_checked(),
        fpc_lab::DENSE_CHECK_MAX_ELEMENTS
    )?;
    writeln!(out, "  unstable equilibria               {}", r.unstable())?;
    writeln!(
        out,
        "  stability unknown (singular)      {}",
        r.stability_unknown()
    )?;
    writeln!(
        out,
        "  findings missed at {} samples     {}",
        fpc_lab::FINE_VALIDITY_SAMPLES,
        r.missed_findings()
    )?;
    for (name, q) in step_distributions(r) {
        if let Some(q) = q {
            writeln!(
                out,
                "  {name:<33} median {}, p90 {}, p99 {}, max {} (n = {})",
                q.median, q.p90, q.p99, q.max, q.n
            )?;
        }
    }
    let converged = |t: &Tally| format!("{}/{}", t.converged, t.cases);
    let by_n: Vec<String> = r
        .by_elements()
        .iter()
        .map(|(n, t)| format!("N={n} {}", converged(t)))
        .collect();
    let by_model: Vec<String> = r
        .by_model()
        .iter()
        .map(|(m, t)| format!("{m} {}", converged(t)))
        .collect();
    for (by, list) in [("N", by_n), ("model", by_model)] {
        writeln!(
            out,
            "  {:<33} {}",
            format!("converged by {by}"),
            list.join(", ")
        )?;
    }
    let inside: Vec<&StressCase> = r.inside_defects().collect();
    let outside: Vec<&StressCase> = r.failures().filter(|c| !c.inside_envelope).collect();
    for (title, cases, with_findings) in [
        ("inside the envelope, not converged cleanly:", inside, true),
        ("failures outside the envelope:", outside, false),
    ] {
        if cases.is_empty() {
            continue;
        }
        writeln!(out)?;
        writeln!(out, "{title}")?;
        for c in cases {
            let findings = if with_findings {
                format!(" [{}]", c.findings.join(", "))
            } else {
                String::new()
            };
            writeln!(
                out,
                "  case {:>4}: {}{findings} | {} | {:.2} s",
                c.index, c.outcome, c.inputs, c.seconds
            )?;
        }
    }
    Ok(())
}
