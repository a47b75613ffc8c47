//! The files of one full run: every one written, and what each holds
//! (units in the headers, counts that agree between the CSVs, the summary
//! and index.html, labelled figures).

use serde_json::Value;

use super::{expected_files, fields, fpc, number, tmp};

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
