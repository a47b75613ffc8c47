//! Gripper errors and warnings.

use super::*;

// ------------------------------------------------------------------ gripper

fn gripper_input(finger: &Finger, params: GripperParams) -> InputError {
    input(Gripper::new(finger.clone(), params))
}

#[test]
fn gripper_designs_are_checked() {
    let f = Finger::paper(0.25, 8).unwrap();
    let d = GripperParams::default();
    for (mu, rule) in [
        (0.0, "must be positive"),
        (-0.6, "must be positive"),
        (f64::NAN, "must be finite"),
        (f64::INFINITY, "must be finite"),
    ] {
        names(
            &gripper_input(&f, GripperParams { mu, ..d }),
            "gripper.mu",
            mu,
            rule,
        );
    }
    names(
        &gripper_input(&f, GripperParams { fingers: 0, ..d }),
        "gripper.fingers",
        0.0,
        "must lie in [1, 12]",
    );
    for a in [f64::NAN, f64::NEG_INFINITY] {
        names(
            &gripper_input(
                &f,
                GripperParams {
                    mounting_angle: a,
                    ..d
                },
            ),
            "gripper.mounting_angle",
            a,
            "must be finite",
        );
    }
    names(
        &gripper_input(
            &f,
            GripperParams {
                geometry: PalmSpec::Overlap(f64::NAN),
                ..d
            },
        ),
        "gripper.overlap",
        f64::NAN,
        "must be finite",
    );
    names(
        &gripper_input(
            &f,
            GripperParams {
                geometry: PalmSpec::Overlap(500.0),
                ..d
            },
        ),
        "gripper.overlap",
        500.0,
        "must not exceed the finger's inward reach",
    );
    names(
        &gripper_input(
            &f,
            GripperParams {
                geometry: PalmSpec::Palm(-1.0),
                ..d
            },
        ),
        "gripper.palm",
        -1.0,
        "must not be negative",
    );
    // finite but past any gripper: the grasp's sizes would overflow
    for (geometry, field, shown) in [
        (PalmSpec::Palm(1e308), "gripper.palm", "1e308"),
        (PalmSpec::Overlap(-1e308), "gripper.overlap", "-1e308"),
    ] {
        let e = gripper_input(&f, GripperParams { geometry, ..d });
        assert_eq!(e.field(), field, "{e}");
        // (the value written short, not in 309 digits)
        assert!(
            e.to_string()
                .starts_with(&format!("{field} = {shown}: must be")),
            "{e}"
        );
    }
}

#[test]
fn a_mounting_angle_outside_the_design_space_is_a_warning() {
    let f = Finger::paper(0.25, 8).unwrap();
    let mu = 0.6;
    let [lo, hi] = design_space(mu);
    assert!((lo - (1.0 / mu).atan()).abs() < 1e-15 && hi == FRAC_PI_2);
    // two fingers face each other across any palm (three or more need a
    // palm wide enough for their roots: a_gripper_s_fingers_must_fit_its_palm)
    let params = |a: f64| GripperParams {
        mounting_angle: a,
        geometry: PalmSpec::Overlap(0.0),
        mu,
        fingers: 2,
        ..GripperParams::default()
    };
    // the design space [arccot mu, pi/2], ends included
    for a in [lo, FRAC_PI_3, hi] {
        let g = Gripper::new(f.clone(), params(a)).unwrap();
        assert!(g.warnings().is_empty(), "{a}: {:?}", g.warnings());
    }
    // outside it on either side, but pointing away from the palm: accepted,
    // with one warning
    for a in [lo - 0.1, 0.2, hi + 0.1, 2.0] {
        let g = Gripper::new(f.clone(), params(a)).unwrap_or_else(|e| panic!("{a}: {e}"));
        assert_eq!(
            g.warnings(),
            [Warning::MountingAngleOutsideDesignSpace { angle: a, lo, hi }],
            "{a}"
        );
        let msg = one_line(&g.warnings()[0]);
        assert!(
            msg.starts_with(&format!("gripper.mounting_angle = {a}: ")),
            "{msg}"
        );
        assert!(msg.contains("outside the design space"), "{msg}");
        assert!(msg.contains(&format!("[{lo}, {hi}]")), "{msg}");
    }
    // outside (0, pi) the finger points into the palm: an input error that
    // names the mounting angle (not the overlap that would follow from it)
    for a in [0.0, -0.3, std::f64::consts::PI, 4.0 * std::f64::consts::PI] {
        match Gripper::new(f.clone(), params(a)) {
            Err(SolveError::Input(e)) => {
                assert_eq!(e.field(), "gripper.mounting_angle", "{a}: {e}");
                assert!(e.to_string().contains("(0, 180) degrees"), "{e}");
            }
            other => panic!("{a}: {other:?}"),
        }
    }
}

