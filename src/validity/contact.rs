//! The self-contact check: the mid-plane sampled along the finger and the
//! closest approach of parts far apart along it ([`self_contact`]), after
//! the clearance proof ([`super::clearance`]) where that settles it.

use std::f64::consts::PI;

use super::clearance;
use crate::element::{self, Element};
use crate::error::Warning;
use crate::model::Kinematics;

/// Largest spacing of the self-contact search's mid-plane samples, as a
/// fraction of the thickness H (chord between neighbouring samples).
pub const CONTACT_SPACING: f64 = 1.0 / 16.0;

/// The most samples one self-contact search takes: a finger more than
/// `MAX_CONTACT_SAMPLES * CONTACT_SPACING` (4096) thicknesses long is
/// sampled more coarsely than [`CONTACT_SPACING`].
pub const MAX_CONTACT_SAMPLES: usize = 1 << 16;

/// The arc-length separation `l = pi H / 2` (mm) from which two parts of
/// the mid-plane closer than the thickness `h` are in contact: half a turn
/// of the tightest circle (radius H / 2) whose inner face does not fold.
pub(crate) fn contact_separation(h: f64) -> f64 {
    0.5 * PI * h
}

/// The total tangent turning `2 acos(2 / pi)` (rad, about 100.9 degrees)
/// below which no two points `l` apart along the mid-plane come closer
/// than H: with every tangent within half of it of one direction,
/// `|p(s2) - p(s1)| >= (s2 - s1) cos(theta / 2) >= l 2 / pi = H`.
pub(crate) fn contact_turning() -> f64 {
    2.0 * (2.0 / PI).acos()
}

/// Samples per block of the contact search's pruning (about one thickness
/// of arc at the finest spacing).
const CONTACT_BLOCK: usize = 16;

/// The self-contact finding of state `k`: the closest approach of the
/// sampled mid-plane to itself between parts at least
/// [`contact_separation`] apart along it, if closer than the thickness,
/// with the elements of the two nearest samples. `stretch[i]` is the
/// largest `|d(X, Z)/dx|` seen in element `i` (sizes its sampling).
pub(super) fn self_contact<M: Kinematics>(
    elements: &[Element<M>],
    h: f64,
    k: &[f64],
    stretch: &[f64],
) -> Option<Warning> {
    let (first, spacing) = sample_counts(elements, stretch, CONTACT_SPACING * h);
    let frames = element::walk::frames(elements, k);
    if clearance::clear(elements, k, &frames, &first, h, contact_turning()) {
        return None;
    }
    search(elements, h, k, &frames, &first, spacing)
}

/// The self-contact search proper: the mid-plane sampled (`first[i]` or
/// more samples in element `i`, chords at most `spacing` where the budget
/// allows; `frames` the elements' root frames) and its closest approach to
/// itself.
fn search<M: Kinematics>(
    elements: &[Element<M>],
    h: f64,
    k: &[f64],
    frames: &[([f64; 2], [f64; 2])],
    first: &[usize],
    spacing: f64,
) -> Option<Warning> {
    let (pts, ends) = contact_samples(elements, k, frames, first, spacing);
    if pts.iter().flatten().any(|v| !v.is_finite()) {
        return None;
    }
    // deformed arc length from the root, by chords, and the longest chord
    let mut arc = Vec::with_capacity(pts.len());
    let (mut s, mut longest) = (0.0, 0.0f64);
    arc.push(s);
    for w in pts.windows(2) {
        let d = dist(w[0], w[1]);
        longest = longest.max(d);
        s += d;
        arc.push(s);
    }
    let (a, b, distance) = closest_pair(&pts, &arc, contact_separation(h), h, longest)?;
    let element = |j: usize| ends.partition_point(|&e| e < j).min(elements.len() - 1);
    Some(Warning::SelfContact {
        element: element(b),
        other: element(a),
        distance,
        thickness: h,
    })
}

