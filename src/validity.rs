//! Where an answer leaves the model's assumptions (docs/model.md section 8).
//!
//! The discrete CCM equations can be solved far outside the range where
//! they predict anything: an element turned past its small-slope limit, a
//! strain the laminate theory or the fitted law does not cover, a finger
//! that passes through itself. A solution keeps its answer and says so,
//! with one [`Warning`] per finding (the worst sample of each element, per
//! kind).

use crate::error::Warning;
use crate::finger::FingerCore;
use crate::model::ElementModel;

/// The CCM's small-slope limit: `|dw/dx| < 1` in the element's frame, a
/// tangent turned at most 45 degrees from the element's root tangent.
pub const SLOPE_LIMIT_DEG: f64 = 45.0;

/// Largest mid-plane axial strain (magnitude) of the small-strain laminate
/// theory (von Karman kinematics, linear laminae).
pub const MIDPLANE_STRAIN_LIMIT: f64 = 0.20;

/// The range of the prestressed layer's own strain `s = eps0 + eps_x` that
/// the uniaxial fit of its law covers.
pub const PRESTRESSED_STRAIN_RANGE: (f64, f64) = (0.0, 0.6);

/// Total tangent turning (rad) below which a sampled mid-plane cannot cross
/// itself (its tangent stays inside an open half-plane, so its projection on
/// one direction is monotone); the pairwise segment test runs only above it.
const TURNING_FOR_CONTACT: f64 = std::f64::consts::PI - 0.05;

/// The findings of state `k` (raw coefficients) of `finger`, checking each
/// element at `samples` points (`x = L/samples .. L`, and the root), and
/// the end tangent's angle (rad, the sum of the elements' turns), which the
/// check needs anyway.
///
/// Cheap on purpose (it runs after every solve): the slope test compares
/// the tangent's components (an angle is computed only for an element that
/// fails); the tangent's turning comes from the element ends; and the
/// self-crossing test, which only runs past half a turn, compares only
/// elements whose bounding boxes overlap.
pub(crate) fn check<M: ElementModel>(
    finger: &FingerCore<M>,
    k: &[f64],
    samples: usize,
) -> (Vec<Warning>, f64) {
    let samples = samples.max(1);
    let mut out = Vec::new();
    let (pz0, pz1) = finger.pemc_z;
    let eps0 = finger.eps0;
    let (slo, shi) = PRESTRESSED_STRAIN_RANGE;
    let limit_tan = SLOPE_LIMIT_DEG.to_radians().tan();
    let mut theta_lo = 0.0f64;
    let mut theta_hi = 0.0f64;
    let mut theta = 0.0f64;
    for (i, e) in finger.elements.iter().enumerate() {
        let ki = FingerCore::<M>::element_coeffs(k, i);
        let l = e.length();
        let mut steep = false;
        let mut mid: (f64, f64) = (0.0, 0.0); // (|strain|, strain)
        let mut pre: Option<(f64, f64)> = None; // (distance outside, s)
        for j in 0..=samples {
            let x = l * j as f64 / samples as f64;
            if j > 0 {
                let [dx, dz] = M::tangent(&ki, x);
                steep |= !(dx > 0.0 && dz.abs() <= limit_tan * dx);
            }
            let m = M::strain(&ki, x, 0.0);
            if m.abs() > mid.0 {
                mid = (m.abs(), m);
            }
            for z in [pz0, pz1] {
                let s = eps0 + M::strain(&ki, x, z);
                let by = (slo - s).max(s - shi);
                if by > 0.0 && pre.is_none_or(|(b, _)| by > b) {
                    pre = Some((by, s));
                }
            }
        }
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
        // within an element that keeps its slope limit the tangent stays
        // within 45 degrees of the element's ends
        let eta = e.end(&ki)[2];
        let margin = if steep { std::f64::consts::PI } else { 0.0 };
        theta_lo = theta_lo.min(theta.min(theta + eta) - margin);
        theta_hi = theta_hi.max(theta.max(theta + eta) + margin);
        theta += eta;
    }
    if theta_hi - theta_lo > TURNING_FOR_CONTACT {
        let pts = finger.shape_raw(k, samples);
        if let Some((a, b)) = first_crossing_by_element(&pts, samples) {
            let element = |seg: usize| (seg / samples).min(finger.len() - 1);
            out.push(Warning::SelfContact {
                element: element(b),
                other: element(a),
            });
        }
    }
    (out, theta)
}

