//! The manifest: specimens, their actuators as scene tables (shared and
//! own), and their tests (CSV files).
//!
//! A specimen's scene document is its layers laid one over the other: its
//! scene file (else the `[shared]` one), the inline `[shared]` tables, its
//! `own` tables. A scene value the library rejects is an error at the
//! layer that writes it, the topmost: the key as written in the manifest
//! (`specimen.own.actuator.pemc.eps0`, `shared.actuator.pemc.e2`) or in
//! the scene file (`actuator.pemc.e2`), at the line and column of its value; a rule
//! between keys, or a default, at the specimen's `own` table (else its
//! name).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use toml::{Spanned, Table, Value};

use super::input::{
    bad_sd, beyond, read_text, MeasureError, TestKind, MAX_ANGLE_DEG, MAX_DATA_BYTES,
    MAX_LENGTH_MM, MAX_MANIFEST_BYTES, MAX_ROWS, MAX_SCENE_BYTES, MAX_SPECIMENS, MAX_TESTS,
    MAX_TOTAL_ROWS,
};
use super::table::{self, bits, Context, Record};
use super::table::{ForceRow, MarkerRow, RadiusRow};
use crate::scene::{key_at, line_col, locate, Scene, SceneError, SceneReadError};

/// `finger = R(angle) camera + offset`, `R` the rotation by `angle`
/// (from X towards Z). Known values for a comparison; a calibrator may fit
/// them as nuisance parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraFrame {
    /// The rotation (degrees).
    pub angle_deg: f64,
    /// The camera origin's X in the finger frame (mm).
    pub x_mm: f64,
    /// The camera origin's Z in the finger frame (mm).
    pub z_mm: f64,
}

impl CameraFrame {
    fn rotate(angle: f64, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = angle.sin_cos();
        [c * p[0] - s * p[1], s * p[0] + c * p[1]]
    }

    /// A camera point in the finger frame.
    pub fn to_finger(&self, p: [f64; 2]) -> [f64; 2] {
        let q = Self::rotate(self.angle_deg.to_radians(), p);
        [q[0] + self.x_mm, q[1] + self.z_mm]
    }

    /// A finger point in the camera frame.
    pub fn to_camera(&self, p: [f64; 2]) -> [f64; 2] {
        let q = [p[0] - self.x_mm, p[1] - self.z_mm];
        Self::rotate(-self.angle_deg.to_radians(), q)
    }
}

/// A test's rows, by kind.
#[derive(Debug, Clone, PartialEq)]
pub enum TestData {
    /// Marker points, in the finger frame or in a camera frame.
    Markers {
        /// The camera frame the points are in (`None`: the finger frame).
        camera: Option<CameraFrame>,
        /// The rows.
        rows: Vec<MarkerRow>,
    },
    /// Radii of curvature.
    Radius(Vec<RadiusRow>),
    /// Tip forces.
    Force(Vec<ForceRow>),
}

impl TestData {
    /// The kind.
    pub fn kind(&self) -> TestKind {
        match self {
            TestData::Markers { .. } => TestKind::Markers,
            TestData::Radius(_) => TestKind::Radius,
            TestData::Force(_) => TestKind::Force,
        }
    }

    /// How many data rows.
    pub fn len(&self) -> usize {
        match self {
            TestData::Markers { rows, .. } => rows.len(),
            TestData::Radius(r) => r.len(),
            TestData::Force(r) => r.len(),
        }
    }

    /// True without rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One test of a specimen: its file and its rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Test {
    /// The CSV file as shown in messages (the manifest's directory joined
    /// with the name the manifest gives).
    pub file: String,
    /// The rows.
    pub data: TestData,
}

