//! Bad measurement input: every class is an error naming the file, the row
//! and column, and the field; good input reads into typed rows.

use tempfile::TempDir;

use super::*;

/// A fresh directory holding `files` (name, text), removed when dropped.
fn dir_with(tag: &str, files: &[(&str, &str)]) -> TempDir {
    let d = tempfile::Builder::new()
        .prefix(&format!("fpc-measure-{tag}-"))
        .tempdir()
        .unwrap();
    for (name, text) in files {
        std::fs::write(d.path().join(name), text).unwrap();
    }
    d
}

/// A manifest of one specimen with one test of `kind` in `data.csv`.
fn one_test(kind: &str, extra: &str) -> String {
    format!(
        "[[specimen]]\nname = \"a\"\n[specimen.own.actuator.pemc]\neps0 = 0.25\n[[specimen.test]]\nkind = \"{kind}\"\nfile = \"data.csv\"\n{extra}"
    )
}

fn load(tag: &str, manifest: &str, files: &[(&str, &str)]) -> Result<Manifest, MeasureError> {
    let d = dir_with(tag, files);
    std::fs::write(d.path().join("m.toml"), manifest).unwrap();
    Manifest::load(&d.path().join("m.toml"))
}

/// Reads a one-test manifest whose data must be rejected at (file, row,
/// col, field), the file being the data file unless `file` says
/// otherwise; returns the error for more checks.
fn rejected(
    tag: &str,
    manifest: &str,
    data: &str,
    (file, row, col, field): (&str, usize, usize, &str),
) -> MeasureError {
    let e = load(tag, manifest, &[("data.csv", data)]).expect_err(tag);
    assert!(e.file.ends_with(file), "{tag}: {e}");
    assert_eq!(e.at, Some((row, col)), "{tag}: {e}");
    assert_eq!(e.field, field, "{tag}: {e}");
    let text = e.to_string();
    assert!(
        text.contains(&format!("{file}:{row}:{col}: {field}: ")),
        "{tag}: {text}"
    );
    e
}

const RADIUS: &str = "pressure_kpa,radius_mm,sd_mm\n";

#[test]
fn good_files_read_into_typed_rows() {
    let m = load(
        "good",
        &one_test("force", ""),
        &[(
            "data.csv",
            "# synthetic\npressure_kpa, axis, displacement_mm, force_n, sd_n, repeats\n27.6,X,10,0.4,0.02,5\n27.6,Z,10,0.3,0.02,4\n",
        )],
    )
    .unwrap();
    let s = &m.specimens[0];
    assert_eq!(s.name, "a");
    assert_eq!(s.scene.actuator.eps0(), 0.25);
    assert_eq!(s.own, ["actuator.pemc.eps0"]);
    let TestData::Force(rows) = &s.tests[0].data else {
        panic!("a force test")
    };
    assert_eq!(rows.len(), 2);
    assert_eq!((rows[0].line, rows[1].line), (3, 4));
    assert_eq!(rows[1].axis, crate::studies::Axis::Z);
    assert!((rows[0].sd_of_mean() - 0.02 / 5f64.sqrt()).abs() < 1e-15);
}

#[test]
fn a_missing_column_names_the_header_row_and_the_column() {
    let e = rejected(
        "missing",
        &one_test("radius", ""),
        "pressure_kpa,radius_mm\n10,50\n",
        ("data.csv", 1, 3, "sd_mm"),
    );
    assert!(e.reason.contains("missing column"), "{e}");
    // after a comment line the header is row 2
    rejected(
        "missing2",
        &one_test("radius", ""),
        "# comment\npressure_kpa,sd_mm\n",
        ("data.csv", 2, 3, "radius_mm"),
    );
}

#[test]
fn unknown_and_repeated_columns_are_errors() {
    rejected(
        "unknown",
        &one_test("radius", ""),
        "pressure_kpa,radius_mm,sd_mm,radius_in\n",
        ("data.csv", 1, 4, "radius_in"),
    );
    rejected(
        "twice",
        &one_test("radius", ""),
        "pressure_kpa,radius_mm,pressure_kpa,sd_mm\n",
        ("data.csv", 1, 3, "pressure_kpa"),
    );
}

/// A file with no header (empty, or comments only) is refused with the
/// columns it needs; a header without rows is a test with nothing measured
/// yet (tests/measure.rs).
#[test]
fn a_file_without_a_header_is_an_error() {
    for (tag, data) in [("empty", ""), ("comments", "# exported\n\n")] {
        let e = rejected(
            tag,
            &one_test("radius", ""),
            data,
            ("data.csv", 1, 1, "header"),
        );
        assert!(
            e.reason.contains("empty") && e.reason.contains("pressure_kpa, radius_mm, sd_mm"),
            "{tag}: {e}"
        );
    }
}

