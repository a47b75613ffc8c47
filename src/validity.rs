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
/// element at `samples` points (`x = L/samples .. L`, and the root).
pub(crate) fn check<M: ElementModel>(
    finger: &FingerCore<M>,
    k: &[f64],
    samples: usize,
) -> Vec<Warning> {
    let samples = samples.max(1);
    let mut out = Vec::new();
    let (pz0, pz1) = finger.pemc_z;
    let eps0 = finger.eps0;
    let (slo, shi) = PRESTRESSED_STRAIN_RANGE;
    let limit_tan = SLOPE_LIMIT_DEG.to_radians().tan();
    let mut theta_lo = 0.0f64;
    let mut theta_hi = 0.0f64;
    let mut theta = 0.0;
    for (i, e) in finger.elements.iter().enumerate() {
        let ki = FingerCore::<M>::element_coeffs(k, i);
        let l = e.length();
        let mut slope: f64 = 0.0;
        let mut mid: (f64, f64) = (0.0, 0.0); // (|strain|, strain)
        let mut pre: Option<f64> = None; // worst s outside the range
        for j in 0..=samples {
            let x = l * j as f64 / samples as f64;
            let [dx, dz] = M::tangent(&ki, x);
            if j > 0 {
                // the angle from the element's root tangent
                let a = dz.atan2(dx);
                slope = slope.max(a.abs());
                theta_lo = theta_lo.min(theta + a);
                theta_hi = theta_hi.max(theta + a);
            }
            let m = M::strain(&ki, x, 0.0);
            if m.abs() > mid.0 {
                mid = (m.abs(), m);
            }
            for z in [pz0, pz1] {
                let s = eps0 + M::strain(&ki, x, z);
                let out_by = (slo - s).max(s - shi);
                if out_by > 0.0 && pre.is_none_or(|p| out_by > (slo - p).max(p - shi)) {
                    pre = Some(s);
                }
            }
        }
        if slope.tan() > limit_tan || slope > std::f64::consts::FRAC_PI_2 {
            out.push(Warning::ElementSlope {
                element: i,
                degrees: slope.to_degrees(),
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
        if let Some(s) = pre {
            out.push(Warning::PrestressedStrain {
                element: i,
                strain: s,
                range: PRESTRESSED_STRAIN_RANGE,
            });
        }
        theta += e.end(&ki)[2];
    }
    if theta_hi - theta_lo > TURNING_FOR_CONTACT {
        let pts = finger.shape_raw(k, samples);
        if let Some((a, b)) = first_crossing(&pts) {
            let element = |seg: usize| (seg / samples).min(finger.len() - 1);
            out.push(Warning::SelfContact {
                element: element(b),
                other: element(a),
            });
        }
    }
    out
}

/// The first pair of non-adjacent segments of a polyline that intersect
/// (segment `i` joins points `i` and `i + 1`), by brute force.
pub(crate) fn first_crossing(pts: &[[f64; 2]]) -> Option<(usize, usize)> {
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
