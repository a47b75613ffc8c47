//! `shape.svg`'s content: the finger or gripper drawing as a [`Figure`] of
//! the report model (one equal-aspect panel in mm, its legend entries and a
//! caption), drawn by the one SVG writer.

use fpc::num::Num;
use fpc::report::{Figure, Panel, PlotAxis, RefLine, Series, SeriesKind};
use fpc::scene::{warning_text, GraspOutcome, GraspSpec, SceneSolution};
use fpc::{Gripper, Solution, Warning};

/// The largest coordinate drawn (mm): a point farther out (1 km) is left
/// out rather than stretching the axes beyond use.
const MAX_COORD_MM: f64 = 1e6;

/// The points that can be drawn: finite and within [`MAX_COORD_MM`].
pub(super) fn drawable(points: impl IntoIterator<Item = [f64; 2]>) -> Vec<[f64; 2]> {
    let ok = |p: &[f64; 2]| p.iter().all(|v| v.is_finite() && v.abs() <= MAX_COORD_MM);
    points.into_iter().filter(ok).collect()
}

/// Adds a series of colour key `color` through the drawable `points` (a
/// line needs two, a marker one), with a legend entry unless `label` is
/// empty.
fn add(
    p: &mut Panel,
    color: &str,
    kind: SeriesKind,
    label: &str,
    points: impl IntoIterator<Item = [f64; 2]>,
) {
    let points = drawable(points);
    let least = if kind == SeriesKind::Points { 1 } else { 2 };
    if points.len() >= least {
        let s = Series::new(color, kind, points);
        p.series
            .push(if label.is_empty() { s } else { s.label(label) });
    }
}

/// Width of the figure (px), and the bounds of its plotting height.
const WIDTH: u32 = 820;
const PLOT_H: (f64, f64) = (260.0, 760.0);

/// `shape.svg`'s figure: the solved shape in its frame.
pub(super) fn shape_figure(stem: &str, solved: &SceneSolution) -> Figure {
    let stem = crate::report::sanitize(stem);
    let warnings = solved.warnings();
    let (title, mut p) = match solved {
        SceneSolution::Finger(s) => finger_panel(&stem, &s.solution),
        SceneSolution::Gripper { gripper, grasp } => {
            gripper_panel(&stem, gripper, grasp.as_deref(), solved.solution())
        }
    };
    p.caption.extend(findings(&warnings));
    p.equal_aspect = true;
    // a height that fits the drawing's aspect and the caption's lines
    let (mut lo, mut hi) = ([0.0_f64; 2], [0.0_f64; 2]);
    for q in p.series.iter().flat_map(|s| &s.points) {
        lo = [lo[0].min(q[0]), lo[1].min(q[1])];
        hi = [hi[0].max(q[0]), hi[1].max(q[1])];
    }
    let aspect = (hi[1] - lo[1]).max(10.0) / (hi[0] - lo[0]).max(10.0);
    let plot_h = (740.0 * aspect).clamp(PLOT_H.0, PLOT_H.1);
    let chars: usize = p.caption.iter().map(|c| c.chars().count() / 100 + 1).sum();
    let height = plot_h as u32 + 120 + 17 * chars as u32;
    Figure::row(title, [WIDTH, height], vec![p])
}

/// A finger scene in the finger frame: X right, Z up, root at the origin.
fn finger_panel(stem: &str, sol: &Solution) -> (String, Panel) {
    let mut p = Panel::new("", PlotAxis::new("X", "mm"), PlotAxis::new("Z", "mm"));
    let length: f64 = sol.element_lengths.iter().sum();
    add(
        &mut p,
        "rest",
        SeriesKind::Dashed,
        "the finger's X axis (straight, unstrained)",
        [[0.0, 0.0], [length.max(10.0), 0.0]],
    );
    add(
        &mut p,
        "finger",
        SeriesKind::Line,
        "finger mid-plane",
        sol.points.iter().copied(),
    );
    add(
        &mut p,
        "palm",
        SeriesKind::Points,
        "root (clamped)",
        [[0.0, 0.0]],
    );
    add(&mut p, "tip", SeriesKind::Points, "tip", [sol.tip]);
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
    let title = format!("{stem}: the finger in its own frame (X right, Z up)");
    (title, p)
}

