//! The gripper analysis (docs/model.md section 5): frame transforms against
//! hand-derived cases, the geometry fixed by the unloaded finger, the
//! validity filters on constructed grasps, and every target solve fed back
//! to a plain forward solve.

#[path = "common/dense_sphere.rs"]
mod dense_sphere;
use dense_sphere::dense_best_angle;

use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, FRAC_PI_4, FRAC_PI_6};

use fpc::gripper::{
    contact_force_to_finger, contact_force_to_gripper, design_space,
    finger_displacement_to_gripper, finger_point_to_gripper, grasping_angle_range,
    gripper_force_to_contact, gripper_force_to_finger, lifting_force, Invalid,
};
use fpc::{
    Finger, Grasp, Gripper, GripperParams, InputError, Load, PalmSpec, SolveError, SolveOptions,
    Warning,
};

const MU: f64 = 0.6;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn assert_vec(got: [f64; 2], want: [f64; 2]) {
    assert!(
        close(got[0], want[0], 1e-12) && close(got[1], want[1], 1e-12),
        "got {got:?}, want {want:?}"
    );
}

/// The gripper of the paper's Sec. 5 (eps0 = 0.25, a = pi/3, g = 20 mm).
fn section5() -> Gripper {
    Gripper::paper(0.25, 8, GripperParams::default()).unwrap()
}

fn field_of(e: SolveError) -> String {
    match e {
        SolveError::Input(i) => i.field().to_string(),
        other => panic!("expected an input error, got {other}"),
    }
}

// ------------------------------------------------------------ transforms

#[test]
fn point_transform_hand_cases() {
    // a = pi/2: the finger hangs straight down (X -> +Zg), Z points out (+Xg)
    assert_vec(
        finger_point_to_gripper([10.0, 0.0], FRAC_PI_2, 60.0),
        [30.0, 10.0],
    );
    assert_vec(
        finger_point_to_gripper([0.0, 5.0], FRAC_PI_2, 60.0),
        [35.0, 0.0],
    );
    // a curl towards -Z moves inwards
    assert_vec(
        finger_point_to_gripper([0.0, -5.0], FRAC_PI_2, 60.0),
        [25.0, 0.0],
    );
    // a = 0: the finger lies along +Xg, Z points up (-Zg)
    assert_vec(finger_point_to_gripper([3.0, 2.0], 0.0, 0.0), [3.0, -2.0]);
    // a = pi/3: root at (l/2, 0), X axis (1/2, sqrt3/2), Z axis (sqrt3/2, -1/2)
    let s3 = 3f64.sqrt();
    assert_vec(
        finger_point_to_gripper([2.0, 4.0], FRAC_PI_3, 10.0),
        [5.0 + 1.0 + 2.0 * s3, s3 - 2.0],
    );
    // the root
    assert_vec(finger_point_to_gripper([0.0, 0.0], 0.7, 42.0), [21.0, 0.0]);
}

#[test]
fn displacement_transform_is_eq25_and_matches_points() {
    assert_vec(
        finger_displacement_to_gripper([1.0, 0.0], FRAC_PI_2),
        [0.0, 1.0],
    );
    assert_vec(
        finger_displacement_to_gripper([0.0, 1.0], FRAC_PI_2),
        [1.0, 0.0],
    );
    let (s, c) = FRAC_PI_6.sin_cos();
    assert_vec(
        finger_displacement_to_gripper([2.0, 3.0], FRAC_PI_6),
        [2.0 * c + 3.0 * s, 2.0 * s - 3.0 * c],
    );
    // the difference of two transformed points
    for a in [0.0, 0.4, FRAC_PI_3, FRAC_PI_2, 2.0] {
        let (p, d) = ([12.0, -7.0], [3.5, 1.25]);
        let q = [p[0] + d[0], p[1] + d[1]];
        let (gp, gq) = (
            finger_point_to_gripper(p, a, 50.0),
            finger_point_to_gripper(q, a, 50.0),
        );
        let gd = finger_displacement_to_gripper(d, a);
        assert!(close(gq[0] - gp[0], gd[0], 1e-12) && close(gq[1] - gp[1], gd[1], 1e-12));
    }
}

