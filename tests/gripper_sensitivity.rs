//! Exact sensitivities of the gripper's outputs (src/sensitivity/gripper.rs,
//! docs/model.md "Sensitivities") against Richardson-extrapolated central
//! differences of full re-solves through the ordinary gripper path: a new
//! actuator, a new `Gripper`, a new grasp solve (or `max_sphere_lift`
//! scan and Brent search) at each perturbed parameter.
//!
//! Agreement is relative per output, `|exact - fd| / max(|exact|, |fd|,
//! floor)`, with an absolute floor for derivatives that vanish (the size of
//! a size grasp does not move with anything but `d`, yet its central
//! differences carry the grasp solves' own tolerance, about 1e-11 mm, over
//! the step): [`FLOOR`] of the output's size (at least 1e-3) per unit of
//! the parameter's scale (its value, or 100 steps where that is larger).
//! Every check must reach 1e-6. Each test prints its worst agreement
//! (`--nocapture`).

use fpc::actuator::ActuatorParam;
use fpc::finger::Solver;
use fpc::gripper::{contact_force_to_gripper, gripper_force_to_contact};
use fpc::sensitivity::{GraspKind, GripperParam};
use fpc::{
    Actuator, Grasp, Gripper, GripperParams, Load, PalmSpec, Partition, SolveError, SolveOptions,
};

const ELEMENTS: usize = 6;
const TOL: f64 = 1e-6;

/// The floor of the relative agreement, as a fraction of an output's
/// logarithmic scale `|y| / |p|` (module docs).
const FLOOR: f64 = 1e-3;

/// Richardson-extrapolated central difference, error O(h^4).
fn richardson(f: &mut dyn FnMut(f64) -> Vec<f64>, x: f64, h: f64) -> Vec<f64> {
    let mut d = |h: f64| -> Vec<f64> {
        let (a, b) = (f(x + h), f(x - h));
        a.iter().zip(&b).map(|(a, b)| (a - b) / (2.0 * h)).collect()
    };
    let d1 = d(h);
    let d2 = d(0.5 * h);
    d1.iter()
        .zip(&d2)
        .map(|(d1, d2)| (4.0 * d2 - d1) / 3.0)
        .collect()
}

/// The step of the central differences in a parameter.
fn step(p: GripperParam, value: f64) -> f64 {
    match p {
        GripperParam::Pressure => 1e-2 * value.abs().max(1.0),
        GripperParam::MountingAngle | GripperParam::Beta => 1e-3,
        GripperParam::Overlap | GripperParam::Palm | GripperParam::Size | GripperParam::Radius => {
            1e-2
        }
        GripperParam::Actuator(_) => 1e-3 * value.abs().max(1e-2),
    }
}

/// The worst agreement of `exact` and `fd` (module docs), with the names
/// of the outputs for the message.
fn agreement(
    what: &str,
    names: &[&str],
    base: &[f64],
    exact: &[f64],
    fd: &[f64],
    scale: f64,
) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..exact.len() {
        let floor = FLOOR * base[i].abs().max(1e-3) / scale;
        let s = exact[i].abs().max(fd[i].abs()).max(floor);
        let e = (exact[i] - fd[i]).abs() / s;
        assert!(
            e <= TOL,
            "{what}: d {} exact {:.12e}, central differences {:.12e}: relative {e:.3e}",
            names[i],
            exact[i],
            fd[i]
        );
        worst = worst.max(e);
    }
    worst
}

/// A gripper design and the state of one grasp.
#[derive(Clone, Copy)]
struct Design {
    actuator_eps0: f64,
    params: GripperParams,
    pressure_kpa: f64,
    beta: f64,
    kind: GraspKind,
}

fn actuator(eps0: f64) -> Actuator {
    Actuator::paper(eps0).unwrap()
}

fn gripper(act: &Actuator, params: GripperParams) -> Gripper {
    let part = Partition::equal(act.geometry().lx, ELEMENTS).unwrap();
    Gripper::from_actuator(act, &part, params).unwrap()
}