#[test]
fn nan_infinite_and_text_values_are_errors() {
    for (tag, v) in [
        ("nan", "NaN"),
        ("inf", "-inf"),
        ("text", "abc"),
        ("empty", ""),
    ] {
        rejected(
            tag,
            &one_test("radius", ""),
            &format!("{RADIUS}10,50,1\n20,{v},1\n"),
            ("data.csv", 3, 2, "radius_mm"),
        );
    }
}

#[test]
fn a_negative_or_zero_sd_is_an_error() {
    for sd in ["-1", "0"] {
        rejected(
            &format!("sd{sd}"),
            &one_test("radius", ""),
            &format!("{RADIUS}10,50,{sd}\n"),
            ("data.csv", 2, 3, "sd_mm"),
        );
    }
    rejected(
        "sdn",
        &one_test("force", ""),
        "pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n0,X,10,0.5,-0.1,3\n",
        ("data.csv", 2, 5, "sd_n"),
    );
    // markers: the test's default sd must be positive too
    let e = load("sdkey", &one_test("markers", "sd_mm = -0.3\n"), &[]).unwrap_err();
    assert_eq!((e.field.as_str(), e.row()), ("sd_mm", Some(8)), "{e}");
}

#[test]
fn a_pressure_below_vacuum_is_an_error() {
    let e = rejected(
        "vacuum",
        &one_test("radius", ""),
        &format!("{RADIUS}-101.4,50,1\n"),
        ("data.csv", 2, 1, "pressure_kpa"),
    );
    assert!(e.reason.contains("vacuum"), "{e}");
    // vacuum itself is a pressure
    load(
        "vacuum-ok",
        &one_test("radius", ""),
        &[("data.csv", &format!("{RADIUS}-101.325,50,1\n"))],
    )
    .unwrap();
}

#[test]
fn a_marker_beyond_the_finger_is_an_error() {
    let head = "pressure_kpa,marker,s_mm,x_mm,z_mm,sd_mm\n";
    for (tag, s) in [("long", "110.5"), ("negative", "-1")] {
        let e = rejected(
            tag,
            &one_test("markers", ""),
            &format!("{head}0,M1,110,100,-5,0.3\n0,M2,{s},1,2,0.3\n"),
            ("data.csv", 3, 3, "s_mm"),
        );
        assert!(e.reason.contains("110 mm"), "{e}");
    }
    // the finger's length is the specimen's own
    let longer = one_test("markers", "").replace(
        "[[specimen.test]]",
        "[specimen.own.actuator.geometry]\nlx = 120.0\n[specimen.own.actuator.channel]\ncx = 115.0\n[[specimen.test]]",
    );
    load(
        "longer",
        &longer,
        &[("data.csv", &format!("{head}0,M2,115,1,2,0.3\n"))],
    )
    .unwrap();
    // no sd anywhere
    rejected(
        "nosd",
        &one_test("markers", ""),
        "pressure_kpa,marker,s_mm,x_mm,z_mm\n0,M1,50,1,2\n",
        ("data.csv", 2, 1, "sd_mm"),
    );
}

#[test]
fn duplicate_rows_are_errors_naming_the_first() {
    let e = rejected(
        "dup",
        &one_test("radius", ""),
        &format!("{RADIUS}10,50,1\n20,60,1\n10.0,51,1\n"),
        ("data.csv", 4, 1, "pressure_kpa"),
    );
    assert!(e.reason.contains("row 2"), "{e}");
    let head = "pressure_kpa,marker,s_mm,x_mm,z_mm,sd_mm\n";
    rejected(
        "dupm",
        &one_test("markers", ""),
        &format!("{head}0,M1,50,1,2,0.3\n0,M2,60,1,2,0.3\n0,M1,50,1,2,0.3\n"),
        ("data.csv", 4, 1, "pressure_kpa"),
    );
    // the same marker at another pressure is another row
    load(
        "nodup",
        &one_test("markers", ""),
        &[(
            "data.csv",
            &format!("{head}0,M1,50,1,2,0.3\n10,M1,50,1,2,0.3\n"),
        )],
    )
    .unwrap();
}

