//! The cost of every sensitivity of one equilibrium (src/sensitivity.rs)
//! against one re-solve, at N = 8 and N = 64, for both element models.
//! Prints a table; the case is the tip-loaded standard finger (eps0 0.25,
//! Fx 0.939782 N, Fz 0.521707 N).
//!
//! - "all sens.": `Finger::sensitivities` for every parameter of the
//!   actuator and the load (`Param::all`): one Hessian and factorisation,
//!   one right-hand side and one refined solve per parameter;
//! - "re-solve": what one central difference needs per side: the finger
//!   rebuilt with eps0 changed by 1e-4 and solved from the equilibrium;
//! - "cold": one solve from scratch (`Finger::solve`);
//! - "FD / sens": central differences of every parameter (two re-solves
//!   each) over the sensitivities.
//!
//! A second table does the same for gripper outputs (src/sensitivity/gripper.rs,
//! the Sec. 5 gripper): a size grasp's sensitivities
//! (`Gripper::grasp_sensitivities`: eps0, pressure, mounting angle,
//! overlap) against one re-solve (the gripper rebuilt with eps0 changed by
//! 1e-4, its rest state solved, the grasp solved warm from the old one),
//! and the best sphere lift's (`Gripper::max_sphere_lift_sensitivities`)
//! against one `max_sphere_lift` (scan and Brent search).
//!
//! ```sh
//! cargo bench --bench sensitivity
//! cargo bench --bench sensitivity -- --quick     # fewer repetitions
//! ```

use fpc::actuator::ActuatorParam;
use fpc::sensitivity::{GraspKind, GripperParam, Param};
use fpc::{Actuator, Finger, Gripper, GripperParams, Load, ModelId, Partition, SolveOptions};

#[path = "common/median.rs"]
mod median;
use median::{median_s, reps};

const FX: f64 = 0.939782;
const FZ: f64 = 0.521707;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let load = Load::unloaded().with_tip_force(FX, FZ);
    let opts = SolveOptions::default().tip_only();
    let act = Actuator::paper(0.25).expect("the paper's actuator");
    let params = Param::all(&act);
    let eps0 = ActuatorParam::Eps0;
    let moved = eps0
        .with_value(&act, 0.25 + 1e-4)
        .expect("a nearby prestrain");
    println!(
        "sensitivities of a tip-loaded equilibrium (eps0 0.25, Fx {FX} N, Fz {FZ} N) against re-solves, release build"
    );
    println!(
        "{:>5} {:>6} {:>7} {:>14} {:>10} {:>14} {:>11} {:>12} {:>10}",
        "model",
        "N",
        "params",
        "all sens. (us)",
        "per param",
        "re-solve (us)",
        "cold (us)",
        "sens/resolve",
        "FD / sens"
    );
    for &model in ModelId::ALL {
        for n in [8usize, 64] {
            let part = Partition::equal(act.geometry().lx, n).expect("a partition");
            let finger = Finger::with_model(model, &act, &part, true);
            let sol = finger.solve(&load, &opts).expect("the finger solves");
            let sens = finger
                .sensitivities(&act, &sol, &load, &params)
                .expect("the sensitivities");
            assert_eq!(sens.rows.len(), params.len());
            let t_sens = median_s(reps(quick, 2e-6 * n as f64 * params.len() as f64), || {
                std::hint::black_box(finger.sensitivities(&act, &sol, &load, &params).ok());
            });
            let t_resolve = median_s(reps(quick, 2e-5 * n as f64), || {
                let f = Finger::with_model(model, &moved, &part, true);
                std::hint::black_box(f.solve_from(&load, &sol.coefficients, &opts).ok());
            });
            let t_cold = median_s(reps(quick, 5e-5 * n as f64), || {
                std::hint::black_box(finger.solve(&load, &opts).ok());
            });
            let p = params.len() as f64;
            println!(
                "{:>5} {n:>6} {:>7} {:>14.1} {:>10.2} {:>14.1} {:>11.1} {:>12.2} {:>10.1}",
                model.name(),
                params.len(),
                t_sens * 1e6,
                t_sens * 1e6 / p,
                t_resolve * 1e6,
                t_cold * 1e6,
                t_sens / t_resolve,
                2.0 * p * t_resolve / t_sens,
            );
        }
    }
    println!(
        "(\"sens/resolve\": all {} sensitivities over one re-solve; \"FD / sens\": two re-solves per parameter over all sensitivities)",
        params.len()
    );
    gripper_table(quick, &act, &moved);
}

/// The gripper outputs' sensitivities against re-solves (module docs).
fn gripper_table(quick: bool, act: &Actuator, moved: &Actuator) {
    let params = [
        GripperParam::Actuator(ActuatorParam::Eps0),
        GripperParam::Pressure,
        GripperParam::MountingAngle,
        GripperParam::Overlap,
    ];
    println!();
    println!(
        "gripper outputs (Sec. 5 gripper, size grasp d = 40 mm at 20 kPa; sphere r = 50 mm), {} parameters, release build",
        params.len()
    );
    println!(
        "{:>6} {:>16} {:>14} {:>12} {:>10}",
        "N", "output", "sens. (us)", "re-solve (us)", "FD / sens"
    );
    let gp = GripperParams::default();
    for n in [8usize, 64] {
        let part = Partition::equal(act.geometry().lx, n).expect("a partition");
        let g = Gripper::from_actuator(act, &part, gp).expect("the gripper");
        let kind = GraspKind::Size { d: 40.0 };
        let grasp = g
            .grasp_load_for_size(20.0, 40.0, 0.0, None)
            .expect("the grasp");
        let t_sens = median_s(reps(quick, 1e-5 * n as f64), || {
            std::hint::black_box(g.grasp_sensitivities(act, &grasp, kind, &params).ok());
        });
        let t_resolve = median_s(reps(quick, 1e-4 * n as f64), || {
            let g2 = Gripper::from_actuator(moved, &part, gp).expect("the gripper");
            std::hint::black_box(g2.grasp_load_for_size(20.0, 40.0, 0.0, Some(&grasp)).ok());
        });
        let p = params.len() as f64;
        println!(
            "{n:>6} {:>16} {:>14.1} {:>12.1} {:>10.1}",
            "size grasp",
            t_sens * 1e6,
            t_resolve * 1e6,
            2.0 * p * t_resolve / t_sens
        );
        let best = g
            .max_sphere_lift(0.0, 50.0, 8)
            .expect("the scan")
            .expect("a valid grasp");
        let t_sens = median_s(reps(quick, 1e-4 * n as f64), || {
            std::hint::black_box(
                g.max_sphere_lift_sensitivities(act, 0.0, &best, &params)
                    .ok(),
            );
        });
        let t_resolve = median_s(reps(quick, 1e-2 * n as f64), || {
            let g2 = Gripper::from_actuator(moved, &part, gp).expect("the gripper");
            std::hint::black_box(g2.max_sphere_lift(0.0, 50.0, 8).ok());
        });
        println!(
            "{n:>6} {:>16} {:>14.1} {:>12.1} {:>10.1}",
            "sphere envelope",
            t_sens * 1e6,
            t_resolve * 1e6,
            2.0 * p * t_resolve / t_sens
        );
    }
    println!("(\"FD / sens\": two re-solves per parameter over all the sensitivities)");
}
