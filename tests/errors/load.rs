//! Load and solver-option errors.

use super::*;

// ------------------------------------------------------------ load, options

#[test]
fn loads_must_be_finite_and_kappa_positive() {
    let f = Finger::paper(0.25, 4).unwrap();
    let d = Load::default();
    let cases = [
        (
            Load {
                pressure: f64::NAN,
                ..d
            },
            "load.pressure",
            f64::NAN,
            "must be finite",
        ),
        (
            Load {
                pressure: f64::NEG_INFINITY,
                ..d
            },
            "load.pressure",
            f64::NEG_INFINITY,
            "must be finite",
        ),
        (
            Load {
                pressure: -0.2,
                ..d
            },
            "load.pressure",
            -0.2,
            "is below absolute vacuum (-101.325 kPa gauge)",
        ),
        (
            Load { kappa: 0.0, ..d },
            "load.kappa",
            0.0,
            "must be positive",
        ),
        (
            Load { kappa: -2.5, ..d },
            "load.kappa",
            -2.5,
            "must be positive",
        ),
        (
            Load {
                kappa: f64::INFINITY,
                ..d
            },
            "load.kappa",
            f64::INFINITY,
            "must be finite",
        ),
        // a gas's gamma above 1.01: kappa = 1/(gamma - 1) at most 100
        (
            Load { kappa: 1e300, ..d },
            "load.kappa",
            1e300,
            "must be at most 100",
        ),
        (
            Load { kappa: 100.5, ..d },
            "load.kappa",
            100.5,
            "must be at most 100",
        ),
        (tip(f64::NAN, 0.0), "load.fx", f64::NAN, "must be finite"),
        (
            tip(0.5, f64::INFINITY),
            "load.fz",
            f64::INFINITY,
            "must be finite",
        ),
    ];
    let coupled = SolveOptions {
        strategy: Strategy::Coupled,
        ..SolveOptions::default()
    };
    for (load, field, value, rule) in cases {
        names(&load.validate().unwrap_err(), field, value, rule);
        for opts in [SolveOptions::default(), coupled] {
            names(&input(f.solve(&load, &opts)), field, value, rule);
        }
    }
    // suction and large finite loads are input the model accepts
    assert!(Load::unloaded().with_pressure_kpa(-10.0).validate().is_ok());
    assert!(tip(-1e6, 1e6).validate().is_ok());
    assert!(Load { kappa: 100.0, ..d }.validate().is_ok());
}

#[test]
fn solve_options_are_checked() {
    let f = Finger::paper(0.25, 4).unwrap();
    let d = SolveOptions::default();
    let cases = [
        (
            SolveOptions { rtol: 0.0, ..d },
            "solve.rtol",
            0.0,
            "must be positive",
        ),
        (
            SolveOptions { rtol: -1e-9, ..d },
            "solve.rtol",
            -1e-9,
            "must be positive",
        ),
        (
            SolveOptions { rtol: 1e-300, ..d },
            "solve.rtol",
            1e-300,
            "must be at least 1e-16",
        ),
        (
            SolveOptions {
                rtol: f64::NAN,
                ..d
            },
            "solve.rtol",
            f64::NAN,
            "must be finite",
        ),
        (
            SolveOptions { max_iter: 0, ..d },
            "solve.max_iter",
            0.0,
            "must lie in [1, 10000]",
        ),
        (
            SolveOptions {
                max_iter: fpc::finger::MAX_NEWTON_ITERATIONS + 1,
                ..d
            },
            "solve.max_iter",
            10_001.0,
            "must lie in [1, 10000]",
        ),
        (
            SolveOptions {
                samples_per_element: 0,
                ..d
            },
            "solve.samples_per_element",
            0.0,
            "must lie in [1, 4096] when the shape is sampled",
        ),
        (
            SolveOptions { max_step: 0.0, ..d },
            "solve.max_step",
            0.0,
            "must be positive",
        ),
        (
            SolveOptions {
                max_step: -0.25,
                ..d
            },
            "solve.max_step",
            -0.25,
            "must be positive",
        ),
        (
            SolveOptions {
                max_step: f64::NAN,
                ..d
            },
            "solve.max_step",
            f64::NAN,
            "must be finite",
        ),
    ];
    let loads = [
        Load::unloaded().with_pressure_kpa(20.0), // decoupled
        tip(0.5, 0.2),                            // coupled
    ];
    for (opts, field, value, rule) in cases {
        for load in loads {
            names(&input(f.solve(&load, &opts)), field, value, rule);
        }
    }
    // the samples in all are bounded too: 1000 elements at 66 each is
    // 66 000 points, past 65 536 (at 65 each, 65 000, within), on a fixed
    // finger and on nested levels alike
    let fine = Finger::paper(0.25, 1000).unwrap();
    let over = SolveOptions {
        samples_per_element: 66,
        ..d
    };
    names(
        &input(fine.solve(&Load::unloaded(), &over)),
        "solve.samples_per_element",
        66.0,
        "with 1000 elements gives 66000 mid-plane samples, more than 65536",
    );
    let within = SolveOptions {
        samples_per_element: 65,
        ..d
    };
    let s = fine.solve(&Load::unloaded(), &within).unwrap();
    assert_eq!(s.points.len(), 65 * 1000 + 1);
    let levels = fpc::PlannedFinger::builder(&fpc::Actuator::paper(0.25).unwrap())
        .plan(fpc::Plan::Levels {
            partition: fpc::plan::PartitionKind::Equal,
            start: 250,
            levels: 3,
            extrapolate: false,
        })
        .build()
        .unwrap();
    names(
        &input(levels.solve(&Load::unloaded(), &over).map(|s| s.solution)),
        "solve.samples_per_element",
        66.0,
        "with 1000 elements gives 66000 mid-plane samples, more than 65536",
    );
    // without shape sampling no samples are needed
    let tip_only = SolveOptions {
        samples_per_element: 0,
        ..d.tip_only()
    };
    for load in loads {
        let s = f.solve(&load, &tip_only).unwrap();
        assert!(s.points.is_empty());
        assert_finite_solution("tip only", &s);
    }
}

#[test]
fn guesses_must_be_finite() {
    let f = Finger::paper(0.25, 4).unwrap();
    let opts = SolveOptions::default();
    let mut guess = Coefficients::zeros(4, 4);
    guess.as_mut_slice()[4 * 2 + 3] = f64::NEG_INFINITY;
    for load in [Load::unloaded(), tip(0.5, 0.2)] {
        // the error shows the offending value
        names(
            &input(f.solve_from(&load, &guess, &opts)),
            "guess",
            f64::NEG_INFINITY,
            "must be finite",
        );
    }
    names(
        &input(f.solve_from(&Load::unloaded(), &Coefficients::zeros(3, 4), &opts)),
        "guess",
        3.0,
        "must hold one set of 4 coefficients per element (4); it holds 3 of 4",
    );
}