/// The design with one parameter changed: (actuator, design).
fn perturbed(base: &Design, act: &Actuator, p: GripperParam, v: f64) -> (Actuator, Design) {
    let mut d = *base;
    let mut a = act.clone();
    match p {
        GripperParam::Actuator(ap) => a = ap.with_value(act, v).unwrap(),
        GripperParam::Pressure => d.pressure_kpa = v,
        GripperParam::MountingAngle => d.params.mounting_angle = v,
        GripperParam::Overlap => d.params.geometry = PalmSpec::Overlap(v),
        GripperParam::Palm => d.params.geometry = PalmSpec::Palm(v),
        GripperParam::Size => match &mut d.kind {
            GraspKind::Size { d } | GraspKind::ForceControl { d, .. } => *d = v,
            _ => unreachable!(),
        },
        GripperParam::Radius => match &mut d.kind {
            GraspKind::SphereAtFrictionLimit { radius } | GraspKind::Sphere { radius, .. } => {
                *radius = v
            }
            _ => unreachable!(),
        },
        GripperParam::Beta => d.beta = v,
    }
    (a, d)
}

const GRASP_OUTPUTS: [&str; 9] = [
    "normal", "friction", "lift", "lambda", "size", "tip_gap", "height", "tip_xg", "tip_zg",
];

/// The grasp of a design through the ordinary gripper path.
fn solve_grasp(g: &Gripper, d: &Design) -> Grasp {
    let p = d.pressure_kpa;
    match d.kind {
        GraspKind::Size { d: size } => g.grasp_load_for_size(p, size, d.beta, None).unwrap(),
        GraspKind::SphereAtFrictionLimit { radius } => {
            g.sphere_grasp_at_friction_limit(p, radius, d.beta, None)
                .unwrap()
                .grasp
        }
        GraspKind::Sphere { radius, lift } => {
            g.sphere_grasp(p, radius, lift, d.beta, None).unwrap().grasp
        }
        GraspKind::ForceControl { d: size, friction } => {
            g.force_control(p, size, friction, None).unwrap()
        }
    }
}

/// The grasp's outputs through the ordinary gripper path: the gripper
/// builds and solves the grasp; its target problem is then solved once
/// more, from that solution, to a tighter tolerance than the gripper's
/// (`rtol` 1e-13, target 1e-12 mm), so that the central differences are
/// not limited by the gripper's stopping tolerances (1e-11, 1e-9 mm). The
/// outputs follow from the polished state by the gripper's own measures
/// (`size_of`, `to_gripper`) and the contact force `lambda (n + mu t)`.
fn grasp_outputs(act: &Actuator, d: &Design) -> Vec<f64> {
    let g = gripper(act, d.params);
    let gr = solve_grasp(&g, d);
    let opts = SolveOptions {
        rtol: 1e-13,
        ..SolveOptions::default().tip_only()
    };
    let (sol, lambda) = Solver::new(g.finger())
        .solve_target(
            &gr.problem,
            &gr.solution.coefficients,
            gr.lambda,
            1e-12,
            &opts,
        )
        .unwrap();
    // the contact force: fixed part plus lambda times the direction
    let (base, u) = match d.kind {
        GraspKind::Size { .. } | GraspKind::SphereAtFrictionLimit { .. } => (
            [0.0, 0.0],
            contact_force_to_gripper(1.0, d.params.mu, d.beta),
        ),
        GraspKind::Sphere { lift, .. } => ([0.0, lift], [1.0, 0.0]),
        GraspKind::ForceControl { friction, .. } => ([0.0, friction], [1.0, 0.0]),
    };
    let force = [base[0] + lambda * u[0], base[1] + lambda * u[1]];
    let (normal, friction) = gripper_force_to_contact(force, d.beta);
    let tip = g.to_gripper(sol.tip);
    vec![
        normal,
        friction,
        force[1],
        lambda,
        g.size_of(sol.tip),
        2.0 * tip[0],
        tip[1],
        tip[0],
        tip[1],
    ]
}

