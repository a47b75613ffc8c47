//! `fpc paper`: run every study of the library's registry
//! ([`fpc::studies::STUDIES`], docs/model.md section 6) with the default actuator and
//! write, into one directory, each study's tables as CSV and its figure as
//! SVG (and PNG or PDF with `--format`), `summary.json` with the key numbers and validity counts, and
//! `index.html` showing every figure.
//!
//! Nothing here knows a particular study: each one hands back its outputs
//! as data ([`fpc::studies::StudyOutput`]) and this module writes them all the same
//! way. Every file is written atomically (temporary file, then rename). A
//! study that fails does not stop the others: its files say so,
//! `summary.json` lists it under `failures`, and the command exits non-zero
//! at the end.

mod index;
/// The SVG writer, where `fpc design` calls it.
pub(crate) use fpc_cli::render::svg as render;

use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use fpc::report::{Cell, Overview};
use fpc::scene::Covariance;
use fpc::studies::{not_propagated, BandColumn, StudyInfo, StudyOutput, STUDIES};
use fpc::studies::{NOTE, STATUS};
use fpc::{Actuator, ModelId, SolveError, StudyOptions};
use serde_json::{json, Map, Value};

use crate::output::write_atomic;
use crate::render::csv;
use crate::render::formats::{remove_figure, FormatArgs};

/// Flags of `fpc paper`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output directory (created if missing; files in it are replaced).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Strict mode: grasps that bend an element backwards are invalid and
    /// dropped, as the paper's analysis assumes.
    #[arg(long)]
    strict: bool,
    /// Coarse sweeps (StudyOptions::coarse()), for tests and previews.
    #[arg(long, hide = true)]
    coarse: bool,
    /// Run the studies on the actuator (and element model) of a scene file
    /// instead of the paper's default actuator; its load, solve and
    /// gripper tables are not used (the studies set their own), nor a
    /// partition other than `elements = N` (a note says so). A scene
    /// with a [calibration] covariance (a calibrated scene) adds 1-sigma
    /// bands to all eight studies (study 5: its envelope) by first-order propagation through exact
    /// sensitivities: a `<column>_sd` column per banded column of their
    /// CSV, shaded bands in their figures, `_sd` values in summary.json
    /// and its `uncertainty` entry (the parameters propagated, those left
    /// out and why: each curve's eps0 and load.kappa are the studies' own,
    /// the method of each column). Without a covariance nothing changes.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// The element model (`fpc models`; default: the scene's, else ccm).
    #[arg(long)]
    model: Option<String>,
    /// Elements per finger (default: the scene's count, else 8).
    #[arg(long, allow_hyphen_values = true)]
    elements: Option<usize>,
    /// Printed width of the figures in inches, 0.5 to 1000 (the SVG's
    /// width and height become inches; default: their pixel size).
    #[arg(long, value_name = "INCHES", allow_hyphen_values = true)]
    width_in: Option<f64>,
    /// Printed size of the figures' tick labels in points, 1 to 100, at
    /// --width-in (every other text scales with it; default: as drawn).
    #[arg(long, value_name = "POINTS", allow_hyphen_values = true)]
    font_pt: Option<f64>,
    // the SVG of every figure is written whatever is asked: index.html
    // shows it
    #[command(flatten)]
    format: crate::render::formats::FormatArgs,
}

/// What the studies run on: the actuator, model and element count, a
/// description of where they came from, and the scene's `[calibration]`
/// covariance if it has one.
struct Setup {
    actuator: Actuator,
    model: ModelId,
    elements: Option<usize>,
    source: String,
    covariance: Option<Covariance>,
    /// The scene's partition when the studies cannot take it (only equal
    /// elements are taken, by their count), as its table says it.
    partition_unused: Option<String>,
}