#[test]
fn force_transform_hand_cases() {
    // a = pi/2, b = 0: F along +Xg is the finger's +Z, friction (down) its +X
    assert_vec(
        contact_force_to_finger(2.0, 0.5, 0.0, FRAC_PI_2),
        [0.5, 2.0],
    );
    // a = b: the normal force is along the finger's X axis, friction along -Z
    assert_vec(
        contact_force_to_finger(2.0, 0.5, FRAC_PI_3, FRAC_PI_3),
        [2.0, -0.5],
    );
    // a = pi/3, b = 0
    let s3 = 3f64.sqrt();
    assert_vec(
        contact_force_to_finger(1.0, 1.0, 0.0, FRAC_PI_3),
        [0.5 + 0.5 * s3, 0.5 * s3 - 0.5],
    );
    // gripper-frame components: n = (cos b, sin b), t = (-sin b, cos b)
    assert_vec(contact_force_to_gripper(1.0, 0.0, FRAC_PI_2), [0.0, 1.0]);
    assert_vec(contact_force_to_gripper(0.0, 1.0, 0.0), [0.0, 1.0]);
    assert!(close(lifting_force(2.0, 0.5, 0.0), 0.5, 1e-15));
    assert!(close(lifting_force(2.0, 0.5, FRAC_PI_2), 2.0, 1e-15));
}

#[test]
fn force_transforms_compose_and_invert() {
    for &(f_n, f_t, b, a) in &[
        (1.3, 0.4, 0.2, FRAC_PI_3),
        (0.7, -0.2, -0.4, FRAC_PI_2),
        (2.0, 1.2, 1.1, 1.2),
        (0.0, 1.0, FRAC_PI_4, 0.3),
    ] {
        let g = contact_force_to_gripper(f_n, f_t, b);
        let direct = contact_force_to_finger(f_n, f_t, b, a);
        let via = gripper_force_to_finger(g, a);
        assert!(close(direct[0], via[0], 1e-12) && close(direct[1], via[1], 1e-12));
        let (n2, t2) = gripper_force_to_contact(g, b);
        assert!(close(n2, f_n, 1e-12) && close(t2, f_t, 1e-12));
        // the lifting force is the vertical component
        assert!(close(lifting_force(f_n, f_t, b), g[1], 1e-12));
        // work is frame independent: F . u in the finger frame = in the gripper frame
        let u = [0.8, -2.5];
        let ug = finger_displacement_to_gripper(u, a);
        assert!(close(
            direct[0] * u[0] + direct[1] * u[1],
            g[0] * ug[0] + g[1] * ug[1],
            1e-12
        ));
    }
}

#[test]
fn angle_ranges() {
    let [lo, hi] = design_space(MU);
    assert!(close(lo, (1.0 / MU).atan(), 1e-15) && hi == FRAC_PI_2);
    // mu sin a >= cos a at the lower bound, with equality
    assert!(close(MU * lo.sin(), lo.cos(), 1e-12));
    let [blo, bhi] = grasping_angle_range(MU);
    assert!(close(blo, -MU.atan(), 1e-15) && bhi == FRAC_PI_2);
}

// ------------------------------------------------------------ geometry

#[test]
fn geometry_from_the_reference_state() {
    let g = section5();
    let a = FRAC_PI_3;
    let (s, c) = a.sin_cos();
    // l0: the largest inward reach over the sampled mid-plane (D6)
    let reach = g
        .reference()
        .points
        .iter()
        .map(|p| -(p[0] * c + p[1] * s))
        .fold(0.0, f64::max);
    assert!(close(g.l0(), reach, 1e-12));
    assert!(g.l0() > 0.0);
    assert!(close(g.palm(), 2.0 * (g.l0() - 20.0), 1e-12));
    assert!(close(g.overlap(), 20.0, 1e-12));
    assert!(close(g.rest_size(), -40.0, 1e-12));
    assert_eq!(g.d_min(), 0.0);
    assert!(close(g.length(), 110.0, 1e-12));
    assert!(close(g.d_max(), g.palm() + 220.0 * c, 1e-12));
    assert!(close(g.d_max(), 2.0 * (g.l0() - 20.0 + 110.0 * c), 1e-9));
    assert!(close(g.r_max(), (0.5 * g.palm() + 110.0 * c) / s, 1e-12));
    assert!(g.warnings().is_empty(), "{:?}", g.warnings());
    // the reference tip is the innermost point, its size is -2 g
    assert!(g.tip_is_innermost());
    assert!(close(g.size_of(g.reference().tip), -40.0, 1e-9));
    let tip = g.to_gripper(g.reference().tip);
    assert!(close(2.0 * tip[0], -40.0, 1e-9));
    // at zero pressure the finger curls inwards: the tip lies below the root, inside
    assert!(tip[1] > 0.0 && tip[0] < 0.5 * g.palm());

    // the same gripper given by its palm
    let by_palm = Gripper::paper(
        0.25,
        8,
        GripperParams {
            geometry: PalmSpec::Palm(g.palm()),
            ..GripperParams::default()
        },
    )
    .unwrap();
    assert!(close(by_palm.overlap(), 20.0, 1e-9));
}

