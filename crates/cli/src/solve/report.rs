//! The text outputs of `fpc solve`: `solution.json`, `shape.csv` and the
//! terminal summary.

use fpc::scene::{warning_text, GraspOutcome, SceneFile, SceneSolution};
use fpc::{Coefficients, Gripper, Invalid, Solution, SolveReport, Warning};
use serde::Serialize;

// ------------------------------------------------------------ solution.json

/// `solution.json`: the finger's equilibrium under the keys of
/// `fpc finger --json`, the run's keys, every finding typed, and in a
/// gripper scene the gripper and its grasp.
#[derive(Serialize)]
pub(super) struct SolutionFile<'a> {
    /// The scene file's name without its extension.
    scene_name: &'a str,
    /// `finger`, `gripper` (no grasp asked) or `grasp`.
    kind: &'static str,
    /// The number of elements used.
    elements: usize,
    /// With `tip_tol_mm`: the estimated tip error (mm); null otherwise.
    tip_error_estimate_mm: Option<f64>,
    /// The finger's equilibrium: the grasp's, or the gripper's rest state.
    #[serde(flatten)]
    solution: SolutionKeys<'a>,
    /// True when no finding puts the answer outside the model
    /// ([`Warning::is_validity`]) and the grasp, if one was asked, breaks
    /// no rule.
    validity: bool,
    /// Every warning once ([`SceneSolution::warnings`]), as
    /// `{kind, message, element?, value?, limit?}`.
    warnings: Vec<Warning>,
    /// The same warnings as text naming the scene's keys (as on stderr).
    warning_messages: Vec<String>,
    /// The scene with every default written out.
    scene: &'a SceneFile,
    /// A gripper scene's keys (absent in a finger scene).
    #[serde(flatten)]
    gripper: Option<GripperKeys<'a>>,
    /// The command, fpc's version and the git commit.
    provenance: crate::provenance::Provenance,
}

/// The keys of a [`Solution`] but its `warnings` (the scene's
/// [`SolutionFile::warnings`] hold them with the gripper's and the
/// grasp's). A test keeps the two key lists in step.
#[derive(Serialize)]
pub(super) struct SolutionKeys<'a> {
    /// Tip (X, Z) in the finger frame (mm).
    tip_mm: &'a [f64; 2],
    /// Tip tangent angle from the X axis (rad).
    end_angle_rad: f64,
    /// Least-squares circle radius (mm); null when straight or not sampled.
    radius_mm: Option<f64>,
    /// Total potential energy (N mm).
    energy_nmm: f64,
    /// Negative Hessian eigenvalues; null when not computed.
    negative_eigenvalues: Option<usize>,
    /// `negative_eigenvalues == 0`; null when not computed.
    stable: Option<bool>,
    /// The element unknowns, one array per element.
    coefficients: &'a Coefficients,
    /// Mid-plane samples, root to tip, in the finger frame (mm).
    points_mm: &'a [[f64; 2]],
    /// Undeformed element lengths, root to tip (mm).
    element_lengths_mm: &'a [f64],
    /// How the solve went.
    report: &'a SolveReport,
}

impl<'a> SolutionKeys<'a> {
    pub(super) fn of(s: &'a Solution) -> SolutionKeys<'a> {
        SolutionKeys {
            tip_mm: &s.tip,
            end_angle_rad: s.end_angle,
            radius_mm: s.radius,
            energy_nmm: s.energy,
            negative_eigenvalues: s.negative_eigenvalues,
            stable: s.stable,
            coefficients: &s.coefficients,
            points_mm: &s.points,
            element_lengths_mm: &s.element_lengths,
            report: &s.report,
        }
    }
}

/// The keys only a gripper scene has.
#[derive(Serialize)]
struct GripperKeys<'a> {
    /// The design and the geometry its rest state fixes.
    gripper: GripperJson<'a>,
    /// The grasp; null when none was asked.
    grasp: Option<GraspJson<'a>>,
    /// `points_mm` in the gripper frame (mm; Zg down).
    points_gripper_mm: Vec<[f64; 2]>,
}

