//! `fpc finger`: solve one finger of the default actuator for a scene given by flags.

use std::io::Write;

use fpc::{solve_to_tip_tolerance, Actuator, Finger, Load, Partition, Solution, SolveOptions};
use serde_json::json;

/// Flags of `fpc finger`.
///
/// Numeric flags take `allow_hyphen_values`, so a separate value starting
/// with `-` is the flag's value: `allow_negative_numbers` only covers what
/// looks like a number, and `--eps0 -inf` would be read as a flag `-i`
/// instead of reaching the library's "must be finite".
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Prestrain of the prestressed EMC layer.
    #[arg(long, default_value_t = 0.25, allow_hyphen_values = true)]
    eps0: f64,
    /// Channel pressure in kPa.
    #[arg(
        long = "pressure-kpa",
        default_value_t = 0.0,
        allow_hyphen_values = true
    )]
    pressure_kpa: f64,
    /// Tip force along the finger's X axis, in newtons.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    fx: f64,
    /// Tip force along the finger's Z axis, in newtons.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    fz: f64,
    /// Number of equal elements N.
    #[arg(long, default_value_t = 8, allow_hyphen_values = true)]
    elements: usize,
    /// Leave out the ribs inside the channel.
    #[arg(long = "no-ribs")]
    no_ribs: bool,
    /// Pressure factor kappa = 1/(gamma - 1).
    #[arg(long, default_value_t = 2.5, allow_hyphen_values = true)]
    kappa: f64,
    /// Choose N by doubling (from --elements, at most 256) until the
    /// estimated tip error (tip change between N/2 and N) is at most this
    /// many millimetres.
    #[arg(long = "tip-tol-mm", allow_hyphen_values = true)]
    tip_tol_mm: Option<f64>,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let act = Actuator::paper(args.eps0)?;
    for w in act.warnings() {
        crate::report::warning(&w.to_string());
    }
    let load = Load {
        kappa: args.kappa,
        ..Load::unloaded()
    }
    .with_pressure_kpa(args.pressure_kpa)
    .with_tip_force(args.fx, args.fz);
    let opts = SolveOptions::default();
    let (sol, elements, estimate) = match args.tip_tol_mm {
        Some(tol) => {
            let r = solve_to_tip_tolerance(&act, !args.no_ribs, &load, tol, args.elements, &opts)?;
            (r.solution, r.elements, Some(r.estimated_tip_error_mm))
        }
        None => {
            let part = Partition::equal(act.geometry().lx, args.elements)?;
            let finger = Finger::new(&act, &part, !args.no_ribs);
            (finger.solve(&load, &opts)?, args.elements, None)
        }
    };
    let mut out = crate::output::stdout();
    if args.json {
        let mut v = to_json(&sol);
        v["elements"] = json!(elements);
        v["tip_error_estimate_mm"] = json!(estimate);
        writeln!(out, "{}", serde_json::to_string(&v)?)?;
    } else {
        summary(&mut out, args, elements, estimate, &sol)?;
    }
    Ok(())
}

/// The JSON form of a solution (keys documented in the README).
pub fn to_json(sol: &Solution) -> serde_json::Value {
    json!({
        "tip_mm": sol.tip,
        "end_angle_rad": sol.end_angle,
        "radius_mm": sol.radius,
        "energy_nmm": sol.energy,
        "min_hessian_eig": sol.min_hessian_eig,
        "stable": sol.min_hessian_eig.map(|e| e > 0.0),
        "coefficients": sol.coefficients,
        "points_mm": sol.points,
        "report": {
            "reason": sol.report.reason.to_string(),
            "iterations": sol.report.iterations,
            "residual_norm": sol.report.residual_norm,
            "evaluations": sol.report.evaluations,
            "coupled": sol.report.coupled,
            "continuation_steps": sol.report.continuation_steps,
        },
    })
}

fn summary(
    out: &mut impl Write,
    args: &Args,
    elements: usize,
    estimate: Option<f64>,
    sol: &Solution,
) -> std::io::Result<()> {
    writeln!(
        out,
        "finger: eps0 = {}, N = {}, ribs {}, P = {} kPa, tip force ({}, {}) N",
        args.eps0,
        elements,
        if args.no_ribs { "off" } else { "on" },
        args.pressure_kpa,
        args.fx,
        args.fz
    )?;
    writeln!(
        out,
        "tip            X = {:.4} mm, Z = {:.4} mm",
        sol.tip[0], sol.tip[1]
    )?;
    if let Some(e) = estimate {
        writeln!(
            out,
            "tip accuracy   estimated error {e:.2e} mm at N = {elements} (change from N = {})",
            elements / 2
        )?;
    }
    writeln!(
        out,
        "end angle      {:.5} rad ({:.2} deg)",
        sol.end_angle,
        sol.end_angle.to_degrees()
    )?;
    match sol.radius {
        Some(r) => writeln!(out, "radius (fit)   {r:.3} mm")?,
        None => writeln!(out, "radius (fit)   none: the finger is straight")?,
    }
    writeln!(out, "energy         {:.6} N mm", sol.energy)?;
    if let Some(eig) = sol.min_hessian_eig {
        let verdict = if eig > 0.0 { "stable" } else { "NOT stable" };
        writeln!(
            out,
            "stability      smallest scaled Hessian eigenvalue {eig:.3e} ({verdict})"
        )?;
    }
    writeln!(
        out,
        "solver         {} iterations, relative residual {:.2e}, {}",
        sol.report.iterations,
        sol.report.residual_norm,
        if sol.report.coupled {
            "coupled system"
        } else {
            "decoupled elements"
        }
    )?;
    Ok(())
}

/// The element model of a `--model` value.
pub fn model_by_name(name: &str) -> anyhow::Result<fpc::ModelId> {
    fpc::ModelId::from_name(name).ok_or_else(|| {
        fpc::InputError::OutOfRange {
            field: "model".into(),
            value: f64::NAN,
            rule: format!(
                "`{name}` is not a model (models: {})",
                fpc::ModelId::names().join(", ")
            ),
        }
        .into()
    })
}