#[test]
fn curled_past_the_innermost_point() {
    // eps0 = 0.4 curls past its innermost point: the tip gap is not d
    let g = Gripper::paper(
        0.4,
        8,
        GripperParams {
            mounting_angle: FRAC_PI_2,
            geometry: PalmSpec::Overlap(0.0),
            ..GripperParams::default()
        },
    )
    .unwrap();
    assert!(!g.tip_is_innermost());
    assert!(g.innermost_point() < g.reference().points.len() - 1);
    let tip = g.to_gripper(g.reference().tip);
    assert!(close(g.size_of(g.reference().tip), 0.0, 1e-9));
    assert!(2.0 * tip[0] > 1.0, "tip gap {}", 2.0 * tip[0]);
    // a grasp reports both measures
    let gr = g.grasp_load_for_size(0.0, 20.0, 0.0, None).unwrap();
    assert!(close(gr.size, 20.0, 1e-6));
    assert!(gr.tip_gap > gr.size);
}

#[test]
fn warnings_for_designs_outside_the_design_space() {
    // a steep angle curls the fingers far past the axis: the overlap that
    // leaves room for three roots on the palm
    let steep = Gripper::paper(
        0.25,
        8,
        GripperParams {
            mounting_angle: FRAC_PI_6,
            geometry: PalmSpec::Palm(40.0),
            ..GripperParams::default()
        },
    )
    .unwrap();
    assert!(matches!(
        steep.warnings(),
        [Warning::MountingAngleOutsideDesignSpace { .. }, ..]
    ));
    let wide = Gripper::paper(
        0.25,
        8,
        GripperParams {
            geometry: PalmSpec::Overlap(-5.0),
            ..GripperParams::default()
        },
    )
    .unwrap();
    assert!(matches!(wide.warnings(), [Warning::PalmGapAtRest { .. }]));
    assert!(wide.d_min() > 0.0);
    assert!(close(wide.d_min(), 10.0, 1e-9));
    // messages name the field
    assert!(wide.warnings()[0].to_string().contains("gripper.palm"));
    assert!(steep.warnings()[0]
        .to_string()
        .contains("gripper.mounting_angle"));
}

#[test]
fn rejected_designs_name_the_field() {
    let finger = Finger::paper(0.25, 4).unwrap();
    let bad = |p: GripperParams| field_of(Gripper::new(finger.clone(), p).unwrap_err());
    let base = GripperParams::default();
    assert_eq!(bad(GripperParams { mu: 0.0, ..base }), "gripper.mu");
    assert_eq!(bad(GripperParams { fingers: 0, ..base }), "gripper.fingers");
    assert_eq!(
        bad(GripperParams {
            mounting_angle: f64::NAN,
            ..base
        }),
        "gripper.mounting_angle"
    );
    assert_eq!(
        bad(GripperParams {
            geometry: PalmSpec::Palm(-1.0),
            ..base
        }),
        "gripper.palm"
    );
    assert_eq!(
        bad(GripperParams {
            geometry: PalmSpec::Overlap(1e3),
            ..base
        }),
        "gripper.overlap"
    );
    assert_eq!(
        bad(GripperParams {
            geometry: PalmSpec::Overlap(f64::INFINITY),
            ..base
        }),
        "gripper.overlap"
    );
}

#[test]
fn d_max_is_approached_by_the_finger_pulled_flat() {
    // a tension along the finger pulls it flat: d grows towards
    // l + 2 Lx cos a from below
    let g = section5();
    let opts = SolveOptions::default().tip_only();
    let mut last = g.rest_size();
    for fx in [1.0, 5.0, 20.0] {
        let s = g
            .finger()
            .solve(&Load::unloaded().with_tip_force(fx, 0.0), &opts)
            .unwrap();
        let d = g.size_of(s.tip);
        assert!(d > last && d < g.d_max(), "fx {fx}: d {d}");
        last = d;
    }
    assert!(
        g.d_max() - last < 0.03 * g.d_max(),
        "d {last} vs {}",
        g.d_max()
    );
}