/// The radius rows of a one-test manifest whose data file is `data`.
fn radius_rows(tag: &str, data: &str) -> Vec<RadiusRow> {
    let m = load(tag, &one_test("radius", ""), &[("data.csv", data)]).expect(tag);
    let TestData::Radius(rows) = &m.specimens[0].tests[0].data else {
        panic!("{tag}: a radius test")
    };
    rows.clone()
}

/// A row's line is its physical line in the file, whatever the line
/// endings (LF, CRLF as Excel writes, a lone CR) and the blank and comment
/// lines before it: in the rows read, in an error's place and in the row a
/// duplicate names.
#[test]
fn a_row_is_its_physical_line_whatever_the_line_endings_and_comments() {
    for (tag, eol) in [("lf", "\n"), ("crlf", "\r\n"), ("cr", "\r")] {
        let file = |rows: &[&str]| {
            let mut t = format!("# exported{eol}{eol}pressure_kpa,radius_mm,sd_mm{eol}");
            for r in rows {
                t.push_str(r);
                t.push_str(eol);
            }
            t
        };
        // header on line 3; rows on lines 4, 7 and 9 (blank and comment
        // lines between them, a comment after the last)
        let good = file(&["0,68,1", "", "# a note", "5,60,1", "", "10,50,1", "# end"]);
        let read = radius_rows(&format!("{tag}-good"), &good);
        let lines: Vec<usize> = read.iter().map(|r| r.line).collect();
        assert_eq!(lines, [4, 7, 9], "{tag}");
        // an error at its line
        rejected(
            &format!("{tag}-text"),
            &one_test("radius", ""),
            &file(&["0,68,1", "", "# a note", "", "5,abc,1"]),
            ("data.csv", 8, 2, "radius_mm"),
        );
        // a duplicate at its line, naming the line of the first
        let e = rejected(
            &format!("{tag}-dup"),
            &one_test("radius", ""),
            &file(&["0,68,1", "# a note", "5,60,1", "", "0,70,1"]),
            ("data.csv", 8, 1, "pressure_kpa"),
        );
        assert!(e.reason.contains("duplicates row 4 "), "{tag}: {e}");
        // a row of too few fields, and a header after blank lines
        rejected(
            &format!("{tag}-fields"),
            &one_test("radius", ""),
            &file(&["0,68,1", "", "5,60"]),
            ("data.csv", 6, 3, "sd_mm"),
        );
        rejected(
            &format!("{tag}-header"),
            &one_test("radius", ""),
            &format!("{eol}# a{eol}{eol}pressure_kpa,sd_mm{eol}"),
            ("data.csv", 4, 3, "radius_mm"),
        );
    }
    // the audit's CRLF file: the bad row is line 3
    rejected(
        "crlf-audit",
        &one_test("radius", ""),
        "pressure_kpa,radius_mm,sd_mm\r\n0,68,1\r\n5,abc,1\r\n",
        ("data.csv", 3, 2, "radius_mm"),
    );
    // line endings mixed in one file, each counted once
    let mixed = "pressure_kpa,radius_mm,sd_mm\r\n0,68,1\r5,60,1\n\r\n10,50,1\r";
    let lines: Vec<usize> = radius_rows("mixed", mixed).iter().map(|r| r.line).collect();
    assert_eq!(lines, [2, 3, 5]);
}

#[test]
fn bad_force_fields_are_errors() {
    let head = "pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n";
    for (tag, row, col, field) in [
        ("axis", "0,Y,10,0.5,0.1,3", 2, "axis"),
        ("zero", "0,X,0,0.5,0.1,3", 3, "displacement_mm"),
        ("repeats0", "0,X,10,0.5,0.1,0", 6, "repeats"),
        ("repeatsf", "0,X,10,0.5,0.1,2.5", 6, "repeats"),
    ] {
        rejected(
            tag,
            &one_test("force", ""),
            &format!("{head}{row}\n"),
            ("data.csv", 2, col, field),
        );
    }
    // a short row names the first missing column
    rejected(
        "short",
        &one_test("force", ""),
        &format!("{head}0,X,10\n"),
        ("data.csv", 2, 4, "force_n"),
    );
}

