//! `fpc finger`: solve one finger of the default actuator for a scene given by flags.

use std::io::Write;

use fpc::field::{PemcKey, RefinementKey};
use fpc::num::Num;
use fpc::plan::{PartitionKind, RefinementRecord};
use fpc::{
    Actuator, Field, InputError, Load, ModelId, Plan, PlannedFinger, Solution, SolveError,
    SolveOptions, Solved,
};

/// `--elements`: a count, or `auto`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Elements {
    /// N equal elements.
    Equal(usize),
    /// The automatic partition ([`fpc::Plan::Auto`]).
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
    /// Number of elements N, or `auto`: boundaries on the material
    /// changes, refined until every element is within the slope limit
    /// (at most 1000 elements and 64 rounds of splits, and no further
    /// once a split meets a fold or does not solve, with a note saying
    /// so; then the findings stay on the answer)
    /// (with --tip-tol-mm: material partitions with extrapolation).
    /// With `--partition material`, N sets the longest piece to lx / N.
    /// [default: 8]
    #[arg(long, value_parser = parse_elements, allow_hyphen_values = true)]
    elements: Option<Elements>,
    /// Where element boundaries go: `equal` elements, or `material`
    /// (boundaries on the rib edges and the channel end, second-order
    /// convergence with a small first-order term under a tip load).
    #[arg(long, default_value = "equal")]
    partition: String,
    /// Solve on this many partitions, each halving the elements of the one
    /// before and starting from it (nested iteration); the answer is the
    /// finest level's, with an error estimate (from three levels on equal
    /// elements).
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    levels: usize,
    /// Extrapolate the tip: from two levels removing the h^2 term, from
    /// three or more removing h and h^2 (needs `--partition material` and
    /// `--levels` of at least 2).
    #[arg(long)]
    extrapolate: bool,
    /// The element model (`fpc models` lists them).
    #[arg(long, default_value_t = ModelId::default().name().to_string())]
    model: String,
    /// Leave out the ribs inside the channel.
    #[arg(long = "no-ribs")]
    no_ribs: bool,
    /// Pressure factor kappa = 1/(gamma - 1), in (0, 100] (a gas's gamma of
    /// at least 1.01).
    #[arg(long, default_value_t = 2.5, allow_hyphen_values = true)]
    kappa: f64,
    /// Refine until the estimated tip error is at most this many
    /// millimetres: with --elements N, equal elements doubled from N (three
    /// levels at least); otherwise material partitions from 27 + 54
    /// elements with extrapolation (docs/performance.md).
    #[arg(long = "tip-tol-mm", allow_hyphen_values = true)]
    tip_tol_mm: Option<f64>,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    json: bool,
}

/// The flag that sets a field of the library, for the fields `fpc
/// finger` sets (values in the flag's unit once in scene terms: kPa).
fn flag(field: &Field) -> Option<&'static str> {
    Some(match field {
        Field::LoadPressure => "--pressure-kpa",
        Field::LoadKappa => "--kappa",
        Field::LoadFx => "--fx",
        Field::LoadFz => "--fz",
        Field::Pemc(PemcKey::Eps0) => "--eps0",
        Field::PartitionN | Field::PartitionMaxLength | Field::Refinement(RefinementKey::Start) => {
            "--elements"
        }
        Field::TipTolMm => "--tip-tol-mm",
        Field::Refinement(RefinementKey::Levels) => "--levels",
        Field::Refinement(RefinementKey::Extrapolate) => "--extrapolate",
        _ => return None,
    })
}

/// An error of the library in the terms the user wrote: the flag, its
/// value in the flag's unit.
fn in_flag_terms(e: anyhow::Error) -> anyhow::Error {
    let in_flags = |i: InputError| match flag(i.field()) {
        Some(f) => fpc::scene::scene_input(i).renamed(fpc::Field::key(f), |v| v),
        None => fpc::scene::scene_input(i),
    };
    let e = match e.downcast::<InputError>() {
        Ok(i) => return in_flags(i).into(),
        Err(e) => e,
    };
    match e.downcast::<SolveError>() {
        Ok(SolveError::Input(i)) => SolveError::Input(in_flags(i)).into(),
        Ok(s) => fpc::scene::scene_solve(s).into(),
        Err(e) => e,
    }
}

/// A warning in the terms the user wrote: the scene's words
/// ([`fpc::scene::warning_text`]), a note on the prestrain naming `--eps0`.
fn flag_text(w: &fpc::Warning) -> String {
    let text = fpc::scene::warning_text(w);
    match w {
        fpc::Warning::Eps0OutsideFit { .. } | fpc::Warning::SofteningPrestressLaw { .. } => {
            text.replacen("actuator.pemc.eps0", "--eps0", 1)
        }
        _ => text,
    }
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    solve_finger(args).map_err(in_flag_terms)
}

