//! The inverse-design optimiser against the brute-force grid it is
//! checked with, on a cuboid requirement over two variables (eps0 and the
//! mounting angle), measured in one run. Prints a table; target (issue
//! "Inverse design"): the optimiser >= 50x faster than a grid at 1 % of
//! each range (101 x 101 points), with a worst margin at least the grid's.
//! Then the design files of scenes/design/ the way `fpc design` runs them
//! (search, final evaluation, reproduction), each `ROUNDS` times: issue
//! 23's budgets are 200 ms for paper_sec5.toml and 1 s for
//! fragile_fruit.toml.
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

/// Runs of each design file.
const ROUNDS: usize = 5;

/// The design files and their time budgets (s).
const FILES: [(&str, f64); 2] = [("paper_sec5.toml", 0.2), ("fragile_fruit.toml", 1.0)];

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
    println!();
    println!("design files (scenes/design/), {ROUNDS} runs each, all cores");
    println!(
        "{:<22} {:>12} {:>10} {:>10} {:>8} {:>16} {:>10}",
        "file", "evaluations", "min (s)", "median (s)", "budget", "worst margin", "feasible"
    );
    for (file, budget) in FILES {
        let path = format!("{}/scenes/design/{file}", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).expect("the design file reads");
        let req = Requirements::parse(&text).expect("the design file parses");
        let mut times = Vec::with_capacity(ROUNDS);
        let mut last = None;
        for _ in 0..ROUNDS {
            let t = Instant::now();
            let d = optimize(&req, &DesignOptions::default()).unwrap();
            times.push(t.elapsed().as_secs_f64());
            last = Some(d);
        }
        times.sort_by(f64::total_cmp);
        let d = last.expect("at least one round");
        println!(
            "{:<22} {:>12} {:>10.3} {:>10.3} {:>8.1} {:>16.9} {:>10}",
            file,
            d.evaluations,
            times[0],
            times[ROUNDS / 2],
            budget,
            d.best.worst,
            d.feasible
        );
    }
}