#[test]
fn manifest_errors_name_their_line_and_key() {
    let e = load(
        "typo",
        "[[specimen]]\nname = \"a\"\n[[specimen.test]]\nkind = \"radius\"\nfiel = \"x.csv\"\n",
        &[],
    )
    .unwrap_err();
    assert!(e.file.ends_with("m.toml"), "{e}");
    assert_eq!(e.row(), Some(5), "{e}");
    assert!(e.reason.contains("fiel"), "{e}");
    // a kind that does not exist
    let e = load("kind", &one_test("volume", ""), &[]).unwrap_err();
    assert_eq!(e.row(), Some(6), "{e}");
    // a camera on a radius test
    let e = load(
        "camera",
        &one_test("radius", "camera = { angle_deg = 1, x_mm = 0, z_mm = 0 }\n"),
        &[("data.csv", RADIUS)],
    )
    .unwrap_err();
    assert_eq!(e.field, "camera", "{e}");
    // a value the model rejects names the scene key, at its value
    let bad = one_test("radius", "").replace("eps0 = 0.25", "eps0 = nan");
    let e = load("eps0", &bad, &[("data.csv", RADIUS)]).unwrap_err();
    assert_eq!(e.field, "specimen.own.actuator.pemc.eps0", "{e}");
    assert_eq!(e.at, Some((4, 8)), "{e}");
    // a specimen's loads are its tests'; of [load], kappa belongs to the
    // finger, and zeros (a calibrated scene's) set nothing
    let with_load = |tag: &str, table: &str| {
        let manifest = format!("[shared.load]\n{table}{}", one_test("radius", ""));
        load(tag, &manifest, &[("data.csv", RADIUS)])
    };
    let e = with_load("load", "pressure_kpa = 10\n").unwrap_err();
    assert_eq!(e.field, "shared.load.pressure_kpa", "{e}");
    assert_eq!(e.row(), Some(2), "{e}");
    let e = with_load("fx", "kappa = 3.0\nfx = 0.1\n").unwrap_err();
    assert_eq!(e.field, "shared.load.fx", "{e}");
    assert_eq!(e.row(), Some(3), "{e}");
    let m = with_load("kappa", "kappa = 3.0\npressure_kpa = 0.0\nfx = 0\n").unwrap();
    assert_eq!(m.specimens[0].scene.load.kappa, 3.0);
    // a missing file is named
    let e = load("nofile", &one_test("radius", ""), &[]).unwrap_err();
    assert!(e.file.ends_with("data.csv") && e.at.is_none(), "{e}");
    // two specimens of one name
    let two = format!("{}{}", one_test("radius", ""), one_test("radius", ""));
    let e = load("twice", &two, &[("data.csv", RADIUS)]).unwrap_err();
    assert_eq!((e.field.as_str(), e.row()), ("name", Some(9)), "{e}");
}

#[test]
fn shared_tables_and_scene_files_reach_every_specimen() {
    let m = load(
        "shared",
        &format!(
            "[shared]\nscene = \"base.toml\"\n[shared.actuator.cl]\nkind = \"isotropic\"\ne = 400.0\nnu = 0.4\n{}",
            one_test("radius", "")
        ),
        &[
            ("data.csv", RADIUS),
            ("base.toml", "[partition]\nelements = 6\n"),
        ],
    )
    .unwrap();
    let s = &m.specimens[0];
    assert_eq!(
        s.scene.file().partition.elements,
        Some(crate::scene::Elements::Count(6))
    );
    assert!(
        m.shared.contains(&"actuator.cl.e".to_string()),
        "{:?}",
        m.shared
    );
    assert!(m.shared.contains(&"partition.elements".to_string()));
    // a bad scene file names its own line
    let e = load(
        "badscene",
        &format!(
            "[shared]\nscene = \"base.toml\"\n{}",
            one_test("radius", "")
        ),
        &[
            ("data.csv", RADIUS),
            ("base.toml", "[partition]\nelements = = 6\n"),
        ],
    )
    .unwrap_err();
    assert!(e.file.ends_with("base.toml") && e.row() == Some(2), "{e}");
}

#[test]
fn sizes_are_bounded_before_reading_further() {
    // a file one byte over the bound
    let big = format!("{RADIUS}{}", "#".repeat(MAX_DATA_BYTES as usize));
    let e = load("big", &one_test("radius", ""), &[("data.csv", &big)]).unwrap_err();
    assert!(e.reason.contains(&MAX_DATA_BYTES.to_string()), "{e}");
    // one row over the bound: the error is at that row
    let mut rows = String::from(RADIUS);
    for i in 0..=MAX_ROWS {
        rows.push_str(&format!("{i},50,1\n"));
    }
    rejected(
        "rows",
        &one_test("radius", ""),
        &rows,
        ("data.csv", MAX_ROWS + 2, 1, "rows"),
    );
    // one specimen over the bound, before any file is read
    let many: String = (0..=MAX_SPECIMENS)
        .map(|i| format!("[[specimen]]\nname = \"s{i}\"\n"))
        .collect();
    let e = load("many", &many, &[]).unwrap_err();
    assert_eq!(
        (e.field.as_str(), e.row()),
        ("specimen", Some(2 * MAX_SPECIMENS + 1)),
        "{e}"
    );
}

