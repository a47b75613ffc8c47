//! `fpc design REQUIREMENTS.toml`: the finger and gripper to build for a
//! set of objects (`fpc::design`). Prints the design with the largest
//! worst-case margin (or the least-violating one and what fails), every
//! margin and its sensitivities, and writes `design.json`, one scene file
//! per object (which `fpc solve` runs to reproduce the claimed grasp; each
//! is run here through the ordinary scene path and compared), and
//! `design.svg` (the fingers at rest and holding each object, the lift
//! curves and the requirements; also or instead `design.png` and
//! `design.pdf` with `--format`).

use std::io::Write as _;
use std::path::PathBuf;

use fpc::design::{
    evaluate, gripper, optimize_with_progress, DesignBase, DesignOptions, DesignProgress,
    DesignStage, Designed, Evaluation, ObjectRequirement, Requirements, RequirementsError,
    VARIABLES,
};
use fpc::num::Num;
use fpc::scene::{Scene, SceneSolution};
use fpc::studies::{Corner, Figure, Panel, PlotAxis, Series, SeriesKind};
use serde::Serialize;

/// Flags of `fpc design`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The requirements file (TOML; scenes/design/ has examples, the README
    /// documents every key): `[vary]` is required, `elements` lies in
    /// [1, 256].
    requirements: PathBuf,
    /// Output directory (default `<stem>-design`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print one JSON object instead of the summary.
    #[arg(long)]
    json: bool,
    /// Random starts of the optimiser besides the centre and the corners
    /// (at most 10000; each costs one evaluation of every requirement,
    /// about 3 ms of one core per sphere on the paper's finger: 10000 on
    /// paper_sec5.toml take about 30 s of one core; a search that takes
    /// more than 2 s shows its progress on stderr).
    #[arg(long, default_value_t = 2, allow_hyphen_values = true)]
    starts: usize,
    /// Design from the finger of a scene file (a calibrated scene from
    /// `fpc calibrate`, say): its element model, actuator, load.kappa (for
    /// the open requirement) and [calibration] table; its eps0 unless
    /// eps0 varies. Default: the paper's actuator.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    #[command(flatten)]
    format: crate::render::formats::FormatArgs,
}

#[derive(Serialize)]
struct Report<'a> {
    feasible: bool,
    design: DesignJson,
    worst_margin: f64,
    /// The requirement that fails most (or holds least), and by how much.
    limiting: Option<&'a fpc::design::Margin>,
    margins: &'a [fpc::design::Margin],
    sensitivities: &'a [fpc::design::MarginSensitivity],
    evaluations: usize,
    starts: usize,
    /// Why the design does not meet its requirements (null when it does).
    failure: Option<&'a str>,
    /// Every object's scene solved again through the ordinary scene path.
    scenes: &'a [fpc::design::Reproduction],
    /// Notes on the requirements (bounds clamped to the design space, or
    /// widened beyond it).
    notes: Vec<String>,
    provenance: crate::provenance::Provenance,
}

#[derive(Serialize)]
struct DesignJson {
    eps0: f64,
    mounting_angle_deg: f64,
    overlap_mm: f64,
    varied: Vec<&'static str>,
}

