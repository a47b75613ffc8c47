//! The eight figures of `fpc paper`, one SVG document per study.

use fpc::{
    Axis, CuboidRegion, CurvatureCurve, DisplacementForceRow, ForceControl, LiftCurve,
    SphereRegion, ViableAngles, PAPER_ANGLES, PAPER_EPS0, PAPER_OVERLAPS,
};
use plotters::prelude::SeriesLabelPosition;

use super::plot::{figure, FilledArea, Panel, Series, Style, GREY, PALETTE};

/// The paper's name of a mounting angle (`π/2`, `π/2.5`, `π/3`), else degrees.
pub fn angle_name(a: f64) -> String {
    for (name, v) in ["π/2", "π/2.5", "π/3"].iter().zip(PAPER_ANGLES) {
        if (a - v).abs() < 1e-12 {
            return (*name).to_string();
        }
    }
    format!("{:.1}°", a.to_degrees())
}

fn index_of(values: &[f64], v: f64) -> usize {
    values
        .iter()
        .position(|x| (x - v).abs() < 1e-12)
        .unwrap_or(0)
}

fn eps_color(eps0: f64) -> plotters::style::RGBColor {
    PALETTE[index_of(&PAPER_EPS0, eps0) % PALETTE.len()]
}

/// Mounting angles get colours of their own (not the prestrains').
fn angle_color(a: f64) -> plotters::style::RGBColor {
    PALETTE[(3 + index_of(&PAPER_ANGLES, a)) % PALETTE.len()]
}

fn lift_points(c: &LiftCurve) -> Vec<(f64, f64)> {
    c.points.iter().map(|p| (p.size, p.lift)).collect()
}

/// Study 1: finger shapes per mounting angle, max f_v versus d, d_max versus a.
pub fn study1(curves: &[LiftCurve]) -> anyhow::Result<String> {
    figure(
        (1600, 1000),
        "Study 1: prestrain × mounting angle (g = 0, b = 0, f = μF)",
        |area| {
            let (top, bottom) = area.split_vertically(500);
            let tops = top.split_evenly((1, 3));
            for (k, &a) in PAPER_ANGLES.iter().enumerate() {
                let mut p = Panel::new(
                    format!("Unloaded fingers, a = {}", angle_name(a)),
                    "Xg (mm)",
                    "−Zg (mm, gripper points down)",
                );
                p.equal_aspect = true;
                p.legend = SeriesLabelPosition::LowerRight;
                for c in curves.iter().filter(|c| c.mounting_angle == a) {
                    let color = eps_color(c.eps0);
                    let shape: Vec<(f64, f64)> =
                        c.rest_shape.iter().map(|q| (q[0], -q[1])).collect();
                    let mirror: Vec<(f64, f64)> = shape.iter().map(|q| (-q.0, q.1)).collect();
                    p.series.push(
                        Series::new(color, Style::Line, shape).label(format!("ε0 = {}", c.eps0)),
                    );
                    p.series.push(Series::new(color, Style::Dashed(5), mirror));
                    p.series.push(Series::new(
                        color,
                        Style::Dots,
                        vec![(0.5 * c.palm, 0.0), (-0.5 * c.palm, 0.0)],
                    ));
                }
                p.hlines.push((0.0, String::new()));
                p.draw(&tops[k])?;
            }
            let cells = bottom.split_evenly((1, 4));
            for (k, &eps0) in PAPER_EPS0.iter().enumerate() {
                let mut p = Panel::new(
                    format!("Max lifting force, ε0 = {eps0}"),
                    "grasping size d (mm)",
                    "max f_v (N)",
                );
                p.y_zero = true;
                p.legend = SeriesLabelPosition::UpperLeft;
                for c in curves.iter().filter(|c| c.eps0 == eps0) {
                    p.series.push(
                        Series::new(angle_color(c.mounting_angle), Style::Line, lift_points(c))
                            .label(format!("a = {}", angle_name(c.mounting_angle))),
                    );
                    if let Some(s) = &c.stopped {
                        p.notes.push(format!(
                            "a = {}: stopped at d = {:.1} mm",
                            angle_name(c.mounting_angle),
                            s.at
                        ));
                    }
                }
                p.draw(&cells[k])?;
            }
            let mut p = Panel::new(
                "Largest grasping size",
                "mounting angle a (deg)",
                "d_max (mm)",
            );
            p.legend = SeriesLabelPosition::UpperRight;
            for eps0 in PAPER_EPS0 {
                let pts = curves
                    .iter()
                    .filter(|c| c.eps0 == eps0)
                    .map(|c| (c.mounting_angle.to_degrees(), c.d_max))
                    .collect();
                p.series.push(
                    Series::new(eps_color(eps0), Style::LineDots, pts)
                        .label(format!("ε0 = {eps0}")),
                );
            }
            p.draw(&cells[3])
        },
    )
}

