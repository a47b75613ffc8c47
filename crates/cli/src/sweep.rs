//! `fpc sweep SCENE.toml --vary KEY=SPEC ...`: a grid over scene
//! parameters, solved in parallel with warm starts along the grid, one CSV
//! row (and one JSON record) per point with its status and warnings.
//!
//! `SPEC` is `from:to:count` (count points, both ends included) or a comma
//! list `v1,v2,...`. The last `--vary` is the fastest-varying axis: each
//! line of the grid along it is solved in order, every point starting from
//! the one before (`Scene::solve_warm`, so a sweep stays on the branch it
//! started on); lines run in parallel (rayon). A key is any numeric scene
//! key (`load.fx`, `actuator.pemc.eps0`, `partition.lengths[2]`, ...), read
//! once into its typed [`SceneKey`]: each
//! point's scene is the file with those keys set, validated as `fpc solve`
//! validates a file, so a bad value is that point's `rejected` status, not
//! the end of the sweep. A row has no shape and no radius of curvature, so
//! a finger scene's shape is not sampled (`solve.shape` does not apply).
//! Ctrl-C stops the sweep: the points done are written, the others are
//! rows with status `stopped`, and the command ends with status 130
//! ([`fpc_cli::interrupt`]).

use std::io::Write as _;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::Context as _;
use fpc::num::Num;
use fpc::scene::{warning_text, Scene, SceneKey, SceneSolution};
use fpc::SolveError;
use rayon::prelude::*;
use serde::Serialize;

/// Flags of `fpc sweep`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scene file (TOML; `fpc solve` documents the keys).
    scene: PathBuf,
    /// A scene key and its values: `KEY=FROM:TO:COUNT` or `KEY=V1,V2,...`,
    /// at most 100000 values (repeat for more axes, at most 1000000 points
    /// in all; the last varies fastest).
    #[arg(
        long = "vary",
        value_name = "KEY=SPEC",
        required = true,
        allow_hyphen_values = true
    )]
    vary: Vec<String>,
    /// Output directory for sweep.csv and sweep.json. Default:
    /// `<stem>-sweep` in the current directory.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads, 1 to 1024 (default: every core).
    #[arg(long, allow_hyphen_values = true)]
    threads: Option<usize>,
}

/// The largest grid a sweep runs.
const MAX_POINTS: usize = 1_000_000;

/// The largest number of values on one axis.
const MAX_AXIS_POINTS: usize = 100_000;

/// One axis of the grid.
#[derive(Debug, Clone, PartialEq)]
struct Axis {
    key: SceneKey,
    values: Vec<f64>,
}

/// Parses `KEY=FROM:TO:COUNT` or `KEY=V1,V2,...`.
fn parse_axis(spec: &str) -> Result<Axis, String> {
    let (key, values) = spec
        .split_once('=')
        .ok_or_else(|| format!("--vary {spec}: expected KEY=FROM:TO:COUNT or KEY=V1,V2,..."))?;
    let key: SceneKey = key.parse().map_err(|e: fpc::InputError| match e {
        fpc::InputError::Unrecognised { value, rule, .. } => {
            format!("--vary {spec}: `{value}` is {rule}")
        }
        e => format!("--vary {spec}: {e}"),
    })?;
    let kind = key.value();
    if !kind.takes_number() {
        return Err(format!("--vary {key}: the key takes {kind}, not a number"));
    }
    let number = |s: &str| -> Result<f64, String> {
        let v: f64 = s
            .trim()
            .parse()
            .map_err(|_| format!("--vary {key}: '{}' is not a number", s.trim()))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("--vary {key}: {v} is not finite"))
        }
    };
    let values = if values.contains(':') {
        let parts: Vec<&str> = values.split(':').collect();
        let [from, to, count] = parts[..] else {
            return Err(format!("--vary {key}: a range is FROM:TO:COUNT"));
        };
        let (from, to) = (number(from)?, number(to)?);
        let count: usize = count.trim().parse().map_err(|_| {
            format!(
                "--vary {key}: COUNT '{}' is not a whole number",
                count.trim()
            )
        })?;
        if !(1..=MAX_AXIS_POINTS).contains(&count) {
            return Err(format!(
                "--vary {key}: COUNT must lie in [1, {MAX_AXIS_POINTS}], got {count}"
            ));
        }
        if count == 1 && from != to {
            return Err(format!(
                "--vary {key}: one point cannot span {} to {}",
                Num(from),
                Num(to)
            ));
        }
        // (a span past f64's range, 1e308 to -1e308, is weighted instead
        // of stepped: the same ends, no overflow)
        let span = to - from;
        (0..count)
            .map(|i| {
                let (i, last) = (i as f64, count.max(2) as f64 - 1.0);
                if span.is_finite() {
                    from + span * i / last
                } else {
                    let t = i / last;
                    from * (1.0 - t) + to * t
                }
            })
            .collect()
    } else {
        values
            .split(',')
            .map(number)
            .collect::<Result<Vec<_>, _>>()?
    };
    if values.is_empty() || values.len() > MAX_AXIS_POINTS {
        return Err(format!(
            "--vary {key}: between 1 and {MAX_AXIS_POINTS} values"
        ));
    }
    Ok(Axis { key, values })
}

