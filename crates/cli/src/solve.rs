//! `fpc solve SCENE.toml`: solve the finger, or the gripper grasp, that a
//! scene file describes, and write `solution.json`, `shape.csv` and
//! `shape.svg` into the output directory (default `./<stem>-out/`).

use std::fs;
use std::io::{Read as _, Write as _};
use std::path::{Path, PathBuf};

use anyhow::Context;
use fpc::scene::{warning_text, GraspOutcome, GraspSpec, SceneFile, SceneSolution};
use fpc::{Coefficients, Gripper, Invalid, Solution, SolveReport, Warning};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use serde::Serialize;

/// Flags of `fpc solve`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scene file (TOML; see scenes/ and the README for the keys).
    scene: PathBuf,
    /// Output directory, created if missing. Default: `<stem>-out` in the
    /// current directory, where `<stem>` is the scene file's name without
    /// its extension.
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let shown = args.scene.display().to_string();
    let text = read_scene(&args.scene, &shown)?;
    // a syntax error is rejected input, its position as file:line:col
    let file =
        SceneFile::parse(&text).map_err(|e| crate::status::rejected(format!("{shown}:{e}")))?;
    let scene = file.resolve().with_context(|| shown.clone())?;
    // notes on the input first: they hold even when the solve fails
    for w in scene.warnings() {
        crate::report::warning(&warning_text(w));
    }
    let solved = scene.solve().with_context(|| shown.clone())?;
    for w in solved
        .warnings()
        .iter()
        .filter(|w| !scene.warnings().contains(w))
    {
        crate::report::warning(&warning_text(w));
    }

    let stem = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{stem}-out")));
    // every file is made before any is written
    let json = serde_json::to_string_pretty(&solution_file(&stem, scene.file(), &solved))? + "\n";
    let csv = shape_csv(&solved)?;
    let svg = shape_svg(&stem, &solved)?;
    crate::output::prepare_dir(&out)?;
    write_atomic(&out, "solution.json", json.as_bytes())?;
    write_atomic(&out, "shape.csv", &csv)?;
    write_atomic(&out, "shape.svg", svg.as_bytes())?;

    let mut stdout = crate::output::stdout();
    summary(&mut stdout, &stem, scene.file(), &solved)?;
    writeln!(
        stdout,
        "wrote          {}",
        ["solution.json", "shape.csv", "shape.svg"]
            .map(|f| out.join(f).display().to_string())
            .join(", ")
    )?;
    Ok(())
}

use crate::output::write_atomic;

/// The largest scene file `fpc solve` reads: 4 MiB. The example scenes are
/// a few hundred bytes; the limit keeps a wrong path (a disk image, a
/// device, an endless pipe) from being read into memory whole.
pub const MAX_SCENE_BYTES: u64 = 4 * 1024 * 1024;

/// The text of the scene file at `path` (`shown` in messages), read
/// through a bounded reader. Missing, unreadable, a directory, larger than
/// [`MAX_SCENE_BYTES`] or not UTF-8: rejected input, one line naming the
/// path.
pub(crate) fn read_scene(path: &Path, shown: &str) -> anyhow::Result<String> {
    let cannot = |why: String| crate::status::rejected(format!("cannot read {shown}: {why}"));
    let file = fs::File::open(path).map_err(|e| cannot(e.to_string()))?;
    let mut bytes = Vec::new();
    file.take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| cannot(e.to_string()))?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(cannot(format!(
            "larger than {} MiB ({MAX_SCENE_BYTES} bytes), the limit for a scene file",
            MAX_SCENE_BYTES >> 20
        )));
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        cannot(format!("not UTF-8 text (invalid byte at offset {at})"))
    })
}

// ------------------------------------------------------------ solution.json

