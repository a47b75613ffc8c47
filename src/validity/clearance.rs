//! A proof, from bounds on pieces of the mid-plane, that the self-contact
//! search cannot find anything: most curled fingers come nowhere near
//! themselves, and this settles them without sampling the mid-plane at
//! H / 16.
//!
//! Each element is cut into pieces in its local `x`; the mid-plane of a
//! piece is a polynomial curve, so its Bernstein control points bound it
//! (the curve lies in their convex hull, and so does every chord between
//! two of its points) and the control points of its derivative bound its
//! tangents (every tangent lies in the cone they span). The search looks
//! at the sampled mid-plane, a polyline with its vertices on the curve,
//! for two segments at least `l = pi H / 2` apart along it and closer than
//! H. Two such segments, with vertices in pieces `p <= q`:
//!
//! - lie with everything between them in pieces `p - 1 ..= q + 1` (no
//!   segment is longer in `x` than a piece), and every segment's direction
//!   is in the tangent cone of the pieces it spans; if that cone is
//!   narrower than the contact turning `2 acos(2 / pi)`, they are at least
//!   `l cos(turning / 2) > H` apart (the argument of `contact_turning`);
//! - else, each point of a segment is within half its length of one of
//!   its vertices, so they are at least the distance of the two pieces'
//!   boxes less the longest segment apart.
//!
//! So when every pair of pieces passes one of the two tests (with a small
//! allowance for rounding), the search would find nothing, and is skipped.
//! Where one pair fails nothing is concluded and the search runs as
//! before: its findings are the same either way.

use crate::element::{self, Element};
use crate::model::Kinematics;

/// Fine samples per piece, about: the pieces are about two thicknesses of
/// arc long at the search's finest spacing (`super::CONTACT_SPACING`).
const SAMPLES_PER_PIECE: usize = 32;

/// The most pieces a proof is tried with (its pairs grow as the square);
/// beyond, the search runs.
const MAX_PIECES: usize = 512;

/// The most pieces cut from the elements before short ones are joined.
const MAX_SUBPIECES: usize = 8 * MAX_PIECES;

/// The widest tangent cone of one piece (cosine of 45 degrees): a wider
/// piece ends the attempt. Kept small so that a run of pieces whose cone is
/// still under `contact_turning` (about 101 degrees) and one more piece
/// spans less than half a turn, where the cone's edges are well defined.
const PIECE_CONE_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Allowance for rounding: relative, on lengths (boxes) and on the cosine
/// of the cone's width.
const ROUNDING: f64 = 1e-9;

/// Pieces per group of the box test (a group out of reach is passed
/// whole).
const GROUP: usize = 8;

/// The largest degree of a mid-plane polynomial handled here.
const MAX_DEGREE: usize = 7;

/// An axis-aligned box in the finger's frame.
#[derive(Debug, Clone, Copy)]
pub(super) struct Bounds {
    pub lo: [f64; 2],
    pub hi: [f64; 2],
}

impl Bounds {
    /// The empty box (the identity of [`Bounds::union`]).
    const EMPTY: Bounds = Bounds {
        lo: [f64::INFINITY; 2],
        hi: [f64::NEG_INFINITY; 2],
    };

    /// The smallest box holding both (a NaN corner of `other` is dropped,
    /// as `f64::min` and `max` drop it; `self`'s are never NaN).
    #[inline]
    fn union(self, other: Bounds) -> Bounds {
        Bounds {
            lo: [
                lesser(self.lo[0], other.lo[0]),
                lesser(self.lo[1], other.lo[1]),
            ],
            hi: [
                greater(self.hi[0], other.hi[0]),
                greater(self.hi[1], other.hi[1]),
            ],
        }
    }

    /// The squared distance between the two boxes (0 where they overlap;
    /// the boxes are finite).
    #[inline]
    fn gap2(&self, other: &Bounds) -> f64 {
        let gap = |d: usize| {
            greater(
                greater(other.lo[d] - self.hi[d], self.lo[d] - other.hi[d]),
                0.0,
            )
        };
        let (gx, gz) = (gap(0), gap(1));
        gx * gx + gz * gz
    }
}

/// One piece of the mid-plane, in the finger's frame: the box of its
/// control points and the two edges of its tangent cone.
#[derive(Debug, Clone, Copy)]
pub(super) struct Piece {
    pub bounds: Bounds,
    /// The cone's clockwise and counter-clockwise edges.
    pub cw: [f64; 2],
    pub ccw: [f64; 2],
    /// Where it starts and ends: (element, local x).
    pub from: (usize, f64),
    pub to: (usize, f64),
    /// The search's samples in it, about.
    samples: usize,
}

