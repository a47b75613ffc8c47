//! Solves that genuinely fail: `NotConverged` with the last iterate's diagnostics, no panic, no NaN.

use super::*;

// ------------------------------------------------------------ failed solves

#[test]
fn an_iteration_limit_reports_the_last_iterate() {
    let f = Finger::paper(0.25, 8).unwrap();
    let load = tip(1.0, 0.0);
    let opts = SolveOptions {
        max_iter: 1,
        continuation: false,
        ..SolveOptions::default()
    };
    // the unloaded start (decoupled, per element) already runs out
    let r = failed(
        "unloaded start",
        8,
        no_panic("solve", || f.solve(&load, &opts)),
    );
    assert_eq!(r.reason, Termination::MaxIterations);
    assert_eq!(r.iterations, 1);
    assert_eq!(r.element, Some(0));
    assert!(r.relative_residual.is_finite() && r.relative_residual > opts.rtol);
    assert!(
        r.message.contains("iteration limit reached"),
        "{}",
        r.message
    );

    // from the unloaded equilibrium, the coupled system runs out
    let rest = f
        .solve(&Load::unloaded(), &SolveOptions::default())
        .unwrap();
    let r = failed(
        "coupled",
        8,
        no_panic("solve_from", || {
            f.solve_from(&load, &rest.coefficients, &opts)
        }),
    );
    assert_eq!(r.reason, Termination::MaxIterations);
    assert_eq!((r.iterations, r.element), (1, None));
    assert!(r.relative_residual.is_finite() && r.relative_residual > opts.rtol);
    // the last iterate moved from the start towards the loaded equilibrium
    assert_ne!(r.last, rest.coefficients);
}

#[test]
fn loads_beyond_reach_fail_with_finite_diagnostics() {
    let f = Finger::paper(0.25, 8).unwrap();
    let opts = SolveOptions::default(); // continuation on
    for (what, load) in [
        ("fx = 1e6 N", tip(1e6, 0.0)),
        ("fz = 1e6 N", tip(0.0, 1e6)),
        ("fx = 1e300 N", tip(1e300, 0.0)),
        ("1e6 kPa", Load::unloaded().with_pressure_kpa(1e6)),
        ("1e300 MPa", Load::unloaded().with_pressure_kpa(1e303)),
    ] {
        let r = failed(what, 8, no_panic(what, || f.solve(&load, &opts)));
        // (which of these depends on the path Newton takes)
        assert!(
            matches!(
                r.reason,
                Termination::MaxIterations
                    | Termination::LineSearchFailed
                    | Termination::StepTolerance
                    | Termination::Singular
            ),
            "{what}: {}",
            r.message
        );
        assert!(r.relative_residual.is_finite(), "{what}: {}", r.message);
        assert!(r.relative_residual > opts.rtol, "{what}: {}", r.message);
        // a pressure alone decouples: the failure names its element
        assert_eq!(r.element.is_some(), !load.has_tip_load(), "{what}");
    }
}

#[test]
fn stalled_solves_are_failures() {
    let f = Finger::paper(0.25, 8).unwrap();
    let d = SolveOptions::default();
    // steps too small to get anywhere
    let tiny = SolveOptions {
        max_step: 1e-15,
        max_iter: 50,
        continuation: false,
        ..d
    };
    for (what, load, opts) in [
        ("tiny steps, unloaded", Load::unloaded(), tiny),
        ("tiny steps, tip load", tip(1.0, 0.0), tiny),
    ] {
        let r = failed(what, 8, no_panic(what, || f.solve(&load, &opts)));
        assert_eq!(
            r.reason,
            Termination::StepTolerance,
            "{what}: {}",
            r.message
        );
        assert!(r.message.contains("stalled"), "{what}: {}", r.message);
        assert!(r.relative_residual.is_finite(), "{what}");
    }
}

/// A tolerance below round-off could only stall: it is refused before any
/// work, naming the option (it was accepted, then failed as "stalled").
#[test]
fn a_tolerance_below_rounding_is_refused() {
    let f = Finger::paper(0.25, 8).unwrap();
    for rtol in [1e-300, 1e-30, 9e-17] {
        let opts = SolveOptions {
            rtol,
            ..SolveOptions::default()
        };
        for load in [Load::unloaded(), tip(0.5, 0.0)] {
            match f.solve(&load, &opts) {
                Err(SolveError::Input(e)) => {
                    assert_eq!(e.field(), "solve.rtol", "{rtol:e}: {e}");
                    assert!(e.to_string().contains("at least"), "{e}");
                }
                other => panic!("rtol {rtol:e}: {other:?}"),
            }
        }
    }
    // the bound itself is solved (the accuracy references use it)
    let opts = SolveOptions {
        rtol: 1e-16,
        ..SolveOptions::default()
    };
    assert!(f.solve(&Load::unloaded(), &opts).is_ok());
}