/// `solution.json`: the finger's equilibrium under the keys of
/// `fpc finger --json`, the run's keys, every finding typed, and in a
/// gripper scene the gripper and its grasp.
#[derive(Serialize)]
struct SolutionFile<'a> {
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
struct SolutionKeys<'a> {
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
    fn of(s: &'a Solution) -> SolutionKeys<'a> {
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
fn solution_file<'a>(
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
fn degrees(rad: f64) -> f64 {
    (rad.to_degrees() * 1e9).round() / 1e9
}

// ------------------------------------------------------------ shape.csv

/// `shape.csv`: the mid-plane samples, root to tip, in the finger frame
/// (`x_mm,z_mm`), and in a gripper scene in the gripper frame too
/// (`xg_mm,zg_mm`). Numbers in Rust's shortest round-trip form.
fn shape_csv(solved: &SceneSolution) -> anyhow::Result<Vec<u8>> {
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

// ------------------------------------------------------------ shape.svg

/// How an item of the drawing looks; the order is the legend's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Look {
    /// The finger's mid-plane.
    Finger,
    /// The opposite finger: the mid-plane mirrored about the gripper axis.
    Mirror,
    /// The fingers at rest, or a lone finger's straight X axis (dashed).
    Rest,
    /// The palm, Zg = 0.
    Palm,
    /// The gripper axis, Xg = 0 (dotted).
    Axis,
    /// The held object's section (filled).
    Object,
    /// The object's surface at the contacts (a size grasp).
    Contact,
    /// The finger's root (a dot).
    Root,
    /// The finger's tip (a dot).
    Tip,
}

const BLUE: RGBColor = RGBColor(31, 95, 191);
const ORANGE: RGBColor = RGBColor(176, 106, 0);
const RED: RGBColor = RGBColor(192, 57, 43);
const GREY: RGBColor = RGBColor(120, 120, 120);
const DARK: RGBColor = RGBColor(51, 51, 51);

impl Look {
    /// The stroke (or, for dots, the fill).
    fn style(self) -> ShapeStyle {
        match self {
            Look::Finger => BLUE.stroke_width(2),
            Look::Mirror => BLUE.mix(0.35).stroke_width(2),
            Look::Rest => GREY.stroke_width(1),
            Look::Palm => DARK.stroke_width(5),
            Look::Axis => GREY.mix(0.8).stroke_width(1),
            Look::Object => ORANGE.stroke_width(1),
            Look::Contact => ORANGE.stroke_width(2),
            Look::Root => DARK.filled(),
            Look::Tip => RED.filled(),
        }
    }

    /// Dash and gap lengths (px) of a dashed line.
    fn dashes(self) -> Option<(u32, u32)> {
        match self {
            Look::Rest => Some((6, 4)),
            Look::Axis => Some((2, 4)),
            _ => None,
        }
    }

    fn is_dot(self) -> bool {
        matches!(self, Look::Root | Look::Tip)
    }
}

/// One item: a line, a filled outline ([`Look::Object`]) or a dot, in
/// plot coordinates (mm, y up).
struct Item {
    look: Look,
    /// Its legend entry; empty for none.
    label: &'static str,
    points: Vec<(f64, f64)>,
}

/// The largest coordinate drawn (mm): a point farther out (1 km) is left
/// out rather than stretching the axes beyond use.
const MAX_COORD_MM: f64 = 1e6;

/// A point that can be drawn: finite and within [`MAX_COORD_MM`].
fn drawable(p: [f64; 2]) -> Option<(f64, f64)> {
    p.iter()
        .all(|v| v.is_finite() && v.abs() <= MAX_COORD_MM)
        .then_some((p[0], p[1]))
}

/// A drawing in one frame, before rendering.
struct Plot {
    /// The first line, above the plot.
    title: String,
    x_desc: &'static str,
    y_desc: &'static str,
    /// The frame's vertical axis points down: the plot's y is its
    /// negative, and the ticks show the frame's values.
    y_down: bool,
    items: Vec<Item>,
    /// Lines under the plot (wrapped to its width when drawn).
    caption: Vec<String>,
}

impl Plot {
    fn new(title: String, x_desc: &'static str, y_desc: &'static str, y_down: bool) -> Plot {
        Plot {
            title,
            x_desc,
            y_desc,
            y_down,
            items: Vec::new(),
            caption: Vec::new(),
        }
    }

    /// Adds an item through the drawable ones of `points`, given in the
    /// frame's coordinates; a line needs two, a dot one.
    fn add(&mut self, look: Look, label: &'static str, points: impl IntoIterator<Item = [f64; 2]>) {
        let flip = if self.y_down { -1.0 } else { 1.0 };
        let points: Vec<(f64, f64)> = points
            .into_iter()
            .filter_map(|p| drawable([p[0], flip * p[1]]))
            .collect();
        if points.len() >= if look.is_dot() { 1 } else { 2 } {
            self.items.push(Item {
                look,
                label,
                points,
            });
        }
    }

    /// The smallest box around every item and the origin (the root, or
    /// the palm's centre), with a margin and at least 10 mm each way.
    fn extent(&self) -> ([f64; 2], [f64; 2]) {
        let (mut lo, mut hi) = ([0.0_f64; 2], [0.0_f64; 2]);
        for &(x, y) in self.items.iter().flat_map(|i| &i.points) {
            lo = [lo[0].min(x), lo[1].min(y)];
            hi = [hi[0].max(x), hi[1].max(y)];
        }
        let pad = (0.06 * (hi[0] - lo[0]).max(hi[1] - lo[1])).max(4.0);
        for k in 0..2 {
            let grow = (0.5 * (10.0 - (hi[k] - lo[k]))).max(0.0) + pad;
            lo[k] -= grow;
            hi[k] += grow;
        }
        (lo, hi)
    }
}

/// `shape.svg`: the solved shape in its frame, with axes in mm at an equal
/// aspect, a legend and a caption.
fn shape_svg(stem: &str, solved: &SceneSolution) -> anyhow::Result<String> {
    let stem = crate::report::sanitize(stem);
    let warnings = solved.warnings();
    let plot = match solved {
        SceneSolution::Finger { solution, .. } => finger_plot(&stem, solution, &warnings),
        SceneSolution::Gripper { gripper, grasp } => gripper_plot(
            &stem,
            gripper,
            grasp.as_deref(),
            solved.solution(),
            &warnings,
        ),
    };
    render(&plot)
}

/// A finger scene in the finger frame: X right, Z up, root at the origin.
fn finger_plot(stem: &str, sol: &Solution, warnings: &[Warning]) -> Plot {
    let mut p = Plot::new(
        format!("{stem}: the finger in its own frame (X right, Z up)"),
        "X (mm)",
        "Z (mm)",
        false,
    );
    let length: f64 = sol.element_lengths.iter().sum();
    p.add(
        Look::Rest,
        "the finger's X axis (straight, unstrained)",
        [[0.0, 0.0], [length.max(10.0), 0.0]],
    );
    p.add(Look::Finger, "finger mid-plane", sol.points.iter().copied());
    p.add(Look::Root, "root (clamped)", [[0.0, 0.0]]);
    p.add(Look::Tip, "tip", [sol.tip]);
    p.caption.push(format!(
        "tip X = {} mm, Z = {} mm, end angle {} deg",
        num(sol.tip[0], 3),
        num(sol.tip[1], 3),
        num(sol.end_angle.to_degrees(), 2)
    ));
    if sol.points.is_empty() {
        p.caption
            .push("shape not sampled (solve.shape = false): only the tip is drawn".into());
    }
    p.caption.extend(findings(warnings));
    p
}

/// A gripper scene in the gripper frame: Xg right, Zg down, the palm's
/// centre at the origin; the opposite finger mirrored about Xg = 0.
fn gripper_plot(
    stem: &str,
    gripper: &Gripper,
    grasp: Option<&GraspOutcome>,
    sol: &Solution,
    warnings: &[Warning],
) -> Plot {
    let mut p = Plot::new(
        format!("{stem}: the gripper frame (Xg right, Zg down)"),
        "Xg (mm)",
        "Zg (mm, pointing down)",
        true,
    );
    let mirror = |q: &[f64; 2]| [-q[0], q[1]];
    let finger: Vec<[f64; 2]> = sol.points.iter().map(|&q| gripper.to_gripper(q)).collect();
    let rest = gripper.rest_shape();
    let depth = finger
        .iter()
        .chain(&rest)
        .map(|q| q[1])
        .filter(|z| z.is_finite())
        .fold(0.0_f64, f64::max);
    p.add(
        Look::Axis,
        "gripper axis (Xg = 0)",
        [[0.0, -5.0], [0.0, depth + 10.0]],
    );
    p.add(
        Look::Rest,
        "fingers at rest (P = 0, unloaded)",
        rest.iter().copied(),
    );
    p.add(Look::Rest, "", rest.iter().map(mirror));
    if let Some(o) = grasp {
        draw_object(&mut p, o, gripper);
    }
    p.add(
        Look::Mirror,
        "opposite finger (mirrored)",
        finger.iter().map(mirror),
    );
    p.add(Look::Finger, "finger mid-plane", finger.iter().copied());
    let half = 0.5 * gripper.palm() + 5.0;
    p.add(Look::Palm, "palm (Zg = 0)", [[-half, 0.0], [half, 0.0]]);
    p.add(Look::Tip, "tip", [gripper.to_gripper(sol.tip)]);
    p.caption.extend(gripper_caption(gripper, sol));
    if let Some(o) = grasp {
        p.caption.extend(grasp_caption(o));
    }
    p.caption.extend(findings(warnings));
    p
}

/// The object of a grasp, in the gripper frame.
fn draw_object(p: &mut Plot, o: &GraspOutcome, gripper: &Gripper) {
    let tip = o.grasp.tip;
    match o.spec {
        GraspSpec::Cuboid { .. } => {
            // the faces the tips touch, at Xg = +-tip Xg; drawn as a
            // square centred on the tips' height
            let h = tip[0].abs().max(1.0);
            let corners = [[-h, -h], [h, -h], [h, h], [-h, h], [-h, -h]];
            p.add(
                Look::Object,
                "cuboid (its faces at the tips)",
                corners.map(|c| [c[0], tip[1] + c[1]]),
            );
        }
        GraspSpec::Size { .. } => {
            // the object's surface at the contact: through the tip along
            // t = (-sin b, cos b), and its mirror
            let (s, c) = o.grasp.beta.sin_cos();
            let l = 0.15 * gripper.length();
            let seg = [
                [tip[0] + s * l, tip[1] - c * l],
                [tip[0] - s * l, tip[1] + c * l],
            ];
            p.add(Look::Contact, "object surface at the contacts", seg);
            p.add(Look::Contact, "", seg.map(|q| [-q[0], q[1]]));
        }
        GraspSpec::Sphere { .. } => {
            if let Some(s) = o.sphere.filter(|s| s.radius > 0.0) {
                let circle = (0..=CIRCLE_SEGMENTS).map(|k| {
                    let t = std::f64::consts::TAU * f64::from(k) / f64::from(CIRCLE_SEGMENTS);
                    [
                        s.center[0] + s.radius * t.cos(),
                        s.center[1] + s.radius * t.sin(),
                    ]
                });
                p.add(Look::Object, "sphere", circle);
            }
        }
    }
}

/// Chords of a drawn sphere.
const CIRCLE_SEGMENTS: u32 = 120;

/// The tip in both frames and the gripper's geometry.
fn gripper_caption(gripper: &Gripper, sol: &Solution) -> [String; 2] {
    let tip = gripper.to_gripper(sol.tip);
    [
        format!(
            "tip Xg = {} mm, Zg = {} mm (finger frame X = {} mm, Z = {} mm), end angle {} deg",
            num(tip[0], 3),
            num(tip[1], 3),
            num(sol.tip[0], 3),
            num(sol.tip[1], 3),
            num(sol.end_angle.to_degrees(), 2)
        ),
        format!(
            "a = {} deg, mu = {}, l0 = {} mm, palm l = {} mm, overlap g = {} mm, d_max = {} mm",
            num(gripper.mounting_angle().to_degrees(), 2),
            num(gripper.mu(), 3),
            num(gripper.l0(), 3),
            num(gripper.palm(), 3),
            num(gripper.overlap(), 3),
            num(gripper.d_max(), 3)
        ),
    ]
}

/// The grasp's load, measures and verdict.
fn grasp_caption(o: &GraspOutcome) -> Vec<String> {
    let g = &o.grasp;
    let mut lines = vec![
        format!(
            "{} grasp at {} kPa, b = {} deg: F = {} N, f = {} N, f_v = {} N (per finger)",
            o.spec.name(),
            num(g.pressure_kpa, 3),
            num(g.beta.to_degrees(), 2),
            num(g.normal, 4),
            num(g.friction, 4),
            num(g.lift, 4),
        ),
        format!(
            "d = {} mm, tip gap = {} mm, h = {} mm: {}",
            num(g.size, 3),
            num(g.tip_gap, 3),
            num(g.height, 3),
            if o.is_valid() { "valid" } else { "NOT valid" }
        ),
    ];
    if let Some(s) = &o.sphere {
        lines.push(format!(
            "sphere r = {} mm, centre Xg = {} mm, Zg = {} mm",
            num(s.radius, 3),
            num(s.center[0], 3),
            num(s.center[1], 3)
        ));
    }
    if let Some(i) = &o.invalid {
        lines.push(format!("NOT valid: {}: {i}", i.kind()));
    }
    lines
}

/// The most validity findings the caption lists one by one.
const MAX_FINDINGS: usize = 12;

/// A line per finding that puts the answer outside the model (at most
/// [`MAX_FINDINGS`], then how many more), or one saying there is none.
fn findings(warnings: &[Warning]) -> Vec<String> {
    let outside: Vec<&Warning> = warnings.iter().filter(|w| w.is_validity()).collect();
    if outside.is_empty() {
        return vec!["within the model's limits (no validity findings)".into()];
    }
    let mut lines: Vec<String> = outside
        .iter()
        .take(MAX_FINDINGS)
        .map(|w| {
            let at = w.element().map(|e| format!(" at element {e}"));
            let text = warning_text(w);
            format!(
                "outside the model: {}{}: {text}",
                w.kind(),
                at.unwrap_or_default()
            )
        })
        .collect();
    if outside.len() > MAX_FINDINGS {
        lines.push(format!(
            "and {} more findings (solution.json lists them all)",
            outside.len() - MAX_FINDINGS
        ));
    }
    lines
}

/// A number with `decimals` decimals; `n/a` when not finite.
fn num(x: f64, decimals: usize) -> String {
    if x.is_finite() {
        format!("{x:.decimals$}")
    } else {
        "n/a".into()
    }
}

/// Width of the SVG (px).
const WIDTH: u32 = 820;
/// Margin around the plot and the caption (px).
const MARGIN: u32 = 14;
/// Heights of the title strip and of one caption line (px).
const TITLE_H: u32 = 34;
const LINE_H: u32 = 19;
/// Room for the tick labels and the axis names (px).
const X_LABEL_AREA: u32 = 46;
const Y_LABEL_AREA: u32 = 66;
/// Bounds of the plotting area's height (px).
const PLOT_H: (f64, f64) = (220.0, 760.0);
/// Text size (plotters' units; the SVG's font-size is 1/1.24 of it) and
/// the average width of one character of it (px).
const TEXT: u32 = 16;
const CHAR_PX: f64 = 7.0;

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Renders a plot: title, the plot with axes at an equal aspect, the
/// legend and the caption.
fn render(plot: &Plot) -> anyhow::Result<String> {
    let (lo, hi) = plot.extent();
    let plot_w = f64::from(WIDTH - Y_LABEL_AREA - 2 * MARGIN);
    let plot_h = (plot_w * (hi[1] - lo[1]) / (hi[0] - lo[0])).clamp(PLOT_H.0, PLOT_H.1);
    let chart_h = plot_h as u32 + X_LABEL_AREA + 2 * MARGIN;
    let text_w = WIDTH - 2 * MARGIN;
    let legend = legend(&plot.items, text_w);
    let rows = legend.last().map_or(0, |e| e.row + 1);
    let chars = (f64::from(text_w) / CHAR_PX) as usize;
    // continued lines are indented
    let caption: Vec<(bool, String)> = plot
        .caption
        .iter()
        .flat_map(|c| wrap(c, chars).into_iter().enumerate())
        .map(|(k, line)| (k > 0, line))
        .collect();
    let caption_h = LINE_H * (rows + caption.len() as u32 + 1);
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (WIDTH, TITLE_H + chart_h + caption_h))
            .into_drawing_area();
        root.fill(&WHITE)?;
        let (head, rest) = root.split_vertically(TITLE_H);
        let (body, foot) = rest.split_vertically(chart_h);
        let title = ("sans-serif", 19).into_font().color(&BLACK);
        head.draw(&Text::new(plot.title.as_str(), (MARGIN as i32, 12), title))?;
        draw_chart(plot, &body, lo, hi)?;
        draw_caption(&foot, &legend, &caption)?;
        root.present()?;
    }
    Ok(buf)
}

