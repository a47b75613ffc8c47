//! Unit tests of the front, the orders and the extrapolation.

use super::reference::{order, richardson_table, terms};
use super::*;

fn row(time_us: f64, error: f64) -> AccuracyRow {
    let plan = Refinement::equal(ModelId::default(), 8);
    AccuracyRow {
        label: plan.label(),
        plan,
        elements: 8,
        elements_per_level: vec![8],
        iterations: vec![6],
        tip: [0.0; 2],
        error_vs_ccm_mm: error,
        error_vs_own_mm: error,
        estimated_error_mm: None,
        time_us,
        rounds_us: vec![time_us],
        runs: 1,
        time_over_n8: 1.0,
        pareto: false,
    }
}

#[test]
fn the_front_keeps_the_undominated_rows_fastest_first() {
    let mut rows = vec![
        row(10.0, 1.0),
        row(5.0, 2.0),
        row(20.0, 0.1),
        row(15.0, 1.0), // dominated by the first
        row(10.0, 1.0), // a tie: neither dominates
        row(30.0, f64::NAN),
    ];
    let front = pareto(&mut rows);
    let on: Vec<usize> = front.iter().map(|f| f.row).collect();
    assert_eq!(on, [1, 0, 4, 2]);
    assert_eq!(
        rows.iter().map(|r| r.pareto).collect::<Vec<_>>(),
        [true, true, true, false, true, false]
    );
}

#[test]
fn a_slightly_slower_more_accurate_row_dominates() {
    let mut rows = vec![
        row(10.0, 1.0),
        row(10.2, 0.5),
        row(5.0, 2.0),
        row(10.6, 0.4),
    ];
    let front = pareto(&mut rows);
    let on: Vec<usize> = front.iter().map(|f| f.row).collect();
    assert_eq!(on, [2, 1, 3]);
    let best = fastest_row(&rows, |r| r.error_vs_ccm_mm <= 1.0).unwrap();
    assert_eq!(best.row, 1, "within the resolution the more accurate");
    assert!(fastest_row(&rows, |r| r.error_vs_ccm_mm < 0.1).is_none());
}

#[test]
fn orders_and_extrapolation() {
    assert!((order(4.0, 1.0) - 2.0).abs() < 1e-15);
    assert!(order(0.0, 1.0).is_nan());
    // exact for t(h) = t* + c1 h + ... + c4 h^4 with h halving
    let t = |h: f64| {
        [
            1.0 + 0.5 * h + 3.0 * h * h - 2.0 * h.powi(3) + h.powi(4),
            -2.0 - 0.1 * h - h * h + 0.3 * h.powi(4),
        ]
    };
    let tips: Vec<[f64; 2]> = (0..5).map(|k| t(0.4 / 2f64.powi(k))).collect();
    let limit = richardson_table(&tips, &[1, 2, 3, 4]);
    assert!(dist(limit, [1.0, -2.0]) < 1e-13, "{limit:?}");
    // a second-order sequence needs only its h^2 term removed
    let r = richardson_table(&[[1.0 + 3.0 * 0.04, 0.0], [1.0 + 3.0 * 0.01, 0.0]], &[2]);
    assert!(dist(r, [1.0, 0.0]) < 1e-14);
    // the terms at the finest level (h = 0.025)
    let got = terms(&tips, limit);
    let h: f64 = 0.025;
    let want = [
        [0.5 * h, -0.1 * h],
        [3.0 * h * h, -h * h],
        [-2.0 * h.powi(3), 0.0],
        [h.powi(4), 0.3 * h.powi(4)],
    ];
    for (g, w) in got.iter().zip(&want) {
        assert!(dist(*g, *w) < 1e-12, "{got:?}");
    }
    let mut v = [3.0, 1.0, 2.0];
    assert_eq!(median(&mut v), 2.0);
}
