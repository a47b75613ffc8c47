//! Timing helpers of the bench binaries that print tables (`scaling`,
//! `sensitivity`): medians over repetitions sized to a time budget.

use std::time::Instant;

/// Median seconds of `f` over `reps` runs (after one warm-up run).
pub fn median_s(reps: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut t: Vec<f64> = (0..reps.max(1))
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// Repetitions for a run of about `estimate_s` seconds: half a second of
/// them (a twentieth with `--quick`), at least 3 and at most 2000.
pub fn reps(quick: bool, estimate_s: f64) -> usize {
    let budget = if quick { 0.05 } else { 0.5 };
    ((budget / estimate_s.max(1e-9)) as usize).clamp(3, 2000)
}
