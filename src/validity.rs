//! Where an answer leaves the model's assumptions (docs/model.md section 8).
//!
//! The discrete CCM equations can be solved far outside the range where
//! they predict anything: an element turned past its small-slope limit, a
//! strain the laminate theory or the fitted law does not cover, a finger
//! whose surfaces meet, a laminate too thick to be a plate. A solution keeps
//! its answer and says so, with one [`Warning`] per finding (the worst
//! sample of each element, per kind; the closest approach for self
//! contact).

use std::f64::consts::{FRAC_PI_2, PI};

use crate::element::{self, Element};
use crate::error::{StripDimension, Warning};
use crate::model::Kinematics;

mod clearance;

use clearance::{greater, lesser};

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

/// Largest spacing of the self-contact search's mid-plane samples, as a
/// fraction of the thickness H (chord between neighbouring samples).
pub const CONTACT_SPACING: f64 = 1.0 / 16.0;

/// The most samples one self-contact search takes: a finger more than
/// `MAX_CONTACT_SAMPLES * CONTACT_SPACING` (4096) thicknesses long is
/// sampled more coarsely than [`CONTACT_SPACING`].
pub const MAX_CONTACT_SAMPLES: usize = 1 << 16;

/// Samples per block of the contact search's pruning (about one thickness
/// of arc at the finest spacing).
const CONTACT_BLOCK: usize = 16;

/// Allowance (rad, 10 degrees) for the tangent turning further between the
/// check points than at them: the contact search runs once the turning
/// seen at the check points exceeds [`contact_turning`] less this.
const TURNING_ALLOWANCE: f64 = 10.0 * PI / 180.0;

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
/// element at `samples` points (`x = L/samples .. L`, and the root), and
/// the end tangent's angle (rad, the sum of the elements' turns), which the
/// check needs anyway.
///
/// Cheap on purpose (it runs after every solve): the slope test compares
/// the tangent's components (an angle is computed only for an element that
/// fails, and two per element for the turning); and the self-contact
/// search, which only runs past about 100 degrees of turning, samples the
/// mid-plane at H / 16 and compares only blocks of samples whose bounding
/// boxes come within H of each other.
pub(crate) fn check<M: Kinematics>(
    elements: &[Element<M>],
    laminate: &Laminate,
    k: &[f64],
    samples: usize,
) -> (Vec<Warning>, f64) {
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
    let mut theta = 0.0f64;
    let mut scanned = [Extremes::default(); SCAN_LANES];
    let rules = ScanRules {
        samples,
        z: [pz0, pz1],
        eps0,
        limit_tan,
    };
    for (i, e) in elements.iter().enumerate() {
        let ki = element::coeffs::<M>(k, i);
        let l = e.length();
        // one pass without branches on the findings, over SCAN_LANES
        // elements at a time: the extremes of what the checks compare; an
        // element past a limit is scanned again for its warning's value
        // (rare)
        if i % SCAN_LANES == 0 {
            scanned = scan::<M>(elements, k, i, rules);
        }
        let Extremes {
            steep,
            forward,
            r: (rlo, rhi),
            stretch: most_stretch,
            mid: most_mid,
            pre: (slo_seen, shi_seen),
        } = scanned[i % SCAN_LANES];
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
        // the tangent's angle is theta + atan(dz/dx) at each check point
        if rlo <= rhi {
            turns.push([theta, rlo, rhi]);
        } else {
            turn_known = false;
        }
        // (the square root is monotone: the root of the largest square is
        // the largest root, bit for bit)
        stretch.push(most_stretch.sqrt());
        theta += e.end(&ki)[2];
    }
    if !turn_known || turns_beyond(&turns, contact_turning() - TURNING_ALLOWANCE) {
        out.extend(self_contact(elements, laminate.thickness, k, &stretch));
    }
    (out, theta)
}

/// Elements scanned side by side by [`scan`] (a vector register's worth of
/// doubles and more: the loop over them vectorises).
const SCAN_LANES: usize = 8;

/// One element's extremes over its check points ([`check`]).
#[derive(Debug, Clone, Copy)]
struct Extremes {
    /// A tangent past the slope limit (the root's excluded).
    steep: bool,
    /// Every tangent points forwards in the element's frame.
    forward: bool,
    /// The range of `dz/dx` over the forward tangents.
    r: (f64, f64),
    /// The largest `|d(X, Z)/dx|`, squared.
    stretch: f64,
    /// The largest `|mid-plane strain|`.
    mid: f64,
    /// The range of `eps0 +` the strain at the prestressed layer's faces.
    pre: (f64, f64),
}

impl Default for Extremes {
    fn default() -> Extremes {
        Extremes {
            steep: false,
            forward: true,
            r: (f64::INFINITY, f64::NEG_INFINITY),
            stretch: 0.0,
            mid: 0.0,
            pre: (f64::INFINITY, f64::NEG_INFINITY),
        }
    }
}

/// What [`scan`] checks: `samples + 1` check points per element, the
/// faces of the prestressed layer at heights `z` with prestrain `eps0`,
/// and the slope limit's tangent.
#[derive(Debug, Clone, Copy)]
struct ScanRules {
    samples: usize,
    z: [f64; 2],
    eps0: f64,
    limit_tan: f64,
}