/// The figure: the finger at rest in the gripper frame with each object's
/// reproduced grasp drawn in (the grasped finger, its mirror image and the
/// object's outline), and per object the design's lift against size
/// (cuboids) or radius (spheres) with the required region.
fn figure(req: &Requirements, e: &Evaluation, solved: &[Option<SceneSolution>]) -> Figure {
    let mut shape = Panel::new(
        "The designed fingers at rest and holding each object (gripper frame)",
        PlotAxis::new("Xg", "mm"),
        PlotAxis::new("−Zg (the gripper points down)", "mm"),
    );
    shape.equal_aspect = true;
    shape.legend = Corner::UpperRight;
    // the gripper frame's Zg points down: drawn as -Zg
    let up = |p: [f64; 2]| [p[0], -p[1]];
    let pair = |label: String, color: &str, kind: SeriesKind, pts: Vec<[f64; 2]>| {
        let mirrored = pts.iter().map(|p| [-p[0], p[1]]).collect();
        [
            Series {
                label: Some(label),
                color: color.into(),
                kind,
                points: pts,
            },
            Series {
                label: None,
                color: color.into(),
                kind,
                points: mirrored,
            },
        ]
    };
    if let Ok(g) = gripper(req, e.design) {
        let rest: Vec<[f64; 2]> = g.rest_shape().iter().map(|&p| up(p)).collect();
        shape.series.extend(pair(
            "fingers at rest".into(),
            "reference",
            SeriesKind::Dashed,
            rest,
        ));
    }
    for (i, s) in solved.iter().enumerate() {
        let Some(SceneSolution::Gripper {
            gripper: g,
            grasp: Some(o),
        }) = s
        else {
            continue;
        };
        let color = format!("object{i}");
        let held: Vec<[f64; 2]> = s
            .as_ref()
            .map(|s| {
                s.solution()
                    .points
                    .iter()
                    .map(|&p| up(g.to_gripper(p)))
                    .collect()
            })
            .unwrap_or_default();
        shape.series.extend(pair(
            format!("holding object {i}"),
            &color,
            SeriesKind::Line,
            held,
        ));
        let outline: Vec<[f64; 2]> = match &o.sphere {
            Some(sp) => (0..=72)
                .map(|k| {
                    let t = std::f64::consts::TAU * k as f64 / 72.0;
                    up([
                        sp.center[0] + sp.radius * t.cos(),
                        sp.center[1] + sp.radius * t.sin(),
                    ])
                })
                .collect(),
            None => {
                // a cuboid of the grasped width, its faces touching the tips
                // at mid-height
                let (w, h) = (o.grasp.size / 2.0, o.grasp.height);
                [
                    [-w, h - w],
                    [w, h - w],
                    [w, h + w],
                    [-w, h + w],
                    [-w, h - w],
                ]
                .into_iter()
                .map(up)
                .collect()
            }
        };
        shape.series.push(Series {
            label: Some(format!("object {i}")),
            color,
            kind: SeriesKind::Dashed,
            points: outline,
        });
    }
    let mut lift = Panel::new(
        "Lift per finger at each sample (bars: required)",
        PlotAxis::new("object size (width d or radius r)", "mm"),
        PlotAxis::new("lift f_v", "N"),
    );
    lift.legend = Corner::LowerLeft;
    lift.y.include_zero = true;
    for (i, o) in req.objects.iter().enumerate() {
        let (kind, need) = match o {
            ObjectRequirement::Cuboid { lift_n, .. } => ("cuboid", *lift_n),
            ObjectRequirement::Sphere { lift_n, .. } => ("sphere", *lift_n),
        };
        let pts: Vec<[f64; 2]> = e
            .margins
            .iter()
            .filter(|m| {
                m.requirement.starts_with(&format!("object[{i}] "))
                    && m.requirement.ends_with("lift")
            })
            // the lift from its margin; below -1, where the margin is
            // compressed (`fpc::design` module docs), the lift itself
            .filter_map(|m| {
                let lift = match m.value {
                    Some(v) if m.margin < -1.0 => v,
                    _ => need * (1.0 + m.margin),
                };
                Some([m.at_mm?, lift])
            })
            .collect();
        let color = format!("object{i}");
        let (lo, hi) = pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[0]), b.max(p[0]))
            });
        lift.series.push(Series {
            label: Some(format!("object {i} ({kind})")),
            color: color.clone(),
            kind: SeriesKind::LinePoints,
            points: pts,
        });
        if lo.is_finite() {
            lift.series.push(Series {
                label: Some(format!("object {i}: required")),
                color,
                kind: SeriesKind::Dashed,
                points: vec![[lo, need], [hi, need]],
            });
        }
    }
    Figure {
        title: format!(
            "fpc design: eps0 = {:.3}, mounting angle = {:.1} deg, overlap = {:.1} mm",
            Num(e.design[0]),
            Num(e.design[1]),
            Num(e.design[2])
        ),
        size: [1200, 520],
        rows: vec![vec![shape, lift]],
    }
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let shown = args.requirements.display().to_string();
    let text = crate::solve::read_scene(&args.requirements, &shown)?;
    let mut req = Requirements::parse(&text)
        .map_err(|e| crate::status::rejected(located(&shown, &text, &e)))?;
    if let Some(path) = &args.scene {
        let scene = crate::solve::load_scene(path)?;
        req = req.with_base(DesignBase::from_scene(
            &scene,
            format!("the scene {}", path.display()),
        ));
    }
    let (_, out) = crate::output::stem_and_dir(
        &args.requirements,
        args.out.as_deref(),
        "requirements",
        "design",
    );
    let opts = DesignOptions {
        random_starts: args.starts,
        ..DesignOptions::default()
    };
    // bounded before the output directory or any work
    opts.validate().map_err(|e| {
        crate::status::rejected(format!(
            "--starts = {}: {}",
            args.starts,
            e.to_string().split_once(": ").map_or("", |(_, r)| r)
        ))
    })?;
    crate::output::prepare_dir(&out)?;
    // a design is reported only once found and checked: stopped before,
    // nothing is written
    let stop = crate::interrupt::arm("nothing is written unless the design was found already");
    // the search's last event, shown once it has taken a while
    let latest = crate::report::Latest::<DesignProgress>::default();
    let observe = |p: &DesignProgress| latest.set(p);
    let search = || optimize_with_progress(&req, &opts, &observe);
    let d = crate::report::with_progress(
        || status(latest.get().as_ref()),
        || match &stop {
            Some(flag) => fpc::cancel::with_flag(flag.clone(), search),
            None => search(),
        },
    );
    if stop.is_some_and(|f| f.load(std::sync::atomic::Ordering::SeqCst)) {
        return Err(crate::status::interrupted(
            "stopped by Ctrl-C before the design was found; nothing written",
        ));
    }
    let d = d?;
    // the requirements' bounds keep every number finite; were one not, no
    // NaN or inf is written in its place
    if let Some(what) = not_finite(&d) {
        anyhow::bail!("{what} is not finite: nothing written");
    }
    // the claim, evaluated once more from scratch
    let again = evaluate(&req, d.best.design);
    anyhow::ensure!(
        (again.worst - d.best.worst).abs() <= 1e-9 * (1.0 + d.best.worst.abs()),
        "the best design's margins do not reproduce ({} vs {})",
        again.worst,
        d.best.worst
    );
    for r in &d.reproductions {
        crate::output::write_atomic(&out, &r.file, r.text.as_bytes())?;
    }
    // the scenes solved once more, for the figure
    let solved: Vec<Option<SceneSolution>> = d
        .reproductions
        .iter()
        .map(|r| Scene::from_toml(&r.text).ok().and_then(|s| s.solve().ok()))
        .collect();
    let svg = crate::paper::render::svg(&figure(&req, &d.best, &solved))?;
    let figures = args.format.write(&out, "design", &svg)?;
    let b = req.bounds();
    let report = Report {
        feasible: d.feasible,
        design: DesignJson {
            eps0: d.best.design[0],
            mounting_angle_deg: d.best.design[1],
            overlap_mm: d.best.design[2],
            varied: VARIABLES
                .iter()
                .zip(b)
                .filter(|(_, b)| b[1] > b[0])
                .map(|(n, _)| *n)
                .collect(),
        },
        worst_margin: d.best.worst,
        limiting: d.best.worst_margin(),
        margins: &d.best.margins,
        sensitivities: &d.sensitivities,
        evaluations: d.evaluations,
        starts: d.starts,
        failure: d.failure.as_deref(),
        scenes: &d.reproductions,
        notes: req.notes(),
        provenance: crate::provenance::Provenance::now(),
    };
    let json = serde_json::to_string_pretty(&report)? + "\n";
    crate::output::write_atomic(&out, "design.json", json.as_bytes())?;
    let mut w = crate::output::stdout();
    if args.json {
        writeln!(w, "{}", serde_json::to_string(&report)?)?;
        return Ok(());
    }
    writeln!(
        w,
        "design         {}: eps0 = {:.4}, mounting angle = {:.2} deg, overlap = {:.2} mm",
        if d.feasible {
            "meets every requirement"
        } else {
            "NO design meets every requirement; the least-violating one"
        },
        Num(d.best.design[0]),
        Num(d.best.design[1]),
        Num(d.best.design[2])
    )?;
    for n in &report.notes {
        writeln!(w, "note           {n}")?;
    }
    if let Some(m) = d.best.worst_margin() {
        writeln!(
            w,
            "worst margin   {} ({}: {})",
            signed(m.margin),
            m.requirement,
            m.detail
        )?;
    }
    writeln!(
        w,
        "margins (normalised; >= 0 met) and d margin / d (eps0, angle deg, overlap mm):"
    )?;
    for (m, s) in d.best.margins.iter().zip(&d.sensitivities) {
        writeln!(
            w,
            "  {}  {:<44} [{:+.3e}, {:+.3e}, {:+.3e}]  {}",
            signed(m.margin),
            m.requirement,
            s.gradient[0],
            s.gradient[1],
            s.gradient[2],
            m.detail
        )?;
        for n in &m.notes {
            writeln!(w, "           note  {n}")?;
        }
    }
    for s in report.scenes {
        writeln!(
            w,
            "scene          {}: {} ({})",
            out.join(&s.file).display(),
            match (s.reproduced, s.claimed_lift_n) {
                (true, Some(_)) => "fpc solve reproduces the claim".to_string(),
                (true, None) => format!("fpc solve confirms no valid grasp: {}", s.requirement),
                (false, _) => "NOT reproduced".to_string(),
            },
            s.detail
        )?;
        for n in &s.notes {
            writeln!(w, "  note         {n}")?;
        }
    }
    if let Some(f) = &d.failure {
        writeln!(w, "not met        {f}")?;
    }
    writeln!(
        w,
        "search         {} evaluations from {} starts; wrote design.json, {}",
        d.evaluations,
        d.starts,
        figures.join(", ")
    )?;
    Ok(())
}