#[test]
fn a_prestrain_outside_the_fitted_range_is_a_gripper_warning() {
    let (lo, hi) = EPS0_FIT_RANGE;
    assert_eq!((lo, hi), (0.0, 0.6));
    let params = |a: f64| GripperParams {
        mounting_angle: a,
        geometry: PalmSpec::Overlap(0.0),
        fingers: 2,
        ..GripperParams::default()
    };
    for eps0 in [lo, 0.25, hi] {
        let g = Gripper::paper(eps0, 8, params(FRAC_PI_3)).unwrap();
        assert!(g.warnings().is_empty(), "{eps0}: {:?}", g.warnings());
    }
    for eps0 in [-0.05, 0.7, 1.0] {
        let g = Gripper::paper(eps0, 8, params(FRAC_PI_3)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            g.warnings(),
            [Warning::Eps0OutsideFit { eps0, lo, hi }],
            "{eps0}"
        );
        let msg = one_line(&g.warnings()[0]);
        assert!(
            msg.starts_with(&format!("actuator.pemc.eps0 = {eps0}: outside [0, 0.6]")),
            "{msg}"
        );
    }
    // both at once: the actuator's warning first, then the design's
    let g = Gripper::paper(0.7, 8, params(2.0)).unwrap();
    assert!(
        matches!(
            g.warnings(),
            [
                Warning::Eps0OutsideFit { .. },
                Warning::MountingAngleOutsideDesignSpace { .. }
            ]
        ),
        "{:?}",
        g.warnings()
    );
    // from an actuator and a partition too
    let act = Actuator::paper(0.7).unwrap();
    let part = Partition::equal(act.geometry().lx, 4).unwrap();
    let g = Gripper::from_actuator(&act, &part, params(FRAC_PI_3)).unwrap();
    assert_eq!(g.warnings(), act.warnings());
}

#[test]
fn a_gripper_s_fingers_must_fit_its_palm() {
    // the Sec. 5 palm (2 (l0 - g) = 66.4 mm) holds 3 fingers 31.75 mm wide
    // (neighbouring roots 57.5 mm apart) and 6 (33.2 mm), not 7 (28.8 mm)
    let params = |fingers: usize| GripperParams {
        fingers,
        ..GripperParams::default()
    };
    for n in [1, 2, 3, 4, 6] {
        Gripper::paper(0.25, 8, params(n)).unwrap_or_else(|e| panic!("{n}: {e}"));
    }
    for (n, says) in [
        (7, "do not fit around the palm"),
        (12, "do not fit around the palm"),
        (13, "must lie in [1, 12]"),
        (100, "must lie in [1, 12]"),
    ] {
        match Gripper::paper(0.25, 8, params(n)) {
            Err(SolveError::Input(e)) => {
                assert_eq!(e.field(), "gripper.fingers", "{n}: {e}");
                assert!(e.to_string().contains(says), "{n}: {e}");
            }
            other => panic!("{n}: {other:?}"),
        }
    }
    // by the chord: l sin(pi / n) >= Ly, here l >= 31.75 / sin(pi / 7)
    let g = Gripper::paper(0.25, 8, params(3)).unwrap();
    let need = 31.75 / (std::f64::consts::PI / 7.0).sin();
    let wide = GripperParams {
        fingers: 7,
        geometry: PalmSpec::Palm(need + 1e-9),
        ..GripperParams::default()
    };
    Gripper::new(g.finger().clone(), wide).unwrap();
    // twelve, the most, on a palm wide enough for them
    let twelve = GripperParams {
        fingers: 12,
        geometry: PalmSpec::Palm(31.75 / (std::f64::consts::PI / 12.0).sin() + 1e-6),
        ..GripperParams::default()
    };
    Gripper::new(g.finger().clone(), twelve).unwrap();
    let narrow = GripperParams {
        geometry: PalmSpec::Palm(need - 1e-6),
        ..wide
    };
    assert!(Gripper::new(g.finger().clone(), narrow).is_err());
}