/// Builds the chart on `area` over the given ranges.
fn chart_on<'a, 'b>(
    area: &'a Area<'b>,
    x: (f64, f64),
    y: (f64, f64),
) -> anyhow::Result<Chart<'a, 'b>> {
    Ok(ChartBuilder::on(area)
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)?)
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws the axes and the items: the ranges cover `lo..hi`, stretched to
/// one scale on both axes of the plotting area.
fn draw_chart(plot: &Plot, area: &Area, lo: [f64; 2], hi: [f64; 2]) -> anyhow::Result<()> {
    // building draws nothing: a first chart measures the plotting area
    let px = chart_on(area, (0.0, 1.0), (0.0, 1.0))?
        .plotting_area()
        .dim_in_pixel();
    let (x, y) = equal_aspect(lo, hi, px);
    let mut chart = chart_on(area, x, y)?;
    let flip = if plot.y_down { -1.0 } else { 1.0 };
    let x_tick = |v: &f64| tick(*v);
    let y_tick = |v: &f64| tick(flip * v);
    // one tick step on both axes, about every TICK_PX pixels
    let step = nice_step(TICK_PX * (x.1 - x.0) / f64::from(px.0.max(2) - 1));
    chart
        .configure_mesh()
        .x_desc(plot.x_desc)
        .y_desc(plot.y_desc)
        .x_label_formatter(&x_tick)
        .y_label_formatter(&y_tick)
        .x_labels(multiples(x, step))
        .y_labels(multiples(y, step))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(RGBColor(242, 242, 242))
        .bold_line_style(RGBColor(222, 222, 222))
        .draw()?;
    for item in &plot.items {
        draw_item(&mut chart, item)?;
    }
    Ok(())
}

