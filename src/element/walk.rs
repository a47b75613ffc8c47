//! The elements of a finger chained from the clamp: each element's root
//! frame, the tip, and the end tangent's angle, by rotations and one
//! `atan2` per finger.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::{coeffs, Element};
use crate::model::Kinematics;

/// Each element's frame at its root: its position and (cos, sin) of its
/// angle, for the raw unknowns `k` of the chain of `elements` ([`walk`]).
pub(crate) fn frames<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
) -> Vec<([f64; 2], [f64; 2])> {
    let mut out = Vec::with_capacity(elements.len());
    walk(
        elements,
        |i| coeffs::<M>(k, i),
        |_, root, rot, _| out.push((root, rot)),
    );
    out
}

/// The chain of `elements` from the clamp to the tip, element `i` at its
/// unknowns `k(i)` (raw): calls `visit(i, root, rotation, end)` with the
/// element's root point, its root frame's `[cos, sin]` and its end point
/// (finger frame), and returns the tip. Chained by rotation, without
/// trigonometric calls.
#[inline(always)]
pub(crate) fn walk<M: Kinematics>(
    elements: &[Element<M>],
    k: impl Fn(usize) -> M::Coeffs,
    mut visit: impl FnMut(usize, [f64; 2], [f64; 2], [f64; 2]),
) -> [f64; 2] {
    let mut w = Walk::new();
    for (i, e) in elements.iter().enumerate() {
        let (root, rot) = (w.tip, w.rot);
        w.step(e.frame(&k(i)));
        visit(i, root, rot, w.tip);
    }
    w.tip
}

/// A walk along a chain of elements from the clamp: the point and the
/// rotation `[cos, sin]` reached so far, chained element by element from
/// each element's [`Element::frame`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Walk {
    /// The point reached (finger frame): the next element's root.
    pub tip: [f64; 2],
    /// The next element's root frame.
    pub rot: [f64; 2],
}

impl Walk {
    /// At the clamp.
    pub fn new() -> Walk {
        Walk {
            tip: [0.0, 0.0],
            rot: [1.0, 0.0],
        }
    }

    /// Past one element of frame `[Xe, Ze, cos eta, sin eta]`.
    #[inline(always)]
    pub fn step(&mut self, [xe, ze, ce, se]: [f64; 4]) {
        let [c, s] = self.rot;
        self.tip[0] += c * xe - s * ze;
        self.tip[1] += s * xe + c * ze;
        self.rot = [c * ce - s * se, s * ce + c * se];
    }

    /// The angle (rad) of the tangent at the walk's end, given the sum of
    /// the elements' [`approx_atan2`] of their turns: the one `atan2` of
    /// the chained rotation, on the branch nearest that sum; NaN if a turn
    /// was NaN. It is the sum of the elements' exact `atan2` within the
    /// rounding of the rotations, at the cost of one `atan2` per finger
    /// instead of one per element.
    pub fn end_angle(&self, approx: f64) -> f64 {
        let [c, s] = self.rot;
        let a = s.atan2(c);
        a + TAU * ((approx - a) / TAU).round()
    }
}

/// How far (rad) a sum of `n` [`approx_atan2`] may lie from the sum of
/// the exact ones (the rounding of the sum included).
pub(crate) fn approx_slack(n: usize) -> f64 {
    n as f64 * APPROX_ATAN2_ERROR * 1.01
}

/// The largest error (rad) of [`approx_atan2`], with a margin of at least
/// 10 over the largest error seen on a dense sweep (tested below).
pub(crate) const APPROX_ATAN2_ERROR: f64 = 1e-6;

/// `atan2(y, x)` to within [`APPROX_ATAN2_ERROR`], on the same branch
/// (`(-pi, pi]`, the sign from `y`'s sign bit as `atan2` takes it), NaN
/// for NaN; a polynomial in the ratio of the smaller component to the
/// larger (Abramowitz and Stegun 4.4.49, error 2e-8 on `[0, 1]`).
#[inline(always)]
pub(crate) fn approx_atan2(y: f64, x: f64) -> f64 {
    // (selects, not branches: the scan runs this in vector lanes)
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay > ax;
    let (num, den) = if steep { (ax, ay) } else { (ay, ax) };
    // atan2(+-0, +-0) is +-0 or +-pi: the ratio taken as 0
    let t = if den == 0.0 { 0.0 } else { num / den };
    let t2 = t * t;
    let p = [
        -0.333_331_452_8,
        0.199_935_508_5,
        -0.142_088_994_4,
        0.106_562_639_3,
        -0.075_289_640_0,
        0.042_909_613_8,
        -0.016_165_736_7,
        0.002_866_225_7,
    ];
    let a = t + t * t2 * p.iter().rev().fold(0.0, |acc, &c| acc * t2 + c);
    let a = if steep { FRAC_PI_2 - a } else { a };
    let a = if x.is_sign_negative() { PI - a } else { a };
    if y.is_sign_negative() {
        -a
    } else {
        a
    }
}