/// One point's outcome.
#[derive(Debug, Clone, Serialize)]
struct Row {
    /// The varied keys' values, in axis order.
    values: Vec<f64>,
    /// `ok`, `failed` (the solve did not converge), `rejected` (the
    /// scene is invalid at this point) or `stopped` (not solved: Ctrl-C
    /// came before its solve returned).
    status: &'static str,
    /// The tip and end angle; with a tip tolerance the refinement's best
    /// (extrapolated) ones, which `tip_error_mm` is of.
    tip_x_mm: Option<f64>,
    tip_z_mm: Option<f64>,
    end_angle_deg: Option<f64>,
    /// With a tip tolerance: the estimated error of the tip (mm).
    tip_error_mm: Option<f64>,
    elements: Option<usize>,
    /// Newton iterations; with a tip tolerance, over every level.
    iterations: Option<usize>,
    residual: Option<f64>,
    stable: Option<bool>,
    /// No validity finding, and the grasp (if any) breaks no rule.
    valid: Option<bool>,
    normal_n: Option<f64>,
    friction_n: Option<f64>,
    lift_n: Option<f64>,
    size_mm: Option<f64>,
    /// Warning kinds, `;`-separated.
    warnings: String,
    /// The error, or the warnings' text.
    message: String,
}

/// A row with no answer yet: `status` and the values only.
fn blank(values: Vec<f64>, status: &'static str) -> Row {
    Row {
        values,
        status,
        tip_x_mm: None,
        tip_z_mm: None,
        end_angle_deg: None,
        tip_error_mm: None,
        elements: None,
        iterations: None,
        residual: None,
        stable: None,
        valid: None,
        normal_n: None,
        friction_n: None,
        lift_n: None,
        size_mm: None,
        warnings: String::new(),
        message: String::new(),
    }
}

/// The status of a point that Ctrl-C left unsolved.
const STOPPED: &str = "stopped";

/// A point that Ctrl-C left unsolved.
fn stopped(values: Vec<f64>) -> Row {
    Row {
        message: "not solved: the sweep was stopped (Ctrl-C)".to_string(),
        ..blank(values, STOPPED)
    }
}

fn row(values: Vec<f64>, r: &Result<SceneSolution, String>, rejected: bool) -> Row {
    let mut out = blank(values, "ok");
    match r {
        Err(e) => {
            out.status = if rejected { "rejected" } else { "failed" };
            out.message = e.clone();
        }
        Ok(s) => {
            let sol = s.solution();
            let (tip, end_angle, tip_error, iterations) = match s {
                SceneSolution::Finger(f) => (
                    f.tip(),
                    f.end_angle(),
                    f.estimated_tip_error_mm(),
                    f.iterations(),
                ),
                SceneSolution::Gripper { .. } => {
                    (sol.tip, sol.end_angle, None, sol.report.iterations)
                }
            };
            out.tip_x_mm = Some(tip[0]);
            out.tip_z_mm = Some(tip[1]);
            out.end_angle_deg = Some(end_angle.to_degrees());
            out.tip_error_mm = tip_error;
            out.elements = Some(s.elements());
            out.iterations = Some(iterations);
            out.residual = Some(sol.report.residual_norm);
            out.stable = sol.stable;
            let warnings = s.warnings();
            let mut valid = !warnings.iter().any(|w| w.is_validity());
            // why a grasp is not valid, as `fpc solve` says it, first
            let mut messages: Vec<String> = Vec::new();
            if let SceneSolution::Gripper { grasp: Some(g), .. } = s {
                valid &= g.is_valid();
                messages.extend(g.invalid().map(|i| format!("not valid: {i}")));
                out.normal_n = Some(g.grasp.normal);
                out.friction_n = Some(g.grasp.friction);
                out.lift_n = Some(g.grasp.lift);
                out.size_mm = Some(g.grasp.size);
            }
            out.valid = Some(valid);
            out.warnings = warnings
                .iter()
                .map(|w| w.kind())
                .collect::<Vec<_>>()
                .join(";");
            messages.extend(warnings.iter().map(warning_text));
            out.message = messages.join("; ");
        }
    }
    out
}

