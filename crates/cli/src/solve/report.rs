//! The text outputs of `fpc solve`: `solution.json`, `shape.csv` and the
//! terminal summary.

use fpc::num::Num;
use fpc::plan::RefinementRecord;
use fpc::scene::{degrees, SceneFile, SceneSolution, SolutionRecord, Uncertainty};
use fpc::{Solution, Solved};
use serde::Serialize;

// ------------------------------------------------------------ solution.json

/// `solution.json`: the scene's record and how the file was made.
#[derive(Serialize)]
pub(super) struct SolutionFile<'a> {
    #[serde(flatten)]
    record: SolutionRecord<'a>,
    /// The command, fpc's version and the git commit.
    provenance: crate::provenance::Provenance,
}

/// The contents of `solution.json` for the solved scene.
pub(super) fn solution_file<'a>(
    stem: &'a str,
    file: &'a SceneFile,
    solved: &'a SceneSolution,
    uncertainty: Option<&'a Uncertainty>,
) -> SolutionFile<'a> {
    SolutionFile {
        record: SolutionRecord::new(stem, file, solved).with_uncertainty(uncertainty),
        provenance: crate::provenance::Provenance::now(),
    }
}

// ------------------------------------------------------------ shape.csv

/// `shape.csv`: the mid-plane samples, root to tip, in the finger frame
/// (`x_mm,z_mm`), and in a gripper scene in the gripper frame too
/// (`xg_mm,zg_mm`). Numbers in Rust's shortest round-trip form.
pub(super) fn shape_csv(solved: &SceneSolution) -> anyhow::Result<Vec<u8>> {
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    let points = &solved.solution().points;
    match solved {
        SceneSolution::Finger(_) => {
            w.write_record(["x_mm", "z_mm"])?;
            for p in points {
                w.write_record(p.map(|v| v.to_string()))?;
            }
        }
        SceneSolution::Gripper { gripper, .. } => {
            w.write_record(["x_mm", "z_mm", "xg_mm", "zg_mm"])?;
            for &p in points {
                let q = gripper.to_gripper(p);
                w.write_record([p[0], p[1], q[0], q[1]].map(|v| v.to_string()))?;
            }
        }
    }
    Ok(w.into_inner().map_err(|e| e.into_error())?)
}

// ------------------------------------------------------------ summary

/// The summary's error bars: 1 sigma by first-order propagation of the
/// scene's `[calibration]` covariance.
pub(super) fn uncertainty_lines(
    out: &mut impl std::io::Write,
    u: &Uncertainty,
) -> std::io::Result<()> {
    writeln!(
        out,
        "uncertainty    1 sigma, first order, from the [calibration] covariance of {}",
        u.parameters.join(", ")
    )?;
    if let (Some(t), Some(a)) = (u.tip_mm, u.end_angle_rad) {
        writeln!(
            out,
            "tip +- 1 sd    X +- {:.4} mm, Z +- {:.4} mm, end angle +- {:.2} deg",
            Num(t[0]),
            Num(t[1]),
            Num(a.to_degrees())
        )?;
    }
    if let Some(r) = u.radius_mm {
        writeln!(out, "radius +- 1 sd +- {:.3} mm (circle fit)", Num(r))?;
    }
    if let Some(why) = &u.radius_unavailable {
        writeln!(out, "radius bar     not available: {why}")?;
    }
    if let Some(why) = &u.unavailable {
        writeln!(out, "error bars     not available: {why}")?;
    }
    if let Some(d) = u.d_max_mm {
        writeln!(out, "d_max +- 1 sd  +- {:.3} mm", Num(d))?;
    }
    if let Some(g) = &u.grasp {
        writeln!(
            out,
            "forces +- 1 sd F +- {:.4} N, f +- {:.4} N, f_v +- {:.4} N",
            Num(g.normal_force_n),
            Num(g.friction_n),
            Num(g.lift_n)
        )?;
        writeln!(
            out,
            "geom. +- 1 sd  d +- {:.3} mm, tip gap +- {:.3} mm, h +- {:.3} mm",
            Num(g.size_mm),
            Num(g.tip_gap_mm),
            Num(g.height_mm)
        )?;
    }
    Ok(())
}