fn check_grasp(name: &str, d: Design, params: &[GripperParam]) -> f64 {
    let act = actuator(d.actuator_eps0);
    let g = gripper(&act, d.params);
    let gr = solve_grasp(&g, &d);
    let sens = g.grasp_sensitivities(&act, &gr, d.kind, params).unwrap();
    let base = grasp_outputs(&act, &d);
    let mut worst = 0.0f64;
    for row in &sens.rows {
        let h = step(row.param, row.value);
        let mut f = |v: f64| {
            let (a, dd) = perturbed(&d, &act, row.param, v);
            grasp_outputs(&a, &dd)
        };
        let fd = richardson(&mut f, row.value, h);
        let exact = [
            row.normal,
            row.friction,
            row.lift,
            row.lambda,
            row.size,
            row.tip_gap,
            row.height,
            row.tip[0],
            row.tip[1],
        ];
        // the friction is mu F at the friction limit: the exact rows agree
        if matches!(
            d.kind,
            GraspKind::Size { .. } | GraspKind::SphereAtFrictionLimit { .. }
        ) {
            assert!(
                (row.friction - d.params.mu * row.normal).abs()
                    <= 1e-12 * row.normal.abs().max(1.0)
            );
        }
        let scale = row.value.abs().max(100.0 * h);
        let e = agreement(
            &format!("{name} / {}", row.param),
            &GRASP_OUTPUTS,
            &base,
            &exact,
            &fd,
            scale,
        );
        println!("{name}: {:<28} worst relative {e:.2e}", row.param.name());
        worst = worst.max(e);
    }
    worst
}

fn eps0() -> GripperParam {
    GripperParam::Actuator(ActuatorParam::Eps0)
}

fn h1() -> GripperParam {
    GripperParam::Actuator(ActuatorParam::H1)
}

#[test]
fn size_grasp_sensitivities_match_re_solves() {
    let d = Design {
        actuator_eps0: 0.25,
        params: GripperParams::default(),
        pressure_kpa: 20.0,
        beta: 0.2,
        kind: GraspKind::Size { d: 40.0 },
    };
    let params = [
        eps0(),
        h1(),
        GripperParam::Pressure,
        GripperParam::MountingAngle,
        GripperParam::Overlap,
        GripperParam::Size,
        GripperParam::Beta,
    ];
    let w = check_grasp("size grasp", d, &params);
    println!("size grasp: worst {w:.2e}");
}

#[test]
fn palm_specified_size_grasp_sensitivities_match_re_solves() {
    let d = Design {
        actuator_eps0: 0.2,
        params: GripperParams {
            geometry: PalmSpec::Palm(40.0),
            ..GripperParams::default()
        },
        pressure_kpa: 0.0,
        beta: 0.0,
        kind: GraspKind::Size { d: 30.0 },
    };
    let params = [eps0(), GripperParam::MountingAngle, GripperParam::Palm];
    let w = check_grasp("palm size grasp", d, &params);
    println!("palm size grasp: worst {w:.2e}");
}

#[test]
fn sphere_grasp_sensitivities_match_re_solves() {
    let d = Design {
        actuator_eps0: 0.25,
        params: GripperParams::default(),
        pressure_kpa: 10.0,
        beta: 0.3,
        kind: GraspKind::SphereAtFrictionLimit { radius: 40.0 },
    };
    let params = [
        eps0(),
        GripperParam::Pressure,
        GripperParam::MountingAngle,
        GripperParam::Overlap,
        GripperParam::Radius,
        GripperParam::Beta,
    ];
    let w = check_grasp("sphere grasp", d, &params);
    println!("sphere grasp: worst {w:.2e}");
}

#[test]
fn fixed_lift_sphere_grasp_sensitivities_match_re_solves() {
    let d = Design {
        actuator_eps0: 0.25,
        params: GripperParams::default(),
        pressure_kpa: 10.0,
        beta: 0.4,
        kind: GraspKind::Sphere {
            radius: 45.0,
            lift: 0.5,
        },
    };
    let params = [
        eps0(),
        GripperParam::Pressure,
        GripperParam::MountingAngle,
        GripperParam::Overlap,
        GripperParam::Radius,
        GripperParam::Beta,
    ];
    let w = check_grasp("fixed-lift sphere grasp", d, &params);
    println!("fixed-lift sphere grasp: worst {w:.2e}");
}

