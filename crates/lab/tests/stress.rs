//! The numerical stress test (`fpc_lab::stress`): a light debug run must find
//! no panics and no silently wrong answers, and the case generator must be
//! deterministic and stay inside its documented ranges.

use std::time::Duration;

use fpc_lab::{
    stress_inputs, stress_with, StressConfig, StressOutcome, MAX_DRAWS, RESIDUAL_LIMIT,
    STRESS_ELEMENT_COUNTS,
};

#[test]
fn light_run_has_no_panics_and_no_silently_wrong_answers() {
    // small element counts keep the debug build well inside the budget
    let config = StressConfig {
        max_elements: 16,
        ..StressConfig::new(7, 24, Duration::from_secs(20))
    };
    let mut calls = 0;
    let report = stress_with(&config, |done, total| {
        calls += 1;
        assert_eq!(total, 24);
        assert_eq!(done, calls);
    });
    assert!(report.cases_run() >= 1);
    assert_eq!(calls, report.cases_run());
    for c in &report.cases {
        assert!(
            !c.outcome.is_bug(),
            "case {}: {} | {}",
            c.index,
            c.outcome,
            c.inputs
        );
        assert!(c.inputs.elements <= 16);
        if c.outcome == StressOutcome::Converged {
            let r = c
                .residual
                .expect("a converged case has a recomputed residual");
            assert!(r <= RESIDUAL_LIMIT, "case {}: residual {r}", c.index);
        }
    }
    assert_eq!(report.panics(), 0);
    assert_eq!(report.silently_wrong(), 0);
    assert_eq!(
        report.converged() + report.failed() + report.rejected() + report.bugs(),
        report.cases_run()
    );
    let by_reason: usize = report.failed_by_reason().values().sum();
    assert_eq!(by_reason, report.failed());
}

#[test]
fn generator_is_deterministic_for_a_seed() {
    for index in 0..50 {
        assert_eq!(stress_inputs(3, index, 128), stress_inputs(3, index, 128));
    }
    let a: Vec<_> = (0..20).map(|i| stress_inputs(3, i, 128).0).collect();
    let b: Vec<_> = (0..20).map(|i| stress_inputs(4, i, 128).0).collect();
    assert_ne!(a, b, "another seed draws other cases");
    // a run draws exactly these inputs, whatever the budget
    let config = StressConfig {
        max_elements: 4,
        ..StressConfig::new(11, 5, Duration::from_secs(20))
    };
    let report = stress_with(&config, |_, _| {});
    for c in &report.cases {
        let (inputs, rejected) = stress_inputs(11, c.index, 4);
        assert_eq!(c.inputs, inputs);
        assert_eq!(c.rejected_draws, rejected);
    }
}

#[test]
fn draws_stay_in_their_ranges() {
    for index in 0..400 {
        let (i, rejected) = stress_inputs(5, index, 128);
        assert!(rejected < MAX_DRAWS);
        assert!((0.01..=0.6).contains(&i.eps0), "eps0 {}", i.eps0);
        assert!((0.0..=600.0).contains(&i.pressure_kpa));
        assert!((-3.0..=10.0).contains(&i.fx));
        assert!((-5.0..=5.0).contains(&i.fz));
        assert!(STRESS_ELEMENT_COUNTS.contains(&i.elements));
        assert_eq!(i.lengths.len(), i.elements);
        let sum: f64 = i.lengths.iter().sum();
        assert!((sum - i.geometry.lx).abs() <= 1e-9 * i.geometry.lx);
        assert!(i.length_ratio >= 1.0 && i.length_ratio <= 100.0 * (1.0 + 1e-12));
        assert!((0.3..=3.0).contains(&i.thickness_scale));
        for f in i.lamina_factors {
            assert!((0.5..=2.0).contains(&f));
        }
    }
    // the cap on N holds
    for index in 0..100 {
        assert!(stress_inputs(5, index, 3).0.elements <= 3);
    }
}
