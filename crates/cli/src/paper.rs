//! `fpc paper`: run the paper's eight studies (docs/model.md section 6) with the
//! default actuator and write, into one directory, a CSV table and an SVG
//! figure per study, `summary.json` with the key numbers, and `index.html`
//! showing every figure.
//!
//! Every file is written atomically (temporary file, then rename). A study
//! that fails does not stop the others: its files say so, `summary.json`
//! lists it under `failures`, and the command exits non-zero at the end.

mod figures;
mod files;
mod plot;

use std::io::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use fpc::{
    Actuator, CuboidRegion, CurvatureCurve, DisplacementForceRow, ForceControl, Invalid, LiftCurve,
    SolveError, SphereRegion, StudyOptions, SweepStop, ViableAngles,
};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Map, Value};

use figures::{angle_name, axis_name};
use files::{escape, num, opt, write_atomic, Cell, Csv};

/// Flags of `fpc paper`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output directory (created if missing; files in it are replaced).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Coarse sweeps (StudyOptions::coarse()), for tests and previews.
    #[arg(long, hide = true)]
    coarse: bool,
}

/// The cuboid tested against the study-3 region: d (mm), f_v (N).
const CUBOID_TEST: (f64, f64) = (100.0, 0.3);

/// Title and one-line description of each study.
const STUDIES: [(&str, &str); 8] = [
    (
        "Prestrain × mounting angle",
        "eps0 in {0.4, 0.25, 0.15} × a in {π/2, π/2.5, π/3}, no overlap (l = 2 l0), grasping angle b = 0, full friction f = μF: unloaded finger shapes in the gripper frame, the max lifting force f_v against the grasping size d, and d_max = l + 2 Lx cos a against a (Sec. 4.1).",
    ),
    (
        "Overlap",
        "eps0 = 0.25, a in {π/2, π/2.5, π/3}, overlap g in {0, 10, 20} mm: max f_v against d per overlap, and d_max = 2 (l0 − g + Lx cos a) against g (Sec. 4.2).",
    ),
    (
        "Cuboid grasping region",
        "The Sec. 5 gripper (eps0 = 0.25, a = π/3, g = 20 mm), b = 0: cuboids of size d needing lifting force f_v per finger can be held when the point lies under the max f_v curve (Sec. 5.1.1).",
    ),
    (
        "Force control by pressure",
        "The same gripper holds a cuboid of d = 100 mm with friction f = 0.3 N per finger; for each pressure, the normal force F that holds it and the finger height h (Sec. 5.1.2).",
    ),
    (
        "Sphere grasping region",
        "The same gripper; grasping angle b swept over [−arctan μ, π/2), at each the grasping size swept with f = μF, r = d / (2 cos b), invalid grasps (not open, second contact, friction) dropped; the envelope is the best b at each radius (Sec. 5.2.1).",
    ),
    (
        "Viable grasping angles",
        "A sphere r = 50 mm needing f_v = 0.5 N per finger: the grasping angles b at which some F with 0 ≤ f ≤ μF holds it validly (Sec. 5.2.2).",
    ),
    (
        "Curvature against pressure",
        "Unloaded fingers, eps0 in {0.15, 0.25, 0.4}, pressure 0 to 400 kPa: radius of curvature by circle fit; past flat the curl reverses (Sec. 6.2).",
    ),
    (
        "Force at a fixed displacement",
        "From the pressurised unloaded shape at 0, 27.6, 55.2 and 82.7 kPa, the tip force that moves the tip 10 mm: along +X for the eps0 = 0.4 sample, along +Z for the eps0 = 0.15 sample (Sec. 6.3).",
    ),
];

pub fn run(args: &Args) -> anyhow::Result<()> {
    let started = Instant::now();
    crate::output::prepare_dir(&args.out)?;
    let dir = args.out.clone();
    let opts = if args.coarse {
        StudyOptions::coarse()
    } else {
        StudyOptions::default()
    };
    let act = Actuator::default();
    let mut out = Output::new(dir, opts, args.coarse);

    let bar = progress_bar(STUDIES.len() as u64);
    let step = |n: usize| {
        bar.set_message(format!("study {n}: {}", STUDIES[n - 1].0));
    };

    // one study: label the bar, run it timed, write its files, tick
    macro_rules! study {
        ($n:expr, $run:path, $write:ident) => {{
            step($n);
            let (r, t) = timed(|| $run(&act, &opts));
            out.finish($n, t, r, &bar, |o, v| o.$write(v))?;
            bar.inc(1);
        }};
    }
    study!(1, fpc::study1_prestrain_angle, study1);
    study!(2, fpc::study2_overlap, study2);
    study!(3, fpc::study3_cuboid_region, study3);
    study!(4, fpc::study4_force_control, study4);
    study!(5, fpc::study5_sphere_region, study5);
    study!(6, fpc::study6_viable_angles, study6);
    study!(7, fpc::study7_curvature, study7);
    study!(8, fpc::study8_force_at_displacement, study8);
    bar.finish_and_clear();

    let elapsed = started.elapsed().as_secs_f64();
    out.write_summary(elapsed)?;
    out.write_index()?;
    writeln!(
        crate::output::stdout(),
        "fpc paper: {} files in {} ({} of 8 studies ok, {} sweeps stopped early) in {:.1} s",
        out.files.len(),
        args.out.display(),
        8 - out.failed_studies().len(),
        out.stops.len(),
        elapsed
    )?;
    if !out.failed.is_empty() {
        let more = match out.failed.len() {
            1 => String::new(),
            k => format!(" (and {} more failures, see summary.json)", k - 1),
        };
        let (n, e) = out.failed.swap_remove(0);
        return Err(e.context(format!(
            "study {n} ({}) failed{more}; the other results were written to {}",
            STUDIES[n - 1].0,
            args.out.display()
        )));
    }
    Ok(())
}