// ------------------------------------------------------------ target solves

/// Forward solve of a grasp's load from the unloaded finger; returns the
/// tip.
fn forward_tip(g: &Gripper, gr: &Grasp) -> [f64; 2] {
    g.finger()
        .solve(&gr.load, &SolveOptions::default().tip_only())
        .or_else(|_| {
            g.finger().solve_from(
                &gr.load,
                &gr.solution.coefficients,
                &SolveOptions::default().tip_only(),
            )
        })
        .unwrap()
        .tip
}

#[test]
fn grasp_load_for_size_meets_its_target() {
    let g = section5();
    let mut warm: Option<Grasp> = None;
    for d in [0.0, 40.0, 100.0, 160.0] {
        let gr = g.grasp_load_for_size(0.0, d, 0.0, warm.as_ref()).unwrap();
        assert!(close(gr.size, d, 1e-6), "{d}: {}", gr.size);
        assert!(close(gr.friction, MU * gr.normal, 1e-12));
        assert!(close(gr.lift, MU * gr.normal, 1e-12));
        assert!(gr.normal > 0.0 && gr.friction_ok(MU));
        // the load is F (n + mu t) in the finger frame
        let want = contact_force_to_finger(gr.normal, gr.friction, 0.0, FRAC_PI_3);
        assert!(close(gr.load.fx, want[0], 1e-12) && close(gr.load.fz, want[1], 1e-12));
        // fed back to a forward solve
        let tip = forward_tip(&g, &gr);
        assert!(close(g.size_of(tip), d, 1e-6), "{d}: {}", g.size_of(tip));
        assert!(close(g.to_gripper(tip)[1], gr.height, 1e-6));
        // F grows with d
        if let Some(w) = &warm {
            assert!(gr.normal > w.normal);
        }
        warm = Some(gr);
    }
    // at other grasping angles and a pressure; a cold start agrees with a warm one
    for (p, d, b) in [(0.0, 60.0, 0.4), (30.0, 80.0, -0.3)] {
        let cold = g.grasp_load_for_size(p, d, b, None).unwrap();
        let warm = g.grasp_load_for_size(p, d, b, warm.as_ref()).unwrap();
        assert!(close(cold.normal, warm.normal, 1e-7));
        assert!(close(cold.size, d, 1e-6));
        assert!(close(
            cold.lift,
            cold.normal * (b.sin() + MU * b.cos()),
            1e-12
        ));
        assert!(close(g.size_of(forward_tip(&g, &cold)), d, 1e-6));
    }
}

#[test]
fn force_control_meets_its_target_and_force_falls_with_pressure() {
    let g = section5();
    let mut warm: Option<Grasp> = None;
    let mut last_f = f64::INFINITY;
    for p in [0.0, 50.0, 100.0] {
        let gr = g.force_control(p, 100.0, 0.3, warm.as_ref()).unwrap();
        assert!(close(gr.size, 100.0, 1e-6));
        assert_eq!(gr.beta, 0.0);
        assert!(close(gr.friction, 0.3, 1e-12) && close(gr.lift, 0.3, 1e-12));
        assert!(close(gr.load.pressure, p * 1e-3, 1e-15));
        let tip = forward_tip(&g, &gr);
        assert!(close(g.size_of(tip), 100.0, 1e-6));
        assert!(gr.normal < last_f && gr.normal > 0.0 && gr.friction_ok(MU));
        last_f = gr.normal;
        warm = Some(gr);
    }
}