#[test]
fn force_control_sensitivities_match_re_solves() {
    let d = Design {
        actuator_eps0: 0.25,
        params: GripperParams::default(),
        pressure_kpa: 20.0,
        beta: 0.0,
        kind: GraspKind::ForceControl {
            d: 100.0,
            friction: 0.3,
        },
    };
    let params = [
        eps0(),
        h1(),
        GripperParam::Pressure,
        GripperParam::MountingAngle,
        GripperParam::Overlap,
        GripperParam::Size,
    ];
    let w = check_grasp("force control", d, &params);
    println!("force control: worst {w:.2e}");
}

const GEOMETRY_OUTPUTS: [&str; 6] = ["l0", "overlap", "palm", "d_max", "r_max", "rest_size"];

fn geometry_outputs(act: &Actuator, d: &Design) -> Vec<f64> {
    let g = gripper(act, d.params);
    vec![
        g.l0(),
        g.overlap(),
        g.palm(),
        g.d_max(),
        g.r_max(),
        g.rest_size(),
    ]
}

fn check_geometry(name: &str, d: Design, params: &[GripperParam], angle_step: f64) -> f64 {
    let act = actuator(d.actuator_eps0);
    let g = gripper(&act, d.params);
    let rows = g.geometry_sensitivities(&act, params).unwrap();
    let base = geometry_outputs(&act, &d);
    let mut worst = 0.0f64;
    for row in &rows {
        let h = match row.param {
            GripperParam::MountingAngle => angle_step,
            p => step(p, row.value),
        };
        let mut f = |v: f64| {
            let (a, dd) = perturbed(&d, &act, row.param, v);
            geometry_outputs(&a, &dd)
        };
        let fd = richardson(&mut f, row.value, h);
        let exact = [
            row.l0,
            row.overlap,
            row.palm,
            row.d_max,
            row.r_max,
            row.rest_size,
        ];
        let scale = row.value.abs().max(100.0 * h);
        let e = agreement(
            &format!("{name} / {}", row.param),
            &GEOMETRY_OUTPUTS,
            &base,
            &exact,
            &fd,
            scale,
        );
        println!("{name}: {:<28} worst relative {e:.2e}", row.param.name());
        worst = worst.max(e);
    }
    worst
}

#[test]
fn geometry_sensitivities_match_rebuilt_grippers() {
    let base = Design {
        actuator_eps0: 0.25,
        params: GripperParams::default(),
        pressure_kpa: 0.0,
        beta: 0.0,
        kind: GraspKind::Size { d: 0.0 },
    };
    let mut w = check_geometry(
        "geometry (overlap)",
        base,
        &[
            eps0(),
            h1(),
            GripperParam::MountingAngle,
            GripperParam::Overlap,
        ],
        1e-3,
    );
    let palm = Design {
        params: GripperParams {
            geometry: PalmSpec::Palm(40.0),
            mounting_angle: 1.2,
            ..GripperParams::default()
        },
        ..base
    };
    w = w.max(check_geometry(
        "geometry (palm)",
        palm,
        &[eps0(), GripperParam::MountingAngle, GripperParam::Palm],
        1e-3,
    ));
    // eps0 = 0.4 curls past its innermost point: the angle is covered (l0
    // at a fixed interior sample), the actuator is not. l0 is a maximum
    // over discrete samples, smooth only while the same sample is the
    // innermost, so the step in the angle is small (the reference state
    // does not move with it: no solve noise)
    let curled = Design {
        actuator_eps0: 0.4,
        ..base
    };
    let act = actuator(0.4);
    let g = gripper(&act, curled.params);
    assert!(!g.tip_is_innermost());
    w = w.max(check_geometry(
        "geometry (eps0 0.4)",
        curled,
        &[GripperParam::MountingAngle, GripperParam::Overlap],
        1e-6,
    ));
    match g.geometry_sensitivities(&act, &[eps0()]) {
        Err(SolveError::Input(e)) => assert_eq!(e.field(), "actuator.pemc.eps0"),
        other => panic!("expected an input error, got {other:?}"),
    }
    println!("geometry: worst {w:.2e}");
}