/// The scene at one grid point, or the reason it is rejected.
fn scene_at(base: &toml::Table, axes: &[Axis], values: &[f64]) -> Result<Scene, String> {
    let mut doc = base.clone();
    for (a, &v) in axes.iter().zip(values) {
        fpc::scene::SceneFile::set_number(&mut doc, a.key, v).map_err(|e| e.to_string())?;
    }
    let file = fpc::scene::SceneFile::from_table(&doc).map_err(|e| e.to_string())?;
    let mut scene = file.resolve().map_err(|e| e.to_string())?;
    // a row has no shape and no radius: a finger is not sampled for them
    // (grasps sample their fingers as they need, whatever this says)
    scene.options.shape = false;
    Ok(scene)
}

/// Solves one line of the grid (the last axis), warm-starting along it.
/// Under a set cancellation flag (Ctrl-C) the rest of the line is
/// `stopped`, and so is a point whose solve returned after it was set: a
/// solve cut short may have failed, or taken another way, because of it.
fn solve_line(base: &toml::Table, axes: &[Axis], outer: &[f64], done: &AtomicUsize) -> Vec<Row> {
    let last = &axes[axes.len() - 1];
    let mut warm: Option<SceneSolution> = None;
    let mut rows = Vec::with_capacity(last.values.len());
    for &v in &last.values {
        let mut values = outer.to_vec();
        values.push(v);
        let r = match scene_at(base, axes, &values) {
            _ if fpc::cancel::is_cancelled() => stopped(values),
            Err(e) => row(values, &Err(e), true),
            Ok(scene) => {
                let solved = scene.solve_warm(warm.as_ref());
                if fpc::cancel::is_cancelled() {
                    stopped(values)
                } else {
                    let rejected = matches!(solved, Err(SolveError::Input(_)));
                    let r = solved.map_err(|e| e.to_string());
                    let out = row(values, &r, rejected);
                    // a failed point starts the next one cold
                    warm = r.ok();
                    out
                }
            }
        };
        rows.push(r);
        done.fetch_add(1, Ordering::Relaxed);
    }
    rows
}

/// Every combination of the outer axes (all but the last), in order.
fn outer_points(axes: &[Axis]) -> Vec<Vec<f64>> {
    let mut points = vec![Vec::new()];
    for a in &axes[..axes.len() - 1] {
        points = points
            .into_iter()
            .flat_map(|p| {
                a.values.iter().map(move |&v| {
                    let mut q = p.clone();
                    q.push(v);
                    q
                })
            })
            .collect();
    }
    points
}

