//! Target-solve errors: unreachable targets are typed errors naming them.

use super::*;

// ------------------------------------------------------------- target solves

#[test]
fn target_problems_are_checked() {
    let f = Finger::paper(0.25, 4).unwrap();
    let opts = SolveOptions::default();
    let rest = f.solve(&Load::unloaded(), &opts).unwrap();
    let good = TargetProblem {
        base: Load::unloaded(),
        direction: [1.0, 0.0],
        weights: [1.0, 0.0],
        target: rest.tip[0] + 1.0,
    };
    let k = rest.coefficients.clone();
    // the good problem solves
    let (sol, lambda) = Solver::new(&f)
        .solve_target(&good, &k, 0.0, 1e-9, &opts)
        .unwrap();
    assert!((sol.tip[0] - good.target).abs() < 1e-6 && lambda.is_finite());

    let run = |p: &TargetProblem, k: &Coefficients, lambda0: f64, ctol: f64, o: &SolveOptions| {
        input(Solver::new(&f).solve_target(p, k, lambda0, ctol, o))
    };
    let zero_rule = "the load direction and the target weights must not be zero";
    let e = run(
        &TargetProblem {
            direction: [0.0, 0.0],
            ..good
        },
        &k,
        0.0,
        1e-9,
        &opts,
    );
    inconsistent(&e, "target", zero_rule);
    let e = run(
        &TargetProblem {
            weights: [0.0, 0.0],
            ..good
        },
        &k,
        0.0,
        1e-9,
        &opts,
    );
    inconsistent(&e, "target", zero_rule);

    let cases = [
        (
            TargetProblem {
                target: f64::NAN,
                ..good
            },
            "target.value",
            f64::NAN,
        ),
        (
            TargetProblem {
                direction: [f64::NAN, 1.0],
                ..good
            },
            "target.direction[0]",
            f64::NAN,
        ),
        (
            TargetProblem {
                weights: [0.0, f64::INFINITY],
                ..good
            },
            "target.weights[1]",
            f64::INFINITY,
        ),
        (
            TargetProblem {
                base: tip(f64::NAN, 0.0),
                ..good
            },
            "load.fx",
            f64::NAN,
        ),
    ];
    for (p, field, value) in cases {
        names(
            &run(&p, &k, 0.0, 1e-9, &opts),
            field,
            value,
            "must be finite",
        );
    }
    let e = run(
        &TargetProblem {
            base: Load {
                kappa: 0.0,
                ..Load::default()
            },
            ..good
        },
        &k,
        0.0,
        1e-9,
        &opts,
    );
    names(&e, "load.kappa", 0.0, "must be positive");

    let e = run(&good, &k, f64::NAN, 1e-9, &opts);
    names(&e, "target.lambda0", f64::NAN, "must be finite");
    let e = run(&good, &k, f64::INFINITY, 1e-9, &opts);
    names(&e, "target.lambda0", f64::INFINITY, "must be finite");
    for ctol in [0.0, -1e-9] {
        names(
            &run(&good, &k, 0.0, ctol, &opts),
            "target.ctol_mm",
            ctol,
            "must be positive",
        );
    }
    names(
        &run(&good, &k, 0.0, f64::NAN, &opts),
        "target.ctol_mm",
        f64::NAN,
        "must be finite",
    );
    let bad_opts = SolveOptions { rtol: 0.0, ..opts };
    names(
        &run(&good, &k, 0.0, 1e-9, &bad_opts),
        "solve.rtol",
        0.0,
        "must be positive",
    );

    // the guess: one finite coefficient set per element
    names(
        &run(
            &good,
            &Coefficients::new(4, k.as_slice()[..12].to_vec()).unwrap(),
            0.0,
            1e-9,
            &opts,
        ),
        "guess",
        3.0,
        "must hold one set of 4 coefficients per element (4); it holds 3 of 4",
    );
    let mut nan = k.clone();
    nan.as_mut_slice()[4] = f64::NAN;
    names(
        &run(&good, &nan, 0.0, 1e-9, &opts),
        "guess",
        f64::NAN,
        "must be finite",
    );
}