/// Study 2: f_v versus d per overlap (one panel per mounting angle), d_max versus g.
pub fn study2(curves: &[LiftCurve]) -> anyhow::Result<String> {
    figure(
        (1200, 900),
        "Study 2: overlap g (ε0 = 0.25, b = 0, f = μF)",
        |area| {
            let cells = area.split_evenly((2, 2));
            for (k, &a) in PAPER_ANGLES.iter().enumerate() {
                let mut p = Panel::new(
                    format!("Max lifting force, a = {}", angle_name(a)),
                    "grasping size d (mm)",
                    "max f_v (N)",
                );
                p.y_zero = true;
                p.legend = SeriesLabelPosition::UpperLeft;
                for c in curves.iter().filter(|c| c.mounting_angle == a) {
                    let color = PALETTE[index_of(&PAPER_OVERLAPS, c.overlap) % PALETTE.len()];
                    p.series.push(
                        Series::new(color, Style::Line, lift_points(c))
                            .label(format!("g = {} mm", c.overlap)),
                    );
                    if let Some(s) = &c.stopped {
                        p.notes.push(format!(
                            "g = {} mm: sweep stopped at d = {:.1} mm",
                            c.overlap, s.at
                        ));
                    }
                }
                p.draw(&cells[k])?;
            }
            let mut p = Panel::new("Largest grasping size", "overlap g (mm)", "d_max (mm)");
            for (k, &a) in PAPER_ANGLES.iter().enumerate() {
                let pts = curves
                    .iter()
                    .filter(|c| c.mounting_angle == a)
                    .map(|c| (c.overlap, c.d_max))
                    .collect();
                p.series.push(
                    Series::new(PALETTE[k], Style::LineDots, pts)
                        .label(format!("a = {}", angle_name(a))),
                );
            }
            p.draw(&cells[3])
        },
    )
}

/// Study 3: the cuboid grasping region and the test cuboid.
pub fn study3(region: &CuboidRegion, test: (f64, f64)) -> anyhow::Result<String> {
    let c = &region.curve;
    figure(
        (1000, 620),
        "Study 3: cuboid grasping region (ε0 = 0.25, a = π/3, g = 20 mm, b = 0)",
        |area| {
            let mut p = Panel::new(
                "Region under the max lifting force curve",
                "grasping size d (mm)",
                "lifting force f_v per finger (N)",
            );
            p.y_zero = true;
            p.areas.push(FilledArea {
                points: lift_points(c),
                color: PALETTE[0],
                label: Some("grasping region".into()),
            });
            let inside = region.contains(test.0, test.1);
            p.series.push(
                Series::new(PALETTE[1], Style::Crosses, vec![test]).label(format!(
                    "cuboid d = {} mm, f_v = {} N ({})",
                    test.0,
                    test.1,
                    if inside { "inside" } else { "outside" }
                )),
            );
            p.vlines
                .push((c.d_max, format!("d_max = {:.1} mm", c.d_max)));
            p.notes.push(format!(
                "palm l = {:.1} mm, reach l0 = {:.1} mm",
                c.palm, c.l0
            ));
            if let Some(s) = &c.stopped {
                p.notes.push(format!("sweep stopped at d = {:.1} mm", s.at));
            }
            p.draw(area)
        },
    )
}