#[test]
fn sphere_grasp_meets_its_target() {
    let g = section5();
    let (r, lift) = (50.0, 0.5);
    let mut warm: Option<Grasp> = None;
    for b in [-0.1, 0.1, 0.3] {
        let sg = g.sphere_grasp(0.0, r, lift, b, warm.as_ref()).unwrap();
        assert!(close(sg.radius, r, 1e-6), "{}", sg.radius);
        assert!(close(sg.center[0], 0.0, 1e-9));
        assert!(close(sg.grasp.lift, lift, 1e-12));
        assert!(close(sg.grasp.tip_gap, 2.0 * r * b.cos(), 1e-6));
        // the tip gap is the paper's d for this gripper (the tip is innermost)
        assert!(close(sg.grasp.size, 2.0 * r * b.cos(), 1e-6));
        // the centre is r from the tip, along -n
        let t = sg.grasp.tip;
        assert!(close(
            (t[0] - sg.center[0]).hypot(t[1] - sg.center[1]),
            r,
            1e-6
        ));
        assert!(sg.is_valid(), "{b}: {:?}", sg.invalid());
        let tip = forward_tip(&g, &sg.grasp);
        assert!(close(g.to_gripper(tip)[0], r * b.cos(), 1e-6));
        warm = Some(sg.grasp);
    }
    // too much friction needed above the equator
    let sg = g.sphere_grasp(0.0, r, lift, -0.5, None).unwrap();
    assert!(matches!(sg.invalid(), Some(Invalid::FrictionCone { .. })));
}

#[test]
fn viable_angle_range_boundaries() {
    let g = section5();
    let v = g.viable_angle_range(0.0, 50.0, 0.5, 12).unwrap();
    let [lo, hi] = v.range().expect("a viable range");
    let [blo, bhi] = grasping_angle_range(MU);
    assert!(lo >= blo && hi < bhi && lo < hi, "{lo} {hi}");
    assert!(v
        .scan
        .iter()
        .all(|s| s.normal.is_finite() && s.friction.is_finite()));
    // just inside the boundaries: viable; just outside: not
    let viable = |b: f64| g.sphere_grasp(0.0, 50.0, 0.5, b, None).unwrap().is_valid();
    assert!(viable(lo + 1e-4) && viable(hi - 1e-4));
    if lo > blo {
        assert!(!viable(lo - 1e-3));
    }
    assert!(!viable(hi + 1e-3));
    // no viable angle for a far too heavy object
    let none = g.viable_angle_range(0.0, 50.0, 50.0, 6).unwrap();
    assert!(none.range().is_none());
}

#[test]
fn max_sphere_lift_is_the_best_valid_angle() {
    let g = section5();
    let best = g.max_sphere_lift(0.0, 50.0, 12).unwrap().unwrap();
    let [lo, hi] = grasping_angle_range(MU);
    assert!(best.beta >= lo && best.beta < hi && best.lift > 0.0);
    // the grasp there is valid, at the friction limit, and carries that lift
    let at = g
        .sphere_grasp_at_friction_limit(0.0, 50.0, best.beta, None)
        .unwrap();
    assert!(at.is_valid(), "{:?}", at.invalid());
    assert!(close(at.grasp.lift, best.lift, 1e-6));
    assert!(close(at.grasp.friction, MU * at.grasp.normal, 1e-12));
    assert!(close(at.radius, 50.0, 1e-6));
    // no valid angle does better on a finer scan
    let mut warm: Option<Grasp> = None;
    for i in 0..24 {
        let b = lo + (hi - lo) * i as f64 / 24.0;
        let Ok(sg) = g.sphere_grasp_at_friction_limit(0.0, 50.0, b, warm.as_ref()) else {
            break;
        };
        if sg.is_valid() {
            assert!(sg.grasp.lift <= best.lift + 1e-9, "{b}: {}", sg.grasp.lift);
        }
        warm = Some(sg.grasp);
    }
    // a lighter sphere at that angle: the normal force alone lifts more
    // than 0.5 N, so friction would have to push down (not viable, study 6)
    let held = g.sphere_grasp(0.0, 50.0, 0.5, best.beta, None).unwrap();
    assert!(held.grasp.friction < 0.0);
    assert!(matches!(held.invalid(), Some(Invalid::FrictionCone { .. })));
}

#[test]
fn stability_is_judged_by_default_and_can_be_switched_off() {
    let g = section5();
    // on by default: the restricted inertia of every grasp is reported
    let checked = g.grasp_load_for_size(0.0, 50.0, 0.0, None).unwrap();
    assert_eq!(checked.solution.negative_eigenvalues, Some(0));
    let g = g.with_stability(false);
    let plain = g.grasp_load_for_size(0.0, 50.0, 0.0, None).unwrap();
    assert!(plain.solution.negative_eigenvalues.is_none());
    // judging stability does not move the answer
    assert!(close(checked.normal, plain.normal, 1e-9));
}

// ------------------------------------------------------------ validity