/// Past the manifest's total of rows, the error says it is the
/// manifest's limit, with its numbers, not the file's.
#[test]
fn the_manifests_row_limit_is_named_as_the_manifests() {
    let per_file = MAX_TOTAL_ROWS / 4 - MAX_ROWS / 10; // 9000 of 10000
    let mut rows = String::from(RADIUS);
    for i in 0..per_file {
        rows.push_str(&format!("{i},50,1\n"));
    }
    let mut manifest =
        String::from("[[specimen]]\nname = \"a\"\n[specimen.own.actuator.pemc]\neps0 = 0.25\n");
    let mut files = Vec::new();
    for k in 0..5 {
        manifest.push_str(&format!(
            "[[specimen.test]]\nkind = \"radius\"\nfile = \"d{k}.csv\"\n"
        ));
        files.push((format!("d{k}.csv"), rows.clone()));
    }
    let files: Vec<(&str, &str)> = files
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect();
    let e = load("total", &manifest, &files).unwrap_err();
    let left = MAX_TOTAL_ROWS - 4 * per_file;
    assert!(e.file.ends_with("d4.csv"), "{e}");
    assert_eq!(
        (e.field.as_str(), e.at),
        ("rows", Some((left + 2, 1))),
        "{e}"
    );
    assert_eq!(
        e.reason,
        format!(
            "more than {left} data rows: the manifest's limit is {MAX_TOTAL_ROWS} data rows in all its files, and its files before this one have {}",
            4 * per_file
        ),
        "{e}"
    );
    // one file past its own limit says so
    let mut rows = String::from(RADIUS);
    for i in 0..=MAX_ROWS {
        rows.push_str(&format!("{i},50,1\n"));
    }
    let e = load("file", &one_test("radius", ""), &[("data.csv", &rows)]).unwrap_err();
    assert!(
        e.reason.starts_with(&format!(
            "more than {MAX_ROWS} data rows, the limit of one file"
        )),
        "{e}"
    );
}

/// A model value that no residual can be formed from (not finite, or so
/// large that its square in standard deviations would overflow) is no
/// prediction: the row says why and holds no residual.
#[test]
fn a_model_value_beyond_the_bound_is_no_prediction() {
    for (value, words) in [
        (1e200, "beyond"),
        (f64::INFINITY, "not a finite number"),
        (f64::NAN, "not a finite number"),
    ] {
        let res = vec![comparison::Residual::new("radius_mm", "mm", 40.0, 1e-6)];
        let p = comparison::predicted(2, 0.0, res, Ok((vec![value], Vec::new())));
        let why = p.failure.as_deref().unwrap_or_default();
        assert!(
            why.contains("radius_mm") && why.contains(words),
            "{value}: {why}"
        );
        assert!(!why.contains("inf") && !why.contains("NaN"), "{why}");
        assert!(!p.valid);
        assert_eq!(p.residuals[0].predicted, None);
        assert_eq!(p.residuals[0].residual_sd, None);
    }
    // the largest value still compared gives a finite square
    let res = vec![comparison::Residual::new("radius_mm", "mm", 40.0, 1e-6)];
    let p = comparison::predicted(2, 0.0, res, Ok((vec![-1e100], Vec::new())));
    let z = p.residuals[0].residual_sd.unwrap();
    assert!((z * z * (2 * MAX_TOTAL_ROWS) as f64).is_finite(), "{z}");
}

/// A failed solve whose residual is not a number says so in words: no
/// record holds `inf` or `NaN`.
#[test]
fn a_failure_with_a_residual_that_is_not_a_number_says_so_in_words() {
    for r in [f64::INFINITY, f64::NAN] {
        let e = crate::SolveError::NotConverged {
            reason: fpc_newton::Termination::MaxIterations,
            iterations: 0,
            relative_residual: r,
            element: Some(0),
            last: crate::coefficients::Coefficients::zeros(1, 4),
        };
        // (SolveError's own message, which every record and line shows)
        let text = e.to_string();
        assert!(text.starts_with("solve failed for element 0"), "{text}");
        assert!(text.contains("not a finite number"), "{text}");
        assert!(!text.contains("inf") && !text.contains("NaN"), "{text}");
    }
}