/// sweep.csv into `out`.
fn write_csv(out: &mut dyn std::io::Write, axes: &[Axis], rows: &[Row]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_writer(out);
    let mut header: Vec<String> = axes.iter().map(|a| a.key.to_string()).collect();
    header.extend(
        [
            "status",
            "tip_x_mm",
            "tip_z_mm",
            "end_angle_deg",
            "tip_error_mm",
            "elements",
            "iterations",
            "residual",
            "stable",
            "valid",
            "normal_n",
            "friction_n",
            "lift_n",
            "size_mm",
            "warnings",
            "message",
        ]
        .map(String::from),
    );
    w.write_record(&header)?;
    // values exactly (`0.5`, `1e-300`); results to 10 decimals, or 10
    // digits after an exponent's point where the decimals show none
    let num = |v: Option<f64>| v.map(|x| format!("{:.10}", Num(x))).unwrap_or_default();
    let text = |v: Option<String>| v.unwrap_or_default();
    for r in rows {
        let mut rec: Vec<String> = r.values.iter().map(|&v| Num(v).to_string()).collect();
        rec.push(r.status.to_string());
        rec.push(num(r.tip_x_mm));
        rec.push(num(r.tip_z_mm));
        rec.push(num(r.end_angle_deg));
        rec.push(text(r.tip_error_mm.map(|v| format!("{v:.3e}"))));
        rec.push(text(r.elements.map(|v| v.to_string())));
        rec.push(text(r.iterations.map(|v| v.to_string())));
        rec.push(text(r.residual.map(|v| format!("{v:.3e}"))));
        rec.push(text(r.stable.map(|v| v.to_string())));
        rec.push(text(r.valid.map(|v| v.to_string())));
        rec.push(num(r.normal_n));
        rec.push(num(r.friction_n));
        rec.push(num(r.lift_n));
        rec.push(num(r.size_mm));
        rec.push(r.warnings.clone());
        rec.push(r.message.clone());
        w.write_record(&rec)?;
    }
    w.flush()?;
    Ok(())
}

#[derive(Serialize)]
struct Report<'a> {
    scene: String,
    axes: Vec<AxisJson<'a>>,
    points: usize,
    ok: usize,
    failed: usize,
    rejected: usize,
    /// Points Ctrl-C left unsolved (rows with status `stopped`).
    stopped: usize,
    invalid: usize,
    provenance: crate::provenance::Provenance,
    rows: &'a [Row],
}

#[derive(Serialize)]
struct AxisJson<'a> {
    key: String,
    values: &'a [f64],
}

/// The most worker threads of a sweep.
const MAX_THREADS: usize = 1024;