/// The search's first count of mid-plane samples per element, for chords
/// at most `spacing` apart (`stretch[i]` the largest `|d(X, Z)/dx|` seen
/// in element `i`), and the spacing they aim at (wider for a finger too
/// long for [`MAX_CONTACT_SAMPLES`] at `spacing`).
fn sample_counts<M: Kinematics>(
    elements: &[Element<M>],
    stretch: &[f64],
    spacing: f64,
) -> (Vec<usize>, f64) {
    // the deformed length estimated from the check points' stretch, with
    // a quarter more to spare; a long finger widens the spacing
    let lengths: Vec<f64> = elements
        .iter()
        .zip(stretch)
        .map(|(e, s)| 1.25 * e.length() * s)
        .collect();
    let total: f64 = lengths.iter().sum();
    let spacing = spacing.max(total / MAX_CONTACT_SAMPLES as f64);
    let count = |len: f64| {
        let m = (len / spacing).ceil();
        if m.is_finite() && m >= 1.0 {
            (m as usize).min(MAX_CONTACT_SAMPLES)
        } else {
            1
        }
    };
    (lengths.into_iter().map(count).collect(), spacing)
}

/// Mid-plane samples from the root, `first[i]` in element `i` or, where a
/// chord comes out longer than `spacing`, twice or four times as many
/// (within the sample budget), and the index of each element's last
/// sample; `frames` are the elements' root frames ([`element::walk::frames`]).
fn contact_samples<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    frames: &[([f64; 2], [f64; 2])],
    first: &[usize],
    spacing: f64,
) -> (Vec<[f64; 2]>, Vec<usize>) {
    let total: usize = first.iter().sum();
    let mut pts = Vec::with_capacity(2 + total.min(1 << 20));
    pts.push([0.0, 0.0]);
    let mut ends = Vec::with_capacity(elements.len());
    let mut local: Vec<[f64; 2]> = Vec::new();
    for (i, (e, &(p, [c, s]))) in elements.iter().zip(frames).enumerate() {
        let ki = element::coeffs::<M>(k, i);
        let l = e.length();
        let first = first[i];
        let mut m = first;
        loop {
            local.clear();
            // the element's root is the previous element's last sample
            let mut prev = M::midplane(&ki, 0.0);
            // the widest chord, squared
            let mut widest = 0.0f64;
            for j in 1..=m {
                let q = M::midplane(&ki, l * j as f64 / m as f64);
                let (dx, dz) = (q[0] - prev[0], q[1] - prev[1]);
                widest = widest.max(dx * dx + dz * dz);
                prev = q;
                local.push(q);
            }
            // twice at most: the stretch at the check points is a close guide
            if widest <= spacing * spacing || m >= 4 * first || m >= MAX_CONTACT_SAMPLES {
                break;
            }
            m *= 2;
        }
        for &[xl, zl] in &local {
            pts.push([p[0] + c * xl - s * zl, p[1] + s * xl + c * zl]);
        }
        ends.push(pts.len() - 1);
    }
    (pts, ends)
}

/// The distance between two points (of a finite mid-plane, mm-sized: the
/// plain square root, several times faster than `hypot`'s guarded one).
fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    let (dx, dz) = (p[0] - q[0], p[1] - q[1]);
    (dx * dx + dz * dz).sqrt()
}