/// The actuator, model and element count the studies run on, and a
/// description of where they came from.
fn setup(args: &Args) -> anyhow::Result<Setup> {
    let Some(path) = &args.scene else {
        let model = match &args.model {
            Some(m) => ModelId::parse(fpc::Field::key("--model"), m)?,
            None => ModelId::default(),
        };
        return Ok(Setup {
            actuator: Actuator::default(),
            model,
            elements: None,
            source: "the default (docs/model.md section 3)".into(),
            covariance: None,
            partition_unused: None,
        });
    };
    let shown = path.display().to_string();
    let text = crate::solve::read_scene(path, &shown)?;
    let scene = fpc::scene::Scene::from_toml(&text)
        .map_err(|e| crate::status::rejected(format!("{shown}:{e}")))?;
    let model = match &args.model {
        Some(m) => ModelId::parse(fpc::Field::key("--model"), m)?,
        None => scene.model,
    };
    let elements = match &scene.partition {
        fpc::scene::PartitionPlan::Fixed(p) => {
            let l = p.lengths();
            // the studies use equal elements: take the count of an equal partition
            (l.iter().all(|&x| (x - l[0]).abs() <= 1e-9 * l[0])).then_some(l.len())
        }
        _ => None,
    };
    let partition_unused = match &scene.partition {
        _ if elements.is_some() => None,
        fpc::scene::PartitionPlan::Fixed(_) => Some("lengths of unequal elements".to_string()),
        fpc::scene::PartitionPlan::TipTolerance { tip_tol_mm, .. } => {
            Some(format!("tip_tol_mm = {}", fpc::num::Num(*tip_tol_mm)))
        }
        fpc::scene::PartitionPlan::Auto => Some("elements = \"auto\"".to_string()),
    };
    Ok(Setup {
        actuator: scene.actuator.clone(),
        model,
        elements,
        source: format!("the scene {shown}'s"),
        covariance: scene.covariance().cloned(),
        partition_unused,
    })
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let started = Instant::now();
    let base = if args.coarse {
        StudyOptions::coarse()
    } else {
        StudyOptions::default()
    };
    let style = render::Style {
        width_in: args.width_in,
        font_pt: args.font_pt,
    };
    style.validate()?;
    let Setup {
        actuator: act,
        model,
        elements: scene_elements,
        source,
        covariance,
        partition_unused,
    } = setup(args)?;
    let opts = StudyOptions {
        strict: args.strict,
        model,
        elements: args.elements.or(scene_elements).unwrap_or(base.elements),
        ..base
    };
    // (the one study option a flag sets is named by it)
    opts.validate().map_err(|e| {
        if args.elements.is_some() && e.field() == "study.elements" {
            e.renamed(fpc::Field::key("--elements"), |v| v)
        } else {
            e
        }
    })?;
    // every input checked: only now the output directory
    crate::output::prepare_dir(&args.out)?;
    for w in act.warnings() {
        crate::report::warning(&w.to_string());
    }
    let mut out = Output::new(args.out.clone(), opts, args.coarse, source);
    out.style = style;
    out.formats = args.format.with_svg();
    out.covariance = covariance;
    if let Some(partition) = partition_unused {
        out.notes.push(format!(
            "the scene's [partition] ({partition}) is not used: the studies run on {} equal elements ({}); its load, solve and gripper tables are not used either",
            opts.elements,
            if args.elements.is_some() { "--elements" } else { "the default; --elements sets the count" }
        ));
    }

    for (i, info) in STUDIES.iter().enumerate() {
        let total = STUDIES.len();
        crate::report::progress_on_terminal(&format!(
            "fpc paper: {i}/{total} studies; {}",
            info.title
        ));
        let t = Instant::now();
        let result = info.output_with(&act, &opts, out.covariance.as_ref());
        out.finish(info, t.elapsed(), result)?;
    }
    crate::report::end_progress();

    let elapsed = started.elapsed().as_secs_f64();
    out.write_summary(elapsed)?;
    out.write_index()?;
    writeln!(
        crate::output::stdout(),
        "fpc paper: {} files in {} ({} of {} studies ok, {} sweeps ended at a natural end, {} stopped early) in {:.1} s",
        out.files.len(),
        args.out.display(),
        STUDIES.len() - out.failed_studies().len(),
        STUDIES.len(),
        out.ends.len(),
        out.stops.len(),
        elapsed
    )?;
    for n in &out.notes {
        writeln!(crate::output::stdout(), "note           {n}")?;
    }
    if !out.failed.is_empty() {
        let more = match out.failed.len() {
            1 => String::new(),
            k => format!(" (and {} more failures, see summary.json)", k - 1),
        };
        let (n, e) = out.failed.swap_remove(0);
        return Err(e.context(format!(
            "study {n} ({}) failed{more}; the other results were written to {}",
            title(n),
            args.out.display()
        )));
    }
    Ok(())
}