#[test]
fn a_guess_where_the_energy_overflows_fails_as_non_finite() {
    let f = Finger::paper(0.25, 8).unwrap();
    let guess = Coefficients::new(4, vec![1e200; 32]).unwrap();
    for (what, load) in [("decoupled", Load::unloaded()), ("coupled", tip(0.5, 0.0))] {
        let opts = SolveOptions {
            continuation: false,
            ..SolveOptions::default()
        };
        let r = failed(
            what,
            8,
            no_panic(what, || f.solve_from(&load, &guess, &opts)),
        );
        assert_eq!(r.reason, Termination::NonFinite, "{what}");
        assert_eq!(r.iterations, 0);
        assert!(r.message.contains("non-finite"), "{}", r.message);
        // nothing finite was evaluated: the residual is unknown (infinite,
        // never NaN) and the last iterate is the guess itself
        assert_eq!(r.relative_residual, f64::INFINITY);
        assert_eq!(r.last, guess);
    }
    // a huge but not overflowing guess runs out of iterations instead
    let r = failed(
        "1e3 guess",
        8,
        f.solve_from(
            &Load::unloaded(),
            &Coefficients::new(4, vec![1e3; 32]).unwrap(),
            &SolveOptions::default(),
        ),
    );
    assert!(
        matches!(
            r.reason,
            Termination::MaxIterations | Termination::LineSearchFailed
        ),
        "{}",
        r.message
    );
    assert!(r.relative_residual.is_finite());
}

#[test]
fn target_solves_fail_with_the_bordered_solver_s_reason() {
    let f = Finger::paper(0.25, 8).unwrap();
    let opts = SolveOptions::default();
    let rest = f.solve(&Load::unloaded(), &opts).unwrap();
    let k = &rest.coefficients;
    let base = TargetProblem {
        base: Load::unloaded(),
        direction: [1.0, 0.0],
        weights: [1.0, 0.0],
        target: rest.tip[0] + 1.0,
    };
    let cases = [
        // a tip X no finite force reaches
        (
            "tip X = 1e4 mm",
            TargetProblem {
                target: 1e4,
                ..base
            },
            0.0,
            1e-9,
            opts,
            &[Termination::MaxIterations, Termination::LineSearchFailed][..],
        ),
        // a load parameter so large the bordered matrix has no usable pivot
        (
            "lambda0 = 1e300",
            base,
            1e300,
            1e-9,
            opts,
            // which check trips first depends on round-off in the chain terms
            &[
                Termination::Singular,
                Termination::LineSearchFailed,
                Termination::NonFinite,
            ],
        ),
        // the target equation's scale overflows the merit function
        (
            "weights 1e300",
            TargetProblem {
                weights: [1e300, 0.0],
                ..base
            },
            0.0,
            1e-9,
            opts,
            &[Termination::LineSearchFailed],
        ),
        (
            "target 1e300 mm",
            TargetProblem {
                target: 1e300,
                ..base
            },
            0.0,
            1e-9,
            opts,
            &[Termination::NonFinite],
        ),
        (
            "max_iter 1",
            base,
            0.0,
            1e-9,
            SolveOptions {
                max_iter: 1,
                ..opts
            },
            &[Termination::MaxIterations],
        ),
    ];
    for (what, p, lambda0, ctol, o, reasons) in cases {
        let r = no_panic(what, || {
            Solver::new(&f).solve_target(&p, k, lambda0, ctol, &o)
        });
        let r = failed(what, 8, r);
        assert!(reasons.contains(&r.reason), "{what}: {}", r.message);
        assert_eq!(r.element, None, "{what}");
        assert!(r.relative_residual.is_finite(), "{what}: {}", r.message);
    }
    // a target tolerance below round-off: met exactly (the refined step can
    // land on the target to the last bit), or a stall, never a wrong answer
    let tol = 1e-300;
    match no_panic("ctol 1e-300", || {
        Solver::new(&f).solve_target(&base, k, 0.0, tol, &opts)
    }) {
        Ok((sol, _)) => assert!((sol.tip[0] - base.target).abs() <= tol, "{:?}", sol.tip),
        Err(e) => {
            let r = failed("ctol 1e-300", 8, Err::<(), _>(e));
            assert_eq!(r.reason, Termination::StepTolerance);
        }
    }
}

#[test]
fn an_unreachable_grasp_is_a_typed_error_naming_the_target() {
    let g = Gripper::paper(0.25, 8, GripperParams::default()).unwrap();
    // wider than the flat fingers: rejected before any solve
    match no_panic("1e4 mm", || g.grasp_load_for_size(0.0, 1e4, 0.0, None)) {
        Err(SolveError::Input(e)) => {
            assert_eq!(e.field(), "grasp.size");
            assert!(e.to_string().contains("exceeds d_max"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    // closed far past the fingers' reach: the path from rest turns back
    // (pulled inwards, the finger cannot come closer to the axis) short of
    // the target
    match no_panic("-1e4 mm", || g.grasp_load_for_size(0.0, -1e4, 0.0, None)) {
        Err(e @ SolveError::NotOnPath { .. }) => {
            let msg = one_line(&e);
            let SolveError::NotOnPath { target, value, .. } = e else {
                unreachable!()
            };
            assert_eq!((target, value), (fpc::Field::GraspSize, -1e4));
            assert!(msg.starts_with("grasp.size = -10000: not reached"), "{msg}");
            assert!(msg.contains("turns back at grasp size"), "{msg}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn extreme_loads_that_do_solve_give_finite_solutions() {
    let f = Finger::paper(0.25, 8).unwrap();
    for (what, load) in [
        ("fz = -1e3 N", tip(0.0, -1e3)),
        ("fx = -1e3 N", tip(-1e3, 0.0)),
        ("fz = 50 N", tip(0.0, 50.0)),
        ("-100 kPa", Load::unloaded().with_pressure_kpa(-100.0)),
    ] {
        let s = no_panic(what, || f.solve(&load, &SolveOptions::default()))
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_finite_solution(what, &s);
    }
}
