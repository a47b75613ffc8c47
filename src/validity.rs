//! Where an answer leaves the model's assumptions (docs/model.md section 8).
//!
//! The discrete CCM equations can be solved far outside the range where
//! they predict anything: an element turned past its small-slope limit, a
//! strain the laminate theory or the fitted law does not cover, a finger
//! whose surfaces meet, a laminate too thick to be a plate. A solution keeps
//! its answer and says so, with one [`Warning`] per finding (the worst
//! sample of each element, per kind; the closest approach for self
//! contact).
//!
//! Here: the limits, the laminate's thickness check and the per-element
//! check (`check`) with its bound on the tangent's turning. The scan of
//! the elements' check points runs in vector lanes (`scan`); the
//! self-contact search (`contact`) runs only where the finger turns far
//! enough, after the clearance proof (`clearance`).

use std::f64::consts::{FRAC_PI_2, PI};

use crate::element::walk::{approx_slack, Walk};
use crate::element::{self, Element};
use crate::error::{StripDimension, Warning};
use crate::model::Kinematics;

mod clearance;
mod contact;
mod scan;

pub(crate) use contact::contact_turning;
use contact::self_contact;
#[cfg(test)]
pub(crate) use contact::{proof_and_search, proof_pieces};
pub use contact::{CONTACT_SPACING, MAX_CONTACT_SAMPLES};
use scan::{scan, Extremes, ScanRules, SCAN_LANES};

/// What the checks read of a finger besides its elements: the laminate's
/// cross-section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Laminate {
    /// The prestressed layer's z range (mm).
    pub pemc_z: (f64, f64),
    /// The prestressed layer's prestrain.
    pub eps0: f64,
    /// The total thickness H (mm; self contact).
    pub thickness: f64,
}

/// The CCM's small-slope limit: `|dw/dx| < 1` in the element's frame, a
/// tangent turned at most 45 degrees from the element's root tangent.
pub const SLOPE_LIMIT_DEG: f64 = 45.0;

/// Largest mid-plane axial strain (magnitude) of the small-strain laminate
/// theory (von Karman kinematics, linear laminae).
pub const MIDPLANE_STRAIN_LIMIT: f64 = 0.20;

/// The range of the prestressed layer's own strain `s = eps0 + eps_x` that
/// the uniaxial fit of its law covers.
pub const PRESTRESSED_STRAIN_RANGE: (f64, f64) = (0.0, 0.6);

/// Largest thickness-to-length ratio `H / Lx` of classical laminate theory
/// (the strip at least ten thicknesses long; docs/model.md section 8).
pub const THICKNESS_TO_LENGTH_LIMIT: f64 = 0.1;

/// Largest thickness-to-width ratio `H / Ly` of classical laminate theory
/// (the strip at least two thicknesses wide; docs/model.md section 8).
pub const THICKNESS_TO_WIDTH_LIMIT: f64 = 0.5;

/// Allowance (rad, 10 degrees) for the tangent turning further between the
/// check points than at them: the contact search runs once the turning
/// seen at the check points exceeds [`contact_turning`] less this.
const TURNING_ALLOWANCE: f64 = 10.0 * PI / 180.0;

/// The thickness findings of a strip `h` thick, `lx` long and `ly` wide:
/// the laminate too thick against its length or its width for classical
/// laminate theory.
pub(crate) fn thickness(h: f64, lx: f64, ly: f64) -> Vec<Warning> {
    [
        (StripDimension::Length, lx, THICKNESS_TO_LENGTH_LIMIT),
        (StripDimension::Width, ly, THICKNESS_TO_WIDTH_LIMIT),
    ]
    .into_iter()
    .filter(|&(_, extent, limit)| h / extent > limit)
    .map(|(dimension, extent, limit)| Warning::ThicknessRatio {
        dimension,
        thickness: h,
        extent,
        limit,
    })
    .collect()
}