/// The least distance between tick labels (px).
const TICK_PX: f64 = 80.0;

/// The smallest of 1, 2 or 5 times a power of ten that is at least `min`
/// (> 0).
fn nice_step(min: f64) -> f64 {
    let p = 10f64.powf(min.log10().floor());
    [1.0, 2.0, 5.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= min * (1.0 - 1e-9))
        .unwrap_or(10.0 * p)
}

/// How many multiples of `step` lie in `range`: as plotters' largest
/// number of labels, it makes plotters choose `step` itself.
fn multiples(range: (f64, f64), step: f64) -> usize {
    ((range.1 / step).floor() - (range.0 / step).ceil() + 1.0).max(1.0) as usize
}

/// A tick label: the value to 1e-6 mm, no `-0`.
fn tick(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6 + 0.0;
    format!("{r}")
}

/// The ranges over `lo..hi` that give both axes one scale (mm per pixel)
/// on a plotting area of `px` pixels: the short range grows about its
/// centre. Plotters maps a range onto `px - 1` pixels.
fn equal_aspect(lo: [f64; 2], hi: [f64; 2], px: (u32, u32)) -> ((f64, f64), (f64, f64)) {
    let span = |n: u32| f64::from(n.max(2) - 1);
    let (w, h) = (span(px.0), span(px.1));
    let per_px = ((hi[0] - lo[0]) / w).max((hi[1] - lo[1]) / h);
    let around = |k: usize, pixels: f64| {
        let c = 0.5 * (lo[k] + hi[k]);
        (c - 0.5 * per_px * pixels, c + 0.5 * per_px * pixels)
    };
    (around(0, w), around(1, h))
}