fn title(n: usize) -> &'static str {
    STUDIES
        .iter()
        .find(|s| s.number == n)
        .map_or("unknown", |s| s.title)
}

/// One study's part of index.html and summary.json.
struct Section {
    info: &'static StudyInfo,
    ok: bool,
    overview: Overview,
    notes: Vec<String>,
    /// What the figure's caption says about its panels (title, note):
    /// axes clipped.
    figure_notes: Vec<(String, String)>,
    csvs: Vec<String>,
    seconds: f64,
    points: usize,
    warnings_by_kind: BTreeMap<String, usize>,
    strict_dropped: usize,
    /// Its banded columns and their methods (with a covariance).
    bands: Vec<BandColumn>,
}

/// Everything written so far and what summary.json and index.html need.
struct Output {
    dir: PathBuf,
    opts: StudyOptions,
    coarse: bool,
    /// Print sizing of the figures.
    style: render::Style,
    /// The formats every figure is written in (svg among them, for
    /// index.html).
    formats: FormatArgs,
    /// Where the actuator came from (`default ...` or `scene PATH`).
    source: String,
    provenance: crate::provenance::Provenance,
    files: Vec<String>,
    summary: Map<String, Value>,
    /// Failed studies and figures: (study, error). A failed solve keeps
    /// its [`SolveError`] in the chain (for the exit code).
    failed: Vec<(usize, anyhow::Error)>,
    /// `sweeps_stopped`: `{study, case, at_mm | at_kpa, reason}` (failed
    /// solves).
    stops: Vec<Value>,
    /// `sweep_ends`: sweeps that ended at a natural end (`end`: a fold, the
    /// validity limit, a force bound).
    ends: Vec<Value>,
    /// The grippers' design warnings, each once.
    warnings: Vec<String>,
    sections: Vec<Section>,
    /// The scene's `[calibration]` covariance: the studies' bands.
    covariance: Option<Covariance>,
    /// What the run does not take from its scene, as `fpc design --scene`
    /// says it: `notes` of summary.json, a `note` line each on stdout.
    notes: Vec<String>,
}

impl Output {
    fn new(dir: PathBuf, opts: StudyOptions, coarse: bool, source: String) -> Output {
        Output {
            dir,
            opts,
            coarse,
            style: render::Style::default(),
            formats: FormatArgs::default(),
            source,
            provenance: crate::provenance::Provenance::now(),
            files: Vec::new(),
            summary: Map::new(),
            failed: Vec::new(),
            stops: Vec::new(),
            ends: Vec::new(),
            warnings: Vec::new(),
            notes: Vec::new(),
            sections: Vec::new(),
            covariance: None,
        }
    }

    fn write(&mut self, name: &str, bytes: &[u8]) -> anyhow::Result<()> {
        write_atomic(&self.dir, name, bytes)?;
        if !self.files.iter().any(|f| f == name) {
            self.files.push(name.to_string());
        }
        Ok(())
    }

    /// Writes one figure's rendered files.
    fn write_files(&mut self, files: Vec<(String, Vec<u8>)>) -> anyhow::Result<()> {
        for (name, bytes) in files {
            self.write(&name, &bytes)?;
        }
        Ok(())
    }