/// The terminal summary of a solved scene.
pub(super) fn summary(
    out: &mut impl std::io::Write,
    stem: &str,
    file: &SceneFile,
    solved: &SceneSolution,
) -> std::io::Result<()> {
    let sol: &Solution = solved.solution();
    let eps0 = file.actuator.pemc.eps0.unwrap_or(f64::NAN);
    match solved {
        SceneSolution::Finger(solved) => {
            let elements = solved.elements();
            let l = &file.load;
            writeln!(
                out,
                "scene          {stem}: finger, eps0 = {}, N = {elements}, P = {} kPa, tip force ({}, {}) N",
                Num(eps0),
                Num(l.pressure_kpa.unwrap_or(0.0)),
                Num(l.fx.unwrap_or(0.0)),
                Num(l.fz.unwrap_or(0.0))
            )?;
            writeln!(
                out,
                "tip            X = {:.4} mm, Z = {:.4} mm, end angle {:.2} deg",
                Num(sol.tip[0]),
                Num(sol.tip[1]),
                Num(sol.end_angle.to_degrees())
            )?;
            refinement_lines(out, solved)?;
            match sol.radius {
                Some(r) => writeln!(out, "radius (fit)   {:.3} mm", Num(r))?,
                None if sol.points.is_empty() => {}
                None => writeln!(out, "radius (fit)   none: the finger is straight")?,
            }
            stability_line(out, sol)?;
            validity_line(out, sol)?;
        }
        SceneSolution::Gripper { gripper, grasp } => {
            writeln!(
                out,
                "scene          {stem}: gripper, eps0 = {}, N = {}, a = {} deg, mu = {}",
                Num(eps0),
                solved.elements(),
                Num(degrees(gripper.mounting_angle())),
                Num(gripper.mu())
            )?;
            writeln!(
                out,
                "gripper        l0 = {:.3} mm, palm l = {:.3} mm, overlap g = {:.3} mm, d_max = {:.3} mm",
                Num(gripper.l0()),
                Num(gripper.palm()),
                Num(gripper.overlap()),
                Num(gripper.d_max())
            )?;
            if let Some(o) = grasp {
                let g = &o.grasp;
                writeln!(
                    out,
                    "grasp          {} at {} kPa, b = {:.2} deg",
                    o.spec.name(),
                    Num(g.pressure_kpa),
                    Num(g.beta.to_degrees())
                )?;
                writeln!(
                    out,
                    "forces         F = {:.4} N, f = {:.4} N, f_v = {:.4} N (per finger)",
                    Num(g.normal),
                    Num(g.friction),
                    Num(g.lift)
                )?;
                writeln!(
                    out,
                    "geometry       d = {:.3} mm, tip gap = {:.3} mm, h = {:.3} mm",
                    Num(g.size),
                    Num(g.tip_gap),
                    Num(g.height)
                )?;
                if let Some(s) = &o.sphere {
                    writeln!(
                        out,
                        "sphere         r = {:.3} mm, centre ({:.3}, {:.3}) mm",
                        Num(s.radius),
                        Num(s.center[0]),
                        Num(s.center[1])
                    )?;
                }
                match &o.invalid() {
                    None => writeln!(out, "valid          yes")?,
                    Some(i) => writeln!(out, "valid          NO: {i}")?,
                }
                writeln!(out, "verdict        {}", verdict_parts(&g.verdict))?;
            }
        }
    }
    let refinement = match solved {
        SceneSolution::Finger(s) => s.refinement.as_ref(),
        SceneSolution::Gripper { .. } => None,
    };
    solver_lines(out, sol, refinement)
}

