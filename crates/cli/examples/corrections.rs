// crates/cli/examples/corrections.rs
// (cargo run -p fpc-cli --example corrections [-- FIGURE.svg])
//
// What each of the paper's named corrections changes (docs/model.md
// section 4.11): the `shear` element, plane strain across the width and
// ribs on the constraining layer, each alone and all together, against the
// paper's CCM. For eps0 0.15, 0.25 and 0.4 it sweeps pressure 0 to 400 kPa
// (study 7's sweep: circle-fit radius) and finds the tip force that moves
// the tip 10 mm (study 8's, at 0 and 27.6 kPa: along +X for eps0 0.4,
// along +Z for 0.15 and 0.25). Prints a markdown table; with a path, also
// writes the curvature-against-pressure figure there, drawn by the CLI's
// renderer: SVG (docs/figures/corrections.svg), or PNG for a `.png` path.
//
// Every configuration is solved on one partition: element ends on every
// rib end (the channel's ribs and the constraining layer's, which sit at
// the same X), pieces at most lx / 8, so a rib stiffens its own few
// millimetres and is not smeared over an element.

use fpc::actuator::ClRib;
use fpc::report::{Figure, Panel, PlotAxis, RefLine, Series, SeriesKind};
use fpc::studies::{tip_force_for_displacement, Axis};
use fpc::{Actuator, ActuatorParams, Finger, Load, ModelId, Partition, SolveOptions};

/// The assumed ribs on the constraining layer: the channel's transverse
/// ribs mirrored on the film (centres X = 8k mm, 2 mm long), across the
/// whole width, 1 mm tall, of the film's polypropylene.
fn cl_ribs(lx: f64, ly: f64) -> Vec<ClRib> {
    (1..)
        .map(|k| 8.0 * f64::from(k))
        .take_while(|c| c + 1.0 <= 105.0_f64.min(lx))
        .map(|c| ClRib {
            x0: c - 1.0,
            x1: c + 1.0,
            width: ly,
            height: 1.0,
        })
        .collect()
}

struct Config {
    name: &'static str,
    /// A colour key of the CLI's renderer, and whether the line is dashed
    /// (the corrections that barely move the curves lie on the CCM's).
    color: &'static str,
    dashed: bool,
    model: ModelId,
    plane_strain: bool,
    ribs: bool,
}

const CONFIGS: [Config; 5] = [
    Config {
        name: "CCM (paper)",
        color: "reference",
        dashed: false,
        model: ModelId::Ccm,
        plane_strain: false,
        ribs: false,
    },
    Config {
        name: "shear",
        color: "eps0=0.25",
        dashed: true,
        model: ModelId::Shear,
        plane_strain: false,
        ribs: false,
    },
    Config {
        name: "plane strain",
        color: "a=pi/3",
        dashed: true,
        model: ModelId::Ccm,
        plane_strain: true,
        ribs: false,
    },
    Config {
        name: "CL ribs",
        color: "eps0=0.15",
        dashed: false,
        model: ModelId::Ccm,
        plane_strain: false,
        ribs: true,
    },
    Config {
        name: "all three",
        color: "g=0mm",
        dashed: true,
        model: ModelId::Shear,
        plane_strain: true,
        ribs: true,
    },
];

const EPS0: [f64; 3] = [0.15, 0.25, 0.4];
const PRESSURES: usize = 21; // 0, 20, ..., 400 kPa

fn actuator(c: &Config, eps0: f64) -> Result<Actuator, fpc::InputError> {
    let d = ActuatorParams::default();
    let mut p = ActuatorParams {
        plane_strain: c.plane_strain,
        cl_ribs: if c.ribs {
            cl_ribs(d.geometry.lx, d.geometry.ly)
        } else {
            Vec::new()
        },
        ..d
    };
    p.pemc.eps0 = eps0;
    Actuator::new(p)
}