#[test]
fn not_open_fingers_are_invalid() {
    // the overlapping fingers at rest: d = -2 g < 0
    let g = section5();
    let c = g.sphere_contact(g.reference(), 0.0);
    assert!(matches!(c.invalid, Some(Invalid::NotOpen { size, .. }) if size < 0.0));
    assert_eq!(c.radius, 0.0);
    // touching fingers (g = 0): d = 0 is not open either
    let touching = Gripper::paper(
        0.25,
        8,
        GripperParams {
            geometry: PalmSpec::Overlap(0.0),
            ..GripperParams::default()
        },
    )
    .unwrap();
    let c = touching.sphere_contact(touching.reference(), 0.2);
    assert!(matches!(c.invalid, Some(Invalid::NotOpen { .. })));
}

#[test]
fn a_huge_sphere_crosses_the_finger() {
    // fingers 60 mm apart at rest (a negative overlap)
    let g = Gripper::paper(
        0.25,
        8,
        GripperParams {
            geometry: PalmSpec::Overlap(-30.0),
            ..GripperParams::default()
        },
    )
    .unwrap();
    let rest = g.reference();
    // a 30 mm sphere touched at its equator fits between the curled fingers
    let small = g.sphere_contact(rest, 0.0);
    assert!(close(small.radius, 30.0, 1e-9) && small.invalid.is_none());
    // touched far below its equator, the sphere is huge and its centre far
    // above the tip: it swallows the finger's root
    let huge = g.sphere_contact(rest, 1.4);
    assert!(huge.radius > 150.0);
    match huge.invalid {
        Some(Invalid::SecondContact {
            element,
            depth,
            point,
            ..
        }) => {
            assert!(element < g.finger().len() && depth > 1.0);
            let dist = (point[0] - huge.center[0]).hypot(point[1] - huge.center[1]);
            assert!(close(huge.radius - dist, depth, 1e-9));
        }
        other => panic!("expected a second contact, got {other:?}"),
    }
}

// ------------------------------------------------------------ errors

#[test]
fn bad_grasp_inputs_are_typed_errors() {
    let g = section5();
    assert_eq!(
        field_of(g.grasp_load_for_size(0.0, f64::NAN, 0.0, None).unwrap_err()),
        "grasp.size"
    );
    assert_eq!(
        field_of(g.grasp_load_for_size(0.0, 10.0, 2.0, None).unwrap_err()),
        "grasp.beta"
    );
    assert_eq!(
        field_of(g.force_control(f64::INFINITY, 10.0, 0.3, None).unwrap_err()),
        "grasp.pressure_kpa"
    );
    assert_eq!(
        field_of(g.sphere_grasp(0.0, -5.0, 0.5, 0.0, None).unwrap_err()),
        "sphere.radius"
    );
    assert_eq!(
        field_of(g.sphere_grasp(0.0, 5.0, 0.5, FRAC_PI_2, None).unwrap_err()),
        "sphere.beta"
    );
    assert_eq!(
        field_of(g.viable_angle_range(0.0, 50.0, 0.5, 2).unwrap_err()),
        "sphere.samples"
    );
    let e: InputError = match g.grasp_load_for_size(0.0, 10.0, f64::NAN, None) {
        Err(SolveError::Input(e)) => e,
        other => panic!("{other:?}"),
    };
    assert!(e.to_string().contains("grasp.beta"));
}

#[test]
fn unreachable_targets_fail_cleanly() {
    // a grasping size far beyond any finger: rejected, naming the target
    let g = section5();
    match g.grasp_load_for_size(0.0, 2000.0, 0.0, None) {
        Err(SolveError::Input(e)) => assert_eq!(e.field(), "grasp.size"),
        Ok(gr) => panic!("reached an impossible size: {}", gr.size),
        Err(e) => panic!("unexpected error {e}"),
    }
    // a friction the finger cannot carry: the path stops short, naming it
    match g.force_control(0.0, 100.0, 500.0, None) {
        Err(SolveError::TargetNotReached { target, .. }) => {
            assert_eq!(target, fpc::Field::GraspFriction)
        }
        Ok(gr) => assert!(!gr.is_valid(), "{gr:?}"),
        Err(e) => panic!("unexpected error {e}"),
    }
}