/// The progress line of a search whose last event is `p`: the stage
/// with its counts, the evaluations so far and the best worst margin.
fn status(p: Option<&DesignProgress>) -> String {
    let Some(p) = p else {
        return "fpc design: starting".into();
    };
    let stage = match p.stage {
        DesignStage::Screening => format!("screening starts {}/{}", p.starts_done, p.starts),
        DesignStage::Ascending => format!(
            "{} starts screened, ascents {}/{}",
            p.starts, p.ascents_done, p.ascents
        ),
        DesignStage::Checking => "checking the best design".into(),
    };
    let best = p
        .best_worst_margin
        .map_or("none yet".into(), |m| format!("{m:+.4}"));
    format!(
        "fpc design: {stage}; {} evaluations; best worst margin {best}",
        p.evaluations
    )
}

/// A requirements error as one line: `FILE:LINE:COL: message`, the
/// position of a syntax error or of the value a value error names (as
/// `fpc solve` names a scene's key), `FILE: message` where the file does
/// not write that key.
fn located(shown: &str, text: &str, e: &RequirementsError) -> String {
    let message = match e {
        RequirementsError::Syntax(s) => s.message.clone(),
        RequirementsError::Input(i) => i.to_string(),
    };
    match e.position(text) {
        Some((line, col)) => format!("{shown}:{line}:{col}: {message}"),
        None => format!("{shown}: {message}"),
    }
}

