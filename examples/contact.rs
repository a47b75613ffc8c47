// examples/contact.rs (cargo run --example contact)
use fpc::finger::PolyCurve;
use fpc::gripper::contact::{deepest, deepest_apart_from, Obstacle};
use fpc::gripper::frames::finger_to_gripper_map;
use fpc::{Finger, Load, SolveOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let finger = Finger::paper(0.25, 8)?;
    let rest = finger.solve(&Load::unloaded(), &SolveOptions::default())?;
    let to_gripper = finger_to_gripper_map(std::f64::consts::FRAC_PI_3, 40.0)?;
    let curves: Vec<PolyCurve> = finger
        .midplane_curves(&rest.coefficients)?
        .iter()
        .map(|c| c.map(to_gripper))
        .collect();
    // a sphere of radius 10 mm through the tip, its centre towards the axis
    let last = curves.last().unwrap();
    let tip = last.end();
    let sphere = Obstacle::disc([tip[0] - 10.0, tip[1]], 10.0)?;
    let deep = deepest(&curves, &sphere)?;
    println!(
        "deepest: {:.2e} mm, element {} at x = {:.3} mm",
        deep.depth, deep.element, deep.x
    );
    let second = deepest_apart_from(&curves, &sphere, curves.len() - 1, last.length())?;
    println!("apart from the tip: {second:?}");
    Ok(())
}
