//! The best grasping angle of a sphere found by brute force, independent
//! of the library's searches (tests/gripper.rs, tests/studies.rs).

use fpc::gripper::{grasping_angle_range, Gripper};

/// The best grasping angle of a sphere of radius `r`, found independently
/// of any search in the library: a dense scan of `m` angles, each an
/// ordinary grasp solved from rest, then, next to the best valid angle,
/// bisection of the validity switch to 1e-12 rad when a neighbour is not
/// valid, else golden sections of the lift to 1e-10 rad.
pub fn dense_best_angle(g: &Gripper, r: f64, m: usize) -> (f64, f64) {
    let [lo, hi] = grasping_angle_range(g.mu());
    let lift_at = |beta: f64| -> Option<f64> {
        let sg = g.sphere_grasp_at_friction_limit(0.0, r, beta, None).ok()?;
        sg.is_valid().then_some(sg.grasp.lift)
    };
    let betas: Vec<f64> = (0..m)
        .map(|i| lo + (hi - lo) * i as f64 / m as f64)
        .collect();
    let lifts: Vec<Option<f64>> = betas.iter().map(|&b| lift_at(b)).collect();
    let i = (0..m)
        .filter(|&i| lifts[i].is_some())
        .max_by(|&a, &b| lifts[a].unwrap().total_cmp(&lifts[b].unwrap()))
        .expect("a valid angle on the scan");
    let valid = |j: Option<usize>| j.and_then(|j| lifts.get(j).copied().flatten()).is_some();
    let (below, above) = (valid(i.checked_sub(1)), valid(Some(i + 1)));
    if below && above {
        let (mut a, mut c) = (betas[i - 1], betas[i + 1]);
        let k = 0.5 * (5f64.sqrt() - 1.0);
        while c - a > 1e-10 {
            let (x1, x2) = (c - k * (c - a), a + k * (c - a));
            if lift_at(x1).unwrap_or(f64::NEG_INFINITY) >= lift_at(x2).unwrap_or(f64::NEG_INFINITY)
            {
                c = x2;
            } else {
                a = x1;
            }
        }
        let b = 0.5 * (a + c);
        return (b, lift_at(b).expect("valid at the optimum"));
    }
    let mut good = betas[i];
    let mut bad = if above {
        betas[i - 1]
    } else {
        betas.get(i + 1).copied().unwrap_or(hi)
    };
    while (bad - good).abs() > 1e-12 {
        let mid = 0.5 * (good + bad);
        if lift_at(mid).is_some() {
            good = mid;
        } else {
            bad = mid;
        }
    }
    let lift = lift_at(good).expect("valid at the boundary");
    assert!(
        lift >= lifts[i].unwrap(),
        "the lift falls towards the boundary at r = {r}"
    );
    (good, lift)
}
