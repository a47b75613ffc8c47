//! `fpc paper`: runs the built binary and checks what it writes.

mod common;

use std::path::Path;
use std::process::Command;

use serde_json::Value;
use tempfile::TempDir;

fn fpc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
}

fn tmp(name: &str) -> TempDir {
    common::tmp("paper", name)
}

fn expected_files() -> Vec<String> {
    let mut v: Vec<String> = (1..=8)
        .flat_map(|n| [format!("study{n}.csv"), format!("study{n}.svg")])
        .collect();
    v.extend(
        [
            "study1_shapes.csv",
            "study5_envelope.csv",
            "summary.json",
            "index.html",
        ]
        .map(String::from),
    );
    v
}

/// Columns without a unit: dimensionless numbers, flags and text.
const UNITLESS: [&str; 11] = [
    "eps0",
    "f_over_F",
    "viable",
    "invalid",
    "friction_ok",
    "reversed",
    "valid",
    "warnings",
    "axis",
    "status",
    "note",
];
const UNITS: [&str; 5] = ["_mm", "_n", "_kpa", "_rad", "_per_mm"];

/// Splits one CSV line (double-quoted fields may hold commas).
fn fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(String::new()),
            _ => out.last_mut().unwrap().push(c),
        }
    }
    out
}

/// The attributes and the trimmed text of every `<text>` element of an
/// SVG.
fn svg_text_elements(svg: &str) -> Vec<(String, String)> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let (attrs, body) = t.split_once('>')?;
            Some((
                attrs.to_string(),
                body.split("</text>").next()?.trim().to_string(),
            ))
        })
        .collect()
}

/// The trimmed text of every `<text>` element of an SVG.
fn svg_texts(svg: &str) -> Vec<String> {
    svg_text_elements(svg).into_iter().map(|(_, t)| t).collect()
}

fn number(v: &Value, what: &str) -> f64 {
    let x = v
        .as_f64()
        .unwrap_or_else(|| panic!("{what} is not a number: {v}"));
    assert!(x.is_finite(), "{what} = {x}");
    x
}

/// Every number in the document is finite (JSON cannot hold NaN, but a
/// writer could emit one as a string or a huge literal).
fn all_finite(v: &Value, path: &str) {
    match v {
        Value::Number(n) => assert!(n.as_f64().is_some_and(f64::is_finite), "{path} = {n}"),
        Value::String(s) => assert!(
            !matches!(s.as_str(), "NaN" | "inf" | "-inf" | "Infinity"),
            "{path} = {s}"
        ),
        Value::Array(a) => a
            .iter()
            .enumerate()
            .for_each(|(i, x)| all_finite(x, &format!("{path}[{i}]"))),
        Value::Object(o) => o
            .iter()
            .for_each(|(k, x)| all_finite(x, &format!("{path}.{k}"))),
        _ => {}
    }
}