/// The [`Extremes`] of elements `first..` (at most [`SCAN_LANES`] of
/// them) of state `k` under `rules`. Each element's numbers are its own
/// scalar arithmetic, in the order of its check points, so they do not
/// depend on which elements share the lanes (lanes past the last element
/// repeat the first and are ignored).
fn scan<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    first: usize,
    rules: ScanRules,
) -> [Extremes; SCAN_LANES] {
    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: the processor has AVX-512 (checked above)
        return unsafe { scan_avx512(elements, k, first, rules) };
    }
    scan_in(elements, k, first, rules)
}

/// [`scan`] compiled for AVX-512 (no fused multiply-adds: the same
/// roundings as the scalar code).
#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
#[target_feature(enable = "avx512f,avx2")]
fn scan_avx512<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    first: usize,
    rules: ScanRules,
) -> [Extremes; SCAN_LANES] {
    scan_in(elements, k, first, rules)
}

#[inline(always)]
fn scan_in<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    first: usize,
    rules: ScanRules,
) -> [Extremes; SCAN_LANES] {
    let ScanRules {
        samples,
        z,
        eps0,
        limit_tan,
    } = rules;
    let at = |l: usize| {
        if first + l < elements.len() {
            first + l
        } else {
            first
        }
    };
    let ks: [M::Coeffs; SCAN_LANES] = std::array::from_fn(|l| element::coeffs::<M>(k, at(l)));
    let ls: [f64; SCAN_LANES] = std::array::from_fn(|l| elements[at(l)].length());
    let mut steep = [false; SCAN_LANES];
    let mut forward = [true; SCAN_LANES];
    let (mut rlo, mut rhi) = ([f64::INFINITY; SCAN_LANES], [f64::NEG_INFINITY; SCAN_LANES]);
    let (mut stretch, mut mid) = ([0.0f64; SCAN_LANES], [0.0f64; SCAN_LANES]);
    let (mut slo, mut shi) = ([f64::INFINITY; SCAN_LANES], [f64::NEG_INFINITY; SCAN_LANES]);
    for j in 0..=samples {
        for l in 0..SCAN_LANES {
            let x = ls[l] * j as f64 / samples as f64;
            let [dx, dz] = M::tangent(&ks[l], x);
            steep[l] |= j > 0 && !(dx > 0.0 && dz.abs() <= limit_tan * dx);
            let fw = dx > 0.0;
            forward[l] &= fw;
            let r = dz / dx;
            rlo[l] = if fw { lesser(rlo[l], r) } else { rlo[l] };
            rhi[l] = if fw { greater(rhi[l], r) } else { rhi[l] };
            stretch[l] = greater(stretch[l], dx * dx + dz * dz);
            mid[l] = greater(mid[l], M::strain(&ks[l], x, 0.0).abs());
            for z in z {
                let s = eps0 + M::strain(&ks[l], x, z);
                slo[l] = lesser(slo[l], s);
                shi[l] = greater(shi[l], s);
            }
        }
    }
    std::array::from_fn(|l| Extremes {
        steep: steep[l],
        forward: forward[l],
        r: (rlo[l], rhi[l]),
        stretch: stretch[l],
        mid: mid[l],
        pre: (slo[l], shi[l]),
    })
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
/// gives; `None` where they do not.
fn turns_bounded(turns: &[[f64; 3]], limit: f64) -> Option<bool> {
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
    if turn_range(turns, above, below) <= limit - TURN_BOUND_MARGIN {
        Some(false)
    } else if turn_range(turns, below, above) > limit + TURN_BOUND_MARGIN {
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
    turns_bounded(turns, limit).unwrap_or_else(|| turn_range(turns, f64::atan, f64::atan) > limit)
}

/// How far (rad) the bounds of [`turns_bounded`] must clear the limit to
/// decide without `atan`: far above the rounding of a sum of angles.
const TURN_BOUND_MARGIN: f64 = 1e-9;

/// The self-contact finding of state `k`: the closest approach of the
/// sampled mid-plane to itself between parts at least
/// [`contact_separation`] apart along it, if closer than the thickness,
/// with the elements of the two nearest samples. `stretch[i]` is the
/// largest `|d(X, Z)/dx|` seen in element `i` (sizes its sampling).
fn self_contact<M: Kinematics>(
    elements: &[Element<M>],
    h: f64,
    k: &[f64],
    stretch: &[f64],
) -> Option<Warning> {
    let (first, spacing) = sample_counts(elements, stretch, CONTACT_SPACING * h);
    let frames = element::frames(elements, k);
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
/// sample; `frames` are the elements' root frames ([`element::frames`]).
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
        let f = [e.r.0, e.r.1, e.stretch, e.mid, e.pre.0, e.pre.1].map(f64::to_bits);
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
                };
                bits(got) == bits(&want)
            })
    })
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
    let frames = element::frames(elements, k);
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
    let frames = element::frames(elements, k);
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

    /// The turning decision from the bounds on `atan`, where they give
    /// one, is the one the `atan` of every element gives, for limits just
    /// below, at and just above the range, and for slopes from 0 to
    /// infinite of both signs; and the bounds decide most cases a tenth of
    /// a radian or more from the limit.
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
        let (mut decided, mut far) = (0, 0);
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
                let bounded = turns_bounded(&turns, limit);
                if let Some(b) = bounded {
                    assert_eq!(b, range > limit, "{turns:?} {limit}");
                }
                if small && (range - limit).abs() >= 0.1 {
                    far += 1;
                    decided += usize::from(bounded.is_some());
                }
            }
        }
        assert!(far >= 100 && decided * 10 >= far * 9, "{decided} of {far}");
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
