//! Accepted steps, events included, do not allocate.

use super::chain::*;
use super::snap::*;
use super::*;

// ------------------------------------------------------------ allocations

#[test]
fn accepted_steps_and_events_do_not_allocate() {
    // dense 1-D, dense n-D, semiseparable chain: a warm-up run, then the
    // same run counted (the Palc workspace and the problems exist already)
    let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
    let mut p = Dense::path(Snap::new());
    let mut tally = Tally {
        points: 0,
        events: 0,
        folds: 0,
    };
    palc.follow(
        &mut p,
        &[-1.3],
        -1.0,
        Direction::Increasing,
        Some(1.0),
        &mut tally,
    );
    let allocs = allocations_in(|| {
        let r = palc.follow(
            &mut p,
            &[-1.3],
            -1.0,
            Direction::Increasing,
            Some(1.0),
            &mut tally,
        );
        assert_eq!(r.termination, PathTermination::ReachedTarget);
    });
    assert_eq!(allocs, 0, "allocations in Palc::follow (1-D)");
    assert_eq!(tally.folds, 4);

    let m = chain(3, 8, 1);
    let dim = m.size();
    let x0 = vec![0.0; dim];
    let mut semi = SemiChain::new(m.clone());
    let mut palc = Palc::new(dim, PalcOptions::default()).unwrap();
    let mut tally = Tally {
        points: 0,
        events: 0,
        folds: 0,
    };
    palc.follow(
        &mut semi,
        &x0,
        0.0,
        Direction::Decreasing,
        Some(0.5),
        &mut tally,
    );
    let mut steps = 0;
    let allocs = allocations_in(|| {
        let r = palc.follow(
            &mut semi,
            &x0,
            0.0,
            Direction::Decreasing,
            Some(0.5),
            &mut tally,
        );
        assert_eq!(r.termination, PathTermination::ReachedTarget);
        steps = r.steps;
    });
    assert_eq!(allocs, 0, "allocations in Palc::follow (semiseparable)");
    assert!(steps > 5 && tally.folds == 2 && tally.events == 2);

    // a closure observer, dense chain
    let mut dense = Dense::path(m);
    let mut palc = Palc::new(dim, PalcOptions::default()).unwrap();
    let mut lowest = f64::INFINITY;
    let mut obs = |pt: &PathPoint<'_>| {
        lowest = lowest.min(pt.lambda);
        Control::Continue
    };
    palc.follow(
        &mut dense,
        &x0,
        0.0,
        Direction::Decreasing,
        Some(0.5),
        &mut obs,
    );
    let allocs = allocations_in(|| {
        palc.follow(
            &mut dense,
            &x0,
            0.0,
            Direction::Decreasing,
            Some(0.5),
            &mut obs,
        );
    });
    assert_eq!(allocs, 0, "allocations in Palc::follow (dense chain)");
    assert!(lowest < 0.0);
}