impl Piece {
    /// `self` and `next` (which follows it) as one piece, where their cone
    /// stays within [`PIECE_CONE_COS`].
    fn merged(&self, next: &Piece) -> Option<Piece> {
        let mut cone = Cone::of(self);
        cone.add(next);
        surely_above(cone.cos_width(), PIECE_CONE_COS).then(|| Piece {
            bounds: self.bounds.union(next.bounds),
            cw: cone.cw,
            ccw: cone.ccw,
            from: self.from,
            to: next.to,
            samples: self.samples + next.samples,
        })
    }
}

/// True when the self-contact search over the mid-plane of state `k` (raw
/// coefficients; `frames` its elements' root frames, [`element::walk::frames`]),
/// sampled `first[i]` or more times in element `i`, cannot find two
/// segments at least `pi h / 2` apart along it and closer than `h`;
/// `turning` is the tangent turning under which no such pair exists
/// (`2 acos(2 / pi)`). False when that is not shown (the search must run).
pub(super) fn clear<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    frames: &[([f64; 2], [f64; 2])],
    first: &[usize],
    h: f64,
    turning: f64,
) -> bool {
    let Some((pieces, chord)) = pieces(elements, k, frames, first) else {
        return false;
    };
    let reach2 = ((h + chord) * (1.0 + ROUNDING)).powi(2);
    // the cone's width below contact_turning: cos(width) above its cosine
    let narrow = turning.cos() + ROUNDING;
    let n = pieces.len();
    // a group whose box is out of reach of a piece passes the box test
    // with every piece in it
    let groups: Vec<Bounds> = pieces
        .chunks(GROUP)
        .map(|g| g.iter().fold(Bounds::EMPTY, |b, p| b.union(p.bounds)))
        .collect();
    for p in 0..n {
        // the first piece q from which pieces p - 1 ..= q + 1 turn too far
        // for the cone test (the pairs before it pass that test)
        let mut cone = Cone::of(&pieces[p.saturating_sub(1)]);
        cone.add(&pieces[p]);
        let mut wide_from = n;
        for q in p..n {
            cone.add(&pieces[(q + 1).min(n - 1)]);
            if !surely_above(cone.cos_width(), narrow) {
                wide_from = q;
                break;
            }
        }
        let piece = &pieces[p].bounds;
        for (g, group) in groups.iter().enumerate() {
            let members = g * GROUP..((g + 1) * GROUP).min(n);
            if members.end <= wide_from || surely_above(piece.gap2(group), reach2) {
                continue;
            }
            for other in &pieces[members.start.max(wide_from)..members.end] {
                if !surely_above(piece.gap2(&other.bounds), reach2) {
                    return false;
                }
            }
        }
    }
    true
}