/// A gripper scene in the gripper frame: Xg right, Zg down, the palm's
/// centre at the origin; the opposite finger mirrored about Xg = 0.
fn gripper_panel(
    stem: &str,
    gripper: &Gripper,
    grasp: Option<&GraspOutcome>,
    sol: &Solution,
) -> (String, Panel) {
    let mut p = Panel::new(
        "",
        PlotAxis::new("Xg", "mm"),
        PlotAxis::new("Zg", "mm, pointing down"),
    );
    p.y.down = true;
    let mirror = |q: &[f64; 2]| [-q[0], q[1]];
    let finger: Vec<[f64; 2]> = sol.points.iter().map(|&q| gripper.to_gripper(q)).collect();
    let rest = gripper.rest_shape();
    p.vlines.push(RefLine {
        at: 0.0,
        label: "gripper axis (Xg = 0)".into(),
    });
    let rest_label = "fingers at rest (P = 0, unloaded)";
    add(
        &mut p,
        "rest",
        SeriesKind::Dashed,
        rest_label,
        rest.iter().copied(),
    );
    add(
        &mut p,
        "rest",
        SeriesKind::Dashed,
        "",
        rest.iter().map(mirror),
    );
    if let Some(o) = grasp {
        draw_object(&mut p, o, gripper);
    }
    let opposite = finger.iter().map(mirror);
    add(
        &mut p,
        "mirror",
        SeriesKind::Line,
        "opposite finger (mirrored)",
        opposite,
    );
    add(
        &mut p,
        "finger",
        SeriesKind::Line,
        "finger mid-plane",
        finger.iter().copied(),
    );
    let half = 0.5 * gripper.palm() + 5.0;
    add(
        &mut p,
        "palm",
        SeriesKind::Line,
        "palm (Zg = 0)",
        [[-half, 0.0], [half, 0.0]],
    );
    add(
        &mut p,
        "tip",
        SeriesKind::Points,
        "tip",
        [gripper.to_gripper(sol.tip)],
    );
    p.caption.extend(gripper_caption(gripper, sol));
    if let Some(o) = grasp {
        p.caption.extend(grasp_caption(o));
    }
    let title = format!("{stem}: the gripper frame (Xg right, Zg down)");
    (title, p)
}

/// The object of a grasp, in the gripper frame.
fn draw_object(p: &mut Panel, o: &GraspOutcome, gripper: &Gripper) {
    let tip = o.grasp.tip;
    match o.spec {
        GraspSpec::Cuboid { .. } => {
            // the faces the tips touch, at Xg = +-tip Xg; drawn as a
            // square centred on the tips' height
            let h = tip[0].abs().max(1.0);
            let corners = [[-h, -h], [h, -h], [h, h], [-h, h], [-h, -h]];
            add(
                p,
                "object",
                SeriesKind::Outline,
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
            let surface = "object surface at the contacts";
            add(p, "object", SeriesKind::Line, surface, seg);
            add(
                p,
                "object",
                SeriesKind::Line,
                "",
                seg.map(|q| [-q[0], q[1]]),
            );
        }
        GraspSpec::Sphere { .. } => {
            if let Some(s) = o.sphere.as_ref().filter(|s| s.radius > 0.0) {
                let circle = (0..=CIRCLE_SEGMENTS).map(|k| {
                    let t = std::f64::consts::TAU * f64::from(k) / f64::from(CIRCLE_SEGMENTS);
                    [
                        s.center[0] + s.radius * t.cos(),
                        s.center[1] + s.radius * t.sin(),
                    ]
                });
                add(p, "object", SeriesKind::Outline, "sphere", circle);
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
    if let Some(i) = &o.invalid() {
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

/// A number with `decimals` decimals, or an exponent at a magnitude they
/// do not show ([`Num`]); `n/a` when not finite.
pub(super) fn num(x: f64, decimals: usize) -> String {
    if x.is_finite() {
        format!("{:.decimals$}", Num(x))
    } else {
        "n/a".into()
    }
}
