//! Synthetic measurement files for the calibration tests, made by the
//! ordinary solve paths of a known finger: included by `#[path]` where
//! used.

#![allow(dead_code)] // each test crate uses some of them

use std::fmt::Write as _;

use fpc::studies::{tip_force_for_displacement, Axis};
use fpc::{Finger, Load, SolveOptions};

/// A markers test's CSV: at each pressure, the mid-plane point at each arc
/// length of `markers` (mm, on the shape samples: 8 per element of 13.75
/// mm), each coordinate plus `noise(sd)`, with standard deviation `sd`.
pub fn markers_csv(
    f: &Finger,
    pressures_kpa: &[f64],
    markers: &[f64],
    sd: f64,
    noise: &mut dyn FnMut(f64) -> f64,
) -> String {
    let mut csv = String::from("pressure_kpa,marker,s_mm,x_mm,z_mm,sd_mm\n");
    for &p in pressures_kpa {
        let sol = f
            .solve(
                &Load::unloaded().with_pressure_kpa(p),
                &SolveOptions::default(),
            )
            .unwrap();
        let pts = f.shape(&sol.coefficients, 8).unwrap();
        for (k, &s_mm) in markers.iter().enumerate() {
            let q = pts[(s_mm / (110.0 / 64.0)).round() as usize];
            let (x, z) = (q[0] + noise(sd), q[1] + noise(sd));
            writeln!(csv, "{p},M{k},{s_mm},{x},{z},{sd}").unwrap();
        }
    }
    csv
}

/// A force test's CSV: study 8's force moving the tip 10 mm along each
/// `(pressure, axis)`, plus `noise(sd)`, with standard deviation
/// `sd(force)` and `repeats`.
pub fn force_csv(
    f: &Finger,
    rows: &[(f64, Axis)],
    sd: impl Fn(f64) -> f64,
    repeats: u32,
    noise: &mut dyn FnMut(f64) -> f64,
) -> String {
    let mut csv = String::from("pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n");
    for &(p, axis) in rows {
        let force = tip_force_for_displacement(f, p, axis, 10.0).unwrap().force;
        let sd = sd(force);
        let name = if axis == Axis::X { "X" } else { "Z" };
        writeln!(csv, "{p},{name},10,{},{sd},{repeats}", force + noise(sd)).unwrap();
    }
    csv
}