/// The pieces of the mid-plane (no more pieces in an element than its
/// samples, so that no segment of the search spans more than two; the
/// short pieces of consecutive short elements joined) and an
/// upper bound on the search's longest segment; `None` where a piece's
/// cone is too wide, the pieces too many or a value not finite.
pub(super) fn pieces<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    frames: &[([f64; 2], [f64; 2])],
    first: &[usize],
) -> Option<(Vec<Piece>, f64)> {
    let d = M::MIDPLANE_DEGREE;
    let subpieces: usize = first.iter().map(|&m| piece_count(m)).sum();
    if d == 0
        || d > MAX_DEGREE
        || first.len() != elements.len()
        || frames.len() != elements.len()
        || subpieces > MAX_SUBPIECES
    {
        return None;
    }
    let mut out: Vec<Piece> = Vec::with_capacity(subpieces);
    let mut chord = 0.0f64;
    let mut poly = [[0.0; 2]; MAX_DEGREE + 1];
    for (i, (e, &(origin, [c, s]))) in elements.iter().zip(frames).enumerate() {
        M::midplane_coefficients(&element::coeffs::<M>(k, i), &mut poly[..=d]);
        let l = e.length();
        // the longest segment: its length at most the largest tangent over
        // the element times its step in x (the search's steps are at most
        // l / first[i])
        let whole = bernstein(&poly[..=d], 0.0, l);
        // (the root of the largest square: the largest root, bit for bit)
        let speed = (0..d)
            .map(|j| {
                let v = sub(whole[j + 1], whole[j]);
                v[0] * v[0] + v[1] * v[1]
            })
            .fold(0.0f64, greater)
            .sqrt()
            * d as f64
            / l;
        chord = chord.max(speed * l / first[i].max(1) as f64);
        let to_finger = |v: [f64; 2]| [c * v[0] - s * v[1], s * v[0] + c * v[1]];
        let m = piece_count(first[i]);
        for j in 0..m {
            let (x0, x1) = (l * j as f64 / m as f64, l * (j + 1) as f64 / m as f64);
            // (one piece: the element's own points, x0 = 0 and x1 = l exactly)
            let b = if m == 1 {
                whole
            } else {
                bernstein(&poly[..=d], x0, x1)
            };
            let bounds = b[..=d].iter().fold(Bounds::EMPTY, |bounds, q| {
                let g = to_finger(*q);
                let at = [origin[0] + g[0], origin[1] + g[1]];
                bounds.union(Bounds { lo: at, hi: at })
            });
            let mut cone = Cone::start(to_finger(sub(b[1], b[0])));
            for t in 1..d {
                cone.extend(to_finger(sub(b[t + 1], b[t])));
            }
            if !surely_above(cone.cos_width(), PIECE_CONE_COS) {
                return None;
            }
            let piece = Piece {
                bounds,
                cw: cone.cw,
                ccw: cone.ccw,
                from: (i, x0),
                to: (i, x1),
                samples: first[i] / m,
            };
            let (lo, hi) = (bounds.lo, bounds.hi);
            if !(lo.iter().chain(&hi).all(|v| v.is_finite()) && chord.is_finite()) {
                return None;
            }
            // the short pieces of short elements (under a quarter of
            // SAMPLES_PER_PIECE samples) joined up to SAMPLES_PER_PIECE:
            // the pairs grow as the square
            let joined = out
                .last()
                .filter(|p| {
                    piece.samples < SAMPLES_PER_PIECE / 4
                        && p.samples + piece.samples <= SAMPLES_PER_PIECE
                })
                .and_then(|p| p.merged(&piece));
            match (joined, out.last_mut()) {
                (Some(joined), Some(last)) => *last = joined,
                _ => out.push(piece),
            }
        }
    }
    (out.len() <= MAX_PIECES).then_some((out, chord))
}

/// The pieces of an element the search samples `first` times or more:
/// about one per [`SAMPLES_PER_PIECE`], at least one, at most `first`.
fn piece_count(first: usize) -> usize {
    first.div_ceil(SAMPLES_PER_PIECE).clamp(1, first.max(1))
}

/// The Bernstein control points on `[x0, x1]` of the polynomial curve with
/// power coefficients `a` (`a[j]` of `x^j`); the first `a.len()` entries.
fn bernstein(a: &[[f64; 2]], x0: f64, x1: f64) -> [[f64; 2]; MAX_DEGREE + 1] {
    let d = a.len() - 1;
    let w = x1 - x0;
    let mut wp = [1.0; MAX_DEGREE + 1]; // w^m
    for m in 1..=d {
        wp[m] = wp[m - 1] * w;
    }
    // power coefficients in t, x = x0 + w t: c_m = sum_j a_j C(j, m) x0^(j-m) w^m
    let mut c = [[0.0; 2]; MAX_DEGREE + 1];
    for (j, aj) in a.iter().enumerate() {
        let mut x0p = 1.0; // x0^(j - m), from m = j down
        for m in (0..=j).rev() {
            let f = BINOMIAL[j][m] * x0p * wp[m];
            c[m][0] += aj[0] * f;
            c[m][1] += aj[1] * f;
            x0p *= x0;
        }
    }
    // b_k = sum_{m <= k} C(k, m) / C(d, m) c_m
    let mut b = [[0.0; 2]; MAX_DEGREE + 1];
    for (kk, bk) in b.iter_mut().enumerate().take(d + 1) {
        for (m, cm) in c.iter().enumerate().take(kk + 1) {
            let f = TO_BERNSTEIN[d][kk][m];
            bk[0] += cm[0] * f;
            bk[1] += cm[1] * f;
        }
    }
    b
}