#[test]
fn opening_size_sensitivities_match_re_solves() {
    let d = Design {
        actuator_eps0: 0.25,
        params: GripperParams::default(),
        pressure_kpa: 30.0,
        beta: 0.0,
        kind: GraspKind::Size { d: 0.0 },
    };
    let opts = SolveOptions {
        rtol: 1e-13,
        ..SolveOptions::default().tip_only()
    };
    let outputs = |act: &Actuator, d: &Design| -> Vec<f64> {
        let g = gripper(act, d.params);
        let load = Load::unloaded().with_pressure_kpa(d.pressure_kpa);
        let sol = g.finger().solve(&load, &opts).unwrap();
        let tip = g.to_gripper(sol.tip);
        vec![g.size_of(sol.tip), 2.0 * tip[0], tip[1]]
    };
    let act = actuator(d.actuator_eps0);
    let g = gripper(&act, d.params);
    let load = Load::unloaded().with_pressure_kpa(d.pressure_kpa);
    let sol = g.finger().solve(&load, &opts).unwrap();
    let params = [
        eps0(),
        h1(),
        GripperParam::Pressure,
        GripperParam::MountingAngle,
        GripperParam::Overlap,
    ];
    let rows = g.size_sensitivities(&act, &sol, &load, &params).unwrap();
    let base = outputs(&act, &d);
    let mut worst = 0.0f64;
    for row in &rows {
        let h = step(row.param, row.value);
        let mut f = |v: f64| {
            let (a, dd) = perturbed(&d, &act, row.param, v);
            outputs(&a, &dd)
        };
        let fd = richardson(&mut f, row.value, h);
        let scale = row.value.abs().max(100.0 * h);
        let e = agreement(
            &format!("opening / {}", row.param),
            &["size", "tip_gap", "height"],
            &base,
            &[row.size, row.tip_gap, row.height],
            &fd,
            scale,
        );
        println!("opening: {:<28} worst relative {e:.2e}", row.param.name());
        worst = worst.max(e);
    }
    println!("opening: worst {worst:.2e}");
}

#[test]
fn envelope_sensitivities_match_re_solved_maxima() {
    const SAMPLES: usize = 8;
    let d = Design {
        actuator_eps0: 0.25,
        params: GripperParams::default(),
        pressure_kpa: 0.0,
        beta: 0.0,
        // off the envelope's peak (about 49.2 mm), where d f_v^max / dr
        // vanishes below the noise of differences of re-solved maxima
        kind: GraspKind::SphereAtFrictionLimit { radius: 45.0 },
    };
    let best_of = |act: &Actuator, d: &Design| {
        let r = match d.kind {
            GraspKind::SphereAtFrictionLimit { radius } => radius,
            _ => unreachable!(),
        };
        gripper(act, d.params)
            .max_sphere_lift(d.pressure_kpa, r, SAMPLES)
            .unwrap()
            .expect("a valid grasp")
    };
    // The best lift through the ordinary path, its angle then pinned
    // further: `max_sphere_lift` finds the second-contact boundary to
    // 1e-9 rad (ENVELOPE_BETA_TOL), i.e. the lift to about 1e-9 N; bisecting
    // on the validity the gripper itself judges (`sphere_grasp_at_friction_limit`)
    // takes it to 1e-15 rad.
    let pinned = |act: &Actuator, d: &Design| -> f64 {
        let best = best_of(act, d);
        let g = gripper(act, d.params);
        let at = |b: f64| {
            g.sphere_grasp_at_friction_limit(d.pressure_kpa, best.radius, b, None)
                .unwrap()
        };
        let (mut good, mut bad) = (best.beta, best.beta + 1e-7);
        assert!(at(good).is_valid() && !at(bad).is_valid());
        while bad - good > 1e-15 {
            let mid = 0.5 * (good + bad);
            if at(mid).is_valid() {
                good = mid;
            } else {
                bad = mid;
            }
        }
        at(good).grasp.lift
    };
    let act = actuator(d.actuator_eps0);
    let g = gripper(&act, d.params);
    let best = best_of(&act, &d);
    let params = [
        eps0(),
        GripperParam::Pressure,
        GripperParam::MountingAngle,
        GripperParam::Overlap,
        GripperParam::Radius,
    ];
    let sens = g
        .max_sphere_lift_sensitivities(&act, d.pressure_kpa, &best, &params)
        .unwrap();
    println!(
        "envelope: b* = {:.6} rad, f_v = {:.6} N, d f_v / d b = {:.3e}, boundary {}",
        sens.beta, sens.lift, sens.d_lift_d_beta, sens.boundary
    );
    // the paper's gripper holds its spheres best where a second contact
    // begins: the angle moves with the parameters along that boundary
    assert!(sens.boundary);
    let mut worst = 0.0f64;
    for row in &sens.rows {
        let value = row.value;
        // The contact is exact (the continuous mid-plane), so the envelope
        // is smooth in every parameter while the same boundary holds the
        // angle: Richardson-extrapolated central differences.
        let h = match row.param {
            GripperParam::Pressure => 1.0,
            _ => step(row.param, value),
        };
        let mut f = |v: f64| {
            let (a, dd) = perturbed(&d, &act, row.param, v);
            vec![pinned(&a, &dd)]
        };
        let fd = richardson(&mut f, value, h);
        let scale = value.abs().max(100.0 * h);
        let e = agreement(
            &format!("envelope / {}", row.param),
            &["lift max"],
            &[best.lift],
            &[row.lift],
            &fd,
            scale,
        );
        println!("envelope: {:<28} worst relative {e:.2e}", row.param.name());
        worst = worst.max(e);
    }
    println!("envelope: worst {worst:.2e}");
    // the angle is optimised out
    assert!(g
        .max_sphere_lift_sensitivities(&act, d.pressure_kpa, &best, &[GripperParam::Beta])
        .is_err());
}