/// The gripper: the library's keys (`params`, `model`, `elements`,
/// `l0_mm`, `palm_mm`, `overlap_mm`, `d_min_mm`, `d_max_mm`, `r_max_mm`,
/// `tip_is_innermost`, `rest_tip_gripper_mm`, `warnings`) and three of its
/// design's at the top.
#[derive(Serialize)]
struct GripperJson<'a> {
    /// The mounting angle `a` (deg).
    mounting_angle_deg: f64,
    /// Friction coefficient between object and tip.
    mu: f64,
    /// Number of fingers.
    fingers: usize,
    #[serde(flatten)]
    gripper: &'a Gripper,
}

/// A solved grasp, per finger.
#[derive(Serialize)]
struct GraspJson<'a> {
    /// `cuboid`, `size` or `sphere`.
    kind: &'static str,
    /// Channel pressure (kPa).
    pressure_kpa: f64,
    /// Grasping angle `b` (deg).
    beta_deg: f64,
    /// Normal force `F` on the finger (N).
    normal_force_n: f64,
    /// Friction `f` on the finger (N).
    friction_n: f64,
    /// The friction cone's limit `mu F` (N).
    friction_limit_n: f64,
    /// Lifting force `f_v` (N).
    lift_n: f64,
    /// Grasping size `d` (mm).
    size_mm: f64,
    /// Gap between the tips (mm).
    tip_gap_mm: f64,
    /// Finger height `h`, the tip's Zg (mm).
    height_mm: f64,
    /// Tip in the gripper frame (mm).
    tip_gripper_mm: [f64; 2],
    /// The contact load on the tip, (Fx, Fz) in the finger frame (N).
    tip_load_finger_n: [f64; 2],
    /// True when the grasp breaks no rule.
    valid: bool,
    /// The first rule broken, `{kind, message}`; null when valid.
    invalid: Option<&'a Invalid>,
    /// A sphere's radius (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    sphere_radius_mm: Option<f64>,
    /// A sphere's centre in the gripper frame (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    sphere_center_gripper_mm: Option<[f64; 2]>,
}

/// The contents of `solution.json` for the solved scene.
pub(super) fn solution_file<'a>(
    stem: &'a str,
    file: &'a SceneFile,
    solved: &'a SceneSolution,
) -> SolutionFile<'a> {
    let warnings = solved.warnings();
    let (kind, tip_error_estimate_mm, gripper) = match solved {
        SceneSolution::Finger {
            tip_error_estimate_mm,
            ..
        } => ("finger", *tip_error_estimate_mm, None),
        SceneSolution::Gripper { gripper, grasp } => (
            if grasp.is_some() { "grasp" } else { "gripper" },
            None,
            Some(gripper_keys(gripper, grasp.as_deref(), solved.solution())),
        ),
    };
    SolutionFile {
        scene_name: stem,
        kind,
        elements: solved.elements(),
        tip_error_estimate_mm,
        solution: SolutionKeys::of(solved.solution()),
        validity: is_valid(solved, &warnings),
        warning_messages: warnings.iter().map(warning_text).collect(),
        warnings,
        scene: file,
        gripper,
        provenance: crate::provenance::Provenance::now(),
    }
}

/// True when no warning is a validity finding and the grasp, if any, is
/// valid.
fn is_valid(solved: &SceneSolution, warnings: &[Warning]) -> bool {
    let grasp_valid = match solved {
        SceneSolution::Gripper { grasp: Some(g), .. } => g.is_valid(),
        _ => true,
    };
    grasp_valid && !warnings.iter().any(Warning::is_validity)
}

fn gripper_keys<'a>(
    gripper: &'a Gripper,
    grasp: Option<&'a GraspOutcome>,
    sol: &Solution,
) -> GripperKeys<'a> {
    GripperKeys {
        gripper: GripperJson {
            mounting_angle_deg: degrees(gripper.mounting_angle()),
            mu: gripper.mu(),
            fingers: gripper.params().fingers,
            gripper,
        },
        grasp: grasp.map(|o| grasp_json(gripper, o)),
        points_gripper_mm: sol.points.iter().map(|&p| gripper.to_gripper(p)).collect(),
    }
}

