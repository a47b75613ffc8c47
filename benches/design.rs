//! The inverse-design optimiser against the brute-force grid it is
//! checked with, on a cuboid requirement over two variables (eps0 and the
//! mounting angle), measured in one run. Prints a table; target (issue
//! "Inverse design"): the optimiser >= 50x faster than a grid at 1 % of
//! each range (101 x 101 points), with a worst margin at least the grid's.
//!
//! ```sh
//! cargo bench --bench design
//! cargo bench --bench design -- --quick      # a 41 x 41 grid
//! ```

use std::time::Instant;

use fpc::design::{grid_search, optimize, DesignOptions, Requirements};

const REQUIREMENTS: &str = r#"
[[object]]
kind = "cuboid"
size_mm = [70.0, 100.0]
lift_n = 0.6
[vary]
eps0 = [0.1, 0.45]
mounting_angle_deg = [55.0, 90.0]
"#;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let per_axis = if quick { 41 } else { 101 };
    let req = Requirements::parse(REQUIREMENTS).expect("the bench's requirements parse");
    let t = Instant::now();
    let d = optimize(&req, &DesignOptions::default()).unwrap();
    let t_opt = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let g = grid_search(&req, per_axis).unwrap();
    let t_grid = t.elapsed().as_secs_f64();
    println!("inverse design: cuboid 70-100 mm, 0.6 N per finger; eps0 x mounting angle");
    println!(
        "{:<22} {:>12} {:>12} {:>14} {:>26}",
        "method", "evaluations", "time (s)", "worst margin", "design (eps0, angle deg)"
    );
    println!(
        "{:<22} {:>12} {:>12.3} {:>14.6} {:>26}",
        "optimiser",
        d.evaluations,
        t_opt,
        d.best.worst,
        format!("({:.4}, {:.3})", d.best.design[0], d.best.design[1])
    );
    println!(
        "{:<22} {:>12} {:>12.3} {:>14.6} {:>26}",
        format!("grid {per_axis} x {per_axis}"),
        g.evaluated,
        t_grid,
        g.best.worst,
        format!("({:.4}, {:.3})", g.best.design[0], g.best.design[1])
    );
    println!(
        "grid / optimiser time: {:.1}x (target >= 50); optimiser - grid worst margin: {:+.2e}",
        t_grid / t_opt,
        d.best.worst - g.best.worst
    );
}
