// examples/finger.rs (cargo run --example finger)
use fpc::{Finger, Load, SolveOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let finger = Finger::paper(0.25, 8)?; // default actuator, 8 equal elements
    let load = Load::unloaded()
        .with_pressure_kpa(50.0)
        .with_tip_force(0.5, 0.2);
    let sol = finger.solve(&load, &SolveOptions::default())?;
    println!("tip at {:?} mm, radius {:?} mm", sol.tip, sol.radius);
    assert!(sol.report.residual_norm <= 1e-10);
    assert!(sol.is_within_model()); // no validity findings
    Ok(())
}