#[test]
fn mismatched_grasps_and_parameters_are_rejected() {
    let act = actuator(0.25);
    let g = gripper(&act, GripperParams::default());
    let gr = g.grasp_load_for_size(0.0, 40.0, 0.0, None).unwrap();
    let field = |r: Result<fpc::sensitivity::GraspSensitivities, SolveError>| match r {
        Err(SolveError::Input(e)) => e.field().to_string(),
        other => panic!("expected an input error, got {other:?}"),
    };
    // a size grasp is not a sphere grasp, nor one of another size
    assert_eq!(
        field(g.grasp_sensitivities(
            &act,
            &gr,
            GraspKind::SphereAtFrictionLimit { radius: 40.0 },
            &[eps0()]
        )),
        "grasp"
    );
    assert_eq!(
        field(g.grasp_sensitivities(&act, &gr, GraspKind::Size { d: 41.0 }, &[eps0()])),
        "grasp"
    );
    // a radius is no parameter of a size grasp, a palm none of an
    // overlap-specified gripper
    assert_eq!(
        field(g.grasp_sensitivities(
            &act,
            &gr,
            GraspKind::Size { d: 40.0 },
            &[GripperParam::Radius]
        )),
        "sphere.r_mm"
    );
    assert_eq!(
        field(g.grasp_sensitivities(
            &act,
            &gr,
            GraspKind::Size { d: 40.0 },
            &[GripperParam::Palm]
        )),
        "gripper.palm_mm"
    );
    // the grasp's parameters are not the geometry's
    for p in [GripperParam::Size, GripperParam::Pressure] {
        match g.geometry_sensitivities(&act, &[p]) {
            Err(SolveError::Input(e)) => assert_eq!(e.field().to_string(), p.name()),
            other => panic!("expected an input error, got {other:?}"),
        }
    }
    // force control holds the grasping angle at 0
    let fc = g.force_control(0.0, 90.0, 0.2, None).unwrap();
    assert_eq!(
        field(g.grasp_sensitivities(
            &act,
            &fc,
            GraspKind::ForceControl {
                d: 90.0,
                friction: 0.2
            },
            &[GripperParam::Beta]
        )),
        "grasp.beta_rad"
    );
    // another actuator than the finger's
    let other = actuator(0.3);
    assert!(g
        .grasp_sensitivities(&other, &gr, GraspKind::Size { d: 40.0 }, &[eps0()])
        .is_err());
    // the design parameters: actuator, angle, overlap
    let design = GripperParam::design(&act, &g);
    assert!(design.contains(&eps0()));
    assert!(design.contains(&GripperParam::MountingAngle));
    assert!(design.contains(&GripperParam::Overlap));
}