/// `tip (extrap.)` and `tip accuracy`: a refinement's extrapolated tip
/// and how, and which tip its error estimate is of.
pub(crate) fn refinement_lines(
    out: &mut impl std::io::Write,
    solved: &Solved,
) -> std::io::Result<()> {
    if let Some(how) = solved.refinement.as_ref().and_then(|r| r.extrapolation()) {
        writeln!(
            out,
            "tip (extrap.)  X = {:.4} mm, Z = {:.4} mm ({})",
            Num(solved.tip()[0]),
            Num(solved.tip()[1]),
            how.describe()
        )?;
    }
    if let Some(e) = solved.estimated_tip_error_mm() {
        let of = if solved.is_extrapolated() {
            "the extrapolated tip".to_string()
        } else {
            format!("the finest level's tip, N = {}", solved.elements())
        };
        writeln!(out, "tip accuracy   estimated error {e:.2e} mm (of {of})")?;
    }
    Ok(())
}

/// `solver` and `steps`: the iterations, residual and where the
/// iterations went. With several refinement levels, the levels' together
/// (the finest level's final solve, from its own converged state, often
/// takes none) and the finest level's share.
pub(crate) fn solver_lines(
    out: &mut impl std::io::Write,
    sol: &Solution,
    refinement: Option<&RefinementRecord>,
) -> std::io::Result<()> {
    let system = if sol.report.coupled {
        "coupled system"
    } else {
        "decoupled elements"
    };
    let residual = sol.report.residual_norm;
    match refinement.filter(|r| r.levels.len() > 1) {
        Some(r) => {
            let finest = r.levels.last().map_or(0, |l| l.iterations);
            writeln!(
                out,
                "solver         {} iterations over {} levels ({finest} at the finest), relative residual {residual:.2e}, {system}",
                r.iterations(),
                r.levels.len(),
            )?;
            writeln!(out, "steps          {} (all levels)", r.steps())
        }
        None => {
            writeln!(
                out,
                "solver         {} iterations, relative residual {residual:.2e}, {system}",
                sol.report.iterations
            )?;
            writeln!(out, "steps          {}", sol.report.steps)
        }
    }
}

/// The verdict's four parts in one line: the rules, the findings, the
/// stability and the path.
fn verdict_parts(v: &fpc::gripper::Verdict) -> String {
    use fpc::gripper::Stability;
    let rules = match &v.rules {
        None => "rules hold".to_string(),
        Some(r) => format!("rule broken ({})", r.kind()),
    };
    let findings = match v.findings.len() {
        0 => "inside the model".to_string(),
        n => {
            let kinds = fpc::studies::validity_kinds(&v.findings);
            format!("{n} finding(s) outside the model ({})", kinds.join(", "))
        }
    };
    let stability = match v.stability {
        Stability::Stable => "stable".to_string(),
        Stability::Unstable { negative } => format!("unstable ({negative} negative)"),
        Stability::Unknown => "stability unknown".to_string(),
        Stability::NotJudged => "stability not judged".to_string(),
    };
    let path = match v.path.from {
        "rest" => format!("closed on from rest in {} step(s)", v.path.steps),
        _ => "continued from the previous grasp".to_string(),
    };
    format!("{rules}; {findings}; {stability}; {path}")
}

/// `stability` and the count of negative Hessian eigenvalues, when judged.
pub(crate) fn stability_line(out: &mut impl std::io::Write, sol: &Solution) -> std::io::Result<()> {
    if let Some(k) = sol.negative_eigenvalues {
        let verdict = if k == 0 { "stable" } else { "NOT stable" };
        writeln!(
            out,
            "stability      {k} negative Hessian eigenvalue(s) ({verdict})"
        )?;
    }
    Ok(())
}

/// `validity`: within the model's limits, or how many findings say not.
pub(crate) fn validity_line(out: &mut impl std::io::Write, sol: &Solution) -> std::io::Result<()> {
    let findings = sol.warnings.iter().filter(|w| w.is_validity()).count();
    if findings == 0 {
        writeln!(out, "validity       within the model's limits")
    } else {
        writeln!(
            out,
            "validity       OUTSIDE the model's limits: {findings} finding(s), see the warnings"
        )
    }
}