fn draw_item(chart: &mut Chart, item: &Item) -> anyhow::Result<()> {
    let style = item.look.style();
    let pts = item.points.iter().copied();
    match item.look {
        Look::Root | Look::Tip => {
            chart.draw_series(pts.map(|p| Circle::new(p, 4, style)))?;
        }
        Look::Object => {
            chart.draw_series(std::iter::once(Polygon::new(
                item.points.clone(),
                ORANGE.mix(0.22).filled(),
            )))?;
            chart.draw_series(LineSeries::new(pts, style))?;
        }
        look => match look.dashes() {
            Some((dash, gap)) => {
                chart.draw_series(DashedLineSeries::new(pts, dash, gap, style))?;
            }
            None => {
                chart.draw_series(LineSeries::new(pts, style))?;
            }
        },
    }
    Ok(())
}

/// A legend entry placed in the caption: its row and its left edge (px).
struct Entry {
    look: Look,
    label: &'static str,
    row: u32,
    x: i32,
}

/// Width of an entry's mark and the gaps after it and after its label (px).
const MARK_W: i32 = 26;
const MARK_GAP: i32 = 7;
const ENTRY_GAP: i32 = 20;

/// The legend: one entry per label, in the order of [`Look`], filled into
/// rows `width` pixels wide.
fn legend(items: &[Item], width: u32) -> Vec<Entry> {
    let mut labelled: Vec<(Look, &'static str)> = Vec::new();
    for i in items.iter().filter(|i| !i.label.is_empty()) {
        if !labelled.iter().any(|(_, l)| *l == i.label) {
            labelled.push((i.look, i.label));
        }
    }
    labelled.sort_by_key(|(look, _)| *look);
    let mut entries = Vec::new();
    let (mut row, mut x) = (0, 0);
    for (look, label) in labelled {
        let w = MARK_W + MARK_GAP + (label.chars().count() as f64 * CHAR_PX) as i32;
        if x > 0 && x + w > width as i32 {
            row += 1;
            x = 0;
        }
        entries.push(Entry {
            look,
            label,
            row,
            x,
        });
        x += w + ENTRY_GAP;
    }
    entries
}

/// Draws the legend, then the caption lines, into `area`.
fn draw_caption(area: &Area, legend: &[Entry], lines: &[(bool, String)]) -> anyhow::Result<()> {
    let text = ("sans-serif", TEXT)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let left = MARGIN as i32;
    let line_y = |row: u32| (LINE_H * row + LINE_H / 2) as i32;
    for e in legend {
        let (x, y) = (left + e.x, line_y(e.row));
        draw_mark(area, e.look, x, y)?;
        area.draw(&Text::new(
            e.label,
            (x + MARK_W + MARK_GAP, y),
            text.clone(),
        ))?;
    }
    let first = legend.last().map_or(0, |e| e.row + 1);
    for (k, (continued, line)) in lines.iter().enumerate() {
        let x = if *continued { left + INDENT_PX } else { left };
        let y = line_y(first + k as u32);
        area.draw(&Text::new(line.as_str(), (x, y), text.clone()))?;
    }
    Ok(())
}

/// A legend entry's mark, `MARK_W` wide from `x`, centred on `y`.
fn draw_mark(area: &Area, look: Look, x: i32, y: i32) -> anyhow::Result<()> {
    let style = look.style();
    let line = vec![(x, y), (x + MARK_W, y)];
    match look {
        Look::Root | Look::Tip => area.draw(&Circle::new((x + MARK_W / 2, y), 4, style))?,
        Look::Object => {
            let corners = [(x, y - 6), (x + MARK_W, y + 6)];
            area.draw(&Rectangle::new(corners, ORANGE.mix(0.22).filled()))?;
            area.draw(&Rectangle::new(corners, style))?;
        }
        look => match look.dashes() {
            Some((dash, gap)) => area.draw(&plotters::element::DashedPathElement::new(
                line, dash, gap, style,
            ))?,
            None => area.draw(&PathElement::new(line, style))?,
        },
    }
    Ok(())
}

/// The indent of a continued caption line (px).
const INDENT_PX: i32 = 24;

/// `text` broken at spaces into lines of at most `width` characters, the
/// continued ones `INDENT_PX` narrower (a longer word keeps a line of its
/// own).
fn wrap(text: &str, width: usize) -> Vec<String> {
    let narrower = (f64::from(INDENT_PX) / CHAR_PX).ceil() as usize;
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let room = if lines.is_empty() {
            width
        } else {
            width.saturating_sub(narrower)
        };
        let len = line.chars().count();
        if len > 0 && len + 1 + word.chars().count() > room {
            lines.push(std::mem::take(&mut line));
        } else if len > 0 {
            line.push(' ');
        }
        line.push_str(word);
    }
    lines.push(line);
    lines
}