fn timed<T>(f: impl FnOnce() -> T) -> (T, Duration) {
    let t = Instant::now();
    let r = f();
    (r, t.elapsed())
}

fn progress_bar(len: u64) -> ProgressBar {
    // draws on stderr, and not at all when stderr is not a terminal
    let bar = ProgressBar::new(len);
    let style = ProgressStyle::with_template("{spinner} [{elapsed}] [{bar:24}] {pos}/{len} {msg}")
        .map(|s| s.progress_chars("=> "))
        .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar.enable_steady_tick(Duration::from_millis(120));
    bar
}

/// A small table for index.html: header row, then rows.
type Table = Vec<Vec<String>>;

/// One study's section of index.html.
struct Section {
    number: usize,
    ok: bool,
    table: Table,
    notes: Vec<String>,
    csvs: Vec<String>,
    seconds: f64,
}

/// Everything written so far and what summary.json and index.html need.
struct Output {
    dir: PathBuf,
    opts: StudyOptions,
    coarse: bool,
    files: Vec<String>,
    summary: Map<String, Value>,
    /// Failed studies and figures: (study, error). A failed solve keeps
    /// its [`SolveError`] in the chain (for the exit code).
    failed: Vec<(usize, anyhow::Error)>,
    stops: Vec<Value>,
    warnings: Vec<String>,
    sections: Vec<Section>,
}

fn fmt(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$}")
    } else {
        "–".into()
    }
}

fn fmt_opt(x: Option<f64>, digits: usize) -> String {
    x.map_or("–".into(), |x| fmt(x, digits))
}

fn stop_json(s: &Option<SweepStop>, unit: &str) -> Value {
    match s {
        Some(s) => json!({ format!("at_{unit}"): num(s.at), "reason": s.reason }),
        None => Value::Null,
    }
}

fn invalid_text(i: &Invalid) -> &'static str {
    i.kind()
}

const LIFT_HEADER_1: &[&str] = &[
    "eps0",
    "angle_rad",
    "palm_mm",
    "l0_mm",
    "dmax_mm",
    "d_mm",
    "tip_gap_mm",
    "F_n",
    "fv_n",
    "h_mm",
    "status",
    "note",
];
const LIFT_HEADER_2: &[&str] = &[
    "angle_rad",
    "g_mm",
    "palm_mm",
    "l0_mm",
    "dmax_mm",
    "d_mm",
    "tip_gap_mm",
    "F_n",
    "fv_n",
    "h_mm",
    "status",
    "note",
];
const SHAPES_HEADER: &[&str] = &["eps0", "angle_rad", "xg_mm", "zg_mm", "status", "note"];
const HEADER_3: &[&str] = &[
    "d_mm",
    "tip_gap_mm",
    "F_n",
    "fv_max_n",
    "h_mm",
    "status",
    "note",
];
const HEADER_4: &[&str] = &[
    "pressure_kpa",
    "F_n",
    "h_mm",
    "tip_gap_mm",
    "friction_ok",
    "status",
    "note",
];
const HEADER_5: &[&str] = &["beta_rad", "r_mm", "fv_n", "F_n", "d_mm", "status", "note"];
const ENVELOPE_HEADER: &[&str] = &["r_mm", "beta_rad", "fv_n", "F_n", "status", "note"];
const HEADER_6: &[&str] = &[
    "beta_rad", "F_n", "f_n", "f_over_F", "viable", "invalid", "status", "note",
];
const HEADER_7: &[&str] = &[
    "eps0",
    "pressure_kpa",
    "radius_mm",
    "curvature_per_mm",
    "reversed",
    "end_angle_rad",
    "tip_x_mm",
    "tip_z_mm",
    "status",
    "note",
];
const HEADER_8: &[&str] = &[
    "eps0",
    "axis",
    "pressure_kpa",
    "displacement_mm",
    "force_n",
    "status",
    "note",
];

/// The CSV files of each study (the first one carries the failure row).
fn csv_files(n: usize) -> Vec<(String, &'static [&'static str])> {
    let main = (
        format!("study{n}.csv"),
        match n {
            1 => LIFT_HEADER_1,
            2 => LIFT_HEADER_2,
            3 => HEADER_3,
            4 => HEADER_4,
            5 => HEADER_5,
            6 => HEADER_6,
            7 => HEADER_7,
            _ => HEADER_8,
        },
    );
    let mut v = vec![main];
    match n {
        1 => v.push(("study1_shapes.csv".into(), SHAPES_HEADER)),
        5 => v.push(("study5_envelope.csv".into(), ENVELOPE_HEADER)),
        _ => {}
    }
    v
}

impl Output {
    fn new(dir: PathBuf, opts: StudyOptions, coarse: bool) -> Output {
        let mut summary = Map::new();
        // the required keys exist even when their study fails
        for (k, v) in [
            ("dmax_mm", json!([])),
            ("cuboid_region_contains", Value::Null),
            ("force_control", json!([])),
            ("sphere_envelope_peak_radius_mm", Value::Null),
            ("sphere_beta_range_rad", Value::Null),
            ("radius_vs_pressure", json!([])),
            ("force_at_10mm", json!([])),
        ] {
            summary.insert(k.into(), v);
        }
        Output {
            dir,
            opts,
            coarse,
            files: Vec::new(),
            summary,
            failed: Vec::new(),
            stops: Vec::new(),
            warnings: Vec::new(),
            sections: Vec::new(),
        }
    }

    fn write(&mut self, name: &str, text: &str) -> anyhow::Result<()> {
        write_atomic(&self.dir, name, text.as_bytes())?;
        if !self.files.iter().any(|f| f == name) {
            self.files.push(name.to_string());
        }
        Ok(())
    }