/// The best grasping angle of a sphere is solved, not sampled: a dense grid
/// of angles (each grasp solved independently, warm-started along the grid)
/// never finds a valid grasp lifting more than the solved maximum, beyond
/// the lift's change over one grid step.
#[test]
fn the_solved_sphere_envelope_is_not_beaten_by_a_dense_grid() {
    use fpc::gripper::grasping_angle_range;
    let params = GripperParams {
        mounting_angle: std::f64::consts::FRAC_PI_3,
        geometry: PalmSpec::Overlap(20.0),
        ..GripperParams::default()
    };
    let g = Gripper::paper(0.25, 8, params).unwrap();
    let [lo, hi] = grasping_angle_range(g.mu());
    for r in [40.0, 60.0] {
        let best = g
            .max_sphere_lift(0.0, r, 24)
            .unwrap()
            .expect("a valid grasp");
        let m = 400;
        let mut warm = None;
        let mut grid_best = f64::NEG_INFINITY;
        let mut max_step_change = 0.0f64;
        let mut last: Option<f64> = None;
        for i in 0..m {
            let beta = lo + (hi - lo) * i as f64 / m as f64;
            match g.sphere_grasp_at_friction_limit(0.0, r, beta, warm.as_ref()) {
                Ok(sg) => {
                    if sg.is_valid() {
                        grid_best = grid_best.max(sg.grasp.lift);
                        if let Some(l) = last {
                            max_step_change = max_step_change.max((sg.grasp.lift - l).abs());
                        }
                        last = Some(sg.grasp.lift);
                    } else {
                        last = None;
                    }
                    warm = Some(sg.grasp);
                }
                Err(_) => {
                    warm = None;
                    last = None;
                }
            }
        }
        assert!(grid_best.is_finite(), "r = {r}: no valid grasp on the grid");
        assert!(
            grid_best <= best.lift + 1e-9 * best.lift.abs(),
            "r = {r}: grid {grid_best} > solved {} (step change {max_step_change:e})",
            best.lift
        );
        // and the solved maximum is not far above the grid either
        assert!(best.lift - grid_best <= max_step_change + 1e-9, "r = {r}");
    }
}

/// The envelope followed along the radius (each radius continued from the
/// ones before, not searched afresh) finds, radius by radius, the optimum
/// an independent dense scan with a local refinement finds: the same angle
/// to 1e-10 rad and the same lift to 1e-9 relative; it searched afresh
/// only to start, and every answer is the grasp traced from rest.
#[test]
fn the_followed_sphere_envelope_matches_a_dense_evaluation() {
    use fpc::gripper::SphereEnvelope;
    let g = Gripper::paper(
        0.25,
        8,
        GripperParams {
            mounting_angle: FRAC_PI_3,
            geometry: PalmSpec::Overlap(20.0),
            ..GripperParams::default()
        },
    )
    .unwrap();
    let mut env = SphereEnvelope::new(&g, 0.0, 24);
    // up to the radii the flat fingers only just reach (r cos b = d_max / 2)
    let radii: Vec<f64> = (0..27).map(|i| 20.0 + 3.0 * i as f64).collect();
    let found: Vec<_> = radii
        .iter()
        .map(|&r| env.at(r).unwrap().expect("a valid grasp"))
        .collect();
    let counts = env.counts();
    assert_eq!(counts.searched, 1, "{counts:?}");
    assert_eq!(
        counts.boundary + counts.interior + counts.reach,
        radii.len() - 1,
        "{counts:?}"
    );
    assert!(counts.reach > 0 && counts.boundary > 0, "{counts:?}");
    // the corrector's steps are probes from neighbouring grasps; every
    // answer is the trace from rest of its angle (below)
    assert!(
        counts.probes > counts.solves && counts.retraced <= 2,
        "{counts:?}"
    );
    for (r, e) in radii.iter().zip(&found) {
        let sg = g
            .sphere_grasp_at_friction_limit(0.0, *r, e.beta, None)
            .unwrap();
        assert!(sg.is_valid() && sg.grasp.lift == e.lift, "r = {r}");
        assert_eq!(sg.grasp.verdict.path.from, "rest", "r = {r}");
    }
    // the same radii at once (`along`: the confirming traces on another
    // thread): the same optima, each again the trace from rest at its angle
    let mut batch = SphereEnvelope::new(&g, 0.0, 24);
    let together = batch.along(&radii).unwrap();
    assert_eq!(batch.counts().searched, 1, "{:?}", batch.counts());
    for ((r, e), t) in radii.iter().zip(&found).zip(&together) {
        let t = t.as_ref().expect("a valid grasp");
        assert!((t.beta - e.beta).abs() <= 1e-10, "r = {r}");
        assert!((t.lift - e.lift).abs() <= 1e-10 * e.lift, "r = {r}");
        let sg = g
            .sphere_grasp_at_friction_limit(0.0, *r, t.beta, None)
            .unwrap();
        assert!(sg.is_valid() && sg.grasp.lift == t.lift, "r = {r}");
    }
    for k in [1, 8, 15, 25] {
        let (r, e) = (radii[k], &found[k]);
        let (beta, lift) = dense_best_angle(&g, r, 200);
        assert!(
            (e.beta - beta).abs() <= 1e-10,
            "r = {r}: b {} against {beta}",
            e.beta
        );
        assert!(
            (e.lift - lift).abs() <= 1e-9 * lift.abs(),
            "r = {r}: f_v {} against {lift}",
            e.lift
        );
        // the answer is an ordinary valid grasp
        let sg = g
            .sphere_grasp_at_friction_limit(0.0, r, e.beta, None)
            .unwrap();
        assert!(sg.is_valid() && sg.grasp.lift == e.lift, "r = {r}");
    }
}