/// `b` where it is below `a`, else `a`: `f64::min` for an `a` that is not
/// NaN (a NaN `b` is dropped), in one instruction where `min` spends
/// several guarding against a NaN `a`.
#[inline(always)]
pub(super) fn lesser(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

/// `b` where it is above `a`, else `a` (`f64::max` for an `a` that is not
/// NaN; see [`lesser`]).
#[inline(always)]
pub(super) fn greater(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// `a > b`, false where either is NaN: every test of the proof fails on a
/// value that is not a number.
fn surely_above(a: f64, b: f64) -> bool {
    a > b
}

/// `BINOMIAL[n][k]`, n choose k, for `n <= MAX_DEGREE` (Pascal's triangle).
const BINOMIAL: [[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1] = {
    let mut t = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
    let mut n = 0;
    while n <= MAX_DEGREE {
        t[n][0] = 1.0;
        let mut k = 1;
        while k <= n {
            t[n][k] = t[n - 1][k - 1] + t[n - 1][k];
            k += 1;
        }
        n += 1;
    }
    t
};

/// `TO_BERNSTEIN[d][k][m] = C(k, m) / C(d, m)` for `m <= k <= d <=
/// MAX_DEGREE` (the same division [`bernstein`] would make, made once).
const TO_BERNSTEIN: [[[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1]; MAX_DEGREE + 1] = {
    let mut t = [[[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1]; MAX_DEGREE + 1];
    let mut d = 0;
    while d <= MAX_DEGREE {
        let mut k = 0;
        while k <= d {
            let mut m = 0;
            while m <= k {
                t[d][k][m] = BINOMIAL[k][m] / BINOMIAL[d][m];
                m += 1;
            }
            k += 1;
        }
        d += 1;
    }
    t
};

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// A cone of directions narrower than half a turn, by its two edges.
#[derive(Debug, Clone, Copy)]
struct Cone {
    cw: [f64; 2],
    ccw: [f64; 2],
}

impl Cone {
    fn start(v: [f64; 2]) -> Cone {
        Cone { cw: v, ccw: v }
    }

    fn of(p: &Piece) -> Cone {
        Cone {
            cw: p.cw,
            ccw: p.ccw,
        }
    }

    /// Widens the cone to hold `v` (the cone and `v` within half a turn).
    fn extend(&mut self, v: [f64; 2]) {
        if cross(self.ccw, v) > 0.0 {
            self.ccw = v;
        } else if cross(v, self.cw) > 0.0 {
            self.cw = v;
        }
    }

    fn add(&mut self, p: &Piece) {
        self.extend(p.cw);
        self.extend(p.ccw);
    }

    /// The cosine of the angle between the edges (NaN for a zero edge).
    fn cos_width(&self) -> f64 {
        let (a, b) = (self.cw, self.ccw);
        let dot = a[0] * b[0] + a[1] * b[1];
        dot / ((a[0] * a[0] + a[1] * a[1]).sqrt() * (b[0] * b[0] + b[1] * b[1]).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lesser_and_greater_are_min_and_max_for_an_accumulator() {
        // every pair of these, the accumulator `a` never NaN; ties of
        // zeros of both signs are left out (min and max may return either)
        let values = [
            -f64::INFINITY,
            -3.5,
            -1e-300,
            0.0,
            2.0,
            7.25e10,
            f64::INFINITY,
        ];
        for &a in &values {
            for b in values.into_iter().chain([f64::NAN]) {
                assert_eq!(lesser(a, b).to_bits(), a.min(b).to_bits(), "{a} {b}");
                assert_eq!(greater(a, b).to_bits(), a.max(b).to_bits(), "{a} {b}");
            }
        }
        // the only difference: a NaN accumulator stays NaN
        assert!(lesser(f64::NAN, 1.0).is_nan() && f64::NAN.min(1.0) == 1.0);
    }

    #[test]
    fn the_bernstein_table_is_the_division_it_replaces() {
        for d in 0..=MAX_DEGREE {
            for k in 0..=d {
                for m in 0..=k {
                    let divided = BINOMIAL[k][m] / BINOMIAL[d][m];
                    assert_eq!(TO_BERNSTEIN[d][k][m].to_bits(), divided.to_bits());
                }
            }
        }
    }

    #[test]
    fn bernstein_points_reproduce_the_polynomial() {
        // de Casteljau at t of the control points equals the polynomial at x
        let a = [[0.3, -1.0], [1.2, 0.5], [-0.7, 0.25], [0.05, -0.02]];
        let (x0, x1) = (2.0, 5.5);
        let b = bernstein(&a, x0, x1);
        for t in [0.0, 0.2, 0.5, 0.9, 1.0] {
            let mut q: Vec<[f64; 2]> = b[..4].to_vec();
            for r in (1..4).rev() {
                for j in 0..r {
                    q[j] = [
                        (1.0 - t) * q[j][0] + t * q[j + 1][0],
                        (1.0 - t) * q[j][1] + t * q[j + 1][1],
                    ];
                }
            }
            let x: f64 = x0 + (x1 - x0) * t;
            let p = (0..4).fold([0.0, 0.0], |acc, j| {
                [
                    acc[0] + a[j][0] * x.powi(j as i32),
                    acc[1] + a[j][1] * x.powi(j as i32),
                ]
            });
            assert!((q[0][0] - p[0]).abs() < 1e-12 && (q[0][1] - p[1]).abs() < 1e-12);
        }
    }
}
