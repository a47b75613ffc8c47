//! `shape.svg`'s content: the items, legend labels and captions of the
//! finger or gripper figure, in plot coordinates.

use fpc::scene::{warning_text, GraspOutcome, GraspSpec, SceneSolution};
use fpc::{Gripper, Solution, Warning};
use plotters::prelude::*;

use super::render::render;

/// How an item of the drawing looks; the order is the legend's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Look {
    /// The finger's mid-plane.
    Finger,
    /// The opposite finger: the mid-plane mirrored about the gripper axis.
    Mirror,
    /// The fingers at rest, or a lone finger's straight X axis (dashed).
    Rest,
    /// The palm, Zg = 0.
    Palm,
    /// The gripper axis, Xg = 0 (dotted).
    Axis,
    /// The held object's section (filled).
    Object,
    /// The object's surface at the contacts (a size grasp).
    Contact,
    /// The finger's root (a dot).
    Root,
    /// The finger's tip (a dot).
    Tip,
}

const BLUE: RGBColor = RGBColor(31, 95, 191);
pub(super) const ORANGE: RGBColor = RGBColor(176, 106, 0);
const RED: RGBColor = RGBColor(192, 57, 43);
const GREY: RGBColor = RGBColor(120, 120, 120);
const DARK: RGBColor = RGBColor(51, 51, 51);

impl Look {
    /// The stroke (or, for dots, the fill).
    pub(super) fn style(self) -> ShapeStyle {
        match self {
            Look::Finger => BLUE.stroke_width(2),
            Look::Mirror => BLUE.mix(0.35).stroke_width(2),
            Look::Rest => GREY.stroke_width(1),
            Look::Palm => DARK.stroke_width(5),
            Look::Axis => GREY.mix(0.8).stroke_width(1),
            Look::Object => ORANGE.stroke_width(1),
            Look::Contact => ORANGE.stroke_width(2),
            Look::Root => DARK.filled(),
            Look::Tip => RED.filled(),
        }
    }

    /// Dash and gap lengths (px) of a dashed line.
    pub(super) fn dashes(self) -> Option<(u32, u32)> {
        match self {
            Look::Rest => Some((6, 4)),
            Look::Axis => Some((2, 4)),
            _ => None,
        }
    }

    pub(super) fn is_dot(self) -> bool {
        matches!(self, Look::Root | Look::Tip)
    }
}

/// One item: a line, a filled outline ([`Look::Object`]) or a dot, in
/// plot coordinates (mm, y up).
pub(super) struct Item {
    pub(super) look: Look,
    /// Its legend entry; empty for none.
    pub(super) label: &'static str,
    pub(super) points: Vec<(f64, f64)>,
}

/// The largest coordinate drawn (mm): a point farther out (1 km) is left
/// out rather than stretching the axes beyond use.
const MAX_COORD_MM: f64 = 1e6;

/// A point that can be drawn: finite and within [`MAX_COORD_MM`].
pub(super) fn drawable(p: [f64; 2]) -> Option<(f64, f64)> {
    p.iter()
        .all(|v| v.is_finite() && v.abs() <= MAX_COORD_MM)
        .then_some((p[0], p[1]))
}

/// A drawing in one frame, before rendering.
pub(super) struct Plot {
    /// The first line, above the plot.
    pub(super) title: String,
    pub(super) x_desc: &'static str,
    pub(super) y_desc: &'static str,
    /// The frame's vertical axis points down: the plot's y is its
    /// negative, and the ticks show the frame's values.
    pub(super) y_down: bool,
    pub(super) items: Vec<Item>,
    /// Lines under the plot (wrapped to its width when drawn).
    pub(super) caption: Vec<String>,
}

impl Plot {
    pub(super) fn new(
        title: String,
        x_desc: &'static str,
        y_desc: &'static str,
        y_down: bool,
    ) -> Plot {
        Plot {
            title,
            x_desc,
            y_desc,
            y_down,
            items: Vec::new(),
            caption: Vec::new(),
        }
    }

    /// Adds an item through the drawable ones of `points`, given in the
    /// frame's coordinates; a line needs two, a dot one.
    pub(super) fn add(
        &mut self,
        look: Look,
        label: &'static str,
        points: impl IntoIterator<Item = [f64; 2]>,
    ) {
        let flip = if self.y_down { -1.0 } else { 1.0 };
        let points: Vec<(f64, f64)> = points
            .into_iter()
            .filter_map(|p| drawable([p[0], flip * p[1]]))
            .collect();
        if points.len() >= if look.is_dot() { 1 } else { 2 } {
            self.items.push(Item {
                look,
                label,
                points,
            });
        }
    }

    /// The smallest box around every item and the origin (the root, or
    /// the palm's centre), with a margin and at least 10 mm each way.
    pub(super) fn extent(&self) -> ([f64; 2], [f64; 2]) {
        let (mut lo, mut hi) = ([0.0_f64; 2], [0.0_f64; 2]);
        for &(x, y) in self.items.iter().flat_map(|i| &i.points) {
            lo = [lo[0].min(x), lo[1].min(y)];
            hi = [hi[0].max(x), hi[1].max(y)];
        }
        let pad = (0.06 * (hi[0] - lo[0]).max(hi[1] - lo[1])).max(4.0);
        for k in 0..2 {
            let grow = (0.5 * (10.0 - (hi[k] - lo[k]))).max(0.0) + pad;
            lo[k] -= grow;
            hi[k] += grow;
        }
        (lo, hi)
    }
}

