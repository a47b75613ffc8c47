//! Refinement: second-order convergence on material partitions, Richardson
//! extrapolation, nested iteration and the tolerance-driven choice
//! (src/refine.rs), checked against independently computed sequences and
//! a fine N -> infinity reference.

use fpc::{
    refine, solve_to_tip_tolerance, Actuator, Coefficients, Finger, Load, ModelId, PartitionKind,
    Refinement, SolveError, SolveOptions,
};

fn tip_load() -> Load {
    Load::unloaded().with_tip_force(0.939782, 0.521707)
}

/// The solves' tolerance is tighter than the default: these tests compare
/// tips to 1e-6 mm, and a residual at the default `rtol` (1e-11) leaves
/// about that much tip error on 27 to 216 elements.
const RTOL: f64 = 1e-13;

fn opts() -> SolveOptions {
    SolveOptions {
        rtol: RTOL,
        ..SolveOptions::default().tip_only()
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn material(levels: usize, extrapolate: bool) -> Refinement {
    Refinement {
        model: ModelId::default(),
        partition: PartitionKind::Material,
        start: 8,
        levels,
        extrapolate,
    }
}

/// Tips of each level, every level solved cold and to full tolerance
/// (independent of the refinement's nested iteration and loosened levels).
fn cold_tips(plan: &Refinement, load: &Load, levels: usize) -> Vec<[f64; 2]> {
    let act = Actuator::default();
    (0..levels)
        .map(|l| {
            let part = plan.partition(&act, true, l).expect("a partition");
            let f = Finger::with_model(plan.model, &act, &part, true);
            f.solve(load, &opts()).expect("the level solves").tip
        })
        .collect()
}

/// Observed orders log2(|t1 - t0| / |t2 - t1|) of successive changes.
fn orders(tips: &[[f64; 2]]) -> Vec<f64> {
    tips.windows(3)
        .map(|w| (dist(w[1], w[0]) / dist(w[2], w[1])).log2())
        .collect()
}

#[test]
fn material_partitions_converge_at_second_order_and_equal_ones_at_first() {
    for load in [tip_load(), Load::unloaded().with_pressure_kpa(40.0)] {
        let m = orders(&cold_tips(&material(1, false), &load, 4));
        for p in &m {
            assert!((1.7..=2.3).contains(p), "material orders {m:?}");
        }
    }
    // equal elements: first order once they are shorter than the rib pitch
    // (coarser, and without a tip load, the rib edges falling in or out of
    // elements make the changes irregular)
    let equal = Refinement {
        partition: PartitionKind::Equal,
        start: 64,
        ..material(1, false)
    };
    let e = orders(&cold_tips(&equal, &tip_load(), 4));
    for p in &e {
        assert!((0.8..=1.2).contains(p), "equal orders {e:?}");
    }
}

#[test]
fn richardson_removes_the_leading_error() {
    let load = tip_load();
    // the reference: extrapolation of levels 108 and 216, solved cold
    let tips = cold_tips(&material(1, false), &load, 4);
    let r = |c: [f64; 2], f: [f64; 2]| [f[0] + (f[0] - c[0]) / 3.0, f[1] + (f[1] - c[1]) / 3.0];
    let reference = r(tips[2], tips[3]);
    let out = refine(
        &Actuator::default(),
        true,
        &load,
        &material(2, true),
        &opts(),
    )
    .unwrap();
    assert!(out.is_extrapolated());
    let fine = dist(out.solution.tip, reference);
    let extrapolated = dist(out.tip, reference);
    assert!(
        extrapolated * 10.0 <= fine,
        "extrapolated {extrapolated:e} mm vs fine {fine:e} mm"
    );
    // the estimate bounds the extrapolated tip's distance from the reference
    let est = out.estimated_tip_error_mm.unwrap();
    assert!(extrapolated <= est, "{extrapolated:e} > estimate {est:e}");
    // and agrees with the cold sequence's own extrapolation, although the
    // coarse level was solved to a looser tolerance (INTERMEDIATE_RTOL): it
    // moves the extrapolated tip by 2.5e-6 mm here, and 1e-5 mm is a
    // thousandth of the 0.01 mm this configuration is chosen for
    assert!(dist(out.tip, r(tips[0], tips[1])) <= 1e-5);
}

#[test]
fn nested_iteration_reaches_the_cold_equilibrium_in_fewer_iterations() {
    let act = Actuator::default();
    let load = tip_load();
    let plan = material(2, false);
    let coarse = Finger::with_model(
        plan.model,
        &act,
        &plan.partition(&act, true, 0).unwrap(),
        true,
    );
    let fine = Finger::with_model(
        plan.model,
        &act,
        &plan.partition(&act, true, 1).unwrap(),
        true,
    );
    let k = coarse.solve(&load, &opts()).unwrap().coefficients;
    let mut halves = Vec::new();
    for e in k.iter() {
        halves.extend_from_slice(e);
        halves.extend_from_slice(e);
    }
    let guess = Coefficients::new(k.per_element(), halves).unwrap();
    let warm = fine.solve_from(&load, &guess, &opts()).unwrap();
    let cold = fine.solve(&load, &opts()).unwrap();
    // both stop at a relative residual of 1e-11, which leaves ~1e-7 mm
    assert!(
        dist(warm.tip, cold.tip) <= 1e-6,
        "{:e}",
        dist(warm.tip, cold.tip)
    );
    assert!(
        warm.report.iterations < cold.report.iterations,
        "nested {} vs cold {} iterations",
        warm.report.iterations,
        cold.report.iterations
    );
    // the refinement does the same
    let out = refine(&act, true, &load, &plan, &opts()).unwrap();
    assert!(dist(out.tip, cold.tip) <= 1e-6);
    assert_eq!(out.levels[1].iterations, warm.report.iterations);
}

#[test]
fn the_tolerance_choice_meets_its_tolerance() {
    let act = Actuator::default();
    let load = tip_load();
    let tips = cold_tips(&material(1, false), &load, 4);
    let reference = [
        tips[3][0] + (tips[3][0] - tips[2][0]) / 3.0,
        tips[3][1] + (tips[3][1] - tips[2][1]) / 3.0,
    ];
    for tol in [1.0, 0.1, 0.01, 0.001] {
        let r = solve_to_tip_tolerance(ModelId::default(), &act, true, &load, tol, None, &opts())
            .unwrap();
        let est = r.estimated_tip_error_mm.unwrap();
        assert!(est <= tol, "tol {tol}: estimate {est:e}");
        let err = dist(r.tip, reference);
        assert!(err <= tol, "tol {tol}: {err:e} mm from the reference");
        let want = if tol >= fpc::EQUAL_PARTITION_TOLERANCE_MM {
            PartitionKind::Equal
        } else {
            PartitionKind::Material
        };
        assert_eq!(r.plan.partition, want, "tol {tol}");
        // the finest level is solved with the caller's options

        assert!(r.solution.report.residual_norm <= RTOL);
    }
}

#[test]
fn bad_plans_name_their_field() {
    let act = Actuator::default();
    let field = |plan: Refinement| match refine(&act, true, &tip_load(), &plan, &opts()) {
        Err(SolveError::Input(e)) => e.field().to_string(),
        other => panic!("expected an input error, got {other:?}"),
    };
    let base = material(2, false);
    assert_eq!(field(Refinement { levels: 0, ..base }), "refinement.levels");
    assert_eq!(field(Refinement { start: 0, ..base }), "refinement.start");
    assert_eq!(
        field(Refinement {
            levels: 1,
            extrapolate: true,
            ..base
        }),
        "refinement.extrapolate"
    );
    assert_eq!(
        field(Refinement {
            partition: PartitionKind::Equal,
            extrapolate: true,
            ..base
        }),
        "refinement.extrapolate"
    );
    // 27 * 2^6 > MAX_REFINED_ELEMENTS
    assert_eq!(field(Refinement { levels: 7, ..base }), "refinement.levels");
    assert!(PartitionKind::parse("partition", "bisected").is_err());
}