    /// Writes one figure from its SVG in every format asked for, and
    /// removes an earlier run's files of it in the others.
    fn write_figure(&mut self, stem: &str, svg: &str) -> anyhow::Result<()> {
        let files = self.formats.render(stem, svg)?;
        self.write_files(files)?;
        remove_figure(&self.dir, stem, &self.formats.list())
    }

    /// Writes a study's figure; a figure that cannot be drawn or rendered
    /// is replaced by a placeholder and recorded as a failure.
    fn figure(&mut self, info: &StudyInfo, svg: anyhow::Result<String>) -> anyhow::Result<()> {
        let stem = info.stem();
        let files = svg.and_then(|text| Ok(self.formats.render(&stem, &text)?));
        match files {
            Ok(files) => {
                self.write_files(files)?;
                remove_figure(&self.dir, &stem, &self.formats.list())
            }
            Err(e) => {
                let n = info.number;
                let e = e.context(format!("cannot draw the figure of study {n}"));
                let text =
                    render::placeholder(&format!("Study {n}: {}", info.title), &format!("{e:#}"));
                self.failed.push((n, e));
                self.write_figure(&stem, &text)
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

    /// Writes a study's files from its outputs (or its failure), and
    /// records its section.
    fn finish(
        &mut self,
        info: &'static StudyInfo,
        time: Duration,
        result: Result<StudyOutput, SolveError>,
    ) -> anyhow::Result<()> {
        let n = info.number;
        let (ok, out) = match result {
            Ok(out) => (true, out),
            Err(e) => {
                if crate::report::is_terminal() {
                    crate::report::end_progress(); // the note on a line of its own
                }
                crate::report::note(&format!("study {n} ({}) failed: {e}", info.title));
                let msg = e.to_string();
                let mut empty = (info.empty)();
                for t in &mut empty.tables {
                    t.push_named(vec![
                        (STATUS.name, "failed".into()),
                        (NOTE.name, Cell::Text(msg.clone())),
                    ]);
                }
                empty.notes = vec![format!("failed: {msg}")];
                let svg = render::placeholder(
                    &format!("Study {n}: {}", info.title),
                    &format!("failed: {msg}"),
                );
                self.write_figure(&info.stem(), &svg)?;
                self.failed.push((n, anyhow::Error::new(e)));
                (false, empty)
            }
        };
        let mut csvs = Vec::new();
        for t in &out.tables {
            let name = format!("{}.csv", t.name);
            self.write(&name, &csv::csv(t)?)?;
            csvs.push(name);
        }
        if ok {
            self.figure(info, render::svg_styled(&out.figure, &self.style))?;
        }
        self.summary.extend(out.summary);
        for s in &out.stops {
            let mut v = serde_json::to_value(s)?;
            if let Value::Object(m) = &mut v {
                m.insert("study".into(), json!(n));
            }
            if s.is_natural() {
                self.ends.push(v);
            } else {
                self.stops.push(v);
            }
        }
        for w in out.design_warnings {
            if !self.warnings.contains(&w) {
                self.warnings.push(w);
            }
        }
        self.sections.push(Section {
            info,
            ok,
            overview: if ok {
                out.overview
            } else {
                Overview::default()
            },
            notes: out.notes,
            figure_notes: if ok {
                out.figure.clip_notes()
            } else {
                Vec::new()
            },
            csvs,
            seconds: time.as_secs_f64(),
            points: out.points,
            warnings_by_kind: out.warnings_by_kind,
            strict_dropped: out.strict_dropped,
            bands: out.bands,
        });
        Ok(())
    }

    fn status(&self, sec: &Section) -> &'static str {
        let n = sec.info.number;
        if !sec.ok || self.failed.iter().any(|f| f.0 == n) {
            "failed"
        } else if self.stops.iter().any(|v| v["study"] == n) {
            "partial"
        } else {
            "ok"
        }
    }

    fn write_summary(&mut self, elapsed: f64) -> anyhow::Result<()> {
        let mut s = self.summary.clone();
        s.insert(
            "failures".into(),
            Value::Array(
                self.failed
                    .iter()
                    .map(|(n, e)| json!({ "study": n, "name": title(*n), "error": format!("{e:#}") }))
                    .collect(),
            ),
        );
        s.insert("sweeps_stopped".into(), Value::Array(self.stops.clone()));
        s.insert("sweep_ends".into(), Value::Array(self.ends.clone()));
        // the folds met: the natural ends that are limit points
        let folds: Vec<Value> = self
            .ends
            .iter()
            .filter(|v| v["end"]["kind"] == "fold")
            .cloned()
            .collect();
        s.insert("folds".into(), Value::Array(folds));
        s.insert("warnings".into(), json!(self.warnings));
        s.insert("notes".into(), json!(self.notes));
        s.insert(
            "studies".into(),
            Value::Array(
                self.sections
                    .iter()
                    .map(|sec| {
                        json!({
                            "study": sec.info.number,
                            "key": sec.info.key,
                            "name": sec.info.title,
                            "status": self.status(sec),
                            "seconds": sec.seconds,
                            "figure": format!("{}.svg", sec.info.stem()),
                            "figures": self.formats.names(&sec.info.stem()),
                            "tables": sec.csvs,
                        })
                    })
                    .collect(),
            ),
        );
        // per study that ran: the points that are grasps or finger states,
        // how many raise each validity kind, and what strict mode ruled out
        let validity: Map<String, Value> = self
            .sections
            .iter()
            .filter(|sec| sec.ok)
            .map(|sec| {
                (
                    sec.info.stem(),
                    json!({
                        "points": sec.points,
                        "warnings_by_kind": sec.warnings_by_kind,
                        "strict_dropped": sec.strict_dropped,
                    }),
                )
            })
            .collect();
        s.insert("validity".into(), Value::Object(validity));
        if let Some(cov) = &self.covariance {
            s.insert("uncertainty".into(), self.uncertainty(cov));
        }
        s.insert("strict".into(), json!(self.opts.strict));
        s.insert(
            "options".into(),
            json!({
                "actuator": self.source,
                "model": self.opts.model.name(),
                "elements": self.opts.elements,
                "mu": self.opts.mu,
                "sweep_points": self.opts.sweep_points,
                "angle_samples": self.opts.angle_samples,
                "pressure_points": self.opts.pressure_points,
                "strict": self.opts.strict,
                "coarse": self.coarse,
                "csv_significant_digits": csv::CSV_DIGITS,
            }),
        );
        s.insert("fpc_version".into(), json!(env!("CARGO_PKG_VERSION")));
        s.insert("provenance".into(), serde_json::to_value(&self.provenance)?);
        s.insert("run_seconds".into(), json!(elapsed));
        let mut files = self.files.clone();
        files.push("summary.json".into());
        files.push("index.html".into());
        s.insert("files".into(), json!(files));
        let text = serde_json::to_string_pretty(&Value::Object(s))? + "\n";
        self.write("summary.json", text.as_bytes())
    }

    /// summary.json's `uncertainty`: what the bands propagate, what they
    /// leave out and why, and per study with bands its columns' methods.
    fn uncertainty(&self, cov: &Covariance) -> Value {
        let left_out = not_propagated(cov);
        let propagated: Vec<String> = cov
            .params()
            .iter()
            .map(|p| p.name())
            .filter(|n| !left_out.iter().any(|l| &l.parameter == n))
            .collect();
        let studies: Map<String, Value> = self
            .sections
            .iter()
            .filter(|sec| sec.ok && !sec.bands.is_empty())
            .map(|sec| {
                let methods: Map<String, Value> = sec
                    .bands
                    .iter()
                    .map(|b| (b.column.clone(), json!(b.method)))
                    .collect();
                (sec.info.stem(), Value::Object(methods))
            })
            .collect();
        json!({
            "sigma": 1,
            "parameters": cov.params().iter().map(|p| p.name()).collect::<Vec<_>>(),
            "propagated": propagated,
            "not_propagated": left_out,
            "studies_with_bands": STUDIES.iter().filter(|s| s.has_bands).map(|s| s.number).collect::<Vec<_>>(),
            "methods": studies,
        })
    }

    fn write_index(&mut self) -> anyhow::Result<()> {
        let html = index::html(self);
        self.write("index.html", html.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fpc::report::{Figure, Panel, PlotAxis, Series, SeriesKind};
    use fpc::studies::{Stop, StopAt};
    use fpc::InputError;
    use std::path::Path;

    /// A colour as the SVG writes it (the renderer's own `hex` is compiled
    /// for its unit tests only, in the fpc_cli library).
    fn hex(c: plotters::style::RGBColor) -> String {
        format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
    }

    /// A fresh scratch directory, removed when dropped (a failed test's too).
    fn scratch(name: &str) -> tempfile::TempDir {
        tempfile::Builder::new()
            .prefix(&format!("fpc-paper-unit-{name}-"))
            .tempdir()
            .unwrap()
    }

    fn read(dir: &Path, name: &str) -> String {
        std::fs::read_to_string(dir.join(name)).unwrap()
    }

    #[test]
    fn a_failed_study_is_recorded_and_the_others_go_on() {
        let tmp = scratch("failed");
        let dir = tmp.path();
        let mut out = Output::new(
            dir.to_path_buf(),
            StudyOptions::coarse(),
            true,
            "default".into(),
        );
        let err = SolveError::Input(InputError::NotFinite {
            field: fpc::Field::key("test.value"),
            value: f64::NAN,
        });
        out.finish(&STUDIES[2], Duration::ZERO, Err(err)).unwrap();
        // a study whose sweep stopped keeps the rows computed before the stop
        let mut partial = (STUDIES[3].empty)();
        let t = &mut partial.tables[0];
        t.push_named(vec![
            ("pressure_kpa", 0.0.into()),
            ("F_n", 1.0.into()),
            ("status", "ok".into()),
        ]);
        t.push_named(vec![
            ("pressure_kpa", 20.0.into()),
            ("status", "stopped".into()),
            ("note", "solve failed: test, \"quoted\"".into()),
        ]);
        partial.stops.push(Stop {
            case: "force control".into(),
            at: StopAt::Kpa(20.0),
            reason: "solve failed: test".into(),
            end: None,
        });
        partial.figure = Figure::row(
            "partial <&>",
            [400, 300],
            vec![Panel::new(
                "p",
                PlotAxis::new("pressure P", "kPa"),
                PlotAxis::new("F", "N"),
            )],
        );
        partial.figure.rows[0][0].series.push(Series::new(
            "normal force",
            SeriesKind::LinePoints,
            vec![[0.0, 1.0], [10.0, 0.9]],
        ));
        partial.overview = Overview::new(&["it's \"quoted\""]);
        out.finish(&STUDIES[3], Duration::ZERO, Ok(partial))
            .unwrap();
        out.figure(&STUDIES[7], Err(anyhow::anyhow!("boom")))
            .unwrap();
        out.write_summary(0.0).unwrap();
        out.write_index().unwrap();

        let svg = read(dir, "study8.svg");
        assert!(
            svg.contains("cannot draw the figure of study 8: boom"),
            "{svg}"
        );
        let csv = read(dir, "study3.csv");
        assert!(csv.starts_with("d_mm,"), "{csv}");
        assert!(csv.contains(",failed,"), "{csv}");
        let svg = read(dir, "study3.svg");
        assert!(svg.starts_with("<svg") && svg.contains("failed") && svg.contains("</svg>"));
        let csv4 = read(dir, "study4.csv");
        let lines: Vec<&str> = csv4.lines().collect();
        assert_eq!(lines.len(), 3, "{csv4}");
        assert!(lines[0].ends_with(",reversed,valid,invalid,warnings,status,note"));
        assert!(
            lines[1].starts_with("0,1,") && lines[1].contains(",ok,"),
            "{csv4}"
        );
        assert!(
            lines[2].starts_with("20,")
                && lines[2].ends_with(",stopped,\"solve failed: test, \"\"quoted\"\"\""),
            "{csv4}"
        );
        let svg4 = read(dir, "study4.svg");
        assert!(svg4.contains("partial &lt;&amp;&gt;"), "{svg4}");

        let s: Value = serde_json::from_str(&read(dir, "summary.json")).unwrap();
        assert_eq!(s["failures"][0]["study"], json!(3));
        assert!(s["failures"][0]["error"]
            .as_str()
            .unwrap()
            .contains("test.value"));
        // a failed study's summary keys are there, empty
        assert_eq!(s["cuboid_region_contains"], Value::Null);
        assert_eq!(s["force_control"], json!([]));
        assert_eq!(s["sweeps_stopped"][0]["study"], json!(4));
        assert_eq!(s["sweeps_stopped"][0]["at_kpa"], json!(20.0));
        assert_eq!(s["studies"][0]["status"], json!("failed"));
        assert_eq!(s["studies"][1]["status"], json!("partial"));
        assert_eq!(s["strict"], json!(false));
        assert!(s["validity"].get("study3").is_none(), "failed: no counts");
        assert_eq!(s["validity"]["study4"]["strict_dropped"], json!(0));
        let html = read(dir, "index.html");
        assert!(html.contains("<img src=\"study3.svg\"") && html.contains("failed"));
        assert!(
            html.contains("<th>it&#39;s &quot;quoted&quot;</th>"),
            "{html}"
        );
        assert_eq!(s["failures"][1]["study"], json!(8));
        assert_eq!(out.failed_studies(), vec![3, 8]);
    }

    /// Every figure of every study on coarse sweeps: each colour key gets
    /// one colour wherever it appears, the SVG draws it in that colour,
    /// and the paper's prestrains and angles get colours of their own.
    #[test]
    fn one_colour_per_colour_key_across_studies() {
        let act = Actuator::default();
        let opts = StudyOptions::coarse();
        let mut seen: BTreeMap<String, String> = BTreeMap::new();
        for info in STUDIES {
            let out = info.output(&act, &opts).unwrap();
            let svg = render::svg(&out.figure).unwrap();
            for s in out.figure.panels().flat_map(|p| &p.series) {
                let c = hex(render::color_of(&s.color));
                if let Some(prev) = seen.insert(s.color.clone(), c.clone()) {
                    assert_eq!(prev, c, "key {}", s.color);
                }
                if s.points
                    .iter()
                    .any(|p| p[0].is_finite() && p[1].is_finite())
                {
                    assert!(
                        svg.contains(&c),
                        "study {}: {} not drawn in {c}",
                        info.number,
                        s.color
                    );
                }
            }
        }
        for key in [
            "eps0=0.4",
            "eps0=0.25",
            "eps0=0.15",
            "a=pi/2",
            "a=pi/3",
            "g=10mm",
        ] {
            assert!(seen.contains_key(key), "{key} not used");
        }
        let keys = [
            "eps0=0.4",
            "eps0=0.25",
            "eps0=0.15",
            "a=pi/2",
            "a=pi/2.5",
            "a=pi/3",
            "g=0mm",
            "g=10mm",
            "g=20mm",
        ];
        let mut colours: Vec<_> = keys.iter().map(|k| hex(render::color_of(k))).collect();
        colours.sort();
        colours.dedup();
        assert_eq!(colours.len(), keys.len(), "a colour per variable value");
        // unknown keys still get a fixed colour
        assert_eq!(render::color_of("x=1"), render::color_of("x=1"));
    }
}
