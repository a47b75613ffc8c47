//! `fpc finger`: solve one finger of the default actuator for a scene given by flags.

use std::io::Write;

use fpc::{
    solve_auto, solve_to_tip_tolerance, Actuator, Finger, InputError, Load, ModelId, Partition,
    Solution, SolveOptions,
};

/// `--elements`: a count, or `auto`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Elements {
    /// N equal elements.
    Equal(usize),
    /// The automatic partition ([`fpc::solve_auto`]).
    Auto,
}

/// Parses `--elements`: a whole number or `auto`.
pub fn parse_elements(s: &str) -> Result<Elements, String> {
    if s == "auto" {
        return Ok(Elements::Auto);
    }
    s.parse::<usize>()
        .map(Elements::Equal)
        .map_err(|_| format!("'{s}' is neither a whole number of elements nor `auto`"))
}

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
    /// Number of equal elements N, or `auto`: boundaries on the material
    /// changes, refined until every element is within the slope limit.
    #[arg(long, default_value = "8", value_parser = parse_elements, allow_hyphen_values = true)]
    elements: Elements,
    /// The element model (`fpc models` lists them).
    #[arg(long, default_value_t = ModelId::default().name().to_string())]
    model: String,
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
    let model = ModelId::parse("model", &args.model)?;
    let act = Actuator::paper(args.eps0)?;
    let load = Load {
        kappa: args.kappa,
        ..Load::unloaded()
    }
    .with_pressure_kpa(args.pressure_kpa)
    .with_tip_force(args.fx, args.fz);
    let opts = SolveOptions::default();
    let ribs = !args.no_ribs;
    // notes on the input first: they hold even when the solve fails
    for w in fpc::input_warnings(model, &act) {
        crate::report::warning(&w.to_string());
    }
    let (sol, estimate) = match (args.tip_tol_mm, args.elements) {
        (Some(_), Elements::Auto) => {
            return Err(InputError::Inconsistent {
                field: "tip_tol_mm".into(),
                rule: "chooses N itself: give a starting --elements count, not auto".into(),
            }
            .into())
        }
        (Some(tol), Elements::Equal(n)) => {
            let r = solve_to_tip_tolerance(model, &act, ribs, &load, tol, n, &opts)?;
            (r.solution, Some(r.estimated_tip_error_mm))
        }
        (None, Elements::Auto) => (solve_auto(model, &act, ribs, &load, &opts)?.solution, None),
        (None, Elements::Equal(n)) => {
            let part = Partition::equal(act.geometry().lx, n)?;
            let finger = Finger::with_model(model, &act, &part, ribs);
            (finger.solve(&load, &opts)?, None)
        }
    };
    for w in sol.warnings.iter().filter(|w| w.is_validity()) {
        crate::report::warning(&w.to_string());
    }
    let mut out = crate::output::stdout();
    if args.json {
        let v = Json {
            model: model.name(),
            elements: sol.element_lengths.len(),
            tip_error_estimate_mm: estimate,
            solution: &sol,
        };
        writeln!(out, "{}", serde_json::to_string(&v)?)?;
    } else {
        summary(&mut out, args, model, estimate, &sol)?;
    }
    Ok(())
}

/// The JSON form of a solution (keys documented in the README).
pub fn to_json(sol: &Solution) -> serde_json::Value {
    serde_json::to_value(sol).unwrap_or(serde_json::Value::Null)
}

/// `fpc finger --json`: the solution's keys (README) and the run's.
#[derive(serde::Serialize)]
struct Json<'a> {
    model: &'static str,
    elements: usize,
    tip_error_estimate_mm: Option<f64>,
    #[serde(flatten)]
    solution: &'a Solution,
}

fn summary(
    out: &mut impl Write,
    args: &Args,
    model: ModelId,
    estimate: Option<f64>,
    sol: &Solution,
) -> std::io::Result<()> {
    let elements = sol.element_lengths.len();
    writeln!(
        out,
        "finger: eps0 = {}, model {model}, N = {}{}, ribs {}, P = {} kPa, tip force ({}, {}) N",
        args.eps0,
        elements,
        if args.elements == Elements::Auto {
            " (auto)"
        } else {
            ""
        },
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
    if let Some(k) = sol.negative_eigenvalues {
        let verdict = if k == 0 { "stable" } else { "NOT stable" };
        writeln!(
            out,
            "stability      {k} negative Hessian eigenvalue(s) ({verdict})"
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
    let findings = sol.warnings.iter().filter(|w| w.is_validity()).count();
    if findings == 0 {
        writeln!(out, "validity       within the model's limits")?;
    } else {
        writeln!(
            out,
            "validity       OUTSIDE the model's limits: {findings} finding(s), see the warnings"
        )?;
    }
    Ok(())
}
