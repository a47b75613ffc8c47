//! `fpc timing`: in-process median solve times for the standard cases
//! (default actuator, N = 8, tip-only output).

use std::io::Write as _;
use std::time::{Duration, Instant};

use fpc::{Coefficients, Finger, Load, Solution, SolveOptions, Solver};
use serde_json::json;

/// Flags of `fpc timing`. Numeric flags take `allow_hyphen_values` (see
/// `finger::Args`): `-1` or `-inf` is a value for the parser to reject.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Wall-clock budget per case, in milliseconds.
    #[arg(long, default_value_t = 400, allow_hyphen_values = true)]
    budget_ms: u64,
}

struct Case {
    name: &'static str,
    median_us: f64,
    runs: usize,
    last: Solution,
}

/// Times repeated solves of `load` from `guess` until the budget is spent.
fn time_case(
    name: &'static str,
    finger: &Finger,
    load: &Load,
    guess: Option<&Coefficients>,
    budget: Duration,
) -> anyhow::Result<Case> {
    let opts = SolveOptions::default().tip_only();
    let mut solver = Solver::new(finger);
    let mut last = solver.solve(load, guess, &opts)?; // warm caches, check it solves
    let mut samples = Vec::new();
    let start = Instant::now();
    while start.elapsed() < budget || samples.len() < 11 {
        let t = Instant::now();
        last = solver.solve(load, guess, &opts)?;
        samples.push(t.elapsed().as_secs_f64() * 1e6);
        if samples.len() >= 200_000 {
            break;
        }
    }
    samples.sort_by(f64::total_cmp);
    let median_us = samples[samples.len() / 2];
    Ok(Case {
        name,
        median_us,
        runs: samples.len(),
        last,
    })
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let budget = Duration::from_millis(args.budget_ms.max(1));
    let opts = SolveOptions::default().tip_only();
    let f25 = Finger::paper(0.25, 8)?;
    let f40 = Finger::paper(0.4, 8)?;
    let cold_load = Load::unloaded().with_tip_force(0.939782, 0.521707);
    let unloaded = f25.solve(&Load::unloaded(), &opts)?;
    let near = f25.solve(&Load::unloaded().with_tip_force(0.9, 0.5), &opts)?;
    let cases = [
        time_case("unloaded", &f25, &Load::unloaded(), None, budget)?,
        time_case(
            "pressure",
            &f40,
            &Load::unloaded().with_pressure_kpa(386.0),
            None,
            budget,
        )?,
        time_case(
            "loaded_cold",
            &f25,
            &cold_load,
            Some(&unloaded.coefficients),
            budget,
        )?,
        time_case(
            "loaded_warm",
            &f25,
            &cold_load,
            Some(&near.coefficients),
            budget,
        )?,
    ];
    let build = if cfg!(debug_assertions) {
        "debug"
    } else {
        "release"
    };
    let mut out = crate::output::stdout();
    if args.json {
        let mut obj = serde_json::Map::new();
        obj.insert("build".into(), json!(build));
        for c in &cases {
            obj.insert(
                c.name.into(),
                json!({
                    "median_us": c.median_us,
                    "runs": c.runs,
                    "iterations": c.last.report.iterations,
                    "residual": c.last.report.residual_norm,
                    "coupled": c.last.report.coupled,
                }),
            );
        }
        obj.insert("loaded_cold_tip_mm".into(), json!(cases[2].last.tip));
        writeln!(out, "{}", serde_json::Value::Object(obj))?;
    } else {
        writeln!(
            out,
            "median time per solve ({build} build, N = 8, default actuator, tip-only output)"
        )?;
        writeln!(
            out,
            "{:<12} {:>12} {:>8} {:>11} {:>12}",
            "case", "median (us)", "runs", "iterations", "residual"
        )?;
        for c in &cases {
            writeln!(
                out,
                "{:<12} {:>12.2} {:>8} {:>11} {:>12.2e}",
                c.name, c.median_us, c.runs, c.last.report.iterations, c.last.report.residual_norm
            )?;
        }
        writeln!(
            out,
            "loaded_cold tip: X = {:.6} mm, Z = {:.6} mm",
            cases[2].last.tip[0], cases[2].last.tip[1]
        )?;
    }
    Ok(())
}