/// Where the best grasping angle sits at the edge of the angles whose grasp
/// is reached on the path from rest (past it, closing from rest first moves
/// the tip away from the sphere and the path folds: the optimum of
/// scenes/design/paper_sec5.toml), the follower holds that edge radius
/// after radius: each answer is valid, a trace 1e-8 rad further fails, and
/// an independent dense scan with bisection of the edge finds the same
/// angle (to 1e-9 rad) and lift (1e-9 relative).
#[test]
fn the_followed_envelope_holds_the_edge_of_the_path_from_rest() {
    use fpc::gripper::SphereEnvelope;
    let g = Gripper::paper(
        0.2841726288042098,
        8,
        GripperParams {
            mounting_angle: 74.30789829896673f64.to_radians(),
            geometry: PalmSpec::Overlap(20.0),
            ..GripperParams::default()
        },
    )
    .unwrap();
    let mut env = SphereEnvelope::new(&g, 0.0, 24);
    let radii = [45.0, 47.5, 50.0, 52.5, 55.0];
    let found: Vec<_> = radii
        .iter()
        .map(|&r| env.at(r).unwrap().expect("a valid grasp"))
        .collect();
    let counts = env.counts();
    assert_eq!((counts.searched, counts.edge), (1, 4), "{counts:?}");
    // the first followed radius tries the usual regimes first; the others
    // trace the predicted turn, one step past it and a grasp further
    // inside: fewer solves in all than one fresh search's 24-angle scan
    assert!(counts.solves <= 30, "{counts:?}");
    for (&r, e) in radii.iter().zip(&found) {
        let sg = g
            .sphere_grasp_at_friction_limit(0.0, r, e.beta, None)
            .unwrap();
        assert!(sg.is_valid() && sg.grasp.lift == e.lift, "r = {r}");
        assert!(
            g.sphere_grasp_at_friction_limit(0.0, r, e.beta + 1e-8, None)
                .is_err(),
            "r = {r}: the path from rest still reaches the sphere past the edge"
        );
        let (beta, lift) = dense_best_angle(&g, r, 96);
        // the first radius is searched afresh, its edge bisected to 1e-9
        // rad; the followed ones are traced around the turn to 1e-11 rad
        let tol = if r == radii[0] { 2e-9 } else { 1e-10 };
        assert!(
            (e.beta - beta).abs() <= 1e-9,
            "r = {r}: b {} against {beta}",
            e.beta
        );
        assert!(
            (e.lift - lift).abs() <= tol * lift,
            "r = {r}: f_v {} against {lift}",
            e.lift
        );
    }
}

#[test]
fn extreme_values_in_grasp_errors_are_compact() {
    // a value far out of range is named as written, not in hundreds of digits
    let g = section5();
    let huge = g.sphere_grasp(0.0, 1e300, 0.5, 0.35, None).unwrap_err();
    let text = huge.to_string();
    assert_eq!(field_of(huge), "sphere.radius");
    assert!(text.contains("Xg = 9.3") && text.len() < 200, "{text}");
    let friction = g.force_control(0.0, 100.0, 1e300, None).unwrap_err();
    let text = friction.to_string();
    assert!(text.starts_with("grasp.friction = 1e300:"), "{text}");
    assert!(text.len() < 400, "{text}");
}