/// Study 4: normal force and finger height against pressure.
pub fn study4(fc: &ForceControl, mu: f64) -> anyhow::Result<String> {
    figure(
        (1200, 560),
        &format!(
            "Study 4: force control by pressure (cuboid d = {} mm, f = {} N per finger)",
            fc.size, fc.friction
        ),
        |area| {
            let cells = area.split_evenly((1, 2));
            let mut p = Panel::new("Normal force", "pressure P (kPa)", "normal force F (N)");
            p.y_zero = true;
            let pts: Vec<(f64, f64)> = fc.rows.iter().map(|r| (r.pressure_kpa, r.normal)).collect();
            p.series
                .push(Series::new(PALETTE[0], Style::LineDots, pts).label("F holding the cuboid"));
            let bad: Vec<(f64, f64)> = fc
                .rows
                .iter()
                .filter(|r| !r.friction_ok)
                .map(|r| (r.pressure_kpa, r.normal))
                .collect();
            if !bad.is_empty() {
                p.series
                    .push(Series::new(PALETTE[1], Style::Rings, bad).label("f > μF: slips"));
            }
            p.hlines.push((
                fc.friction / mu,
                format!("F = f/μ = {:.2} N (friction limit)", fc.friction / mu),
            ));
            if let Some(s) = &fc.stopped {
                p.notes.push(format!("sweep stopped at {:.1} kPa", s.at));
            }
            p.draw(&cells[0])?;
            let mut p = Panel::new("Finger height", "pressure P (kPa)", "finger height h (mm)");
            let pts = fc.rows.iter().map(|r| (r.pressure_kpa, r.height)).collect();
            p.series
                .push(Series::new(PALETTE[2], Style::LineDots, pts).label("h = tip Zg"));
            p.draw(&cells[1])
        },
    )
}

/// Study 5: valid sphere grasps and the max-lift envelope.
pub fn study5(region: &SphereRegion) -> anyhow::Result<String> {
    figure(
        (1000, 640),
        "Study 5: sphere grasping region (ε0 = 0.25, a = π/3, g = 20 mm, f = μF)",
        |area| {
            let mut p = Panel::new(
                "Valid grasps and the max lifting force envelope",
                "sphere radius r (mm)",
                "lifting force f_v per finger (N)",
            );
            p.y_zero = true;
            let pts = region.points.iter().map(|q| (q.radius, q.lift)).collect();
            p.series.push(
                Series::new(PALETTE[0], Style::SmallDots, pts)
                    .label(format!("valid grasps ({})", region.points.len())),
            );
            let env = region.envelope.iter().map(|e| (e.radius, e.lift)).collect();
            p.series
                .push(Series::new(PALETTE[1], Style::Line, env).label("envelope (best b)"));
            if let Some(pk) = region.peak {
                p.series.push(
                    Series::new(PALETTE[2], Style::Crosses, vec![(pk.radius, pk.lift)]).label(
                        format!(
                            "peak: r = {:.1} mm, f_v = {:.3} N, b = {:.1}°",
                            pk.radius,
                            pk.lift,
                            pk.beta.to_degrees()
                        ),
                    ),
                );
            }
            p.notes
                .push(format!("{} invalid grasps dropped", region.dropped));
            if !region.stopped.is_empty() {
                p.notes.push(format!(
                    "{} of the angle sweeps stopped early",
                    region.stopped.len()
                ));
            }
            p.draw(area)
        },
    )
}