fn grasp_json<'a>(gripper: &Gripper, o: &'a GraspOutcome) -> GraspJson<'a> {
    let g = &o.grasp;
    GraspJson {
        kind: o.spec.name(),
        pressure_kpa: g.pressure_kpa,
        beta_deg: degrees(g.beta),
        normal_force_n: g.normal,
        friction_n: g.friction,
        friction_limit_n: gripper.mu() * g.normal,
        lift_n: g.lift,
        size_mm: g.size,
        tip_gap_mm: g.tip_gap,
        height_mm: g.height,
        tip_gripper_mm: g.tip,
        tip_load_finger_n: [g.load.fx, g.load.fz],
        valid: o.is_valid(),
        invalid: o.invalid.as_ref(),
        sphere_radius_mm: o.sphere.map(|s| s.radius),
        sphere_center_gripper_mm: o.sphere.map(|s| s.center),
    }
}

/// Radians in degrees, rounded to 1e-9 deg (60 deg prints as 60).
pub(super) fn degrees(rad: f64) -> f64 {
    (rad.to_degrees() * 1e9).round() / 1e9
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
        SceneSolution::Finger { .. } => {
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
        SceneSolution::Finger {
            elements,
            tip_error_estimate_mm,
            ..
        } => {
            let l = &file.load;
            writeln!(
                out,
                "scene          {stem}: finger, eps0 = {eps0}, N = {elements}, P = {} kPa, tip force ({}, {}) N",
                l.pressure_kpa.unwrap_or(0.0),
                l.fx.unwrap_or(0.0),
                l.fz.unwrap_or(0.0)
            )?;
            writeln!(
                out,
                "tip            X = {:.4} mm, Z = {:.4} mm, end angle {:.2} deg",
                sol.tip[0],
                sol.tip[1],
                sol.end_angle.to_degrees()
            )?;
            if let Some(e) = tip_error_estimate_mm {
                writeln!(
                    out,
                    "tip accuracy   estimated error {e:.2e} mm at N = {elements}"
                )?;
            }
            match sol.radius {
                Some(r) => writeln!(out, "radius (fit)   {r:.3} mm")?,
                None if sol.points.is_empty() => {}
                None => writeln!(out, "radius (fit)   none: the finger is straight")?,
            }
        }
        SceneSolution::Gripper { gripper, grasp } => {
            writeln!(
                out,
                "scene          {stem}: gripper, eps0 = {eps0}, N = {}, a = {} deg, mu = {}",
                solved.elements(),
                degrees(gripper.mounting_angle()),
                gripper.mu()
            )?;
            writeln!(
                out,
                "gripper        l0 = {:.3} mm, palm l = {:.3} mm, overlap g = {:.3} mm, d_max = {:.3} mm",
                gripper.l0(),
                gripper.palm(),
                gripper.overlap(),
                gripper.d_max()
            )?;
            if let Some(o) = grasp {
                let g = &o.grasp;
                writeln!(
                    out,
                    "grasp          {} at {} kPa, b = {:.2} deg",
                    o.spec.name(),
                    g.pressure_kpa,
                    g.beta.to_degrees()
                )?;
                writeln!(
                    out,
                    "forces         F = {:.4} N, f = {:.4} N, f_v = {:.4} N (per finger)",
                    g.normal, g.friction, g.lift
                )?;
                writeln!(
                    out,
                    "geometry       d = {:.3} mm, tip gap = {:.3} mm, h = {:.3} mm",
                    g.size, g.tip_gap, g.height
                )?;
                if let Some(s) = &o.sphere {
                    writeln!(
                        out,
                        "sphere         r = {:.3} mm, centre ({:.3}, {:.3}) mm",
                        s.radius, s.center[0], s.center[1]
                    )?;
                }
                match &o.invalid {
                    None => writeln!(out, "valid          yes")?,
                    Some(i) => writeln!(out, "valid          NO: {i}")?,
                }
            }
        }
    }
    writeln!(
        out,
        "solver         {} iterations, relative residual {:.2e}",
        sol.report.iterations, sol.report.residual_norm
    )?;
    Ok(())
}