/// The closest approach `(a, b, distance)` of the polyline `pts` to
/// itself, if closer than `limit`: the smallest distance between two of its
/// segments at least `sep` apart along it (from the end of the first to the
/// start of the second, in `arc`, non-decreasing), 0 where two cross; `a <
/// b` are vertices of the two segments.
///
/// Segments are compared only through a pair of their vertices within the
/// best distance so far plus `spacing` (the longest segment: no point of
/// two segments comes closer than their nearest vertices less that), in
/// blocks of [`CONTACT_BLOCK`] vertices: a pair of blocks is skipped when
/// their bounding boxes are that far apart, or when no two of their
/// vertices are `sep` apart along the arc; blocks are swept in order of
/// their boxes' lower X.
fn closest_pair(
    pts: &[[f64; 2]],
    arc: &[f64],
    sep: f64,
    limit: f64,
    spacing: f64,
) -> Option<(usize, usize, f64)> {
    let n = pts.len();
    let blocks = n.div_ceil(CONTACT_BLOCK);
    let range = |c: usize| c * CONTACT_BLOCK..((c + 1) * CONTACT_BLOCK).min(n);
    let boxes: Vec<([f64; 2], [f64; 2])> = (0..blocks)
        .map(|c| {
            let mut lo = [f64::INFINITY; 2];
            let mut hi = [f64::NEG_INFINITY; 2];
            for p in &pts[range(c)] {
                for d in 0..2 {
                    lo[d] = lo[d].min(p[d]);
                    hi[d] = hi[d].max(p[d]);
                }
            }
            (lo, hi)
        })
        .collect();
    let mut order: Vec<usize> = (0..blocks).collect();
    order.sort_by(|&a, &b| boxes[a].0[0].total_cmp(&boxes[b].0[0]));
    let mut best = limit;
    let mut found = None;
    for (o, &ca) in order.iter().enumerate() {
        for &cb in &order[o..] {
            let reach = best + spacing;
            let ((la, ha), (lb, hb)) = (boxes[ca], boxes[cb]);
            if lb[0] - ha[0] >= reach {
                break; // and every later block in the order
            }
            if lb[1] - ha[1] >= reach || la[1] - hb[1] >= reach {
                continue;
            }
            let (c1, c2) = (ca.min(cb), ca.max(cb));
            let (r1, r2) = (range(c1), range(c2));
            if arc[r2.end - 1] - arc[r1.start] < sep {
                continue;
            }
            let (l2, h2) = boxes[c2];
            for a in r1 {
                // no vertex of the second block within reach of a: none can
                // pass the test below
                let reach = best + spacing;
                let p = pts[a];
                let gx = (l2[0] - p[0]).max(p[0] - h2[0]).max(0.0);
                let gz = (l2[1] - p[1]).max(p[1] - h2[1]).max(0.0);
                if gx * gx + gz * gz >= reach * reach {
                    continue;
                }
                // the vertices of the second block at least sep beyond a
                let beyond = r2.start + arc[r2.clone()].partition_point(|&s| s - arc[a] < sep);
                for b in beyond.max(a + 1)..r2.end {
                    let reach = best + spacing;
                    let (dx, dz) = (pts[b][0] - pts[a][0], pts[b][1] - pts[a][1]);
                    if dx * dx + dz * dz >= reach * reach {
                        continue;
                    }
                    let d = segments_near(pts, arc, sep, a, b);
                    if d < best {
                        best = d;
                        found = Some((a, b, d));
                    }
                }
            }
        }
    }
    found
}

/// The smallest distance between the polyline's segments next to vertices
/// `a` and `b` (those ending or starting there) that are at least `sep`
/// apart along it (0 where two cross), infinite when there are none.
fn segments_near(pts: &[[f64; 2]], arc: &[f64], sep: f64, a: usize, b: usize) -> f64 {
    let segments = |j: usize| [j.checked_sub(1), Some(j)].into_iter().flatten();
    let mut best = f64::INFINITY;
    for sa in segments(a) {
        for sb in segments(b) {
            if sb + 1 < pts.len() && arc[sb] - arc[sa + 1] >= sep {
                best = best.min(segment_distance(pts[sa], pts[sa + 1], pts[sb], pts[sb + 1]));
            }
        }
    }
    best
}

/// The distance between the closed segments `pq` and `rs`.
fn segment_distance(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> f64 {
    if segments_cross(p, q, r, s) {
        return 0.0;
    }
    point_segment(p, r, s)
        .min(point_segment(q, r, s))
        .min(point_segment(r, p, q))
        .min(point_segment(s, p, q))
}

/// The distance from `p` to the closed segment `ab`.
fn point_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (ux, uz) = (b[0] - a[0], b[1] - a[1]);
    let len2 = ux * ux + uz * uz;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * ux + (p[1] - a[1]) * uz) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, [a[0] + t * ux, a[1] + t * uz])
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