/// Study 6: friction needed against the grasping angle, with the viable band.
pub fn study6(v: &ViableAngles, mu: f64) -> anyhow::Result<String> {
    figure(
        (1200, 580),
        &format!(
            "Study 6: viable grasping angles (sphere r = {} mm, f_v = {} N per finger)",
            v.radius, v.lift
        ),
        |area| {
            let cells = area.split_evenly((1, 2));
            let solved: Vec<_> = v.scan.iter().filter(|s| s.failure.is_none()).collect();
            let ratio = |s: &&fpc::AngleSample| {
                (s.normal > 0.0).then(|| (s.beta.to_degrees(), s.friction / s.normal))
            };
            let (lo, hi) = (-1.0, (3.0 * mu).max(2.0));
            let in_range = |p: &(f64, f64)| p.1 >= lo && p.1 <= hi;
            let all: Vec<(f64, f64)> = solved.iter().filter_map(ratio).collect();
            let viable: Vec<(f64, f64)> = solved
                .iter()
                .filter(|s| s.viable)
                .filter_map(ratio)
                .filter(in_range)
                .collect();
            let not: Vec<(f64, f64)> = solved
                .iter()
                .filter(|s| !s.viable)
                .filter_map(ratio)
                .filter(in_range)
                .collect();
            let clipped = all.iter().filter(|p| !in_range(p)).count();
            let mut p = Panel::new(
                "Friction needed",
                "grasping angle b (deg)",
                "required friction ratio f/F",
            );
            let ys: Vec<f64> = all.iter().filter(|p| in_range(p)).map(|p| p.1).collect();
            let (ymin, ymax) = ys
                .iter()
                .fold((0.0f64, mu), |(a, b), &y| (a.min(y), b.max(y)));
            let pad = 0.06 * (ymax - ymin);
            p.y_range = Some((ymin - pad, ymax + pad));
            for iv in &v.intervals {
                p.bands
                    .push((iv[0].to_degrees(), iv[1].to_degrees(), PALETTE[2]));
            }
            p.band_label = Some("viable range of b".into());
            p.series.push(Series::new(
                GREY,
                Style::Line,
                all.iter().copied().filter(in_range).collect(),
            ));
            p.series
                .push(Series::new(PALETTE[2], Style::Dots, viable).label("viable grasp"));
            p.series
                .push(Series::new(PALETTE[1], Style::Rings, not).label("not viable"));
            p.hlines.push((mu, format!("μ = {mu}")));
            p.hlines.push((0.0, String::new()));
            match v.range() {
                Some([a, b]) => p.notes.push(format!(
                    "viable b in [{:.1}°, {:.1}°] (shaded)",
                    a.to_degrees(),
                    b.to_degrees()
                )),
                None => p.notes.push("no viable grasping angle".into()),
            }
            if clipped > 0 {
                p.notes
                    .push(format!("{clipped} samples off the plotted range"));
            }
            let failed = v.scan.len() - solved.len();
            if failed > 0 {
                p.notes.push(format!("{failed} angles did not solve"));
            }
            p.x_range = Some((fpc::grasping_angle_range(mu)[0].to_degrees() - 2.0, 92.0));
            p.draw(&cells[0])?;
            let mut p = Panel::new(
                "Normal force",
                "grasping angle b (deg)",
                "normal force F (N)",
            );
            p.x_range = Some((fpc::grasping_angle_range(mu)[0].to_degrees() - 2.0, 92.0));
            for iv in &v.intervals {
                p.bands
                    .push((iv[0].to_degrees(), iv[1].to_degrees(), PALETTE[2]));
            }
            let pts = solved
                .iter()
                .map(|s| (s.beta.to_degrees(), s.normal))
                .collect();
            p.series
                .push(Series::new(PALETTE[0], Style::LineDots, pts).label("F"));
            p.hlines.push((0.0, String::new()));
            p.draw(&cells[1])
        },
    )
}

/// Largest radius drawn in study 7 (mm): near flat the radius diverges.
pub const STUDY7_RADIUS_CAP_MM: f64 = 1000.0;