/// The findings of state `k` (raw coefficients) of a finger of `elements`
/// with the cross-section `laminate`, checking each
/// element at `samples` points (`x = L/samples .. L`, and the root), with
/// the tip and the end tangent's angle (rad, the sum of the elements'
/// turns, from one `atan2`: [`Walk::end_angle`]), which the check walks
/// to anyway: the tip the same bits as [`element::walk::walk`]'s.
///
/// Cheap on purpose (it runs after every solve): the slope test compares
/// the tangent's components (an angle is computed only for an element that
/// fails); the turning test takes the roots' angles from cheap approximate
/// turns and bounds on `atan`, and the exact `atan2` of every element only
/// where those leave it undecided; and the self-contact
/// search, which only runs past about 100 degrees of turning, samples the
/// mid-plane at H / 16 and compares only blocks of samples whose bounding
/// boxes come within H of each other.
pub(crate) fn check<M: Kinematics>(
    elements: &[Element<M>],
    laminate: &Laminate,
    k: &[f64],
    samples: usize,
) -> (Vec<Warning>, [f64; 2], f64) {
    let samples = samples.max(1);
    let mut out = Vec::new();
    let (pz0, pz1) = laminate.pemc_z;
    let eps0 = laminate.eps0;
    let (slo, shi) = PRESTRESSED_STRAIN_RANGE;
    let limit_tan = SLOPE_LIMIT_DEG.to_radians().tan();
    // each element's root angle and the range of dz/dx over its check
    // points, for the tangent's angle range, and whether that range is
    // known (every tangent points forwards in its element's frame)
    let mut turns = Vec::with_capacity(elements.len());
    let mut turn_known = true;
    let mut stretch = Vec::with_capacity(elements.len());
    // the walk to the tip, and the sum of the elements' approximate turns:
    // each element's root angle within `approx_slack` of the exact sum
    let mut walk = Walk::new();
    let mut approx = 0.0;
    let rules = ScanRules {
        samples,
        z: [pz0, pz1],
        eps0,
        limit_tan,
    };
    // one pass without branches on the findings, over SCAN_LANES elements
    // at a time: the extremes of what the checks compare; an element past
    // a limit is scanned again for its warning's value (rare)
    let scanned = (0..elements.len())
        .step_by(SCAN_LANES)
        .flat_map(|first| scan::<M>(elements, k, first, rules));
    for ((i, e), extremes) in elements.iter().enumerate().zip(scanned) {
        let ki = element::coeffs::<M>(k, i);
        let l = e.length();
        let Extremes {
            steep,
            forward,
            r: (rlo, rhi),
            stretch: most_stretch,
            mid: most_mid,
            pre: (slo_seen, shi_seen),
            frame,
            turn,
        } = extremes;
        turn_known &= forward;
        // (NaN strains are dropped by both the extremes and the scan)
        let (mid, pre) = if most_mid > MIDPLANE_STRAIN_LIMIT || slo_seen < slo || shi_seen > shi {
            strain_extremes::<M>(&ki, l, samples, [pz0, pz1], eps0)
        } else {
            ((0.0, 0.0), None)
        };
        if steep {
            // the angle, only for an element that breaks the limit
            let most = (1..=samples)
                .map(|j| {
                    let [dx, dz] = M::tangent(&ki, l * j as f64 / samples as f64);
                    dz.atan2(dx).abs()
                })
                .fold(0.0f64, f64::max);
            out.push(Warning::ElementSlope {
                element: i,
                degrees: most.to_degrees(),
                limit: SLOPE_LIMIT_DEG,
            });
        }
        if mid.0 > MIDPLANE_STRAIN_LIMIT {
            out.push(Warning::MidplaneStrain {
                element: i,
                strain: mid.1,
                limit: MIDPLANE_STRAIN_LIMIT,
            });
        }
        if let Some((_, s)) = pre {
            out.push(Warning::PrestressedStrain {
                element: i,
                strain: s,
                range: PRESTRESSED_STRAIN_RANGE,
            });
        }
        // the tangent's angle is theta + atan(dz/dx) at each check point,
        // with theta the root's angle (here within the turning's slack)
        if rlo <= rhi {
            turns.push([approx, rlo, rhi]);
        } else {
            turn_known = false;
        }
        // (the square root is monotone: the root of the largest square is
        // the largest root, bit for bit)
        stretch.push(most_stretch.sqrt());
        walk.step(frame);
        approx += turn;
    }
    let limit = contact_turning() - TURNING_ALLOWANCE;
    let beyond = !turn_known
        || turns_bounded(&turns, limit, approx_slack(elements.len())).unwrap_or_else(|| {
            // the roots' angles exactly (as the sum of the elements' atan2;
            // with every turn known, `turns` has one entry per element)
            let mut theta = 0.0;
            for (i, e) in elements.iter().enumerate() {
                turns[i][0] = theta;
                theta += e.end(&element::coeffs::<M>(k, i))[2];
            }
            turns_beyond(&turns, limit)
        });
    if beyond {
        out.extend(self_contact(elements, laminate.thickness, k, &stretch));
    }
    (out, walk.tip, walk.end_angle(approx))
}

