//! `fpc solve SCENE.toml`: solve the finger, or the gripper grasp, that a
//! scene file describes, and write `solution.json`, `shape.csv` and
//! `shape.svg` into the output directory (default `./<stem>-out/`).

use std::fmt::Write as _;
use std::fs;
use std::io::{Read as _, Write as _};
use std::path::{Path, PathBuf};

use anyhow::Context;
use fpc::scene::{warning_text, GraspOutcome, GraspSpec, SceneFile, SceneSolution};
use fpc::{Gripper, Invalid, Solution};
use serde_json::json;

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
    crate::output::prepare_dir(&out)?;

    let json = solution_json(&stem, scene.file(), &solved)?;
    write_atomic(
        &out,
        "solution.json",
        (serde_json::to_string_pretty(&json)? + "\n").as_bytes(),
    )?;
    write_atomic(&out, "shape.csv", shape_csv(&solved).as_bytes())?;
    write_atomic(&out, "shape.svg", shape_svg(&stem, &solved).as_bytes())?;

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
fn read_scene(path: &Path, shown: &str) -> anyhow::Result<String> {
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

fn solution_json(
    stem: &str,
    file: &SceneFile,
    solved: &SceneSolution,
) -> anyhow::Result<serde_json::Value> {
    let mut v = crate::finger::to_json(solved.solution());
    v["elements"] = json!(solved.elements());
    v["tip_error_estimate_mm"] = match solved {
        SceneSolution::Finger {
            tip_error_estimate_mm,
            ..
        } => json!(tip_error_estimate_mm),
        SceneSolution::Gripper { .. } => json!(null),
    };
    v["scene_name"] = json!(stem);
    v["scene"] = serde_json::to_value(file)?;
    v["warnings"] = json!(solved
        .warnings()
        .iter()
        .map(warning_text)
        .collect::<Vec<_>>());
    match solved {
        SceneSolution::Finger { .. } => v["kind"] = json!("finger"),
        SceneSolution::Gripper { gripper, grasp } => {
            v["kind"] = json!(if grasp.is_some() { "grasp" } else { "gripper" });
            v["gripper"] = gripper_json(gripper);
            v["grasp"] = match grasp {
                Some(g) => grasp_json(gripper, g),
                None => json!(null),
            };
            v["points_gripper_mm"] = json!(solved
                .solution()
                .points
                .iter()
                .map(|&p| gripper.to_gripper(p))
                .collect::<Vec<_>>());
        }
    }
    Ok(v)
}

fn gripper_json(g: &Gripper) -> serde_json::Value {
    json!({
        "mounting_angle_deg": degrees(g.mounting_angle()),
        "mu": g.mu(),
        "fingers": g.params().fingers,
        "l0_mm": g.l0(),
        "palm_mm": g.palm(),
        "overlap_mm": g.overlap(),
        "d_min_mm": g.d_min(),
        "d_max_mm": g.d_max(),
        "r_max_mm": g.r_max(),
        "tip_is_innermost": g.tip_is_innermost(),
        "rest_tip_gripper_mm": g.to_gripper(g.reference().tip),
    })
}

fn grasp_json(gripper: &Gripper, o: &GraspOutcome) -> serde_json::Value {
    let g = &o.grasp;
    let mut v = json!({
        "kind": o.spec.name(),
        "pressure_kpa": g.pressure_kpa,
        "beta_deg": degrees(g.beta),
        "normal_force_n": g.normal,
        "friction_n": g.friction,
        "friction_limit_n": gripper.mu() * g.normal,
        "lift_n": g.lift,
        "size_mm": g.size,
        "tip_gap_mm": g.tip_gap,
        "height_mm": g.height,
        "tip_gripper_mm": g.tip,
        "tip_load_finger_n": [g.load.fx, g.load.fz],
        "valid": o.is_valid(),
        "invalid": o.invalid.as_ref().map(invalid_text),
    });
    if let Some(s) = &o.sphere {
        v["sphere_radius_mm"] = json!(s.radius);
        v["sphere_center_gripper_mm"] = json!(s.center);
    }
    v
}

/// Radians in degrees, rounded to 1e-9 deg (60 deg prints as 60).
fn degrees(rad: f64) -> f64 {
    (rad.to_degrees() * 1e9).round() / 1e9
}

fn invalid_text(i: &Invalid) -> String {
    i.to_string()
}

// ------------------------------------------------------------ shape.csv

fn shape_csv(solved: &SceneSolution) -> String {
    let pts = &solved.solution().points;
    let mut s = String::new();
    match solved {
        SceneSolution::Finger { .. } => {
            s.push_str("x_mm,z_mm\n");
            for p in pts {
                let _ = writeln!(s, "{},{}", p[0], p[1]);
            }
        }
        SceneSolution::Gripper { gripper, .. } => {
            s.push_str("x_mm,z_mm,xg_mm,zg_mm\n");
            for &p in pts {
                let q = gripper.to_gripper(p);
                let _ = writeln!(s, "{},{},{},{}", p[0], p[1], q[0], q[1]);
            }
        }
    }
    s
}

// ------------------------------------------------------------ shape.svg

/// A drawing in millimetres, y down (SVG's own orientation).
struct Drawing {
    items: Vec<String>,
    lo: [f64; 2],
    hi: [f64; 2],
}

impl Drawing {
    fn new() -> Drawing {
        Drawing {
            items: Vec::new(),
            lo: [f64::INFINITY; 2],
            hi: [f64::NEG_INFINITY; 2],
        }
    }

    fn include(&mut self, p: [f64; 2]) {
        if p.iter().all(|v| v.is_finite()) {
            for ((lo, hi), v) in self.lo.iter_mut().zip(&mut self.hi).zip(p) {
                *lo = lo.min(v);
                *hi = hi.max(v);
            }
        }
    }

    fn polyline(&mut self, pts: &[[f64; 2]], style: &str) {
        if pts.is_empty() {
            return;
        }
        let mut d = String::new();
        for p in pts {
            self.include(*p);
            let _ = write!(d, "{:.4},{:.4} ", p[0], p[1]);
        }
        self.items.push(format!(
            r#"<polyline points="{}" fill="none" {style}/>"#,
            d.trim_end()
        ));
    }

    fn circle(&mut self, c: [f64; 2], r: f64, style: &str) {
        self.include([c[0] - r, c[1] - r]);
        self.include([c[0] + r, c[1] + r]);
        self.items.push(format!(
            r#"<circle cx="{:.4}" cy="{:.4}" r="{:.4}" {style}/>"#,
            c[0], c[1], r
        ));
    }

    fn dot(&mut self, c: [f64; 2], style: &str) {
        self.include(c);
        self.items.push(format!(
            r#"<circle cx="{:.4}" cy="{:.4}" r="1.2" {style}/>"#,
            c[0], c[1]
        ));
    }

    fn render(mut self, title: &str, caption: &[String]) -> String {
        if !self.lo[0].is_finite() {
            self.include([0.0, 0.0]);
        }
        let margin = 10.0;
        let (x0, y0) = (self.lo[0] - margin, self.lo[1] - margin);
        // captions: 3.5 mm text, or smaller down to 2 mm to fit the
        // drawing's width; wider still widens the drawing
        let chars = caption.iter().map(|c| c.chars().count()).max().unwrap_or(0) as f64;
        let mut w = (self.hi[0] - self.lo[0] + 2.0 * margin).max(20.0);
        let font = (w / (0.56 * chars + 4.0)).clamp(2.0, 3.5);
        w = w.max(0.56 * font * chars + 4.0);
        let line = 1.5 * font;
        let h = (self.hi[1] - self.lo[1] + 2.0 * margin).max(20.0) + line * caption.len() as f64;
        let scale = 4.0; // px per mm
        let mut s = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="{x0:.4} {y0:.4} {w:.4} {h:.4}">
<title>{}</title>
<rect x="{x0:.4}" y="{y0:.4}" width="{w:.4}" height="{h:.4}" fill="white"/>
"#,
            w * scale,
            h * scale,
            escape(title)
        );
        for it in &self.items {
            s.push_str(it);
            s.push('\n');
        }
        let base = self.hi[1] + margin;
        for (i, c) in caption.iter().enumerate() {
            let _ = writeln!(
                s,
                r#"<text x="{:.4}" y="{:.4}" font-family="sans-serif" font-size="{font:.3}" fill="black">{}</text>"#,
                x0 + 2.0,
                base + line * (i as f64 + 0.5),
                escape(c)
            );
        }
        s.push_str("</svg>\n");
        s
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

const FINGER: &str = r##"stroke="#1f5fbf" stroke-width="0.8" stroke-linejoin="round""##;
const MIRROR: &str = r##"stroke="#1f5fbf" stroke-opacity="0.35" stroke-width="0.8""##;
const REST: &str = r##"stroke="#888888" stroke-width="0.5" stroke-dasharray="2 1.5""##;
const OBJECT: &str = r##"fill="#e8a33d" fill-opacity="0.25" stroke="#b06a00" stroke-width="0.6""##;
const PALM: &str = r##"stroke="#333333" stroke-width="2""##;
const AXIS: &str = r##"stroke="#aaaaaa" stroke-width="0.3" stroke-dasharray="4 1 1 1""##;
const TIP: &str = r##"fill="#c0392b""##;

fn shape_svg(stem: &str, solved: &SceneSolution) -> String {
    let sol = solved.solution();
    let mut d = Drawing::new();
    match solved {
        SceneSolution::Finger { .. } => {
            // finger frame, Z up: draw (X, -Z)
            let flip = |p: &[f64; 2]| [p[0], -p[1]];
            let len = sol.points.last().map_or(0.0, |_| {
                sol.points
                    .windows(2)
                    .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
                    .sum::<f64>()
            });
            d.polyline(&[[0.0, 0.0], [len.max(10.0), 0.0]], REST);
            d.polyline(&sol.points.iter().map(flip).collect::<Vec<_>>(), FINGER);
            d.dot([0.0, 0.0], r##"fill="#333333""##);
            d.dot(flip(&sol.tip), TIP);
            let mut caption = vec![
                format!("{stem}: mid-plane in the finger frame, mm (X right, Z up)"),
                "dashed: the finger's X axis; red: the tip".to_string(),
            ];
            caption.push(format!(
                "tip X = {:.3} mm, Z = {:.3} mm, end angle {:.2} deg",
                sol.tip[0],
                sol.tip[1],
                sol.end_angle.to_degrees()
            ));
            if sol.points.is_empty() {
                caption.push("shape not sampled (solve.shape = false)".into());
            }
            d.render(stem, &caption)
        }
        SceneSolution::Gripper { gripper, grasp } => {
            // gripper frame, Zg down = SVG's y
            let palm = gripper.palm();
            let to_g = |p: &[f64; 2]| gripper.to_gripper(*p);
            let mirror = |p: [f64; 2]| [-p[0], p[1]];
            let finger: Vec<[f64; 2]> = sol.points.iter().map(to_g).collect();
            let rest = gripper.rest_shape();
            let depth = finger
                .iter()
                .chain(&rest)
                .map(|p| p[1])
                .fold(0.0_f64, f64::max);
            d.polyline(&[[0.0, -5.0], [0.0, depth + 10.0]], AXIS);
            d.polyline(&rest, REST);
            d.polyline(&rest.iter().map(|&p| mirror(p)).collect::<Vec<_>>(), REST);
            let mut caption = vec![
                format!("{stem}: gripper frame, mm (Xg right, Zg down)"),
                "dashed: fingers at rest (P = 0, unloaded); pale: the opposite finger".to_string(),
            ];
            if let Some(o) = grasp {
                draw_object(&mut d, o, gripper);
                caption.extend(grasp_caption(o));
            } else {
                caption.push(format!(
                    "l0 = {:.3} mm, palm l = {:.3} mm, overlap g = {:.3} mm, d_max = {:.3} mm",
                    gripper.l0(),
                    palm,
                    gripper.overlap(),
                    gripper.d_max()
                ));
            }
            d.polyline(
                &finger.iter().map(|&p| mirror(p)).collect::<Vec<_>>(),
                MIRROR,
            );
            d.polyline(&finger, FINGER);
            d.polyline(&[[-0.5 * palm - 5.0, 0.0], [0.5 * palm + 5.0, 0.0]], PALM);
            d.dot(gripper.to_gripper(sol.tip), TIP);
            d.render(stem, &caption)
        }
    }
}

fn draw_object(d: &mut Drawing, o: &GraspOutcome, gripper: &Gripper) {
    let g = &o.grasp;
    let tip = g.tip;
    match o.spec {
        GraspSpec::Cuboid { .. } => {
            // the faces the tips touch, at Xg = +-tip Xg; the block is
            // drawn as a square centred on the tips' height
            let half = tip[0].abs().max(1.0);
            let pts = [
                [-half, tip[1] - half],
                [half, tip[1] - half],
                [half, tip[1] + half],
                [-half, tip[1] + half],
                [-half, tip[1] - half],
            ];
            d.items.push(format!(
                r#"<polygon points="{}" {OBJECT}/>"#,
                pts.iter()
                    .map(|p| format!("{:.4},{:.4}", p[0], p[1]))
                    .collect::<Vec<_>>()
                    .join(" ")
            ));
            for p in pts {
                d.include(p);
            }
        }
        GraspSpec::Size { .. } => {
            // the object's surface at the contact: through the tip along
            // t = (-sin b, cos b), and its mirror
            let (s, c) = g.beta.sin_cos();
            let l = 0.15 * gripper.length();
            let seg = [
                [tip[0] + s * l, tip[1] - c * l],
                [tip[0] - s * l, tip[1] + c * l],
            ];
            let style = r##"stroke="#b06a00" stroke-width="1""##;
            d.polyline(&seg, style);
            d.polyline(&seg.map(|p| [-p[0], p[1]]), style);
        }
        GraspSpec::Sphere { .. } => {
            if let Some(s) = &o.sphere {
                if s.radius > 0.0 {
                    d.circle(s.center, s.radius, OBJECT);
                }
            }
        }
    }
}

fn grasp_caption(o: &GraspOutcome) -> [String; 2] {
    let g = &o.grasp;
    [
        format!(
            "{} grasp at {} kPa, b = {:.2} deg: F = {:.4} N, f = {:.4} N, f_v = {:.4} N",
            o.spec.name(),
            g.pressure_kpa,
            g.beta.to_degrees(),
            g.normal,
            g.friction,
            g.lift,
        ),
        format!(
            "d = {:.3} mm, tip gap = {:.3} mm, h = {:.3} mm: {}",
            g.size,
            g.tip_gap,
            g.height,
            if o.is_valid() { "valid" } else { "NOT valid" }
        ),
    ]
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
                    Some(i) => writeln!(out, "valid          NO: {}", invalid_text(i))?,
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