#[test]
fn paper_writes_every_file() {
    let scratch = tmp("full");
    // not there yet: the run makes it
    let dir = scratch.path().join("out");
    let out = fpc().args(["paper", "--out"]).arg(&dir).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "fpc paper failed: {stderr}");

    for f in expected_files() {
        assert!(dir.join(&f).is_file(), "{f} missing");
    }
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') || n.ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");

    // no absolute path in any output
    let abs = dir.to_string_lossy().into_owned();
    for f in expected_files() {
        let text = std::fs::read_to_string(dir.join(&f)).unwrap();
        assert!(!text.contains(&abs), "{f} contains the output path");
    }

    // summary.json
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let s: Value = serde_json::from_str(&text).expect("summary.json parses");
    all_finite(&s, "summary");
    assert_eq!(s["failures"], Value::Array(vec![]), "{}", s["failures"]);

    let dmax = s["dmax_mm"].as_array().expect("dmax_mm is a list");
    assert_eq!(dmax.len(), 9);
    for d in dmax {
        number(&d["eps0"], "eps0");
        number(&d["angle_rad"], "angle_rad");
        assert!(number(&d["dmax_mm"], "dmax_mm") > 0.0);
    }
    assert!(s["cuboid_region_contains"].is_boolean());

    let fc = s["force_control"].as_array().expect("force_control");
    assert!(fc.len() >= 2);
    let forces: Vec<f64> = fc.iter().map(|r| number(&r["F_n"], "F_n")).collect();
    let pressures: Vec<f64> = fc
        .iter()
        .map(|r| number(&r["pressure_kpa"], "pressure_kpa"))
        .collect();
    for r in fc {
        number(&r["h_mm"], "h_mm");
    }
    assert!(pressures.windows(2).all(|w| w[1] > w[0]), "{pressures:?}");
    assert!(
        forces.windows(2).all(|w| w[1] < w[0]),
        "F does not decrease with pressure: {forces:?}"
    );

    let peak = number(
        &s["sphere_envelope_peak_radius_mm"],
        "sphere_envelope_peak_radius_mm",
    );
    assert!(peak > 0.0);

    let range = &s["sphere_beta_range_rad"];
    assert!(range.is_null() || range.is_array(), "{range}");
    if let Some(r) = range.as_array() {
        assert_eq!(r.len(), 2);
        let (lo, hi) = (number(&r[0], "lo"), number(&r[1], "hi"));
        assert!(
            lo <= hi && lo >= -std::f64::consts::FRAC_PI_2 && hi <= std::f64::consts::FRAC_PI_2
        );
    }

    let rvp = s["radius_vs_pressure"]
        .as_array()
        .expect("radius_vs_pressure");
    assert_eq!(rvp.len(), 3);
    for c in rvp {
        number(&c["eps0"], "eps0");
        assert!(c["reversed"].is_boolean());
        let pts = c["points"].as_array().expect("points");
        assert!(!pts.is_empty());
        for p in pts {
            number(&p["pressure_kpa"], "pressure_kpa");
            let r = &p["radius_mm"];
            assert!(r.is_null() || number(r, "radius_mm") > 0.0);
            assert!(p["reversed"].is_boolean());
        }
    }

    let f10 = s["force_at_10mm"].as_array().expect("force_at_10mm");
    assert_eq!(f10.len(), 8);
    for r in f10 {
        assert!(
            matches!(r["axis"].as_str(), Some("X" | "Z")),
            "{}",
            r["axis"]
        );
        number(&r["eps0"], "eps0");
        number(&r["pressure_kpa"], "pressure_kpa");
        assert!(r["force_n"].is_null() || r["force_n"].is_number());
    }

    // CSV: headers with units, rows as wide as the header
    for f in expected_files().iter().filter(|f| f.ends_with(".csv")) {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        let mut lines = text.lines();
        let header = fields(lines.next().expect("header"));
        for col in &header {
            assert!(
                UNITLESS.contains(&col.as_str()) || UNITS.iter().any(|u| col.ends_with(u)),
                "{f}: column {col} has no unit"
            );
        }
        assert_eq!(header.last().map(String::as_str), Some("note"));
        let mut rows = 0;
        for line in lines {
            assert_eq!(fields(line).len(), header.len(), "{f}: {line}");
            rows += 1;
        }
        assert!(rows > 0, "{f} has no rows");
    }

    // the words agree with the data: the sweeps that ended or stopped
    // early, counted from the CSV rows, are the summary's, the closing
    // line's and index.html's
    let mut ended = 0;
    let mut stopped = 0;
    let mut ended_study5 = 0;
    for f in expected_files().iter().filter(|f| f.ends_with(".csv")) {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        let mut lines = text.lines();
        let header = fields(lines.next().unwrap());
        let Some(col) = header.iter().position(|c| c == "status") else {
            continue;
        };
        for line in lines {
            match fields(line)[col].as_str() {
                "ended" => {
                    ended += 1;
                    ended_study5 += usize::from(f == "study5.csv");
                }
                "stopped" => stopped += 1,
                _ => {}
            }
        }
    }
    assert_eq!(s["sweep_ends"].as_array().unwrap().len(), ended);
    assert_eq!(s["sweeps_stopped"].as_array().unwrap().len(), stopped);
    let region = &s["sphere_region"];
    assert_eq!(region["ended_sweeps"], ended_study5);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains(&format!(
            "{ended} sweeps ended at a natural end, {stopped} stopped early"
        )),
        "{stdout}"
    );
    let index = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let said = index
        .split("grasping-angle sweeps ended before d_max")
        .next()
        .filter(|_| ended_study5 > 0)
        .map(|before| before.rsplit('>').next().unwrap().trim().to_string());
    if let Some(said) = said {
        assert!(
            said.starts_with(&format!("{ended_study5} of the ")),
            "index.html says {said:?}, study5.csv has {ended_study5} ended sweeps"
        );
    }
    assert_eq!(
        index.contains("grasping-angle sweeps stopped"),
        region["stopped_sweeps"].as_u64().unwrap() > 0
    );

    // every row that is a grasp says whether it is bent backwards and
    // valid, every grasp or finger state which validity kinds it raises
    let header = |f: &str| {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        fields(text.lines().next().unwrap())
    };
    for f in [
        "study1.csv",
        "study2.csv",
        "study3.csv",
        "study4.csv",
        "study5.csv",
        "study5_envelope.csv",
        "study6.csv",
    ] {
        let h = header(f);
        let n = h.len();
        assert_eq!(
            h[n - 6..],
            ["reversed", "valid", "invalid", "warnings", "status", "note"],
            "{f}"
        );
    }
    for f in ["study7.csv", "study8.csv"] {
        assert!(header(f).contains(&"warnings".to_string()), "{f}");
    }
    let kinds = [
        "element_slope",
        "strain_range",
        "self_contact",
        "thickness_ratio",
        "curvature_reversal",
        "beyond_flat",
    ];
    let text = std::fs::read_to_string(dir.join("study1.csv")).unwrap();
    let mut lines = text.lines();
    let h = fields(lines.next().unwrap());
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (rev, warn) = (col("reversed"), col("warnings"));
    let (valid, invalid, status) = (col("valid"), col("invalid"), col("status"));
    let mut reversed = 0;
    for line in lines {
        let f = fields(line);
        // one verdict: valid exactly when no reason is given, and never
        // with a finding outside the model (a reversal is not one)
        if f[status] == "ok" {
            assert_eq!(f[valid] == "true", f[invalid].is_empty(), "{line}");
            let outside = f[warn]
                .split(';')
                .any(|k| !k.is_empty() && k != "curvature_reversal");
            if outside {
                assert_eq!(f[valid], "false", "{line}");
            }
        }
        if f[warn].is_empty() {
            continue;
        }
        let listed: Vec<&str> = f[warn].split(';').collect();
        assert!(listed.iter().all(|k| kinds.contains(k)), "{line}");
        // reversed is the curvature_reversal finding
        assert_eq!(
            f[rev] == "true",
            listed.contains(&"curvature_reversal"),
            "{line}"
        );
        reversed += usize::from(f[rev] == "true");
    }
    // summary.json counts the same points, not strict by default
    assert_eq!(s["strict"], Value::Bool(false));
    let v1 = &s["validity"]["study1"];
    assert_eq!(v1["warnings_by_kind"]["curvature_reversal"], reversed);
    assert_eq!(v1["strict_dropped"], 0);
    for n in 1..=8 {
        let v = &s["validity"][format!("study{n}")];
        let points = v["points"].as_u64().expect("points");
        assert!(points > 0, "study {n}");
        for k in kinds {
            assert!(
                v["warnings_by_kind"][k].as_u64().unwrap() <= points,
                "{n} {k}"
            );
        }
    }

    // a sweep that stopped early is marked in its CSV
    for stop in s["sweeps_stopped"].as_array().expect("sweeps_stopped") {
        let n = stop["study"].as_u64().expect("study number");
        let csv = std::fs::read_to_string(dir.join(format!("study{n}.csv"))).unwrap();
        let marked = csv.lines().any(|l| {
            let f = fields(l);
            matches!(f[f.len() - 2].as_str(), "stopped" | "failed")
        });
        assert!(marked, "study {n}: the stop is not in study{n}.csv");
    }

    // SVG figures with labelled axes
    for n in 1..=8 {
        let svg = std::fs::read_to_string(dir.join(format!("study{n}.svg"))).unwrap();
        let start = svg.trim_start();
        assert!(
            start.starts_with("<svg") || start.starts_with("<?xml"),
            "study{n}.svg"
        );
        assert!(svg.trim_end().ends_with("</svg>"), "study{n}.svg");
        assert!(svg.contains("<text"), "study{n}.svg has no text");
        assert!(
            ["(mm)", "(N)", "(kPa)", "(deg)"]
                .iter()
                .any(|u| svg.contains(u)),
            "study{n}.svg has no axis unit"
        );
    }

    // index.html shows every figure
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    for n in 1..=8 {
        assert!(
            html.contains(&format!("<img src=\"study{n}.svg\"")),
            "index.html lacks study{n}.svg"
        );
    }
    assert!(html.contains("<table>"));
    assert!(html.trim_end().ends_with("</html>"));

    // tick labels without needless decimals: along one axis (the labels
    // right-aligned at one x, or centred at one y), a label ending in
    // zeros after the point only beside one with as many decimals that
    // needs them (0.5, 1.0)
    for n in 1..=8 {
        let svg = std::fs::read_to_string(dir.join(format!("study{n}.svg"))).unwrap();
        let mut axes: std::collections::BTreeMap<String, Vec<String>> = Default::default();
        for (attrs, text) in svg_text_elements(&svg) {
            if text.parse::<f64>().is_err() {
                continue;
            }
            let attr = |name: &str| {
                attrs
                    .split(&format!(" {name}=\""))
                    .nth(1)
                    .and_then(|r| r.split('"').next())
                    .unwrap_or("")
                    .to_string()
            };
            let axis = if attr("text-anchor") == "end" {
                format!("y axis at x = {}", attr("x"))
            } else {
                format!("x axis at y = {}", attr("y"))
            };
            axes.entry(axis).or_default().push(text);
        }
        assert!(axes.len() >= 2, "study{n}.svg: {axes:?}");
        let decimals = |t: &str| t.split_once('.').map_or(0, |(_, d)| d.len());
        for (axis, labels) in &axes {
            for t in labels
                .iter()
                .filter(|t| t.contains('.') && t.ends_with('0'))
            {
                assert!(
                    labels
                        .iter()
                        .any(|u| decimals(u) == decimals(t) && !u.ends_with('0')),
                    "study{n}.svg, {axis}: tick label {t} among {labels:?}"
                );
            }
        }
    }
    let svg1 = std::fs::read_to_string(dir.join("study1.svg")).unwrap();
    let texts1 = svg_texts(&svg1);
    for t in ["0", "50", "100", "150"] {
        assert!(texts1.iter().any(|x| x == t), "study1.svg: no tick {t}");
    }

    // study 1: the shape panels say what the dashed fingers are
    let mirrored = texts1
        .iter()
        .filter(|t| *t == "opposite finger (mirror image)")
        .count();
    assert_eq!(mirrored, 3, "one legend entry per shape panel");
    // and the eps0 = 0.4 lift panel is clipped below its largest value,
    // which the note names with its grasping size (from study1.csv)
    let csv = std::fs::read_to_string(dir.join("study1.csv")).unwrap();
    let mut lines = csv.lines();
    let header = fields(lines.next().unwrap());
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (eps0, d, fv) = (col("eps0"), col("d_mm"), col("fv_n"));
    let (d_max, fv_max) = lines
        .map(fields)
        .filter(|f| f[eps0] == "0.4" && !f[fv].is_empty())
        .map(|f| (f[d].parse::<f64>().unwrap(), f[fv].parse::<f64>().unwrap()))
        .fold(
            (0.0, f64::NEG_INFINITY),
            |a, b| if b.1 > a.1 { b } else { a },
        );
    assert!(fv_max > 20.0, "the outlier of the issue: {fv_max}");
    let three = |v: f64| {
        let d = (2 - v.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.d$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    let largest = format!(
        "{} N at grasping size d = {} mm",
        three(fv_max),
        three(d_max)
    );
    let notes: String = texts1.join(" ");
    assert!(notes.contains("axis clipped at"), "{notes}");
    assert!(notes.contains(&largest), "{largest} not in {notes}");
    let caption = "Panel “Max lifting force, ε0 = 0.4”: axis clipped at";
    assert!(html.contains(caption), "index.html lacks the clip caption");
    assert!(html.contains(&largest), "index.html lacks {largest}");
}

#[test]
fn paper_creates_nested_output_directory() {
    let base = tmp("nested");
    let dir = base.path().join("a").join("b");
    let out = fpc()
        .args(["paper", "--coarse", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("summary.json").is_file());
    let s: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["options"]["coarse"], Value::Bool(true));
}

#[test]
fn paper_rejects_a_file_as_output_directory() {
    let scratch = tmp("file");
    let base = scratch.path();
    let file = base.join("not-a-dir");
    std::fs::write(&file, "keep me").unwrap();
    let out = fpc()
        .args(["paper", "--coarse", "--out"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert_eq!(out.status.code(), Some(2), "an input error");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("not a directory"),
        "unclear message: {stderr}"
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep me");
    assert_eq!(std::fs::read_dir(base).unwrap().count(), 1);
}

/// An element count beyond a study's bound is refused before any study
/// runs, under the flag's name (it used to run all eight studies, each
/// failing on `partition.n`), and nothing is written.
#[test]
fn paper_rejects_too_many_elements_before_any_work() {
    let scratch = tmp("elements");
    let out_dir = scratch.path().join("out");
    for n in ["0", "100000"] {
        let out = fpc()
            .args(["paper", "--coarse", "--elements", n, "--out"])
            .arg(&out_dir)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "an input error");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains(&format!("--elements = {n}: must lie in [1, 1000]")),
            "{stderr}"
        );
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(!out_dir.exists());
    }
}

/// Every expected file of a run is there and complete: JSON that parses,
/// CSV rows as wide as their header, SVG and HTML documents that close.
fn assert_complete(dir: &Path) {
    for f in expected_files() {
        let text = std::fs::read_to_string(dir.join(&f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        if f.ends_with(".json") {
            let s: Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{f}: {e}"));
            assert_eq!(s["failures"], Value::Array(vec![]), "{f}");
        } else if f.ends_with(".csv") {
            let mut lines = text.lines();
            let width = fields(lines.next().expect("header")).len();
            assert!(text.ends_with('\n'), "{f} is cut short");
            for line in lines {
                assert_eq!(fields(line).len(), width, "{f}: {line}");
            }
        } else if f.ends_with(".svg") {
            assert!(text.trim_start().starts_with("<svg"), "{f}");
            assert!(text.trim_end().ends_with("</svg>"), "{f} is cut short");
            assert_eq!(text.matches("<svg").count(), 1, "{f}: two documents");
        } else {
            assert!(text.trim_end().ends_with("</html>"), "{f} is cut short");
            assert_eq!(text.matches("<html").count(), 1, "{f}: two documents");
        }
    }
}

#[test]
fn two_runs_into_one_directory_both_succeed() {
    use std::os::unix::fs::PermissionsExt as _;
    use std::time::{Duration, SystemTime};
    let scratch = tmp("concurrent");
    let dir = scratch.path();
    // a temporary file of a run killed an hour ago, one of a live run, and
    // a file that is none of fpc's business
    let hour_ago = SystemTime::now() - Duration::from_secs(3600);
    std::fs::File::create(dir.join(".fpc-tmp-killed.tmp"))
        .unwrap()
        .set_modified(hour_ago)
        .unwrap();
    std::fs::write(dir.join(".fpc-tmp-live.tmp"), "").unwrap();
    std::fs::File::create(dir.join(".keep"))
        .unwrap()
        .set_modified(hour_ago)
        .unwrap();

    let run = || {
        fpc()
            .args(["paper", "--coarse", "--out"])
            .arg(dir)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (run(), run());
    for child in [a, b] {
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{:?}: {stderr}", out.status);
        assert!(stderr.is_empty(), "{stderr}");
        assert!(String::from_utf8_lossy(&out.stdout).starts_with("fpc paper: 20 files in "));
    }
    assert_complete(dir);

    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    names.sort();
    assert_eq!(
        names,
        [".fpc-tmp-live.tmp", ".keep"],
        "stale removed, the rest kept"
    );

    // the files get the mode a plain File::create gets (not 0600)
    let probe = dir.join("probe");
    std::fs::File::create(&probe).unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&dir.join("summary.json")), mode(&probe));
}

/// `--strict` drops the grasps that bend an element backwards: fewer rows,
/// counted under `validity`, and none of the remaining rows reversed.
#[test]
fn strict_mode_drops_reversed_grasps() {
    let scratch = tmp("strict");
    let base = scratch.path();
    let run = |name: &str, strict: bool| {
        let dir = base.join(name);
        let mut cmd = fpc();
        cmd.args(["paper", "--coarse", "--out"]).arg(&dir);
        if strict {
            cmd.arg("--strict");
        }
        let out = cmd.output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let s: Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        (dir, s)
    };
    let (loose_dir, loose) = run("loose", false);
    let (strict_dir, strict) = run("strict", true);
    assert_eq!(strict["strict"], Value::Bool(true));
    assert_eq!(strict["options"]["strict"], Value::Bool(true));
    let count =
        |s: &Value, n: u32, what: &str| s["validity"][format!("study{n}")][what].as_u64().unwrap();
    let reversed = |s: &Value, n: u32| {
        s["validity"][format!("study{n}")]["warnings_by_kind"]["curvature_reversal"]
            .as_u64()
            .unwrap()
    };
    // study 1: every reversed grasp of the default run is dropped
    let dropped = count(&strict, 1, "strict_dropped");
    assert!(dropped > 0, "the coarse study 1 has reversed grasps");
    assert_eq!(dropped, reversed(&loose, 1));
    assert_eq!(reversed(&strict, 1), 0);
    assert_eq!(
        count(&strict, 1, "points") + dropped,
        count(&loose, 1, "points")
    );
    let rows = |dir: &Path| {
        std::fs::read_to_string(dir.join("study1.csv"))
            .unwrap()
            .lines()
            .count()
    };
    assert_eq!(rows(&strict_dir) + dropped as usize, rows(&loose_dir));
    // study 5 drops its reversed sweep grasps too
    assert!(count(&strict, 5, "strict_dropped") > 0);
    assert!(
        strict["sphere_region"]["valid_points"].as_u64()
            < loose["sphere_region"]["valid_points"].as_u64()
    );
    for n in 1..=8 {
        assert_eq!(count(&loose, n, "strict_dropped"), 0, "not strict");
    }
    let html = std::fs::read_to_string(strict_dir.join("index.html")).unwrap();
    assert!(html.contains("strict mode"));
}

/// A calibrated scene's covariance (as `fpc calibrate` writes one: the
/// prestrain, kappa and the prestressed layer's p1), and the same scene
/// without it.
const CALIBRATED: &str = r#"
[actuator.pemc]
eps0 = 0.25
[load]
kappa = 2.5
[partition]
elements = 4
[calibration]
parameters = ["actuator.pemc.eps0", "load.kappa", "actuator.pemc.p1"]
covariance = [[1.8e-6, -2.9e-5, -2.1e-5], [-2.9e-5, 6.1e-4, 3.8e-4], [-2.1e-5, 3.8e-4, 2.7e-4]]
"#;

/// A CSV without its `_sd` columns, and without the notes that say why
/// a row has no error bars.
fn without_sd(csv: &str) -> String {
    let mut lines = csv.lines();
    let header = fields(lines.next().unwrap());
    let keep: Vec<bool> = header.iter().map(|h| !h.ends_with("_sd")).collect();
    let mut out = String::new();
    for line in csv.lines() {
        let row: Vec<String> = fields(line)
            .into_iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(f, _)| {
                if f.starts_with("no error bar") {
                    return String::new();
                }
                if f.contains([',', '"']) {
                    format!("\"{}\"", f.replace('"', "\"\""))
                } else {
                    f
                }
            })
            .collect();
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

#[test]
fn paper_scene_bands_only_with_a_covariance() {
    let scratch = tmp("bands");
    let base = scratch.path();
    let with = base.join("calibrated.toml");
    let without = base.join("plain.toml");
    std::fs::write(&with, CALIBRATED).unwrap();
    std::fs::write(&without, CALIBRATED.split("[calibration]").next().unwrap()).unwrap();
    let run = |scene: &Path, out: &str| {
        let dir = base.join(out);
        let o = fpc()
            .args(["paper", "--coarse", "--scene"])
            .arg(scene)
            .arg("--out")
            .arg(&dir)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        dir
    };
    let (plain, banded) = (run(&without, "plain"), run(&with, "banded"));
    let read = |d: &Path, f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    let csvs: Vec<String> = std::fs::read_dir(&plain)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".csv"))
        .collect();
    assert!(csvs.len() >= 10, "{csvs:?}");
    // without a covariance: no _sd column, no band, no uncertainty entry
    for f in &csvs {
        let header = read(&plain, f).lines().next().unwrap().to_string();
        assert!(!header.contains("_sd"), "{f}: {header}");
    }
    let s: Value = serde_json::from_str(&read(&plain, "summary.json")).unwrap();
    assert!(s.get("uncertainty").is_none());
    assert!(!read(&plain, "study7.svg").contains("1 sd"));
    // with one: the banded studies gain _sd columns and nothing else
    // changes; the other studies are the same bytes
    for f in &csvs {
        let (a, b) = (read(&plain, f), read(&banded, f));
        if [
            "study1.csv",
            "study2.csv",
            "study3.csv",
            "study4.csv",
            "study5_envelope.csv",
            "study6.csv",
            "study7.csv",
            "study8.csv",
        ]
        .contains(&f.as_str())
        {
            assert_ne!(a, b, "{f}");
            assert_eq!(without_sd(&b), without_sd(&a), "{f} beyond its _sd columns");
        } else {
            assert_eq!(a, b, "{f}");
        }
    }
    // study 1's eps0 = 0.4 fingers curl past their tips: no bands, and why
    let study1 = read(&banded, "study1.csv");
    let why = study1.lines().filter(|l| l.starts_with("0.4,")).all(|l| {
        l.contains("no error bars") && l.contains("innermost point") && l.contains(",,,,")
    });
    assert!(why, "{study1}");
    let header7 = fields(read(&banded, "study7.csv").lines().next().unwrap());
    for c in [
        "radius_mm_sd",
        "curvature_per_mm_sd",
        "end_angle_rad_sd",
        "tip_x_mm_sd",
        "tip_z_mm_sd",
    ] {
        assert!(header7.iter().any(|h| h == c), "{c} in {header7:?}");
    }
    let csv8 = read(&banded, "study8.csv");
    let header8 = fields(csv8.lines().next().unwrap());
    let col = header8.iter().position(|h| h == "force_n_sd").unwrap();
    for line in csv8.lines().skip(1) {
        let sd: f64 = fields(line)[col].parse().unwrap();
        assert!(sd > 0.0 && sd.is_finite(), "{line}");
    }
    assert!(read(&banded, "study5.svg").contains("1 sd"));
    assert!(read(&banded, "study6.svg").contains("1 sd"));
    assert!(read(&banded, "study7.svg").contains("1 sd"));
    assert!(read(&banded, "study8.svg").contains("1 sd"));
    let s: Value = serde_json::from_str(&read(&banded, "summary.json")).unwrap();
    let u = &s["uncertainty"];
    assert_eq!(u["propagated"], serde_json::json!(["actuator.pemc.p1"]));
    let left: Vec<&str> = u["not_propagated"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["parameter"].as_str().unwrap())
        .collect();
    assert_eq!(left, ["actuator.pemc.eps0", "load.kappa"]);
    assert_eq!(
        u["studies_with_bands"],
        serde_json::json!([1, 2, 3, 4, 5, 6, 7, 8])
    );
    assert_eq!(u["methods"]["study1"]["fv_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study2"]["dmax_mm_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study3"]["fv_max_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study4"]["F_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study5"]["fv_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study5"]["F_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study6"]["f_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study7"]["radius_mm_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study8"]["force_n_sd"], "first_order_exact");
    let row = &s["force_at_10mm"][0];
    assert!(number(&row["force_n_sd"], "force_n_sd") > 0.0);
    let peak = &s["sphere_region"]["peak"];
    assert!(number(&peak["fv_n_sd"], "fv_n_sd") > 0.0);
    // the envelope's band: positive wherever a row has one, and most do
    let csv5 = read(&banded, "study5_envelope.csv");
    let header5 = fields(csv5.lines().next().unwrap());
    let (fv, f) = (
        header5.iter().position(|h| h == "fv_n_sd").unwrap(),
        header5.iter().position(|h| h == "F_n_sd").unwrap(),
    );
    let rows5: Vec<Vec<String>> = csv5.lines().skip(1).map(fields).collect();
    let banded5 = rows5.iter().filter(|r| !r[fv].is_empty()).count();
    assert!(2 * banded5 > rows5.len(), "{csv5}");
    for r in &rows5 {
        if r[fv].is_empty() {
            assert!(
                r[f].is_empty() && r.iter().any(|c| c.starts_with("no error bars")),
                "{r:?}"
            );
        } else {
            let (a, b): (f64, f64) = (r[fv].parse().unwrap(), r[f].parse().unwrap());
            assert!(
                a > 0.0 && b > 0.0 && a.is_finite() && b.is_finite(),
                "{r:?}"
            );
        }
    }
    // study 6: both ends of its viable interval move
    let ends = &s["sphere_viable_angles"]["intervals_sd_rad"][0];
    assert!(number(&ends[0], "lower end's sd") > 0.0);
    assert!(number(&ends[1], "upper end's sd") > 0.0);
    let point = &s["radius_vs_pressure"][0]["points"][0];
    assert!(number(&point["radius_mm_sd"], "radius_mm_sd") > 0.0);
}
