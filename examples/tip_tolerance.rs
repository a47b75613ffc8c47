// examples/tip_tolerance.rs (cargo run --example tip_tolerance)
use fpc::{Actuator, Load, Plan, PlannedFinger, SolveOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let finger = PlannedFinger::builder(&Actuator::default()) // default model, ribs on
        .plan(Plan::TipTolerance {
            tip_tol_mm: 0.01,
            start: None,
        })
        .build()?; // bounds checked here
    let load = Load::unloaded().with_tip_force(0.939782, 0.521707);
    let r = finger.solve(&load, &SolveOptions::default())?;
    println!(
        "tip {:?} mm (estimated error {:?} mm, {} elements)",
        r.tip(),
        r.estimated_tip_error_mm(),
        r.elements()
    );
    assert!(r.is_extrapolated() && r.is_valid());
    Ok(())
}