/// The tip and the end tangent's angle (rad) of the chain of `elements`
/// at raw unknowns `k` ([`Walk`]).
pub(crate) fn tip_and_end_angle<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
) -> ([f64; 2], f64) {
    let mut w = Walk::new();
    let mut approx = 0.0;
    for (i, e) in elements.iter().enumerate() {
        let f = e.frame(&coeffs::<M>(k, i));
        approx += approx_atan2(f[3], f[2]);
        w.step(f);
    }
    (w.tip, w.end_angle(approx))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `approx_atan2` stays within a tenth of the bound it claims of the
    /// library's `atan2` on a dense sweep of directions and magnitudes,
    /// and on the axes and signed zeros it takes `atan2`'s branch (an
    /// answer 2 pi off would send the chain's angle to another branch).
    #[test]
    fn the_approximate_atan2_keeps_its_bound_and_branch() {
        let mut worst = 0.0f64;
        let n = 400_000;
        for j in 0..=n {
            let phi = -PI + 2.0 * PI * j as f64 / n as f64;
            for r in [1e-300, 1e-3, 1.0, 7.5, 1e200] {
                let (y, x) = (r * phi.sin(), r * phi.cos());
                worst = worst.max((approx_atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst <= APPROX_ATAN2_ERROR / 10.0, "{worst}");
        for (y, x) in [
            (0.0, 1.0),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (1.0, -0.0),
            (-1.0, -0.0),
            (1e-310, -3.0),
            (-1e-310, -3.0),
        ] {
            let (got, want) = (approx_atan2(y, x), f64::atan2(y, x));
            assert!((got - want).abs() <= 1e-5, "({y}, {x}): {got} vs {want}");
        }
        assert!(approx_atan2(f64::NAN, 1.0).is_nan() && approx_atan2(1.0, f64::NAN).is_nan());
    }

    /// The walk's end angle from one `atan2` is the sum of the turns'
    /// `atan2` within rounding, for random chains of 1 to 1000 turns of
    /// every size up to a half turn (sums far past one revolution), and
    /// the approximate sum keeps within its slack of it.
    #[test]
    fn the_walks_end_angle_is_the_sum_of_the_turns() {
        let mut rng = fastrand::Rng::with_seed(23);
        let mut beyond = 0;
        for case in 0..2000 {
            let n = 1 + rng.usize(0..1000) * (case % 2) + rng.usize(0..8);
            let size = [1e-6, 0.05, 0.5, 3.1, PI][case % 5];
            let bias = (rng.f64() - 0.5) * size;
            let mut walk = Walk::new();
            let (mut sum, mut approx) = (0.0, 0.0);
            for i in 0..n {
                let phi = (bias + (rng.f64() - 0.5) * size).clamp(-PI, PI);
                let (c, s) = (phi.cos(), phi.sin());
                sum += s.atan2(c);
                approx += approx_atan2(s, c);
                walk.step([1.0, 0.0, c, s]);
                assert!((approx - sum).abs() <= approx_slack(i + 1), "case {case}");
            }
            let got = walk.end_angle(approx);
            assert!(
                (got - sum).abs() <= 1e-13 * n as f64 * sum.abs().max(1.0),
                "case {case}: {got} vs {sum}"
            );
            beyond += usize::from(sum.abs() > 2.0 * PI);
        }
        assert!(beyond > 200, "{beyond}");
        assert_eq!(Walk::new().end_angle(0.0), 0.0);
        let mut nan = Walk::new();
        nan.step([1.0, 0.0, f64::NAN, 0.0]);
        assert!(nan.end_angle(approx_atan2(0.0, f64::NAN)).is_nan());
    }
}