/// A specimen: a finger with its actuator and its tests.
#[derive(Debug, Clone)]
pub struct Specimen {
    /// Its name (unique in the manifest).
    pub name: String,
    /// The finger, resolved from the scene tables: the scene file, then
    /// `[shared]`, then the specimen's `own` tables.
    pub scene: Scene,
    /// The scene keys that are this specimen's own parameters (dotted
    /// paths, e.g. `actuator.pemc.eps0`).
    pub own: Vec<String>,
    /// Its tests.
    pub tests: Vec<Test>,
}

/// A measurement manifest, read and checked ([`Manifest::load`]).
#[derive(Debug, Clone)]
pub struct Manifest {
    /// The manifest file as shown in messages.
    pub file: String,
    /// The scene keys every specimen shares (dotted paths of the
    /// `[shared]` tables and the shared scene file).
    pub shared: Vec<String>,
    /// The specimens, in the manifest's order.
    pub specimens: Vec<Specimen>,
}

// ------------------------------------------------------------ the document

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Doc {
    #[serde(default)]
    shared: Option<Spanned<Table>>,
    #[serde(default)]
    specimen: Vec<Spanned<SpecimenDoc>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SpecimenDoc {
    name: Spanned<String>,
    #[serde(default)]
    scene: Option<Spanned<String>>,
    #[serde(default)]
    own: Option<Spanned<Table>>,
    #[serde(default)]
    test: Vec<Spanned<TestDoc>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TestDoc {
    kind: TestKind,
    file: Spanned<String>,
    #[serde(default)]
    sd_mm: Option<Spanned<f64>>,
    #[serde(default)]
    camera: Option<Spanned<CameraFrame>>,
}

/// The manifest's text and name, for errors at a span.
struct Source<'a> {
    text: &'a str,
    file: &'a str,
    dir: &'a Path,
}

impl Source<'_> {
    fn err<T>(&self, s: &Spanned<T>, field: &str, reason: impl Into<String>) -> MeasureError {
        let (row, col) = line_col(self.text, s.span().start);
        MeasureError::at(self.file, row, col, field, reason)
    }

    /// A file named in the manifest: its path and how it is shown.
    fn path(&self, name: &str) -> (PathBuf, String) {
        let p = self.dir.join(name);
        let shown = p.display().to_string();
        (p, shown)
    }
}

/// Every leaf of a table as a dotted path.
fn leaves(t: &Table, prefix: &str, out: &mut Vec<String>) {
    for (k, v) in t {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            Value::Table(inner) => leaves(inner, &path, out),
            _ => out.push(path),
        }
    }
}

/// `from` laid over `into`, tables merged key by key.
fn merge(into: &mut Table, from: &Table) {
    for (k, v) in from {
        match (into.get_mut(k), v) {
            (Some(Value::Table(a)), Value::Table(b)) => merge(a, b),
            _ => {
                into.insert(k.clone(), v.clone());
            }
        }
    }
}

/// A scene file: its name as shown, its text and its tables.
struct SceneFileText {
    shown: String,
    text: String,
    tables: Table,
}

/// Reads a scene file.
fn scene_file(path: &Path, shown: &str) -> Result<SceneFileText, MeasureError> {
    let text = read_text(path, shown, MAX_SCENE_BYTES)?;
    let tables = text.parse::<Table>().map_err(|e| {
        let s = SceneError::from_toml(&text, &e);
        MeasureError::at(shown, s.line, s.col, "scene", s.message)
    })?;
    Ok(SceneFileText {
        shown: shown.to_string(),
        text,
        tables,
    })
}

// ------------------------------------------------------------ scene keys

/// The byte offset of a line and column (both from 1, the column in
/// characters) of `text`.
fn byte_offset(text: &str, line: usize, col: usize) -> usize {
    let start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    let rest = &text[start.min(text.len())..];
    start
        + rest
            .char_indices()
            .nth(col.saturating_sub(1))
            .map_or(rest.len(), |(i, _)| i)
}