/// The mid-plane strain of the largest magnitude at element `ki`'s check
/// points (magnitude, value; the first of equals) and the prestressed
/// layer's strain (at heights `z`) farthest outside
/// [`PRESTRESSED_STRAIN_RANGE`] (distance, value), if any.
fn strain_extremes<M: Kinematics>(
    ki: &M::Coeffs,
    l: f64,
    samples: usize,
    z: [f64; 2],
    eps0: f64,
) -> ((f64, f64), Option<(f64, f64)>) {
    let (slo, shi) = PRESTRESSED_STRAIN_RANGE;
    let mut mid: (f64, f64) = (0.0, 0.0);
    let mut pre: Option<(f64, f64)> = None;
    for j in 0..=samples {
        let x = l * j as f64 / samples as f64;
        let m = M::strain(ki, x, 0.0);
        if m.abs() > mid.0 {
            mid = (m.abs(), m);
        }
        for z in z {
            let s = eps0 + M::strain(ki, x, z);
            let by = (slo - s).max(s - shi);
            if by > 0.0 && pre.is_none_or(|(b, _)| by > b) {
                pre = Some((by, s));
            }
        }
    }
    (mid, pre)
}

/// Whether the range of the tangent's angle, `theta + atan(r)` for each
/// element's `[theta, r_lo, r_hi]` of `turns` together with the root's 0,
/// exceeds `limit`, where cheap bounds on `atan` settle it (`x / (1 + x^2)
/// <= atan x <= x` for `x >= 0`, and odd) with a margin far above
/// rounding, so that the answer is the one the `atan` of every element
/// gives; `None` where they do not. Each `theta` may be off the exact root
/// angle by up to `slack` (rad; 0 for exact angles), which widens the
/// margin.
fn turns_bounded(turns: &[[f64; 3]], limit: f64, slack: f64) -> Option<bool> {
    // (an infinite slope makes the quotient NaN, which max and min drop
    // for the bound 0)
    let below = |x: f64| {
        if x >= 0.0 {
            (x / (1.0 + x * x)).max(0.0)
        } else {
            x.max(-FRAC_PI_2)
        }
    };
    let above = |x: f64| {
        if x >= 0.0 {
            x.min(FRAC_PI_2)
        } else {
            (x / (1.0 + x * x)).min(0.0)
        }
    };
    // each root's angle off by up to `slack` moves the range by twice it
    let margin = TURN_BOUND_MARGIN + 2.0 * slack;
    if turn_range(turns, above, below) <= limit - margin {
        Some(false)
    } else if turn_range(turns, below, above) > limit + margin {
        Some(true)
    } else {
        None
    }
}

/// The range of the tangent's angle over `turns` and the root, with each
/// element's `atan` at its largest slope taken as `hi` and at its smallest
/// as `lo` (bounds, or `atan` itself).
fn turn_range(turns: &[[f64; 3]], hi: impl Fn(f64) -> f64, lo: impl Fn(f64) -> f64) -> f64 {
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for &[theta, rlo, rhi] in turns {
        a = a.min(theta + lo(rlo));
        b = b.max(theta + hi(rhi));
    }
    b - a
}

/// [`turns_bounded`] where the bounds decide, else every element's `atan`.
fn turns_beyond(turns: &[[f64; 3]], limit: f64) -> bool {
    turns_bounded(turns, limit, 0.0)
        .unwrap_or_else(|| turn_range(turns, f64::atan, f64::atan) > limit)
}

/// How far (rad) the bounds of [`turns_bounded`] must clear the limit to
/// decide without `atan`: far above the rounding of a sum of angles.
const TURN_BOUND_MARGIN: f64 = 1e-9;