/// Study 7: radius and signed curvature against pressure.
pub fn study7(curves: &[CurvatureCurve]) -> anyhow::Result<String> {
    figure(
        (1200, 580),
        "Study 7: curvature against pressure (unloaded fingers)",
        |area| {
            let cells = area.split_evenly((1, 2));
            let mut p = Panel::new(
                "Radius of curvature (circle fit)",
                "pressure P (kPa)",
                "radius R (mm)",
            );
            p.y_zero = true;
            let mut capped = 0;
            for (k, c) in curves.iter().enumerate() {
                let color = PALETTE[k % PALETTE.len()];
                let pick = |rev: bool| -> Vec<(f64, f64)> {
                    c.rows
                        .iter()
                        .filter(|r| r.reversed() == rev)
                        .filter_map(|r| r.radius.map(|rad| (r.pressure_kpa, rad)))
                        .filter(|q| q.1 <= STUDY7_RADIUS_CAP_MM)
                        .collect()
                };
                capped += c
                    .rows
                    .iter()
                    .filter(|r| r.radius.is_some_and(|x| x > STUDY7_RADIUS_CAP_MM))
                    .count();
                p.series.push(
                    Series::new(color, Style::LineDots, pick(false))
                        .label(format!("ε0 = {}", c.eps0)),
                );
                let rev = pick(true);
                if !rev.is_empty() {
                    p.series.push(
                        Series::new(color, Style::Crosses, rev)
                            .label(format!("ε0 = {}: reversed curl", c.eps0)),
                    );
                }
                if let Some(s) = &c.stopped {
                    p.notes
                        .push(format!("ε0 = {}: stopped at {:.0} kPa", c.eps0, s.at));
                }
            }
            if capped > 0 {
                p.notes.push(format!(
                    "{capped} points with R > {STUDY7_RADIUS_CAP_MM} mm (nearly flat) not drawn"
                ));
            }
            p.draw(&cells[0])?;
            let mut p = Panel::new(
                "Signed curvature (> 0: curls to the prestressed side)",
                "pressure P (kPa)",
                "curvature 1/R (1/m)",
            );
            for (k, c) in curves.iter().enumerate() {
                let pts = c
                    .rows
                    .iter()
                    .map(|r| (r.pressure_kpa, 1000.0 * r.curvature))
                    .collect();
                p.series.push(
                    Series::new(PALETTE[k % PALETTE.len()], Style::LineDots, pts)
                        .label(format!("ε0 = {}", c.eps0)),
                );
            }
            p.hlines.push((0.0, "flat".into()));
            p.draw(&cells[1])
        },
    )
}

/// The axis name used in study 8's outputs.
pub fn axis_name(a: Axis) -> &'static str {
    match a {
        Axis::X => "X",
        Axis::Z => "Z",
    }
}

/// Study 8: tip force for a 10 mm displacement against pressure.
pub fn study8(rows: &[DisplacementForceRow]) -> anyhow::Result<String> {
    figure(
        (1000, 600),
        "Study 8: tip force that moves the tip 10 mm, from the pressurised shape",
        |area| {
            let mut p = Panel::new("", "pressure P (kPa)", "tip force (N)");
            p.y_zero = true;
            let mut cases: Vec<(f64, Axis)> = Vec::new();
            for r in rows {
                if !cases.contains(&(r.eps0, r.axis)) {
                    cases.push((r.eps0, r.axis));
                }
            }
            for (k, &(eps0, axis)) in cases.iter().enumerate() {
                let sel: Vec<_> = rows
                    .iter()
                    .filter(|r| r.eps0 == eps0 && r.axis == axis)
                    .collect();
                let pts = sel
                    .iter()
                    .filter_map(|r| r.force.map(|f| (r.pressure_kpa, f)))
                    .collect();
                p.series.push(
                    Series::new(PALETTE[k % PALETTE.len()], Style::LineDots, pts).label(format!(
                        "ε0 = {eps0}, force and displacement along +{}",
                        axis_name(axis)
                    )),
                );
                for r in sel.iter().filter(|r| r.force.is_none()) {
                    p.notes.push(format!(
                        "ε0 = {eps0}, +{}: no solution at {} kPa",
                        axis_name(axis),
                        r.pressure_kpa
                    ));
                }
            }
            p.draw(area)
        },
    )
}