fn solve_finger(args: &Args) -> anyhow::Result<()> {
    let model = ModelId::parse(fpc::Field::key("--model"), &args.model)?;
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
    let input = fpc::finger::input_warnings(model, &act);
    for w in &input {
        crate::report::warning(&flag_text(w));
    }
    let partition = PartitionKind::parse(fpc::Field::key("--partition"), &args.partition)?;
    let plan = match (args.tip_tol_mm, args.elements) {
        (Some(tip_tol_mm), elements) => {
            let start = match elements {
                Some(Elements::Equal(n)) => Some(n),
                None | Some(Elements::Auto) => None,
            };
            if args.levels != 1 || args.extrapolate || partition != PartitionKind::Equal {
                return Err(InputError::Inconsistent {
                    field: fpc::Field::key("--tip-tol-mm"),
                    rule: "chooses the partition, levels and extrapolation itself: leave out --partition, --levels and --extrapolate".into(),
                }
                .into());
            }
            Plan::TipTolerance { tip_tol_mm, start }
        }
        (None, Some(Elements::Auto)) => {
            if args.levels != 1 || args.extrapolate {
                return Err(InputError::Inconsistent {
                    field: fpc::Field::key("--elements"),
                    rule: "auto chooses the partition itself: leave out --levels and --extrapolate"
                        .into(),
                }
                .into());
            }
            Plan::Auto
        }
        (None, elements) => {
            let n = match elements {
                Some(Elements::Equal(n)) => n,
                _ => DEFAULT_ELEMENTS,
            };
            if args.levels == 1 && !args.extrapolate && partition == PartitionKind::Equal {
                Plan::Equal(n)
            } else {
                Plan::Levels {
                    partition,
                    start: n,
                    levels: args.levels,
                    extrapolate: args.extrapolate,
                }
            }
        }
    };
    let solved = PlannedFinger::builder(&act)
        .model(model)
        .ribs(ribs)
        .plan(plan)
        .build()?
        .solve(&load, &opts)?;
    let sol = &solved.solution;
    // the solution's own findings and notes (the input's were printed
    // above), a fold of the automatic partition among them
    crate::report::warnings(
        sol.warnings.iter().filter(|w| !input.contains(w)),
        |w| w.to_string(),
        "the --json output",
    );
    let mut out = crate::output::stdout();
    if args.json {
        let v = Json {
            model: model.name(),
            elements: sol.element_lengths.len(),
            tip_error_estimate_mm: solved.estimated_tip_error_mm(),
            refinement: solved.refinement.as_ref(),
            solution: sol,
            validity: solved.is_valid(),
            provenance: crate::provenance::Provenance::now(),
        };
        writeln!(out, "{}", serde_json::to_string(&v)?)?;
    } else {
        summary(&mut out, args, model, &solved)?;
    }
    Ok(())
}

/// The default `--elements`.
const DEFAULT_ELEMENTS: usize = 8;

/// `fpc finger --json`: the solution's keys (README) and the run's.
#[derive(serde::Serialize)]
struct Json<'a> {
    model: &'static str,
    elements: usize,
    tip_error_estimate_mm: Option<f64>,
    /// With a refinement: its levels and best tip (extrapolated or the
    /// finest level's); the solution below is the finest level's.
    #[serde(skip_serializing_if = "Option::is_none")]
    refinement: Option<&'a RefinementRecord>,
    #[serde(flatten)]
    solution: &'a Solution,
    /// The one verdict, as `fpc solve`'s: no finding puts the answer
    /// outside the model.
    validity: bool,
    /// The command, fpc's version and the git commit.
    provenance: crate::provenance::Provenance,
}

fn summary(
    out: &mut impl Write,
    args: &Args,
    model: ModelId,
    solved: &Solved,
) -> std::io::Result<()> {
    let sol = &solved.solution;
    let elements = sol.element_lengths.len();
    writeln!(
        out,
        "finger: eps0 = {}, model {model}, N = {}{}, ribs {}, P = {} kPa, tip force ({}, {}) N",
        Num(args.eps0),
        elements,
        if args.elements == Some(Elements::Auto) && args.tip_tol_mm.is_none() {
            " (auto)"
        } else {
            ""
        },
        if args.no_ribs { "off" } else { "on" },
        Num(args.pressure_kpa),
        Num(args.fx),
        Num(args.fz)
    )?;
    if let Some(r) = &solved.refinement {
        let levels: Vec<usize> = r.levels.iter().map(|l| l.elements).collect();
        writeln!(
            out,
            "refinement     {}: levels of {levels:?} elements",
            r.plan.label()
        )?;
    }
    writeln!(
        out,
        "tip            X = {:.4} mm, Z = {:.4} mm",
        Num(sol.tip[0]),
        Num(sol.tip[1])
    )?;
    crate::solve::refinement_lines(out, solved)?;
    writeln!(
        out,
        "end angle      {:.5} rad ({:.2} deg)",
        Num(sol.end_angle),
        Num(sol.end_angle.to_degrees())
    )?;
    match sol.radius {
        Some(r) => writeln!(out, "radius (fit)   {:.3} mm", Num(r))?,
        None => writeln!(out, "radius (fit)   none: the finger is straight")?,
    }
    writeln!(out, "energy         {:.6} N mm", Num(sol.energy))?;
    crate::solve::stability_line(out, sol)?;
    crate::solve::solver_lines(out, sol, solved.refinement.as_ref())?;
    crate::solve::validity_line(out, sol)
}
