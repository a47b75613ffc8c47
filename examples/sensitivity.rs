// examples/sensitivity.rs (cargo run --example sensitivity)
use fpc::actuator::ActuatorParam;
use fpc::sensitivity::{GraspKind, GripperParam};
use fpc::{Actuator, Gripper, GripperParams, Partition};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let act = Actuator::paper(0.25)?;
    let part = Partition::equal(act.geometry().lx, 8)?;
    let gripper = Gripper::from_actuator(&act, &part, GripperParams::default())?;
    let grasp = gripper.grasp_load_for_size(0.0, 40.0, 0.0, None)?;
    let eps0 = GripperParam::Actuator(ActuatorParam::Eps0);
    let sens = gripper.grasp_sensitivities(
        &act,
        &grasp,
        GraspKind::Size { d: 40.0 },
        &[eps0, GripperParam::MountingAngle],
    )?;
    println!(
        "d f_v / d eps0 = {:.4} N, per rad of a: {:.4} N",
        sens.rows[0].lift, sens.rows[1].lift
    );
    Ok(())
}