/// `shape.svg`: the solved shape in its frame, with axes in mm at an equal
/// aspect, a legend and a caption.
pub(super) fn shape_svg(stem: &str, solved: &SceneSolution) -> anyhow::Result<String> {
    let stem = crate::report::sanitize(stem);
    let warnings = solved.warnings();
    let plot = match solved {
        SceneSolution::Finger { solution, .. } => finger_plot(&stem, solution, &warnings),
        SceneSolution::Gripper { gripper, grasp } => gripper_plot(
            &stem,
            gripper,
            grasp.as_deref(),
            solved.solution(),
            &warnings,
        ),
    };
    render(&plot)
}

/// A finger scene in the finger frame: X right, Z up, root at the origin.
fn finger_plot(stem: &str, sol: &Solution, warnings: &[Warning]) -> Plot {
    let mut p = Plot::new(
        format!("{stem}: the finger in its own frame (X right, Z up)"),
        "X (mm)",
        "Z (mm)",
        false,
    );
    let length: f64 = sol.element_lengths.iter().sum();
    p.add(
        Look::Rest,
        "the finger's X axis (straight, unstrained)",
        [[0.0, 0.0], [length.max(10.0), 0.0]],
    );
    p.add(Look::Finger, "finger mid-plane", sol.points.iter().copied());
    p.add(Look::Root, "root (clamped)", [[0.0, 0.0]]);
    p.add(Look::Tip, "tip", [sol.tip]);
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
    p.caption.extend(findings(warnings));
    p
}

/// A gripper scene in the gripper frame: Xg right, Zg down, the palm's
/// centre at the origin; the opposite finger mirrored about Xg = 0.
fn gripper_plot(
    stem: &str,
    gripper: &Gripper,
    grasp: Option<&GraspOutcome>,
    sol: &Solution,
    warnings: &[Warning],
) -> Plot {
    let mut p = Plot::new(
        format!("{stem}: the gripper frame (Xg right, Zg down)"),
        "Xg (mm)",
        "Zg (mm, pointing down)",
        true,
    );
    let mirror = |q: &[f64; 2]| [-q[0], q[1]];
    let finger: Vec<[f64; 2]> = sol.points.iter().map(|&q| gripper.to_gripper(q)).collect();
    let rest = gripper.rest_shape();
    let depth = finger
        .iter()
        .chain(&rest)
        .map(|q| q[1])
        .filter(|z| z.is_finite())
        .fold(0.0_f64, f64::max);
    p.add(
        Look::Axis,
        "gripper axis (Xg = 0)",
        [[0.0, -5.0], [0.0, depth + 10.0]],
    );
    p.add(
        Look::Rest,
        "fingers at rest (P = 0, unloaded)",
        rest.iter().copied(),
    );
    p.add(Look::Rest, "", rest.iter().map(mirror));
    if let Some(o) = grasp {
        draw_object(&mut p, o, gripper);
    }
    p.add(
        Look::Mirror,
        "opposite finger (mirrored)",
        finger.iter().map(mirror),
    );
    p.add(Look::Finger, "finger mid-plane", finger.iter().copied());
    let half = 0.5 * gripper.palm() + 5.0;
    p.add(Look::Palm, "palm (Zg = 0)", [[-half, 0.0], [half, 0.0]]);
    p.add(Look::Tip, "tip", [gripper.to_gripper(sol.tip)]);
    p.caption.extend(gripper_caption(gripper, sol));
    if let Some(o) = grasp {
        p.caption.extend(grasp_caption(o));
    }
    p.caption.extend(findings(warnings));
    p
}

/// The object of a grasp, in the gripper frame.
fn draw_object(p: &mut Plot, o: &GraspOutcome, gripper: &Gripper) {
    let tip = o.grasp.tip;
    match o.spec {
        GraspSpec::Cuboid { .. } => {
            // the faces the tips touch, at Xg = +-tip Xg; drawn as a
            // square centred on the tips' height
            let h = tip[0].abs().max(1.0);
            let corners = [[-h, -h], [h, -h], [h, h], [-h, h], [-h, -h]];
            p.add(
                Look::Object,
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
            p.add(Look::Contact, "object surface at the contacts", seg);
            p.add(Look::Contact, "", seg.map(|q| [-q[0], q[1]]));
        }
        GraspSpec::Sphere { .. } => {
            if let Some(s) = o.sphere.filter(|s| s.radius > 0.0) {
                let circle = (0..=CIRCLE_SEGMENTS).map(|k| {
                    let t = std::f64::consts::TAU * f64::from(k) / f64::from(CIRCLE_SEGMENTS);
                    [
                        s.center[0] + s.radius * t.cos(),
                        s.center[1] + s.radius * t.sin(),
                    ]
                });
                p.add(Look::Object, "sphere", circle);
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
    if let Some(i) = &o.invalid {
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

/// A number with `decimals` decimals; `n/a` when not finite.
pub(super) fn num(x: f64, decimals: usize) -> String {
    if x.is_finite() {
        format!("{x:.decimals$}")
    } else {
        "n/a".into()
    }
}