/// One layer of a specimen's scene document and where its keys are
/// written: a scene file, the manifest's `[shared]` tables or the
/// specimen's `own` tables.
struct Layer<'a> {
    /// The file the keys are written in (as shown) and its text.
    file: &'a str,
    text: &'a str,
    /// The dotted path of the layer's tables in that file
    /// (`specimen[2].own`, `shared`; empty for a scene file).
    at: String,
    /// The prefix an error names the layer's keys with
    /// (`specimen.own`, `shared`; empty for a scene file).
    named: &'static str,
}

/// `prefix.key`, or `key` alone under an empty prefix.
fn under(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

/// An error at the scene key `key` (`actuator.pemc.eps0`,
/// `partition.lengths[2]`) of a specimen's document: at the value the
/// first layer that writes it (the specimen's own tables, the shared
/// tables, the scene file) writes, the field named as written there
/// (`specimen.own.actuator.pemc.eps0`, `shared.actuator.pemc.e2`, a scene
/// file's `actuator.pemc.e2`); `None` when no layer writes it (a default,
/// or a rule between keys).
fn at_key(layers: &[Layer], key: &str, reason: &str) -> Option<MeasureError> {
    if key.is_empty() {
        return None;
    }
    layers.iter().find_map(|l| {
        let (row, col) = locate(l.text, &under(&l.at, key))?;
        Some(MeasureError::at(
            l.file,
            row,
            col,
            under(l.named, key),
            reason,
        ))
    })
}

impl Manifest {
    /// Reads a manifest and every file it names, relative to its
    /// directory. Nothing is computed: every error is input.
    pub fn load(path: &Path) -> Result<Manifest, MeasureError> {
        let file = path.display().to_string();
        let text = read_text(path, &file, MAX_MANIFEST_BYTES)?;
        let dir = path.parent().unwrap_or(Path::new(""));
        Manifest::parse(&text, &file, dir)
    }

    /// A manifest from its text: `file` is its name in messages and `dir`
    /// the directory the files it names are relative to.
    pub fn parse(text: &str, file: &str, dir: &Path) -> Result<Manifest, MeasureError> {
        let src = Source { text, file, dir };
        let doc: Doc = toml::from_str(text).map_err(|e| {
            let s = SceneError::from_toml(text, &e);
            MeasureError::at(file, s.line, s.col, "manifest", s.message)
        })?;
        if let Some(extra) = doc.specimen.get(MAX_SPECIMENS) {
            return Err(src.err(
                extra,
                "specimen",
                format!("more than {MAX_SPECIMENS} specimens, the limit of a manifest"),
            ));
        }
        if doc.specimen.is_empty() {
            return Err(MeasureError::at(
                file,
                1,
                1,
                "specimen",
                "no [[specimen]]: a manifest lists at least one",
            ));
        }
        // the shared tables: a scene file, then inline tables
        let mut shared_file = None;
        let mut inline = Table::new();
        if let Some(s) = &doc.shared {
            inline = s.get_ref().clone();
            match inline.remove("scene") {
                None => {}
                Some(Value::String(name)) => {
                    let (p, shown) = src.path(&name);
                    shared_file = Some(scene_file(&p, &shown)?);
                }
                // at the key, not at the [shared] table
                Some(_) => {
                    let reason = "must be a file name";
                    return Err(match locate(text, "shared.scene") {
                        Some((row, col)) => {
                            MeasureError::at(file, row, col, "shared.scene", reason)
                        }
                        None => src.err(s, "shared.scene", reason),
                    });
                }
            }
        }
        let mut shared = shared_file
            .as_ref()
            .map_or_else(Table::new, |f| f.tables.clone());
        merge(&mut shared, &inline);
        let mut shared_keys = Vec::new();
        leaves(&shared, "", &mut shared_keys);
        let mut specimens: Vec<Specimen> = Vec::new();
        let mut rows_left = MAX_TOTAL_ROWS;
        for (index, sp) in doc.specimen.iter().enumerate() {
            let s = sp.get_ref();
            let name = s.name.get_ref().trim().to_string();
            if name.is_empty() {
                return Err(src.err(&s.name, "name", "must not be empty"));
            }
            if specimens.iter().any(|o| o.name == name) {
                return Err(src.err(&s.name, "name", format!("a second specimen {name:?}")));
            }
            if let Some(extra) = s.test.get(MAX_TESTS) {
                return Err(src.err(
                    extra,
                    "test",
                    format!("more than {MAX_TESTS} tests, the limit of a specimen"),
                ));
            }
            // the layers: its scene file (else the shared one), the
            // inline shared tables, its own tables
            let own_file = match &s.scene {
                Some(f) => {
                    let (p, shown) = src.path(f.get_ref());
                    Some(scene_file(&p, &shown)?)
                }
                None => None,
            };
            let base = own_file.as_ref().or(shared_file.as_ref());
            let own_tables = s
                .own
                .as_ref()
                .map_or_else(Table::new, |o| o.get_ref().clone());
            let mut doc_tables = base.map_or_else(Table::new, |f| f.tables.clone());
            merge(&mut doc_tables, &inline);
            merge(&mut doc_tables, &own_tables);
            let mut own = Vec::new();
            leaves(&own_tables, "", &mut own);
            let mut layers = vec![
                Layer {
                    file,
                    text,
                    at: format!("specimen[{index}].own"),
                    named: "specimen.own",
                },
                Layer {
                    file,
                    text,
                    at: "shared".into(),
                    named: "shared",
                },
            ];
            if let Some(f) = base {
                layers.push(Layer {
                    file: &f.shown,
                    text: &f.text,
                    at: String::new(),
                    named: "",
                });
            }
            // an error at a scene key: where a layer writes it, else at the
            // specimen's own table (or its name)
            let at_own = |field: &str, reason: String| {
                at_key(&layers, field, &reason).unwrap_or_else(|| match &s.own {
                    Some(o) => src.err(o, field, reason),
                    None => src.err(&s.name, field, reason),
                })
            };
            if doc_tables.contains_key("gripper") {
                return Err(at_own(
                    "gripper",
                    format!(
                        "specimen {name:?}: a measured specimen is a finger whose tests set its loads; remove [gripper] from its scene tables"
                    ),
                ));
            }
            if let Some(key) = test_load_key(&doc_tables) {
                return Err(at_own(
                    &key,
                    format!(
                        "specimen {name:?}: a measured specimen's tests set its pressure and tip forces; of [load] its scene tables may set only kappa (and zeros, as a calibrated scene writes them)"
                    ),
                ));
            }
            let scene_text = toml::to_string(&doc_tables)
                .map_err(|e| at_own("own", format!("specimen {name:?}: {e}")))?;
            let scene = Scene::from_toml(&scene_text).map_err(|e| match e {
                SceneReadError::Syntax(e) => {
                    // the key of the generated document the error is at
                    let offset = byte_offset(&scene_text, e.line, e.col);
                    let reason = format!("specimen {name:?}: {}", e.message);
                    match key_at(&scene_text, offset).and_then(|k| at_key(&layers, &k, &reason)) {
                        Some(located) => located,
                        None => at_own("own", reason),
                    }
                }
                SceneReadError::Input(i) => {
                    at_own(&i.field().to_string(), format!("specimen {name:?}: {i}"))
                }
            })?;
            let length_mm = scene.actuator.geometry().lx;
            let mut tests = Vec::new();
            for t in &s.test {
                let test = read_test(&src, t, length_mm, &mut rows_left)?;
                tests.push(test);
            }
            specimens.push(Specimen {
                name,
                scene,
                own,
                tests,
            });
        }
        Ok(Manifest {
            file: file.to_string(),
            shared: shared_keys,
            specimens,
        })
    }
}

/// The scene key of a specimen's `[load]` that its tests set instead (a
/// pressure or tip force other than zero, any other key, or `load` itself
/// when it is not a table); `kappa`, the gas law's factor, belongs to the
/// finger and may be given.
fn test_load_key(tables: &Table) -> Option<String> {
    let Some(Value::Table(load)) = tables.get("load") else {
        return tables.get("load").map(|_| "load".to_string());
    };
    let zero = |v: &Value| matches!(v, Value::Integer(0)) || v.as_float() == Some(0.0);
    let set_by_tests = |k: &str, v: &Value| {
        k != "kappa" && !(["pressure_kpa", "fx", "fz"].contains(&k) && zero(v))
    };
    load.iter()
        .find(|(k, v)| set_by_tests(k, v))
        .map(|(k, _)| format!("load.{k}"))
}

/// Reads one test's file, checking the keys that belong to its kind.
fn read_test(
    src: &Source,
    t: &Spanned<TestDoc>,
    length_mm: f64,
    rows_left: &mut usize,
) -> Result<Test, MeasureError> {
    let d = t.get_ref();
    let kind = d.kind;
    let markers_only = |key: &str| {
        src.err(
            t,
            key,
            format!(
                "only a markers test has this key, not a {} test",
                kind.name()
            ),
        )
    };
    if kind != TestKind::Markers {
        if d.sd_mm.is_some() {
            return Err(markers_only("sd_mm"));
        }
        if d.camera.is_some() {
            return Err(markers_only("camera"));
        }
    }
    if let Some(sd) = &d.sd_mm {
        let x = *sd.get_ref();
        if !x.is_finite() {
            return Err(src.err(sd, "sd_mm", format!("{x} must be a positive number")));
        }
        if let Some(why) = bad_sd(x, MAX_LENGTH_MM, "mm") {
            return Err(src.err(sd, "sd_mm", why));
        }
    }
    if let Some(c) = &d.camera {
        let f = c.get_ref();
        for (key, x, max, unit) in [
            ("camera.angle_deg", f.angle_deg, MAX_ANGLE_DEG, "degrees"),
            ("camera.x_mm", f.x_mm, MAX_LENGTH_MM, "mm"),
            ("camera.z_mm", f.z_mm, MAX_LENGTH_MM, "mm"),
        ] {
            if !x.is_finite() {
                return Err(src.err(c, key, format!("{x} is not a finite number")));
            }
            if let Some(why) = beyond(x, max, unit) {
                return Err(src.err(c, key, why));
            }
        }
    }
    let (path, shown) = src.path(d.file.get_ref());
    let text = read_text(&path, &shown, MAX_DATA_BYTES)?;
    let ctx = Context {
        file: &shown,
        length_mm,
        default_sd_mm: d.sd_mm.as_ref().map(|s| *s.get_ref()),
        max_rows: (*rows_left).min(MAX_ROWS),
    };
    let data = match kind {
        TestKind::Markers => TestData::Markers {
            camera: d.camera.as_ref().map(|c| *c.get_ref()),
            rows: table::read(
                kind,
                &text,
                &ctx,
                |r: &Record| r.marker(),
                |r: &MarkerRow| {
                    (
                        format!("{} {}", bits(r.pressure_kpa), r.marker),
                        "pressure_kpa and marker",
                    )
                },
            )?,
        },
        TestKind::Radius => TestData::Radius(table::read(
            kind,
            &text,
            &ctx,
            |r: &Record| r.radius(),
            |r: &RadiusRow| (bits(r.pressure_kpa).to_string(), "pressure_kpa"),
        )?),
        TestKind::Force => TestData::Force(table::read(
            kind,
            &text,
            &ctx,
            |r: &Record| r.force(),
            |r: &ForceRow| {
                (
                    format!(
                        "{} {} {}",
                        bits(r.pressure_kpa),
                        r.axis.name(),
                        bits(r.displacement_mm)
                    ),
                    "pressure_kpa, axis and displacement_mm",
                )
            },
        )?),
    };
    *rows_left -= data.len();
    Ok(Test { file: shown, data })
}
