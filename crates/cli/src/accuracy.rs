//! `fpc accuracy`: run time against error over N and the Newton tolerance.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

use fpc_lab::{accuracy_study, AccuracyStudy};

/// Flags of `fpc accuracy`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Directory for accuracy.csv (created if missing).
    #[arg(long, default_value = "accuracy-out")]
    out: PathBuf,
}

const ELEMENTS: [usize; 8] = [1, 2, 4, 8, 16, 32, 64, 128];
const RTOLS: [f64; 5] = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12];

/// The CSV text of a study (columns with units).
pub fn csv(study: &AccuracyStudy) -> String {
    let mut s =
        String::from("elements,rtol,time_us,tip_error_mm,radius_error_mm,grasp_error_mm,pareto\n");
    for r in &study.rows {
        let _ = writeln!(
            s,
            "{},{:e},{:.3},{:.6e},{:.6e},{:.6e},{}",
            r.elements,
            r.rtol,
            r.time_us,
            r.tip_error_mm,
            r.radius_error_mm,
            r.grasp_error_mm,
            r.pareto
        );
    }
    s
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let study = accuracy_study(&ELEMENTS, &RTOLS, |done, total| {
        crate::report::progress(&format!("fpc accuracy: {done}/{total} points"));
    })?;
    crate::report::end_progress();
    crate::output::prepare_dir(&args.out)?;
    crate::output::write_atomic(&args.out, "accuracy.csv", csv(&study).as_bytes())?;
    let svg = crate::output::accuracy_svg(&study);
    crate::output::write_atomic(&args.out, "accuracy.svg", svg.as_bytes())?;
    let r = &study.reference;
    let mut out = crate::output::stdout();
    writeln!(
        out,
        "reference: N = {}, tip ({:.4}, {:.4}) mm, radius {:.4} mm, grasp size {:.4} mm",
        r.elements, r.tip[0], r.tip[1], r.radius, r.grasp_size
    )?;
    writeln!(
        out,
        "reference check: observed tip order {:.2} from N = 64, 128, 256; Richardson gap {:.2e} mm",
        r.observed_order, r.richardson_gap_mm
    )?;
    writeln!(
        out,
        "{:>5} {:>8} {:>11} {:>12} {:>12} {:>12} pareto",
        "N", "rtol", "time (us)", "tip (mm)", "radius (mm)", "grasp (mm)"
    )?;
    for row in &study.rows {
        writeln!(
            out,
            "{:>5} {:>8.0e} {:>11.2} {:>12.3e} {:>12.3e} {:>12.3e} {}",
            row.elements,
            row.rtol,
            row.time_us,
            row.tip_error_mm,
            row.radius_error_mm,
            row.grasp_error_mm,
            if row.pareto { "*" } else { "" }
        )?;
    }
    let rec =
        |n: Option<usize>| n.map_or("none of the tested N".to_string(), |n| format!("N = {n}"));
    writeln!(
        out,
        "tip within 0.1 mm: {}; within 0.01 mm: {}",
        rec(study.n_for_0_1_mm),
        rec(study.n_for_0_01_mm)
    )?;
    writeln!(
        out,
        "wrote {} and accuracy.svg",
        args.out.join("accuracy.csv").display()
    )?;
    Ok(())
}