pub fn run(args: &Args) -> anyhow::Result<()> {
    if let Some(t) = args.threads {
        if !(1..=MAX_THREADS).contains(&t) {
            return Err(crate::status::rejected(format!(
                "--threads = {t}: must lie in [1, {MAX_THREADS}]"
            )));
        }
    }
    let axes: Vec<Axis> = args
        .vary
        .iter()
        .map(|s| parse_axis(s).map_err(crate::status::rejected))
        .collect::<anyhow::Result<_>>()?;
    for (i, a) in axes.iter().enumerate() {
        if axes[..i].iter().any(|b| b.key == a.key) {
            return Err(crate::status::rejected(format!(
                "--vary {}: the key is varied twice",
                a.key
            )));
        }
    }
    let total = axes
        .iter()
        .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
        .filter(|&n| n <= MAX_POINTS)
        .ok_or_else(|| {
            crate::status::rejected(format!("the grid has more than {MAX_POINTS} points"))
        })?;
    let shown = args.scene.display().to_string();
    let text = crate::solve::read_scene(&args.scene, &shown)?;
    // the file must be a valid scene as it stands
    Scene::from_toml(&text).map_err(|e| crate::status::rejected(format!("{shown}:{e}")))?;
    let base: toml::Table =
        toml::from_str(&text).map_err(|e| crate::status::rejected(format!("{shown}: {e}")))?;
    // every varied key is a numeric key of the schema (parse_axis); a list
    // entry must also exist in the file, and a whole-number key must get
    // whole numbers: each value is set once before any work (a value out of
    // range is the point's own rejection, found later)
    for a in &axes {
        for &v in &a.values {
            fpc::scene::SceneFile::set_number(&mut base.clone(), a.key, v)
                .map_err(|e| crate::status::rejected(format!("--vary {e}")))?;
        }
    }
    let (_, out) = crate::output::stem_and_dir(&args.scene, args.out.as_deref(), "scene", "sweep");
    crate::output::prepare_dir(&out)?;

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("cannot start the worker threads")?;
    let done = AtomicUsize::new(0);
    let lines = outer_points(&axes);
    let stop = crate::interrupt::arm("the points done are written, the others marked `stopped`");
    let status = || {
        let d = done.load(Ordering::Relaxed);
        format!("fpc sweep: {d}/{total} points")
    };
    let rows: Vec<Row> = crate::report::with_progress(status, || {
        pool.install(|| {
            lines
                .par_iter()
                .map(|outer| {
                    let line = || solve_line(&base, &axes, outer, &done);
                    match &stop {
                        Some(flag) => fpc::cancel::with_flag(flag.clone(), line),
                        None => line(),
                    }
                })
                .collect::<Vec<_>>()
        })
    })
    .into_iter()
    .flatten()
    .collect();
    let count = |s: &str| rows.iter().filter(|r| r.status == s).count();
    let report = Report {
        scene: shown.clone(),
        axes: axes
            .iter()
            .map(|a| AxisJson {
                key: a.key.to_string(),
                values: &a.values,
            })
            .collect(),
        points: rows.len(),
        ok: count("ok"),
        failed: count("failed"),
        rejected: count("rejected"),
        stopped: count(STOPPED),
        invalid: rows.iter().filter(|r| r.valid == Some(false)).count(),
        provenance: crate::provenance::Provenance::now(),
        rows: &rows,
    };
    // streamed: a million rows are never one string in memory
    crate::output::write_atomic_with(&out, "sweep.csv", |w| write_csv(w, &axes, &rows))?;
    crate::output::write_atomic_with(&out, "sweep.json", |w| {
        serde_json::to_writer_pretty(&mut *w, &report)?;
        Ok(writeln!(w)?)
    })?;
    let mut stdout = crate::output::stdout();
    writeln!(
        stdout,
        "sweep          {shown}: {} points over {}",
        rows.len(),
        axes.iter()
            .map(|a| format!("{} ({} values)", a.key, a.values.len()))
            .collect::<Vec<_>>()
            .join(" x ")
    )?;
    writeln!(
        stdout,
        "outcome        {} ok ({} outside the model or invalid), {} failed, {} rejected{}",
        report.ok,
        report.invalid,
        report.failed,
        report.rejected,
        match report.stopped {
            0 => String::new(),
            n => format!(", {n} stopped (Ctrl-C)"),
        }
    )?;
    writeln!(
        stdout,
        "wrote          {}, {}",
        out.join("sweep.csv").display(),
        out.join("sweep.json").display()
    )?;
    if report.stopped > 0 {
        return Err(crate::status::interrupted(format!(
            "stopped by Ctrl-C: {} of {total} points done; the other {} are rows with status `stopped`",
            total - report.stopped,
            report.stopped
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_parse_ranges_and_lists() {
        let a = parse_axis("load.fx=0:2:5").unwrap();
        assert_eq!(a.key.to_string(), "load.fx");
        assert_eq!(a.values, vec![0.0, 0.5, 1.0, 1.5, 2.0]);
        let b = parse_axis("load.pressure_kpa=0,50,100").unwrap();
        assert_eq!(b.values, vec![0.0, 50.0, 100.0]);
        assert_eq!(
            parse_axis("load.fz=-1:-3:3").unwrap().values,
            vec![-1.0, -2.0, -3.0]
        );
        assert_eq!(parse_axis("load.fz=7:7:1").unwrap().values, vec![7.0]);
        // ends whose difference overflows: the same ends, finite between
        assert_eq!(
            parse_axis("load.pressure_kpa=1e308:-1e308:3")
                .unwrap()
                .values,
            vec![1e308, 0.0, -1e308]
        );
        assert_eq!(
            parse_axis("partition.lengths[3]=1,2")
                .unwrap()
                .key
                .to_string(),
            "partition.lengths[3]"
        );
        for bad in [
            "load.fx",
            "=1,2",
            "load..fx=1",
            "load.fx=1:2",
            "load.fx=1:2:0",
            "load.fx=a,b",
            "load.fx=nan",
            "load.fx=1:2:1",
            "load fx=1",
            "load.fx=0:1:1000001",
            "a.b=1,2",
            "gripper.strict=0,1",
        ] {
            assert!(parse_axis(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_grid_is_the_cartesian_product_in_order() {
        let axes = vec![
            parse_axis("load.fx=1,2").unwrap(),
            parse_axis("load.fz=10,20,30").unwrap(),
            parse_axis("load.kappa=0,1").unwrap(),
        ];
        let outer = outer_points(&axes);
        assert_eq!(
            outer,
            vec![
                vec![1.0, 10.0],
                vec![1.0, 20.0],
                vec![1.0, 30.0],
                vec![2.0, 10.0],
                vec![2.0, 20.0],
                vec![2.0, 30.0]
            ]
        );
        assert_eq!(outer_points(&axes[2..]), vec![Vec::<f64>::new()]);
    }
}