// ------------------------------------------------------------ summary

fn summary(
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

#[cfg(test)]
mod tests {
    use super::*;

    fn solved(text: &str) -> SceneSolution {
        fpc::Scene::from_toml(text).unwrap().solve().unwrap()
    }

    fn keys(v: serde_json::Value) -> Vec<String> {
        let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
        k.sort();
        k
    }

    #[test]
    fn the_solution_keys_are_the_librarys() {
        // every key of the library's Solution but `warnings`, which
        // solution.json holds for the whole scene
        let sol = solved("");
        let ours = serde_json::to_value(SolutionKeys::of(sol.solution())).unwrap();
        let mut ours = keys(ours);
        ours.push("warnings".into());
        ours.sort();
        assert_eq!(ours, keys(serde_json::to_value(sol.solution()).unwrap()));
    }

    /// The keys of a JSON object in the order written, repeats kept.
    struct Keys(Vec<String>);

    impl<'de> serde::Deserialize<'de> for Keys {
        fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Keys, D::Error> {
            struct Visitor;
            impl<'de> serde::de::Visitor<'de> for Visitor {
                type Value = Keys;
                fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                    f.write_str("an object")
                }
                fn visit_map<A: serde::de::MapAccess<'de>>(
                    self,
                    mut m: A,
                ) -> Result<Keys, A::Error> {
                    let mut keys = Vec::new();
                    while let Some((k, _)) = m.next_entry::<String, serde::de::IgnoredAny>()? {
                        keys.push(k);
                    }
                    Ok(Keys(keys))
                }
            }
            d.deserialize_map(Visitor)
        }
    }

    #[test]
    fn solution_json_has_no_key_twice() {
        for text in [
            "",
            "[gripper]\n",
            "[gripper]\n[gripper.grasp]\nkind = \"sphere\"\n",
        ] {
            let s = solved(text);
            let file = fpc::Scene::from_toml(text).unwrap().file().clone();
            let json = serde_json::to_string(&solution_file("t", &file, &s)).unwrap();
            let Keys(mut top) = serde_json::from_str(&json).unwrap();
            let written = top.len();
            top.sort();
            top.dedup();
            assert_eq!(top.len(), written, "{text:?}: a key twice in {json}");
            let v: serde_json::Value = serde_json::from_str(&json).unwrap();
            if let Some(g) = v.get("gripper") {
                let Keys(mut inner) = serde_json::from_value(g.clone()).unwrap();
                let written = inner.len();
                inner.sort();
                inner.dedup();
                assert_eq!(inner.len(), written, "{text:?}: gripper");
            }
            assert_eq!(v["warnings"], serde_json::json!([]), "{text:?}");
            assert_eq!(v["validity"], true, "{text:?}");
        }
    }

    #[test]
    fn equal_aspect_gives_one_scale() {
        for (lo, hi, px) in [
            ([0.0, -80.0], [110.0, 5.0], (734, 600)),
            ([-60.0, -150.0], [60.0, 5.0], (734, 760)),
            ([0.0, 0.0], [10.0, 1000.0], (300, 220)),
            ([-1.0, -1.0], [1.0, 1.0], (2, 2)),
        ] {
            let (x, y) = equal_aspect(lo, hi, px);
            let sx = (x.1 - x.0) / f64::from(px.0 - 1);
            let sy = (y.1 - y.0) / f64::from(px.1 - 1);
            assert!((sx - sy).abs() <= 1e-12 * sx, "{sx} {sy}");
            assert!(x.0 <= lo[0] && x.1 >= hi[0] && y.0 <= lo[1] && y.1 >= hi[1]);
        }
    }

    /// The corners (px) of the first `<polygon>` of an SVG.
    fn polygon_px(svg: &str) -> Vec<(f64, f64)> {
        let tag = &svg[svg.find("<polygon").unwrap()..];
        let start = tag.find("points=\"").unwrap() + "points=\"".len();
        let end = start + tag[start..].find('"').unwrap();
        tag[start..end]
            .split_whitespace()
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect()
    }

    #[test]
    fn a_square_is_drawn_square() {
        for (y_down, wide) in [(false, 300.0), (true, 20.0), (false, 5.0)] {
            let mut p = Plot::new("t".into(), "X (mm)", "Z (mm)", y_down);
            p.add(
                Look::Object,
                "square",
                [[0.0, 0.0], [40.0, 0.0], [40.0, 40.0], [0.0, 40.0]],
            );
            p.add(Look::Finger, "line", [[-wide, 0.0], [wide, 10.0]]);
            let corners = polygon_px(&render(&p).unwrap());
            let span = |f: fn(&(f64, f64)) -> f64| {
                let v: Vec<f64> = corners.iter().map(f).collect();
                v.iter().cloned().fold(f64::MIN, f64::max)
                    - v.iter().cloned().fold(f64::MAX, f64::min)
            };
            let (w, h) = (span(|c| c.0), span(|c| c.1));
            assert!(w > 10.0 && (w - h).abs() <= 1.0, "{w} x {h} px");
        }
    }

    #[test]
    fn non_finite_values_draw_nothing_and_print_no_nan() {
        let mut s = solved("");
        let SceneSolution::Finger { solution, .. } = &mut s else {
            panic!()
        };
        solution.tip = [f64::NAN, f64::INFINITY];
        solution.end_angle = f64::NAN;
        solution.points[3] = [f64::NAN, 1.0];
        solution.points[4] = [1e300, -1e300];
        let svg = shape_svg("t", &s).unwrap();
        assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
        assert!(svg.contains("tip X = n/a mm"));
        // nothing drawable at all still gives axes around the origin
        let mut p = Plot::new("t".into(), "X (mm)", "Z (mm)", false);
        p.add(Look::Finger, "f", [[f64::NAN, 0.0], [f64::INFINITY, 1.0]]);
        p.add(Look::Tip, "tip", [[f64::NAN, f64::NAN]]);
        assert!(p.items.is_empty());
        let svg = render(&p).unwrap();
        assert!(svg.contains("X (mm)") && !svg.contains("NaN"));
    }

    #[test]
    fn ticks_and_text() {
        assert_eq!(tick(-0.0), "0");
        assert_eq!(tick(-1e-9), "0");
        assert_eq!(tick(20.000000000004), "20");
        assert_eq!(tick(-12.5), "-12.5");
        assert_eq!(nice_step(16.0), 20.0);
        assert_eq!(nice_step(20.0), 20.0);
        assert_eq!(nice_step(0.3), 0.5);
        assert_eq!(nice_step(7.0), 10.0);
        assert_eq!(multiples((-5.0, 105.0), 20.0), 6);
        assert_eq!(num(f64::NAN, 2), "n/a");
        assert_eq!(num(1.23456, 2), "1.23");
        let text = "outside the model: element_slope at element 1: element 1 turns 64.9 degrees";
        let lines = wrap(text, 30);
        assert!(lines.len() > 1);
        assert!(lines.iter().all(|l| l.chars().count() <= 30), "{lines:?}");
        assert_eq!(lines.join(" "), text);
        assert_eq!(wrap("", 10), [""]);
        assert_eq!(wrap(&"x".repeat(50), 10), ["x".repeat(50)]);
    }
}
