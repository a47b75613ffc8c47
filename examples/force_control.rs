// examples/force_control.rs (cargo run --example force_control)
use fpc::{Gripper, GripperParams, PalmSpec};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // the Sec. 5 gripper: eps0 = 0.25, a = pi/3, overlap 20 mm, 3 fingers, mu = 0.6
    let params = GripperParams {
        mounting_angle: std::f64::consts::FRAC_PI_3,
        geometry: PalmSpec::Overlap(20.0),
        ..GripperParams::default()
    };
    let gripper = Gripper::paper(0.25, 8, params)?;
    // the normal force that holds a 100 mm cuboid with 0.3 N friction per finger at 20 kPa
    let grasp = gripper.force_control(20.0, 100.0, 0.3, None)?;
    println!(
        "F = {:.3} N, finger height {:.1} mm",
        grasp.normal, grasp.height
    );
    Ok(())
}