    fn stop(&mut self, study: usize, case: String, unit: &str, s: &SweepStop) {
        self.stops.push(json!({
            "study": study,
            "case": case,
            format!("at_{unit}"): num(s.at),
            "reason": s.reason,
        }));
    }

    /// Writes study `n`'s figure; a figure that cannot be drawn is
    /// replaced by a placeholder and recorded as a failure.
    fn svg(&mut self, n: usize, svg: anyhow::Result<String>) -> anyhow::Result<()> {
        match svg {
            Ok(text) => self.write(&format!("study{n}.svg"), &text),
            Err(e) => {
                let e = e.context(format!("cannot draw the figure of study {n}"));
                let text = plot::placeholder(
                    &format!("Study {n}: {}", STUDIES[n - 1].0),
                    &format!("{e:#}"),
                );
                self.failed.push((n, e));
                self.write(&format!("study{n}.svg"), &text)
            }
        }
    }

    /// The studies with a failure, in order, without repeats.
    fn failed_studies(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self.failed.iter().map(|f| f.0).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Writes study `n`'s files from its result (or its failure), and
    /// records its section.
    fn finish<T>(
        &mut self,
        n: usize,
        time: Duration,
        result: Result<T, SolveError>,
        bar: &ProgressBar,
        write: impl FnOnce(&mut Output, &T) -> anyhow::Result<(Table, Vec<String>)>,
    ) -> anyhow::Result<()> {
        let csvs: Vec<String> = csv_files(n).into_iter().map(|c| c.0).collect();
        let (ok, table, notes) = match result {
            Ok(v) => {
                let (table, notes) = write(self, &v)?;
                (true, table, notes)
            }
            Err(e) => {
                bar.suspend(|| {
                    crate::report::note(&format!("study {n} ({}) failed: {e}", STUDIES[n - 1].0))
                });
                let msg = e.to_string();
                for (name, header) in csv_files(n) {
                    let mut t = Csv::new(header);
                    t.sparse_row(vec![
                        ("status", "failed".into()),
                        ("note", msg.clone().into()),
                    ]);
                    self.write(&name, &t.into_string())?;
                }
                let svg = plot::placeholder(
                    &format!("Study {n}: {}", STUDIES[n - 1].0),
                    &format!("failed: {msg}"),
                );
                self.write(&format!("study{n}.svg"), &svg)?;
                self.failed.push((n, anyhow::Error::new(e)));
                (false, Vec::new(), vec![format!("failed: {msg}")])
            }
        };
        self.sections.push(Section {
            number: n,
            ok,
            table,
            notes,
            csvs,
            seconds: time.as_secs_f64(),
        });
        Ok(())
    }

    fn lift_rows(t: &mut Csv, c: &LiftCurve, lead: [Cell; 2]) {
        for p in &c.points {
            let [x, y] = lead.clone();
            t.row(vec![
                x,
                y,
                c.palm.into(),
                c.l0.into(),
                c.d_max.into(),
                p.size.into(),
                p.tip_gap.into(),
                p.normal.into(),
                p.lift.into(),
                p.height.into(),
                "ok".into(),
                Cell::Empty,
            ]);
        }
        if let Some(s) = &c.stopped {
            let [x, y] = lead;
            t.row(vec![
                x,
                y,
                c.palm.into(),
                c.l0.into(),
                c.d_max.into(),
                s.at.into(),
                Cell::Empty,
                Cell::Empty,
                Cell::Empty,
                Cell::Empty,
                "stopped".into(),
                s.reason.clone().into(),
            ]);
        }
    }

    fn collect_warnings(&mut self, curves: &[LiftCurve]) {
        for c in curves {
            for w in &c.warnings {
                let w = w.to_string();
                if !self.warnings.contains(&w) {
                    self.warnings.push(w);
                }
            }
        }
    }

    fn study1(&mut self, curves: &[LiftCurve]) -> anyhow::Result<(Table, Vec<String>)> {
        let mut t = Csv::new(LIFT_HEADER_1);
        let mut shapes = Csv::new(SHAPES_HEADER);
        let mut dmax = Vec::new();
        let mut table = vec![row(&[
            "eps0",
            "a",
            "l0 (mm)",
            "l (mm)",
            "d_max (mm)",
            "swept to d (mm)",
            "max f_v (N)",
        ])];
        let mut notes = Vec::new();
        for c in curves {
            Self::lift_rows(&mut t, c, [c.eps0.into(), c.mounting_angle.into()]);
            for q in &c.rest_shape {
                shapes.row(vec![
                    c.eps0.into(),
                    c.mounting_angle.into(),
                    q[0].into(),
                    q[1].into(),
                    "ok".into(),
                    Cell::Empty,
                ]);
            }
            let max_lift = max_of(c.points.iter().map(|p| p.lift));
            dmax.push(json!({
                "eps0": c.eps0,
                "angle_rad": num(c.mounting_angle),
                "dmax_mm": num(c.d_max),
                "l0_mm": num(c.l0),
                "palm_mm": num(c.palm),
                "reached_mm": num(c.reached()),
                "max_fv_n": opt(max_lift),
                "stopped": stop_json(&c.stopped, "mm"),
            }));
            table.push(vec![
                c.eps0.to_string(),
                angle_name(c.mounting_angle),
                fmt(c.l0, 1),
                fmt(c.palm, 1),
                fmt(c.d_max, 1),
                fmt(c.reached(), 1),
                fmt_opt(max_lift, 3),
            ]);
            if let Some(s) = &c.stopped {
                let case = format!("eps0 = {}, a = {}", c.eps0, angle_name(c.mounting_angle));
                notes.push(format!(
                    "{case}: sweep stopped at d = {:.1} mm: {}",
                    s.at, s.reason
                ));
                self.stop(1, case, "mm", s);
            }
        }
        self.collect_warnings(curves);
        self.summary.insert("dmax_mm".into(), Value::Array(dmax));
        self.write("study1.csv", &t.into_string())?;
        self.write("study1_shapes.csv", &shapes.into_string())?;
        self.svg(1, figures::study1(curves))?;
        Ok((table, notes))
    }

    fn study2(&mut self, curves: &[LiftCurve]) -> anyhow::Result<(Table, Vec<String>)> {
        let mut t = Csv::new(LIFT_HEADER_2);
        let mut list = Vec::new();
        let mut table = vec![row(&[
            "a",
            "g (mm)",
            "l (mm)",
            "d_max (mm)",
            "swept to d (mm)",
            "max f_v (N)",
        ])];
        let mut notes = Vec::new();
        for c in curves {
            Self::lift_rows(&mut t, c, [c.mounting_angle.into(), c.overlap.into()]);
            let max_lift = max_of(c.points.iter().map(|p| p.lift));
            list.push(json!({
                "angle_rad": num(c.mounting_angle),
                "g_mm": num(c.overlap),
                "dmax_mm": num(c.d_max),
                "l0_mm": num(c.l0),
                "palm_mm": num(c.palm),
                "reached_mm": num(c.reached()),
                "max_fv_n": opt(max_lift),
                "stopped": stop_json(&c.stopped, "mm"),
            }));
            table.push(vec![
                angle_name(c.mounting_angle),
                fmt(c.overlap, 0),
                fmt(c.palm, 1),
                fmt(c.d_max, 1),
                fmt(c.reached(), 1),
                fmt_opt(max_lift, 3),
            ]);
            if let Some(s) = &c.stopped {
                let case = format!("a = {}, g = {} mm", angle_name(c.mounting_angle), c.overlap);
                notes.push(format!(
                    "{case}: sweep stopped at d = {:.1} mm: {}",
                    s.at, s.reason
                ));
                self.stop(2, case, "mm", s);
            }
        }
        self.collect_warnings(curves);
        self.summary
            .insert("overlap_dmax_mm".into(), Value::Array(list));
        self.write("study2.csv", &t.into_string())?;
        self.svg(2, figures::study2(curves))?;
        Ok((table, notes))
    }

    fn study3(&mut self, region: &CuboidRegion) -> anyhow::Result<(Table, Vec<String>)> {
        let c = &region.curve;
        let mut t = Csv::new(HEADER_3);
        for p in &c.points {
            t.row(vec![
                p.size.into(),
                p.tip_gap.into(),
                p.normal.into(),
                p.lift.into(),
                p.height.into(),
                "ok".into(),
                Cell::Empty,
            ]);
        }
        let mut notes = Vec::new();
        if let Some(s) = &c.stopped {
            t.sparse_row(vec![
                ("d_mm", s.at.into()),
                ("status", "stopped".into()),
                ("note", s.reason.clone().into()),
            ]);
            notes.push(format!("sweep stopped at d = {:.1} mm: {}", s.at, s.reason));
            self.stop(3, "cuboid region".into(), "mm", s);
        }
        let (d, fv) = CUBOID_TEST;
        let contains = region.contains(d, fv);
        let at_test = c.max_lift(d);
        let d_min = c.points.first().map(|p| p.size);
        self.summary
            .insert("cuboid_region_contains".into(), Value::Bool(contains));
        self.summary.insert(
            "cuboid_region".into(),
            json!({
                "test_d_mm": d,
                "test_fv_n": fv,
                "max_fv_at_test_d_n": opt(at_test),
                "d_min_mm": opt(d_min),
                "reached_mm": num(c.reached()),
                "dmax_mm": num(c.d_max),
                "palm_mm": num(c.palm),
                "l0_mm": num(c.l0),
                "stopped": stop_json(&c.stopped, "mm"),
            }),
        );
        let table = vec![
            row(&["quantity", "value"]),
            vec![
                format!("cuboid d = {d} mm, f_v = {fv} N inside the region"),
                if contains { "yes" } else { "no" }.into(),
            ],
            vec![format!("max f_v at d = {d} mm (N)"), fmt_opt(at_test, 3)],
            vec![
                "grasping sizes swept (mm)".into(),
                format!("{} to {}", fmt_opt(d_min, 1), fmt(c.reached(), 1)),
            ],
            vec!["d_max (mm)".into(), fmt(c.d_max, 1)],
            vec![
                "palm l / reach l0 (mm)".into(),
                format!("{} / {}", fmt(c.palm, 1), fmt(c.l0, 1)),
            ],
        ];
        self.collect_warnings(std::slice::from_ref(c));
        self.write("study3.csv", &t.into_string())?;
        self.svg(3, figures::study3(region, CUBOID_TEST))?;
        Ok((table, notes))
    }

    fn study4(&mut self, fc: &ForceControl) -> anyhow::Result<(Table, Vec<String>)> {
        let mut t = Csv::new(HEADER_4);
        let mut list = Vec::new();
        let mut table = vec![row(&["P (kPa)", "F (N)", "h (mm)", "f ≤ μF"])];
        for r in &fc.rows {
            t.row(vec![
                r.pressure_kpa.into(),
                r.normal.into(),
                r.height.into(),
                r.tip_gap.into(),
                r.friction_ok.into(),
                "ok".into(),
                Cell::Empty,
            ]);
            list.push(json!({
                "pressure_kpa": num(r.pressure_kpa),
                "F_n": num(r.normal),
                "h_mm": num(r.height),
                "tip_gap_mm": num(r.tip_gap),
                "friction_ok": r.friction_ok,
            }));
            table.push(vec![
                fmt(r.pressure_kpa, 0),
                fmt(r.normal, 3),
                fmt(r.height, 1),
                if r.friction_ok { "yes" } else { "no" }.into(),
            ]);
        }
        let mut notes = Vec::new();
        if let Some(s) = &fc.stopped {
            t.sparse_row(vec![
                ("pressure_kpa", s.at.into()),
                ("status", "stopped".into()),
                ("note", s.reason.clone().into()),
            ]);
            notes.push(format!(
                "pressure sweep stopped at {:.1} kPa: {}",
                s.at, s.reason
            ));
            self.stop(4, "force control".into(), "kpa", s);
        }
        self.summary
            .insert("force_control".into(), Value::Array(list));
        self.summary.insert(
            "force_control_case".into(),
            json!({
                "d_mm": num(fc.size),
                "f_n": num(fc.friction),
                "stopped": stop_json(&fc.stopped, "kpa"),
            }),
        );
        self.write("study4.csv", &t.into_string())?;
        self.svg(4, figures::study4(fc, self.opts.mu))?;
        Ok((table, notes))
    }

    fn study5(&mut self, region: &SphereRegion) -> anyhow::Result<(Table, Vec<String>)> {
        let mut t = Csv::new(HEADER_5);
        for p in &region.points {
            t.row(vec![
                p.beta.into(),
                p.radius.into(),
                p.lift.into(),
                p.normal.into(),
                p.size.into(),
                "ok".into(),
                Cell::Empty,
            ]);
        }
        let mut notes = Vec::new();
        for (beta, s) in &region.stopped {
            t.sparse_row(vec![
                ("beta_rad", (*beta).into()),
                ("d_mm", s.at.into()),
                ("status", "stopped".into()),
                ("note", s.reason.clone().into()),
            ]);
            self.stop(5, format!("b = {beta:.6} rad"), "mm", s);
        }
        if !region.stopped.is_empty() {
            notes.push(format!(
                "{} of the {} grasping-angle sweeps stopped before d_max (rows with status 'stopped' in study5.csv)",
                region.stopped.len(),
                self.opts.angle_samples
            ));
        }
        let mut env = Csv::new(ENVELOPE_HEADER);
        for e in &region.envelope {
            env.row(vec![
                e.radius.into(),
                e.beta.into(),
                e.lift.into(),
                e.normal.into(),
                "ok".into(),
                Cell::Empty,
            ]);
        }
        let peak = region.peak;
        self.summary.insert(
            "sphere_envelope_peak_radius_mm".into(),
            opt(peak.map(|p| p.radius)),
        );
        self.summary.insert(
            "sphere_region".into(),
            json!({
                "valid_points": region.points.len(),
                "dropped_points": region.dropped,
                "stopped_sweeps": region.stopped.len(),
                "peak": peak.map(|p| json!({
                    "r_mm": num(p.radius),
                    "beta_rad": num(p.beta),
                    "fv_n": num(p.lift),
                    "F_n": num(p.normal),
                })),
            }),
        );
        let table = vec![
            row(&["quantity", "value"]),
            vec![
                "valid grasps / dropped".into(),
                format!("{} / {}", region.points.len(), region.dropped),
            ],
            vec![
                "envelope peak radius (mm)".into(),
                fmt_opt(peak.map(|p| p.radius), 2),
            ],
            vec![
                "envelope peak f_v (N)".into(),
                fmt_opt(peak.map(|p| p.lift), 3),
            ],
            vec![
                "grasping angle at the peak (deg)".into(),
                fmt_opt(peak.map(|p| p.beta.to_degrees()), 1),
            ],
            vec![
                "radii covered (mm)".into(),
                match (
                    min_of(region.points.iter().map(|p| p.radius)),
                    max_of(region.points.iter().map(|p| p.radius)),
                ) {
                    (Some(a), Some(b)) => format!("{} to {}", fmt(a, 1), fmt(b, 1)),
                    _ => "–".into(),
                },
            ],
        ];
        self.write("study5.csv", &t.into_string())?;
        self.write("study5_envelope.csv", &env.into_string())?;
        self.svg(5, figures::study5(region))?;
        Ok((table, notes))
    }

    fn study6(&mut self, v: &ViableAngles) -> anyhow::Result<(Table, Vec<String>)> {
        let mut t = Csv::new(HEADER_6);
        let mut failed = 0;
        for s in &v.scan {
            let solved = s.failure.is_none();
            failed += usize::from(!solved);
            let ratio = (solved && s.normal != 0.0).then(|| s.friction / s.normal);
            t.row(vec![
                s.beta.into(),
                if solved {
                    Cell::Num(s.normal)
                } else {
                    Cell::Empty
                },
                if solved {
                    Cell::Num(s.friction)
                } else {
                    Cell::Empty
                },
                ratio.into(),
                s.viable.into(),
                s.invalid
                    .as_ref()
                    .map_or(Cell::Empty, |i| invalid_text(i).into()),
                if solved { "ok" } else { "failed" }.into(),
                s.failure.clone().map_or(Cell::Empty, Cell::Text),
            ]);
        }
        let range = v.range();
        self.summary.insert(
            "sphere_beta_range_rad".into(),
            range.map_or(Value::Null, |[a, b]| json!([num(a), num(b)])),
        );
        self.summary.insert(
            "sphere_viable_angles".into(),
            json!({
                "r_mm": num(v.radius),
                "fv_n": num(v.lift),
                "intervals_rad": v.intervals.iter().map(|iv| json!([num(iv[0]), num(iv[1])])).collect::<Vec<_>>(),
                "samples": v.scan.len(),
                "viable_samples": v.scan.iter().filter(|s| s.viable).count(),
                "failed_samples": failed,
            }),
        );
        let mut table = vec![row(&["quantity", "value"])];
        table.push(vec![
            "viable b (rad)".into(),
            range.map_or("none".into(), |[a, b]| {
                format!("[{}, {}]", fmt(a, 4), fmt(b, 4))
            }),
        ]);
        table.push(vec![
            "viable b (deg)".into(),
            range.map_or("none".into(), |[a, b]| {
                format!("[{}, {}]", fmt(a.to_degrees(), 1), fmt(b.to_degrees(), 1))
            }),
        ]);
        table.push(vec![
            "separate intervals".into(),
            v.intervals.len().to_string(),
        ]);
        table.push(vec![
            "angles scanned / viable".into(),
            format!(
                "{} / {}",
                v.scan.len(),
                v.scan.iter().filter(|s| s.viable).count()
            ),
        ]);
        let mut notes = Vec::new();
        if failed > 0 {
            notes.push(format!(
                "{failed} scanned angles did not solve (status 'failed' in study6.csv)"
            ));
        }
        self.write("study6.csv", &t.into_string())?;
        self.svg(6, figures::study6(v, self.opts.mu))?;
        Ok((table, notes))
    }

    fn study7(&mut self, curves: &[CurvatureCurve]) -> anyhow::Result<(Table, Vec<String>)> {
        let mut t = Csv::new(HEADER_7);
        let mut list = Vec::new();
        let mut table = vec![row(&[
            "eps0",
            "R at 0 kPa (mm)",
            "R at the last pressure (mm)",
            "last pressure (kPa)",
            "curl reversed from (kPa)",
        ])];
        let mut notes = Vec::new();
        for c in curves {
            let mut points = Vec::new();
            for r in &c.rows {
                t.row(vec![
                    c.eps0.into(),
                    r.pressure_kpa.into(),
                    r.radius.into(),
                    r.curvature.into(),
                    r.reversed().into(),
                    r.end_angle.into(),
                    r.tip[0].into(),
                    r.tip[1].into(),
                    "ok".into(),
                    if r.radius.is_none() {
                        "straight".into()
                    } else {
                        Cell::Empty
                    },
                ]);
                points.push(json!({
                    "pressure_kpa": num(r.pressure_kpa),
                    "radius_mm": opt(r.radius),
                    "curvature_per_mm": num(r.curvature),
                    "reversed": r.reversed(),
                }));
            }
            if let Some(s) = &c.stopped {
                t.sparse_row(vec![
                    ("eps0", c.eps0.into()),
                    ("pressure_kpa", s.at.into()),
                    ("status", "stopped".into()),
                    ("note", s.reason.clone().into()),
                ]);
                let case = format!("eps0 = {}", c.eps0);
                notes.push(format!(
                    "{case}: pressure sweep stopped at {:.1} kPa: {}",
                    s.at, s.reason
                ));
                self.stop(7, case, "kpa", s);
            }
            let reversed_from = c.rows.iter().find(|r| r.reversed()).map(|r| r.pressure_kpa);
            list.push(json!({
                "eps0": c.eps0,
                "reversed": reversed_from.is_some(),
                "reversed_from_kpa": opt(reversed_from),
                "points": points,
                "stopped": stop_json(&c.stopped, "kpa"),
            }));
            let first = c.rows.first();
            let last = c.rows.last();
            table.push(vec![
                c.eps0.to_string(),
                fmt_opt(first.and_then(|r| r.radius), 1),
                match last {
                    Some(r) => {
                        let s = fmt_opt(r.radius, 1);
                        if r.reversed() {
                            format!("{s} (reversed)")
                        } else {
                            s
                        }
                    }
                    None => "–".into(),
                },
                fmt_opt(last.map(|r| r.pressure_kpa), 0),
                reversed_from.map_or("not reversed".into(), |p| fmt(p, 0)),
            ]);
        }
        self.summary
            .insert("radius_vs_pressure".into(), Value::Array(list));
        self.write("study7.csv", &t.into_string())?;
        self.svg(7, figures::study7(curves))?;
        Ok((table, notes))
    }

    fn study8(&mut self, rows: &[DisplacementForceRow]) -> anyhow::Result<(Table, Vec<String>)> {
        let mut t = Csv::new(HEADER_8);
        let mut list = Vec::new();
        let mut table = vec![row(&["eps0", "axis", "P (kPa)", "force for 10 mm (N)"])];
        let mut notes = Vec::new();
        for r in rows {
            let axis = axis_name(r.axis);
            t.row(vec![
                r.eps0.into(),
                axis.into(),
                r.pressure_kpa.into(),
                10.0.into(),
                r.force.into(),
                if r.force.is_some() { "ok" } else { "failed" }.into(),
                if r.force.is_some() {
                    Cell::Empty
                } else {
                    "no solution".into()
                },
            ]);
            list.push(json!({
                "axis": axis,
                "eps0": r.eps0,
                "pressure_kpa": num(r.pressure_kpa),
                "force_n": opt(r.force),
            }));
            table.push(vec![
                r.eps0.to_string(),
                format!("+{axis}"),
                r.pressure_kpa.to_string(),
                fmt_opt(r.force, 4),
            ]);
            if r.force.is_none() {
                let case = format!("eps0 = {}, axis {axis}", r.eps0);
                notes.push(format!("{case}: no solution at {} kPa", r.pressure_kpa));
                self.stop(
                    8,
                    case,
                    "kpa",
                    &SweepStop {
                        at: r.pressure_kpa,
                        reason: "no solution".into(),
                    },
                );
            }
        }
        self.summary
            .insert("force_at_10mm".into(), Value::Array(list));
        self.write("study8.csv", &t.into_string())?;
        self.svg(8, figures::study8(rows))?;
        Ok((table, notes))
    }

    fn write_summary(&mut self, elapsed: f64) -> anyhow::Result<()> {
        let mut s = self.summary.clone();
        s.insert(
            "failures".into(),
            Value::Array(
                self.failed
                    .iter()
                    .map(|(n, e)| json!({ "study": n, "name": STUDIES[n - 1].0, "error": format!("{e:#}") }))
                    .collect(),
            ),
        );
        s.insert("sweeps_stopped".into(), Value::Array(self.stops.clone()));
        s.insert("warnings".into(), json!(self.warnings));
        s.insert(
            "studies".into(),
            Value::Array(
                self.sections
                    .iter()
                    .map(|sec| {
                        json!({
                            "study": sec.number,
                            "name": STUDIES[sec.number - 1].0,
                            "status": if !sec.ok || self.failed.iter().any(|f| f.0 == sec.number) { "failed" } else if self.stops.iter().any(|v| v["study"] == sec.number) { "partial" } else { "ok" },
                            "seconds": num(sec.seconds),
                            "figure": format!("study{}.svg", sec.number),
                            "tables": sec.csvs,
                        })
                    })
                    .collect(),
            ),
        );
        s.insert(
            "options".into(),
            json!({
                "actuator": "default (docs/model.md section 3)",
                "elements": self.opts.elements,
                "mu": num(self.opts.mu),
                "sweep_points": self.opts.sweep_points,
                "angle_samples": self.opts.angle_samples,
                "pressure_points": self.opts.pressure_points,
                "coarse": self.coarse,
            }),
        );
        s.insert("fpc_version".into(), json!(env!("CARGO_PKG_VERSION")));
        s.insert("run_seconds".into(), num(elapsed));
        let mut files = self.files.clone();
        files.push("summary.json".into());
        files.push("index.html".into());
        s.insert("files".into(), json!(files));
        let text = serde_json::to_string_pretty(&Value::Object(s))? + "\n";
        self.write("summary.json", &text)
    }

    fn write_index(&mut self) -> anyhow::Result<()> {
        let mut h = String::new();
        h.push_str(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <title>fpc: the paper's studies</title>\n<style>\n\
             body { font-family: sans-serif; max-width: 1400px; margin: 2em auto; padding: 0 1em; color: #222; }\n\
             section { border-top: 1px solid #ccc; padding-top: 1em; margin-top: 2em; }\n\
             img { max-width: 100%; height: auto; border: 1px solid #eee; }\n\
             table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.92em; }\n\
             th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }\n\
             th { background: #f3f3f3; }\n\
             .failed { color: #b00000; font-weight: bold; }\n\
             .note { color: #8a5a00; }\n\
             .small { color: #666; font-size: 0.9em; }\n\
             </style>\n</head>\n<body>\n",
        );
        h.push_str("<h1>Fluidic prestressed composite grippers: the paper's eight studies</h1>\n");
        h.push_str(&format!(
            "<p class=\"small\">fpc {}, default actuator, N = {} elements, μ = {}{}. \
             Key numbers: <a href=\"summary.json\">summary.json</a>.</p>\n",
            env!("CARGO_PKG_VERSION"),
            self.opts.elements,
            self.opts.mu,
            if self.coarse {
                ", coarse sweeps (preview)"
            } else {
                ""
            }
        ));
        let failed = self.failed_studies();
        if !failed.is_empty() {
            h.push_str(&format!(
                "<p class=\"failed\">{} of 8 studies failed: {}.</p>\n",
                failed.len(),
                failed
                    .iter()
                    .map(|n| format!("<a href=\"#study{n}\">study {n}</a>"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        if !self.warnings.is_empty() {
            h.push_str("<p class=\"note\">Design warnings:</p>\n<ul>\n");
            for w in &self.warnings {
                h.push_str(&format!("<li class=\"note\">{}</li>\n", escape(w)));
            }
            h.push_str("</ul>\n");
        }
        for sec in &self.sections {
            let n = sec.number;
            let (title, desc) = STUDIES[n - 1];
            h.push_str(&format!(
                "<section id=\"study{n}\">\n<h2>Study {n}: {}</h2>\n<p>{}</p>\n",
                escape(title),
                escape(desc)
            ));
            if !sec.ok {
                h.push_str("<p class=\"failed\">This study failed; no results.</p>\n");
            } else {
                for (_, e) in self.failed.iter().filter(|f| f.0 == n) {
                    h.push_str(&format!(
                        "<p class=\"failed\">{}</p>\n",
                        escape(&format!("{e:#}"))
                    ));
                }
            }
            for note in &sec.notes {
                let class = if sec.ok { "note" } else { "failed" };
                h.push_str(&format!("<p class=\"{class}\">{}</p>\n", escape(note)));
            }
            h.push_str(&format!(
                "<img src=\"study{n}.svg\" alt=\"Figure of study {n}: {}\">\n",
                escape(title)
            ));
            if let Some((head, rows)) = sec.table.split_first() {
                h.push_str("<table>\n<tr>");
                for c in head {
                    h.push_str(&format!("<th>{}</th>", escape(c)));
                }
                h.push_str("</tr>\n");
                for r in rows {
                    h.push_str("<tr>");
                    for c in r {
                        h.push_str(&format!("<td>{}</td>", escape(c)));
                    }
                    h.push_str("</tr>\n");
                }
                h.push_str("</table>\n");
            }
            h.push_str(&format!(
                "<p class=\"small\">Data: {} · computed in {:.2} s</p>\n</section>\n",
                sec.csvs
                    .iter()
                    .map(|c| format!("<a href=\"{0}\">{0}</a>", escape(c)))
                    .collect::<Vec<_>>()
                    .join(", "),
                sec.seconds
            ));
        }
        h.push_str("</body>\n</html>\n");
        self.write("index.html", &h)
    }
}

fn row(cells: &[&str]) -> Vec<String> {
    cells.iter().map(|c| c.to_string()).collect()
}

fn max_of(it: impl Iterator<Item = f64>) -> Option<f64> {
    it.filter(|x| x.is_finite()).reduce(f64::max)
}

fn min_of(it: impl Iterator<Item = f64>) -> Option<f64> {
    it.filter(|x| x.is_finite()).reduce(f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fpc::InputError;
    use std::path::Path;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("fpc-paper-unit-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn read(dir: &Path, name: &str) -> String {
        std::fs::read_to_string(dir.join(name)).unwrap()
    }

    #[test]
    fn a_failed_study_is_recorded_and_the_others_go_on() {
        let dir = scratch("failed");
        let mut out = Output::new(dir.clone(), StudyOptions::coarse(), true);
        let bar = ProgressBar::hidden();
        let err = SolveError::Input(InputError::NotFinite {
            field: "test.value".into(),
            value: f64::NAN,
        });
        out.finish(
            3,
            Duration::ZERO,
            Err::<CuboidRegion, _>(err),
            &bar,
            |o, v| o.study3(v),
        )
        .unwrap();
        // a sweep that stopped keeps the points computed before the stop
        let row = |p: f64| fpc::ForceControlRow {
            pressure_kpa: p,
            normal: 1.0 - 0.01 * p,
            height: 50.0,
            tip_gap: 100.0,
            friction_ok: true,
            valid: true,
            invalid: None,
            reversed: false,
            warnings: Vec::new(),
        };
        let fc = ForceControl {
            size: 100.0,
            friction: 0.3,
            rows: vec![row(0.0), row(10.0)],
            stopped: Some(SweepStop {
                at: 20.0,
                reason: "solve failed: test".into(),
            }),
        };
        out.finish(4, Duration::ZERO, Ok(fc), &bar, |o, v| o.study4(v))
            .unwrap();
        out.svg(8, Err(anyhow::anyhow!("boom"))).unwrap();
        out.write_summary(0.0).unwrap();
        out.write_index().unwrap();

        let svg = read(&dir, "study8.svg");
        assert!(
            svg.contains("cannot draw the figure of study 8: boom"),
            "{svg}"
        );
        let csv = read(&dir, "study3.csv");
        assert!(csv.starts_with("d_mm,"), "{csv}");
        assert!(csv.contains(",failed,"), "{csv}");
        let svg = read(&dir, "study3.svg");
        assert!(svg.starts_with("<svg") && svg.contains("failed") && svg.contains("</svg>"));
        let csv4 = read(&dir, "study4.csv");
        let lines: Vec<&str> = csv4.lines().collect();
        assert_eq!(lines.len(), 4, "{csv4}");
        assert!(
            lines[1].starts_with("0,") && lines[1].contains(",ok,"),
            "{csv4}"
        );
        assert!(
            lines[2].starts_with("10,") && lines[2].contains(",ok,"),
            "{csv4}"
        );
        assert!(
            lines[3].starts_with("20,") && lines[3].ends_with(",stopped,solve failed: test"),
            "{csv4}"
        );

        let s: Value = serde_json::from_str(&read(&dir, "summary.json")).unwrap();
        assert_eq!(s["failures"][0]["study"], json!(3));
        assert!(s["failures"][0]["error"]
            .as_str()
            .unwrap()
            .contains("test.value"));
        assert_eq!(s["cuboid_region_contains"], Value::Null);
        assert_eq!(s["sweeps_stopped"][0]["study"], json!(4));
        assert_eq!(s["sweeps_stopped"][0]["at_kpa"], json!(20.0));
        assert_eq!(s["force_control"].as_array().map(Vec::len), Some(2));
        assert_eq!(s["studies"][0]["status"], json!("failed"));
        assert_eq!(s["studies"][1]["status"], json!("partial"));
        for key in [
            "dmax_mm",
            "force_control",
            "sphere_envelope_peak_radius_mm",
            "sphere_beta_range_rad",
            "radius_vs_pressure",
            "force_at_10mm",
        ] {
            assert!(s.get(key).is_some(), "{key} missing");
        }
        let html = read(&dir, "index.html");
        assert!(html.contains("<img src=\"study3.svg\"") && html.contains("failed"));
        assert_eq!(s["failures"][1]["study"], json!(8));
        assert_eq!(out.failed_studies(), vec![3, 8]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_stopped_lift_sweep_is_a_csv_row() {
        let curve = LiftCurve {
            eps0: 0.25,
            mounting_angle: std::f64::consts::FRAC_PI_3,
            overlap: 20.0,
            palm: 66.4,
            l0: 53.2,
            d_max: 176.4,
            rest_shape: vec![[33.2, 0.0], [40.0, 20.0]],
            points: vec![fpc::LiftPoint {
                size: 0.0,
                tip_gap: 0.0,
                normal: 0.4,
                lift: 0.24,
                height: 78.0,
                reversed: false,
                valid: true,
                warnings: Vec::new(),
            }],
            dropped: 0,
            stopped: Some(SweepStop {
                at: 5.5,
                reason: "solve failed: line search, test".into(),
            }),
            warnings: Vec::new(),
        };
        let mut t = Csv::new(LIFT_HEADER_2);
        Output::lift_rows(&mut t, &curve, [curve.mounting_angle.into(), 20.0.into()]);
        let text = t.into_string();
        let lines: Vec<&str> = text.lines().collect();
        // header, the point computed before the stop, the stop
        assert_eq!(lines.len(), 3, "{text}");
        assert!(lines[1].ends_with(",ok,"), "{text}");
        let last = lines[2];
        assert!(
            last.ends_with(",5.5,,,,,stopped,\"solve failed: line search, test\""),
            "{last}"
        );
    }
}