/// Signed curvature (1/mm, positive while curling towards -Z) and radius
/// (mm) at each pressure of the sweep.
fn sweep(finger: &Finger) -> Result<Vec<(f64, f64, Option<f64>)>, fpc::SolveError> {
    let opts = SolveOptions {
        stability: false,
        ..SolveOptions::default()
    };
    let mut solver = fpc::finger::Solver::new(finger);
    let mut guess = None;
    let mut out = Vec::new();
    for i in 0..PRESSURES {
        let p = 400.0 * i as f64 / (PRESSURES - 1) as f64;
        let sol = solver.solve(
            &Load::unloaded().with_pressure_kpa(p),
            guess.as_ref(),
            &opts,
        )?;
        let curvature = match fpc::circle_fit::fit_circle(&sol.points) {
            Some(c) if c.radius > 0.0 && c.center[1] != 0.0 => -c.center[1].signum() / c.radius,
            _ => 0.0,
        };
        out.push((p, curvature, sol.radius));
        guess = Some(sol.coefficients);
    }
    Ok(out)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let figure = std::env::args().nth(1);
    // one partition for all: the channel's ribs and the CL ribs share their ends
    let all = actuator(&CONFIGS[4], 0.25)?;
    let part = Partition::material(&all, true, all.geometry().lx / 8.0)?;
    println!(
        "{} elements; radius R (mm) at 0 and 100 kPa, force F (N) for a 10 mm tip move at 0 and 27.6 kPa\n",
        part.len()
    );
    println!("| eps0 | correction | R 0 kPa | R 100 kPa | F 0 kPa | F 27.6 kPa |");
    println!("|---|---|---|---|---|---|");
    let mut curves: Vec<Vec<Vec<[f64; 2]>>> = Vec::new();
    for eps0 in EPS0 {
        let axis = if eps0 > 0.3 { Axis::X } else { Axis::Z };
        let mut per_config = Vec::new();
        let mut base: Option<[f64; 4]> = None;
        for c in &CONFIGS {
            let finger = Finger::with_model(c.model, &actuator(c, eps0)?, &part, true);
            let s = sweep(&finger)?;
            let radius_at = |p: f64| {
                s.iter()
                    .find(|r| r.0 == p)
                    .and_then(|r| r.2)
                    .unwrap_or(f64::NAN)
            };
            let force = |p: f64| -> Result<f64, fpc::SolveError> {
                Ok(tip_force_for_displacement(&finger, p, axis, 10.0)?.force)
            };
            let v = [radius_at(0.0), radius_at(100.0), force(0.0)?, force(27.6)?];
            // radii to 0.1 mm, forces to 1 mN; the change from the CCM in %
            let cell = |i: usize| {
                let digits = if i < 2 { 1 } else { 3 };
                match base {
                    Some(b) if c.name != CONFIGS[0].name => {
                        format!("{:.digits$} ({:+.2} %)", v[i], 100.0 * (v[i] / b[i] - 1.0))
                    }
                    _ => format!("{:.digits$}", v[i]),
                }
            };
            println!(
                "| {eps0} | {} | {} | {} | {} | {} |",
                c.name,
                cell(0),
                cell(1),
                cell(2),
                cell(3)
            );
            if base.is_none() {
                base = Some(v);
            }
            per_config.push(s.iter().map(|r| [r.0, 1e3 * r.1]).collect());
        }
        curves.push(per_config);
    }
    if let Some(path) = figure {
        let svg = svg(&curves)?;
        if path.ends_with(".png") {
            use fpc_cli::render::formats;
            std::fs::write(&path, formats::png(&formats::parse(&svg)?)?)?;
        } else {
            std::fs::write(&path, svg)?;
        }
        println!("\nwrote {path}");
    }
    Ok(())
}

/// Three panels (one per eps0) of curvature (1/m) against pressure (kPa),
/// one line per configuration, drawn by the CLI's renderer.
fn svg(curves: &[Vec<Vec<[f64; 2]>>]) -> Result<String, Box<dyn std::error::Error>> {
    let panels = curves
        .iter()
        .zip(EPS0)
        .map(|(per_config, eps0)| {
            let mut panel = Panel::new(
                format!("eps0 = {eps0}"),
                PlotAxis::new("pressure", "kPa"),
                PlotAxis::new("curvature 1/R (+: curls towards -Z)", "1/m"),
            );
            panel.series = CONFIGS
                .iter()
                .zip(per_config)
                .map(|(c, line)| {
                    let kind = if c.dashed {
                        SeriesKind::Dashed
                    } else {
                        SeriesKind::Line
                    };
                    Series::new(c.color, kind, line.clone()).label(c.name)
                })
                .collect();
            panel.hlines.push(RefLine {
                at: 0.0,
                label: String::new(),
            });
            panel
        })
        .collect();
    let figure = Figure::row(
        "Curvature against pressure: the paper's CCM and its corrections (docs/model.md 4.11)",
        [1200, 420],
        panels,
    );
    Ok(fpc_cli::render::svg::svg(&figure)?)
}