/// The first number of the design's report that is not finite, named;
/// `None` when all are.
fn not_finite(d: &Designed) -> Option<String> {
    let bad = |v: f64| !v.is_finite();
    if d.best.design.iter().any(|&v| bad(v)) {
        return Some("the design".into());
    }
    if bad(d.best.worst) {
        return Some("the worst margin".into());
    }
    for m in &d.best.margins {
        let numbers = [Some(m.margin), m.at_mm, m.beta_deg, m.value, m.normal_n];
        if numbers.into_iter().flatten().any(bad) {
            return Some(format!("the margin of {}", m.requirement));
        }
    }
    d.sensitivities
        .iter()
        .find(|s| s.gradient.iter().any(|&v| bad(v)))
        .map(|s| format!("the sensitivity of {}", s.requirement))
}

/// A margin with its sign, never `-0.0000`: a margin too small for four
/// decimals keeps its magnitude in scientific notation (a margin of
/// -3e-6 is an unmet requirement, and says so), zero is `+0.0000`.
fn signed(x: f64) -> String {
    if x == 0.0 {
        "+0.0000".into()
    } else if x.abs() < 5e-5 {
        format!("{x:+.2e}")
    } else {
        format!("{x:+.4}")
    }
}

#[cfg(test)]
mod tests {
    use super::{not_finite, signed};
    use fpc::design::{Designed, Evaluation, Margin, MarginSensitivity};

    /// A design with one margin `margin` and one sensitivity `gradient`.
    fn designed(margin: f64, gradient: [f64; 3]) -> Designed {
        let m = Margin {
            requirement: "object[0] cuboid d = 60.0 mm: lift".into(),
            margin,
            detail: String::new(),
            at_mm: Some(60.0),
            beta_deg: Some(0.0),
            value: Some(0.4),
            normal_n: Some(1.0),
            valid: Some(true),
            notes: Vec::new(),
        };
        Designed {
            feasible: true,
            best: Evaluation {
                design: [0.25, 60.0, 20.0],
                margins: vec![m.clone()],
                worst: margin,
            },
            sensitivities: vec![MarginSensitivity {
                requirement: m.requirement,
                gradient,
            }],
            evaluations: 1,
            starts: 1,
            reproductions: Vec::new(),
            failure: None,
        }
    }

    #[test]
    fn a_report_with_a_number_that_is_not_finite_is_not_written() {
        assert_eq!(not_finite(&designed(0.2, [0.1, -0.2, 0.0])), None);
        let worst = not_finite(&designed(f64::INFINITY, [0.0; 3])).unwrap();
        assert!(worst.contains("worst margin"), "{worst}");
        let mut d = designed(0.2, [0.0; 3]);
        d.best.margins[0].margin = f64::NAN;
        assert!(not_finite(&d).unwrap().contains("margin of object[0]"));
        let s = not_finite(&designed(0.2, [f64::NAN; 3])).unwrap();
        assert!(s.contains("sensitivity of object[0]"), "{s}");
    }

    #[test]
    fn margins_never_print_as_negative_zero() {
        assert_eq!(signed(-3e-6), "-3.00e-6");
        assert_eq!(signed(2e-7), "+2.00e-7");
        assert_eq!(signed(0.0), "+0.0000");
        assert_eq!(signed(-0.0), "+0.0000");
        assert_eq!(signed(-0.12345), "-0.1235");
        assert_eq!(signed(4.1), "+4.1000");
    }
}