/// For tests above this module: whether the lane scan of state `k` at
/// `samples` check points per element gives each element's extremes of a
/// plain scalar loop over that element alone, bit for bit.
#[cfg(test)]
pub(crate) fn scan_matches_elements<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    samples: usize,
    z: [f64; 2],
    eps0: f64,
) -> bool {
    let limit_tan = SLOPE_LIMIT_DEG.to_radians().tan();
    let rules = ScanRules {
        samples,
        z,
        eps0,
        limit_tan,
    };
    let bits = |e: &Extremes| {
        let f = [
            e.r.0, e.r.1, e.stretch, e.mid, e.pre.0, e.pre.1, e.frame[0], e.frame[1], e.frame[2],
            e.frame[3], e.turn,
        ]
        .map(f64::to_bits);
        (e.steep, e.forward, f)
    };
    (0..elements.len()).step_by(SCAN_LANES).all(|first| {
        let lanes = scan(elements, k, first, rules);
        elements[first..]
            .iter()
            .zip(&lanes)
            .enumerate()
            .all(|(l, (e, got))| {
                let ki = element::coeffs::<M>(k, first + l);
                let frame = e.frame(&ki);
                let xs = (0..=samples).map(|j| e.length() * j as f64 / samples as f64);
                let t: Vec<[f64; 2]> = xs.clone().map(|x| M::tangent(&ki, x)).collect();
                let ahead: Vec<f64> = t
                    .iter()
                    .filter(|t| t[0] > 0.0)
                    .map(|t| t[1] / t[0])
                    .collect();
                let strains = |z: f64| xs.clone().map(move |x| M::strain(&ki, x, z));
                let pre: Vec<f64> = z
                    .iter()
                    .flat_map(|&z| strains(z))
                    .map(|s| eps0 + s)
                    .collect();
                let max = |v: &mut dyn Iterator<Item = f64>| v.fold(f64::NEG_INFINITY, f64::max);
                let min = |v: &mut dyn Iterator<Item = f64>| v.fold(f64::INFINITY, f64::min);
                let want = Extremes {
                    steep: t[1..]
                        .iter()
                        .any(|t| !(t[0] > 0.0 && t[1].abs() <= limit_tan * t[0])),
                    forward: ahead.len() == t.len(),
                    r: (
                        min(&mut ahead.iter().copied()),
                        max(&mut ahead.iter().copied()),
                    ),
                    stretch: max(&mut t.iter().map(|t| t[0] * t[0] + t[1] * t[1])),
                    mid: max(&mut strains(0.0).map(f64::abs)),
                    pre: (min(&mut pre.iter().copied()), max(&mut pre.iter().copied())),
                    frame,
                    turn: element::walk::approx_atan2(frame[3], frame[2]),
                };
                bits(got) == bits(&want)
            })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The turning decision from the bounds on `atan`, where they give
    /// one, is the one the `atan` of every element gives, for limits just
    /// below, at and just above the range, and for slopes from 0 to
    /// infinite of both signs; and the bounds decide most cases a tenth of
    /// a radian or more from the limit, also with root angles known only
    /// within a slack.
    #[test]
    fn the_turning_decision_is_the_exact_one() {
        let direct = |turns: &[[f64; 3]]| {
            let (mut lo, mut hi) = (0.0f64, 0.0f64);
            for &[t, a, b] in turns {
                lo = lo.min(t + a.atan());
                hi = hi.max(t + b.atan());
            }
            hi - lo
        };
        let mut rng = fastrand::Rng::with_seed(17);
        let slopes = [0.0, 1e-300, 1e-8, 0.3, 1.0, 7.0, 1e10, 1e200, f64::INFINITY];
        // a case of small slopes (a finger within the slope limit) or of
        // any slopes
        let slope = |rng: &mut fastrand::Rng, small: bool| {
            if small {
                return (rng.f64() - 0.5) * 0.8;
            }
            let s = if rng.bool() {
                slopes[rng.usize(..slopes.len())]
            } else {
                (rng.f64() * 3.0).powi(3)
            };
            if rng.bool() {
                -s
            } else {
                s
            }
        };
        let (mut decided, mut decided_loose, mut far) = (0, 0, 0);
        for _ in 0..3000 {
            let n = rng.usize(1..30);
            let small = rng.bool();
            let mut theta = 0.0;
            let turns: Vec<[f64; 3]> = (0..n)
                .map(|_| {
                    let (a, b) = (slope(&mut rng, small), slope(&mut rng, small));
                    let t = [theta, a.min(b), a.max(b)];
                    theta += (rng.f64() - 0.3) * 0.6;
                    t
                })
                .collect();
            let range = direct(&turns);
            for limit in [
                range - 0.3,
                range - 1e-6,
                range - 1e-12,
                range,
                range + 1e-12,
                range + 1e-6,
                range + 0.3,
                1.587,
            ] {
                assert_eq!(
                    turns_beyond(&turns, limit),
                    range > limit,
                    "{turns:?} {limit}"
                );
                let bounded = turns_bounded(&turns, limit, 0.0);
                if let Some(b) = bounded {
                    assert_eq!(b, range > limit, "{turns:?} {limit}");
                }
                // root angles known only within a slack (the check's
                // approximate turns) decide the same where they decide
                let slack = [1e-6 * n as f64, 0.05][rng.usize(0..2)];
                let mut off = turns.clone();
                for t in &mut off {
                    t[0] += slack * (2.0 * rng.f64() - 1.0);
                }
                let loose = turns_bounded(&off, limit, slack);
                if let Some(b) = loose {
                    assert_eq!(b, range > limit, "{turns:?} {limit} {slack}");
                }
                if small && (range - limit).abs() >= 0.1 {
                    far += 1;
                    decided += usize::from(bounded.is_some());
                    decided_loose += usize::from(loose.is_some());
                }
            }
        }
        assert!(far >= 100 && decided * 10 >= far * 9, "{decided} of {far}");
        assert!(decided_loose * 10 >= far * 8, "{decided_loose} of {far}");
    }
}