/// For tests above this module (which solve fingers): whether the
/// clearance proof settles state `k` at thickness `h`, and the distance
/// of the search's finding (the search run anyway); `first` and the
/// spacing from `stretch` as the check sizes them.
#[cfg(test)]
pub(crate) fn proof_and_search<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    stretch: &[f64],
    h: f64,
) -> (bool, Option<f64>) {
    let (first, spacing) = sample_counts(elements, stretch, CONTACT_SPACING * h);
    let frames = element::walk::frames(elements, k);
    let cleared = clearance::clear(elements, k, &frames, &first, h, contact_turning());
    let found = match search(elements, h, k, &frames, &first, spacing) {
        Some(Warning::SelfContact { distance, .. }) => Some(distance),
        _ => None,
    };
    (cleared, found)
}

/// For tests above this module: the clearance proof's pieces of state `k`
/// at thickness `h` (unit stretch), as `(box low, box high, cone edges,
/// start, end)` in order along the finger (start and end as element and
/// local x), its bound on the search's longest segment, and the longest
/// segment the search samples; `None` where the proof gives up.
#[cfg(test)]
#[allow(clippy::type_complexity)]
pub(crate) fn proof_pieces<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    h: f64,
) -> Option<(
    Vec<(
        [f64; 2],
        [f64; 2],
        [[f64; 2]; 2],
        (usize, f64),
        (usize, f64),
    )>,
    f64,
    f64,
)> {
    let stretch = vec![1.0; elements.len()];
    let (first, spacing) = sample_counts(elements, &stretch, CONTACT_SPACING * h);
    let frames = element::walk::frames(elements, k);
    let (pieces, chord) = clearance::pieces(elements, k, &frames, &first)?;
    let (pts, _) = contact_samples(elements, k, &frames, &first, spacing);
    let longest = pts.windows(2).map(|w| dist(w[0], w[1])).fold(0.0, f64::max);
    let pieces = pieces
        .iter()
        .map(|p| (p.bounds.lo, p.bounds.hi, [p.cw, p.ccw], p.from, p.to))
        .collect();
    Some((pieces, chord, longest))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random walk with a random turning rate (coils and straights):
    /// `n` steps of length `step`.
    fn walk(rng: &mut fastrand::Rng, n: usize, step: f64) -> Vec<[f64; 2]> {
        let (mut p, mut a) = ([0.0, 0.0], 0.0f64);
        let turn = rng.f64() * 0.5;
        let mut pts = vec![p];
        for _ in 0..n {
            a += turn + 0.3 * (rng.f64() - 0.5);
            p = [p[0] + step * a.cos(), p[1] + step * a.sin()];
            pts.push(p);
        }
        pts
    }

    fn chords(pts: &[[f64; 2]]) -> Vec<f64> {
        let mut arc = vec![0.0];
        for w in pts.windows(2) {
            arc.push(arc.last().unwrap() + dist(w[0], w[1]));
        }
        arc
    }

    /// Solved states of random fingers (three models, 1-16 elements,
    /// prestrains 0.1-0.5, pressures to 300 kPa, tip loads to 1.5 N):
    /// wherever the clearance proof skips the search, the search (run
    /// anyway) finds nothing, at the laminate's thickness and at thicknesses
    /// up to 60 times it, in steps of 15 % (which bring parts of a curl
    /// into contact). The
    /// proof must also settle most curled states at the real thickness, or
    /// it saves nothing.
    #[test]
    fn the_pruned_search_finds_the_brute_force_closest_pair() {
        let mut rng = fastrand::Rng::with_seed(11);
        let mut hits = 0;
        for _ in 0..400 {
            let n = 1 + rng.usize(..300);
            let step = 0.2 + rng.f64();
            let pts = walk(&mut rng, n, step);
            let arc = chords(&pts);
            let limit = 0.5 + 4.0 * rng.f64();
            let sep = 0.5 * PI * limit;
            // every pair of segments, by brute force
            let mut brute: Option<f64> = None;
            for b in 1..pts.len() - 1 {
                for a in 0..b - 1 {
                    let d = segment_distance(pts[a], pts[a + 1], pts[b], pts[b + 1]);
                    if arc[b] - arc[a + 1] >= sep && d < limit && brute.is_none_or(|e| d < e) {
                        brute = Some(d);
                    }
                }
            }
            let spacing = pts.windows(2).map(|w| dist(w[0], w[1])).fold(0.0, f64::max);
            let found = closest_pair(&pts, &arc, sep, limit, spacing);
            assert_eq!(found.map(|f| f.2), brute, "n {n}, limit {limit}");
            hits += usize::from(found.is_some());
        }
        assert!(
            hits > 50 && hits < 350,
            "{hits} of 400 walks meet themselves"
        );
    }

    #[test]
    fn segment_distances_agree_with_dense_sampling() {
        let mut rng = fastrand::Rng::with_seed(5);
        let mut point = || [4.0 * rng.f64() - 2.0, 4.0 * rng.f64() - 2.0];
        for _ in 0..300 {
            let (p, q, r, s) = (point(), point(), point(), point());
            let along = |a: [f64; 2], b: [f64; 2], t: f64| {
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
            };
            let m = 400;
            let mut dense = f64::INFINITY;
            for i in 0..=m {
                for j in 0..=m {
                    let (t, u) = (i as f64 / m as f64, j as f64 / m as f64);
                    dense = dense.min(dist(along(p, q, t), along(r, s, u)));
                }
            }
            let d = segment_distance(p, q, r, s);
            // dense sampling is within one step of either segment
            let step = (dist(p, q) + dist(r, s)) / m as f64;
            assert!(d <= dense + 1e-12 && dense <= d + step, "{d} vs {dense}");
        }
        // a figure of eight crosses itself: distance 0
        assert_eq!(
            segment_distance([0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]),
            0.0
        );
        // touching end to start counts
        assert_eq!(
            segment_distance([0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]),
            0.0
        );
        // parallel segments one apart
        assert_eq!(
            segment_distance([0.0, 0.0], [1.0, 0.0], [0.5, 1.0], [3.0, 1.0]),
            1.0
        );
    }

    #[test]
    fn a_curve_turning_less_than_the_bound_never_comes_within_h_of_itself() {
        // 2 acos(2/pi), and the circle of radius H/2: half a turn is l long
        // and its ends are exactly H apart
        assert!((contact_turning().to_degrees() - 100.92).abs() < 0.005);
        let h = 3.0;
        let l = contact_separation(h);
        assert!((l - PI * (h / 2.0)).abs() < 1e-12);
        // random curves whose tangents stay within the bound's turning
        let mut rng = fastrand::Rng::with_seed(3);
        let theta = contact_turning() * 0.999;
        let mut closest = f64::INFINITY;
        for _ in 0..200 {
            let n = 400;
            let step = h / 16.0;
            let (mut p, mut a) = ([0.0, 0.0], theta * (rng.f64() - 0.5));
            let mut pts = vec![p];
            for _ in 0..n {
                // a tangent wandering inside [-theta/2, theta/2]
                a = (a + 0.4 * (rng.f64() - 0.5)).clamp(-theta / 2.0, theta / 2.0);
                p = [p[0] + step * a.cos(), p[1] + step * a.sin()];
                pts.push(p);
            }
            let arc = chords(&pts);
            assert_eq!(closest_pair(&pts, &arc, l, h, step), None);
            for b in 0..pts.len() {
                for a in 0..b {
                    if arc[b] - arc[a] >= l {
                        closest = closest.min(dist(pts[a], pts[b]));
                    }
                }
            }
        }
        assert!(closest >= h, "{closest}");
        // a circle of radius H/2 run one and a half turns: the search finds
        // points l apart whose distance is about H, and more than that
        // closes the circle on itself
        let r = 0.6 * h;
        let pts: Vec<[f64; 2]> = (0..=600)
            .map(|i| {
                let t = 3.0 * PI * i as f64 / 600.0;
                [r * t.sin(), r - r * t.cos()]
            })
            .collect();
        let arc = chords(&pts);
        let (a, b, d) = closest_pair(&pts, &arc, l, h, 3.0 * PI * r / 600.0).unwrap();
        assert_eq!(d, 0.0, "the circle crosses itself");
        assert!((arc[b] - arc[a] - 2.0 * PI * r).abs() < 0.1, "{a} {b}");
    }
}