/// [`first_crossing`] for a polyline of `per` segments per element: only
/// the segments of elements whose bounding boxes overlap are compared.
fn first_crossing_by_element(pts: &[[f64; 2]], per: usize) -> Option<(usize, usize)> {
    let segments = pts.len().checked_sub(1)?;
    let elements = segments.div_ceil(per);
    let bbox = |e: usize| {
        let (a, b) = (e * per, ((e + 1) * per).min(segments));
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in &pts[a..=b] {
            for c in 0..2 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        (lo, hi)
    };
    let boxes: Vec<([f64; 2], [f64; 2])> = (0..elements).map(bbox).collect();
    for eb in 0..elements {
        for ea in 0..=eb {
            let ((la, ha), (lb, hb)) = (boxes[ea], boxes[eb]);
            if la[0] > hb[0] || lb[0] > ha[0] || la[1] > hb[1] || lb[1] > ha[1] {
                continue;
            }
            for b in eb * per..((eb + 1) * per).min(segments) {
                for a in ea * per..((ea + 1) * per).min(segments) {
                    if a + 1 < b && segments_cross(pts[a], pts[a + 1], pts[b], pts[b + 1]) {
                        return Some((a, b));
                    }
                }
            }
        }
    }
    None
}

/// The first pair of non-adjacent segments of a polyline that intersect
/// (segment `i` joins points `i` and `i + 1`), by brute force.
#[cfg(test)]
fn first_crossing(pts: &[[f64; 2]]) -> Option<(usize, usize)> {
    let n = pts.len().checked_sub(1)?;
    for b in 2..n {
        for a in 0..b - 1 {
            if segments_cross(pts[a], pts[a + 1], pts[b], pts[b + 1]) {
                return Some((a, b));
            }
        }
    }
    None
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// True when the closed segments `pq` and `rs` share a point.
fn segments_cross(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    let d1 = cross(r, s, p);
    let d2 = cross(r, s, q);
    let d3 = cross(p, q, r);
    let d4 = cross(p, q, s);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        c[0] >= a[0].min(b[0])
            && c[0] <= a[0].max(b[0])
            && c[1] >= a[1].min(b[1])
            && c[1] <= a[1].max(b[1])
    };
    (d1 == 0.0 && on(r, s, p))
        || (d2 == 0.0 && on(r, s, q))
        || (d3 == 0.0 && on(p, q, r))
        || (d4 == 0.0 && on(p, q, s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_by_element_agree_with_brute_force() {
        let mut rng = fastrand::Rng::with_seed(7);
        let mut next = || rng.f64();
        for _ in 0..300 {
            // a random walk with a random turning rate: coils and straights
            let per = 1 + (next() * 5.0) as usize;
            let n = per * (1 + (next() * 12.0) as usize);
            let (mut p, mut a) = ([0.0, 0.0], 0.0);
            let turn = next() * 0.8;
            let mut pts = vec![p];
            for _ in 0..n {
                a += turn + 0.3 * (next() - 0.5);
                p = [p[0] + a.cos(), p[1] + a.sin()];
                pts.push(p);
            }
            assert_eq!(
                first_crossing(&pts).is_some(),
                first_crossing_by_element(&pts, per).is_some(),
                "{pts:?}"
            );
        }
    }

    #[test]
    fn crossings_of_hand_drawn_polylines() {
        // a figure of eight crosses itself
        let eight = [[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]];
        assert_eq!(first_crossing(&eight), Some((0, 2)));
        // a spiral that never meets itself
        let spiral: Vec<[f64; 2]> = (0..200)
            .map(|i| {
                let t = i as f64 * 0.1;
                [(1.0 + 0.2 * t) * t.cos(), (1.0 + 0.2 * t) * t.sin()]
            })
            .collect();
        assert_eq!(first_crossing(&spiral), None);
        // a circle run past its start closes on itself
        let circle: Vec<[f64; 2]> = (0..=80)
            .map(|i| {
                let t = i as f64 * 0.1;
                [t.cos(), t.sin()]
            })
            .collect();
        assert!(first_crossing(&circle).is_some());
        // touching end to start counts
        let touch = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]];
        assert_eq!(first_crossing(&touch), Some((0, 3)));
    }
}
