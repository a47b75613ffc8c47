//! Exact minima of a real polynomial on a sub-interval of `[0, 1]`: the
//! Bernstein-basis machinery behind [`super`].
//!
//! A polynomial `p(s) = sum_j a_j s^j` of degree `n` is also
//! `sum_i b_i B_i(s)` with the Bernstein polynomials `B_i(s) = C(n, i) s^i
//! (1 - s)^(n - i)`. On an interval the Bernstein coefficients of `p` there
//! (de Casteljau's subdivision) give:
//!
//! - the values at both ends (`b_0`, `b_n`), exactly;
//! - a lower bound `min_i b_i <= p` over the whole interval (the curve lies
//!   in the convex hull of its control points), which tends to the true
//!   minimum quadratically as the interval shrinks;
//! - the derivative's Bernstein coefficients, `n (b_{i+1} - b_i)`, whose
//!   sign variations `V` bound the number of roots of `p'` inside the
//!   interval, with the same parity (Descartes' rule in the Bernstein
//!   basis): `V = 0` means `p` is monotone there, `V = 1` that `p'` has
//!   exactly one root there.
//!
//! [`Search::minimise`] is a branch and bound on these facts: an interval
//! whose lower bound cannot beat the best value found is dropped, a
//! monotone one contributes its ends, one with a single critical point
//! contributes it (a safeguarded Newton iteration on `p'` inside the
//! bracket), and any other is halved. Nothing is sampled, so no interior
//! extremum is missed.

/// Intervals narrower than this (in the unit parameter) are not halved
/// further: only a cluster of critical points (a multiple root of `p'`)
/// gets there, where `p` is flat to second order.
pub(crate) const MIN_WIDTH: f64 = 1.0 / (1u64 << 42) as f64;

/// Newton or bisection steps on `p'` before the bracket is accepted.
const MAX_ROOT_STEPS: usize = 200;

/// The best value found so far and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Best {
    /// The smallest value of the polynomial found (`+inf`: none yet).
    pub value: f64,
    /// Where (unit parameter).
    pub s: f64,
    /// Whose (the caller's tag, an element index).
    pub tag: usize,
}

impl Best {
    pub fn none() -> Best {
        Best {
            value: f64::INFINITY,
            s: 0.0,
            tag: usize::MAX,
        }
    }

    #[inline]
    pub fn consider(&mut self, value: f64, s: f64, tag: usize) {
        if value < self.value {
            *self = Best { value, s, tag };
        }
    }
}

/// `out[i]`, the Bernstein coefficients on `[0, 1]` of the polynomial with
/// power coefficients `a` (ascending): `b_i = sum_{j <= i} C(i, j) / C(n, j)
/// a_j`.
pub(crate) fn to_bernstein(a: &[f64], out: &mut [f64]) {
    let n = a.len() - 1;
    // C(i, j) / C(n, j) built row by row: ratio(i, j) = prod_{k<j} (i-k)/(n-k)
    for (i, o) in out.iter_mut().enumerate().take(n + 1) {
        let mut ratio = 1.0;
        let mut sum = a[0];
        for (j, &aj) in a.iter().enumerate().take(i + 1).skip(1) {
            ratio *= (i + 1 - j) as f64 / (n + 1 - j) as f64;
            sum += ratio * aj;
        }
        *o = sum;
    }
}

/// De Casteljau's subdivision of Bernstein coefficients `b` at `t` in
/// `[0, 1]` of their interval: the coefficients on the left part into
/// `left` and on the right part into `right`.
pub(crate) fn split(b: &[f64], t: f64, left: &mut [f64], right: &mut [f64]) {
    let n = b.len();
    right[..n].copy_from_slice(b);
    let u = 1.0 - t;
    for (r, l) in left.iter_mut().enumerate().take(n) {
        *l = right[0];
        for i in 0..n - 1 - r {
            right[i] = u * right[i] + t * right[i + 1];
        }
    }
    // the last pass leaves right[0] = p(t), which left[n - 1] must hold too
    left[n - 1] = right[0];
}

/// The Bernstein coefficients of the same polynomial on the sub-interval
/// `[lo, hi]` of their interval (`0 <= lo <= hi <= 1`), into `out`;
/// `scratch` holds at least `2 b.len()` values.
pub(crate) fn restrict(b: &[f64], lo: f64, hi: f64, out: &mut [f64], scratch: &mut [f64]) {
    let n = b.len();
    let (upto, rest) = scratch[..2 * n].split_at_mut(n);
    // [0, hi] first, then its part from lo / hi on
    if hi < 1.0 {
        split(b, hi, upto, rest);
    } else {
        upto.copy_from_slice(b);
    }
    if lo > 0.0 {
        let t = if hi > 0.0 { (lo / hi).min(1.0) } else { 1.0 };
        split(upto, t, rest, out);
    } else {
        out[..n].copy_from_slice(upto);
    }
}

/// Sign variations of the forward differences `b_{i+1} - b_i` (the
/// derivative's Bernstein coefficients up to a positive factor), zeros
/// skipped, with the first and the last difference.
#[inline]
pub(crate) fn derivative_variations(b: &[f64]) -> (usize, f64, f64) {
    let n = b.len();
    if n < 2 {
        return (0, 0.0, 0.0);
    }
    let mut v = 0;
    let mut last = 0i8;
    for w in b.windows(2) {
        let d = w[1] - w[0];
        let s = if d > 0.0 {
            1
        } else if d < 0.0 {
            -1
        } else {
            0
        };
        if s != 0 {
            if last != 0 && s != last {
                v += 1;
            }
            last = s;
        }
    }
    (v, b[1] - b[0], b[n - 1] - b[n - 2])
}

/// `p(s)` by Horner's rule from power coefficients.
#[inline]
pub(crate) fn value(a: &[f64], s: f64) -> f64 {
    a.iter().rev().fold(0.0, |acc, &c| acc * s + c)
}

/// `(p'(s), p''(s))` from power coefficients.
#[inline]
pub(crate) fn derivatives(a: &[f64], s: f64) -> (f64, f64) {
    let (mut f, mut df) = (0.0, 0.0);
    for j in (1..a.len()).rev() {
        df = df * s + f;
        f = f * s + j as f64 * a[j];
    }
    (f, df)
}

/// The root of `p'` in `[lo, hi]`, given that `p'` goes from negative at
/// `lo` to positive at `hi` (`rising`) or the other way: Newton's method
/// kept inside a shrinking bracket, bisection whenever Newton would leave
/// it, to the resolution of `f64`.
pub(crate) fn derivative_root(a: &[f64], mut lo: f64, mut hi: f64, rising: bool) -> f64 {
    let mut s = 0.5 * (lo + hi);
    for _ in 0..MAX_ROOT_STEPS {
        let (f, df) = derivatives(a, s);
        if f == 0.0 {
            return s;
        }
        // keep the bracket: below the root p' has the sign it has at lo
        if (f < 0.0) == rising {
            lo = s;
        } else {
            hi = s;
        }
        let newton = s - f / df;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let step = (next - s).abs();
        s = next;
        if step <= 2.0 * f64::EPSILON * s.abs().max(f64::MIN_POSITIVE) || hi - lo <= 0.0 {
            break;
        }
        if hi - lo <= 4.0 * f64::EPSILON * lo.abs().max(hi.abs()) {
            s = 0.5 * (lo + hi);
            break;
        }
    }
    s
}

/// The roots of `p` (power coefficients `a`, ascending) inside `(0, 1)`,
/// ascending: intervals are halved until the Bernstein coefficients show
/// at most one sign change (Descartes' rule in the Bernstein basis: none,
/// no root; one, exactly one, of odd multiplicity), and each single root
/// is located as the critical point of `p`'s antiderivative (to the
/// resolution of `f64`). A root of even multiplicity, where `p` touches 0
/// without changing sign, may be missed; the sign of `p` between the roots
/// returned is constant, which is what they are for.
pub(crate) fn roots(a: &[f64]) -> Vec<f64> {
    let n1 = a.len();
    if n1 < 2 {
        return Vec::new();
    }
    // the antiderivative: its critical points are p's roots
    let mut anti = vec![0.0; n1 + 1];
    for (j, &aj) in a.iter().enumerate() {
        anti[j + 1] = aj / (j + 1) as f64;
    }
    let sign_changes = |b: &[f64]| {
        let mut v = 0;
        let mut last = 0.0f64;
        for &x in b {
            if x != 0.0 {
                if last != 0.0 && x.signum() != last.signum() {
                    v += 1;
                }
                last = x;
            }
        }
        v
    };
    let mut b = vec![0.0; n1];
    to_bernstein(a, &mut b);
    let mut out = Vec::new();
    let mut stack: Vec<(f64, f64, Vec<f64>)> = vec![(0.0, 1.0, b)];
    let (mut left, mut right) = (vec![0.0; n1], vec![0.0; n1]);
    while let Some((lo, hi, b)) = stack.pop() {
        match sign_changes(&b) {
            0 => {}
            1 if b[0] != 0.0 && b[n1 - 1] != 0.0 => {
                out.push(derivative_root(&anti, lo, hi, b[0] < 0.0));
            }
            _ if hi - lo <= MIN_WIDTH => out.push(0.5 * (lo + hi)),
            _ => {
                split(&b, 0.5, &mut left, &mut right);
                let mid = 0.5 * (lo + hi);
                // the right half first, so the left is popped first
                stack.push((mid, hi, right.clone()));
                stack.push((lo, mid, left.clone()));
            }
        }
    }
    out.retain(|&r| r > 0.0 && r < 1.0);
    out.sort_by(f64::total_cmp);
    out.dedup();
    out
}

/// Reusable buffers of the branch and bound.
#[derive(Debug, Default)]
pub(crate) struct Search {
    /// Coefficients of the pending intervals, `n + 1` per interval.
    pool: Vec<f64>,
    /// Pending intervals `(lo, hi)`, in step with `pool`.
    stack: Vec<(f64, f64)>,
    cur: Vec<f64>,
    left: Vec<f64>,
    right: Vec<f64>,
}

impl Search {
    /// Starts a search over `[lo, hi]` with the Bernstein coefficients `b`.
    fn start(&mut self, b: &[f64], lo: f64, hi: f64) {
        let n1 = b.len();
        if self.cur.len() < n1 {
            self.cur.resize(n1, 0.0);
            self.left.resize(n1, 0.0);
            self.right.resize(n1, 0.0);
        }
        self.pool.clear();
        self.stack.clear();
        self.pool.extend_from_slice(b);
        self.stack.push((lo, hi));
    }

    /// Takes the next pending interval, its coefficients into `cur`.
    fn pop(&mut self, n1: usize) -> Option<(f64, f64)> {
        let (lo, hi) = self.stack.pop()?;
        let start = self.pool.len() - n1;
        self.cur[..n1].copy_from_slice(&self.pool[start..]);
        self.pool.truncate(start);
        Some((lo, hi))
    }

    /// Halves the interval in `cur` at its middle into `left` and `right`.
    fn halve(&mut self, n1: usize) {
        split(
            &self.cur[..n1],
            0.5,
            &mut self.left[..n1],
            &mut self.right[..n1],
        );
    }

    /// Pushes both halves made by [`Search::halve`]; the left one is popped
    /// first when `left_first`.
    fn push_halves(&mut self, n1: usize, (lo, mid, hi): (f64, f64, f64), left_first: bool) {
        let (later, sooner) = if left_first {
            ((mid, hi, &self.right), (lo, mid, &self.left))
        } else {
            ((lo, mid, &self.left), (mid, hi, &self.right))
        };
        // pushed last is popped first
        self.pool.extend_from_slice(&later.2[..n1]);
        self.stack.push((later.0, later.1));
        self.pool.extend_from_slice(&sooner.2[..n1]);
        self.stack.push((sooner.0, sooner.1));
    }

    /// Lowers `best` to the minimum of `p` (power coefficients `a`, any
    /// degree) over `[lo, hi]`, given `p`'s Bernstein coefficients `b` on
    /// that interval: every value `best` ends with is a value of `p` at its
    /// `s`, and no point of `[lo, hi]` is lower than it by more than
    /// `tol(best)`. A minimum at a simple critical point is located to the
    /// resolution of `f64`; `tol` only stops the halving of intervals with
    /// several critical points (a flat stretch of `p`).
    pub fn minimise(
        &mut self,
        a: &[f64],
        b: &[f64],
        (lo, hi): (f64, f64),
        tag: usize,
        best: &mut Best,
        tol: &dyn Fn(f64) -> f64,
    ) {
        let n1 = b.len();
        best.consider(b[0], lo, tag);
        best.consider(b[n1 - 1], hi, tag);
        self.start(b, lo, hi);
        while let Some((lo, hi)) = self.pop(n1) {
            let c = &self.cur[..n1];
            let bound = c.iter().copied().fold(f64::INFINITY, f64::min);
            if bound >= best.value {
                continue;
            }
            let (v, first, last) = derivative_variations(c);
            if v == 0 {
                // monotone: its ends are already candidates
                continue;
            }
            if v == 1 && first != 0.0 && last != 0.0 {
                if first < 0.0 {
                    // one critical point, a minimum: located exactly
                    let s = derivative_root(a, lo, hi, true);
                    best.consider(value(a, s), s, tag);
                }
                // else one maximum: the minimum is at an end
                continue;
            }
            // several critical points: halved unless nothing in here can be
            // lower than the best by more than the tolerance
            if bound >= best.value - tol(best.value) || hi - lo <= MIN_WIDTH {
                continue;
            }
            let mid = 0.5 * (lo + hi);
            self.halve(n1);
            best.consider(self.left[n1 - 1], mid, tag);
            // the half with the lower bound is searched first
            let lmin = self.left[..n1]
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            let rmin = self.right[..n1]
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            self.push_halves(n1, (lo, mid, hi), lmin <= rmin);
        }
    }

    /// The sign change of `p'` in `[lo, hi]` nearest to `lo` (`forward`) or
    /// to `hi`, given `p`'s Bernstein coefficients `b` on `[lo, hi]`; `None`
    /// when `p'` keeps its sign there (zeros of even multiplicity aside; a
    /// cluster of critical points narrower than [`MIN_WIDTH`] counts as
    /// one, at its middle).
    pub fn nearest_critical(
        &mut self,
        a: &[f64],
        b: &[f64],
        lo: f64,
        hi: f64,
        forward: bool,
    ) -> Option<f64> {
        let n1 = b.len();
        self.start(b, lo, hi);
        while let Some((lo, hi)) = self.pop(n1) {
            let (v, first, last) = derivative_variations(&self.cur[..n1]);
            if v == 0 {
                continue;
            }
            if v == 1 && first != 0.0 && last != 0.0 {
                return Some(derivative_root(a, lo, hi, first < 0.0));
            }
            if hi - lo <= MIN_WIDTH {
                return Some(0.5 * (lo + hi));
            }
            // the near half is popped first
            self.halve(n1);
            self.push_halves(n1, (lo, 0.5 * (lo + hi), hi), forward);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn bern(a: &[f64]) -> Vec<f64> {
        let mut b = vec![0.0; a.len()];
        to_bernstein(a, &mut b);
        b
    }

    /// The Bernstein form evaluated directly, `sum_i b_i C(n,i) s^i (1-s)^(n-i)`.
    fn bernstein_value(b: &[f64], s: f64) -> f64 {
        let n = b.len() - 1;
        let mut binom = 1.0;
        let mut sum = 0.0;
        for (i, &bi) in b.iter().enumerate() {
            if i > 0 {
                binom *= (n + 1 - i) as f64 / i as f64;
            }
            sum += bi * binom * s.powi(i as i32) * (1.0 - s).powi((n - i) as i32);
        }
        sum
    }

    /// The minimum over `[lo, hi]` by this module.
    fn minimum(a: &[f64], lo: f64, hi: f64) -> Best {
        let b = bern(a);
        let mut r = vec![0.0; a.len()];
        let mut scratch = vec![0.0; 2 * a.len()];
        restrict(&b, lo, hi, &mut r, &mut scratch);
        let mut best = Best::none();
        Search::default().minimise(a, &r, (lo, hi), 0, &mut best, &|_| 0.0);
        best
    }

    /// Dense samples: the lowest, and a Lipschitz bound of p on [lo, hi].
    fn sampled(a: &[f64], lo: f64, hi: f64, n: usize) -> (f64, f64) {
        let mut low = f64::INFINITY;
        for i in 0..=n {
            let s = lo + (hi - lo) * i as f64 / n as f64;
            low = low.min(value(a, s));
        }
        // |p'| <= sum_j j |a_j| max(|lo|, |hi|)^(j-1)
        let m = lo.abs().max(hi.abs()).max(1.0);
        let lip = a
            .iter()
            .enumerate()
            .skip(1)
            .map(|(j, c)| j as f64 * c.abs() * m.powi(j as i32 - 1))
            .sum::<f64>();
        (low, lip)
    }

    #[test]
    fn bernstein_form_is_the_same_polynomial() {
        let a = [0.3, -2.0, 5.0, -1.0, 0.25, 0.7];
        let b = bern(&a);
        for i in 0..=10 {
            let s = i as f64 / 10.0;
            assert!((bernstein_value(&b, s) - value(&a, s)).abs() < 1e-13);
        }
        // subdivision: each half's coefficients describe the same polynomial
        let mut l = vec![0.0; 6];
        let mut r = vec![0.0; 6];
        split(&b, 0.3, &mut l, &mut r);
        for i in 0..=10 {
            let u = i as f64 / 10.0;
            assert!((bernstein_value(&l, u) - value(&a, 0.3 * u)).abs() < 1e-13);
            assert!((bernstein_value(&r, u) - value(&a, 0.3 + 0.7 * u)).abs() < 1e-13);
        }
        let mut out = vec![0.0; 6];
        let mut scratch = vec![0.0; 12];
        restrict(&b, 0.2, 0.65, &mut out, &mut scratch);
        for i in 0..=10 {
            let u = i as f64 / 10.0;
            let s = 0.2 + 0.45 * u;
            assert!((bernstein_value(&out, u) - value(&a, s)).abs() < 1e-13);
        }
    }

    #[test]
    fn a_parabola_and_its_vertex() {
        // p = 3 (s - 0.37)^2 - 1: the minimum -1 at 0.37
        let a = [3.0 * 0.37 * 0.37 - 1.0, -6.0 * 0.37, 3.0];
        let best = minimum(&a, 0.0, 1.0);
        assert!((best.s - 0.37).abs() < 1e-15, "{best:?}");
        assert!((best.value + 1.0).abs() < 1e-15);
        // the vertex outside: the minimum at an end
        let best = minimum(&a, 0.5, 1.0);
        assert_eq!(best.s, 0.5);
        // a constant and a line
        assert_eq!(minimum(&[2.0], 0.0, 1.0).value, 2.0);
        let best = minimum(&[1.0, -3.0], 0.0, 1.0);
        assert_eq!((best.value, best.s), (-2.0, 1.0));
    }

    #[test]
    fn a_double_root_of_the_derivative() {
        // p = (s - 0.4)^4: p' has a triple root, p a flat minimum 0 at 0.4
        let r = 0.4f64;
        let a = [r.powi(4), -4.0 * r.powi(3), 6.0 * r * r, -4.0 * r, 1.0];
        let best = minimum(&a, 0.0, 1.0);
        assert!(best.value.abs() < 1e-15, "{best:?}");
        assert!((best.s - r).abs() < 1e-3, "{best:?}");
        // p = (s - 0.3)^3 on [0, 1]: no interior minimum (an inflection)
        let a = [-0.027, 0.27, -0.9, 1.0];
        let best = minimum(&a, 0.0, 1.0);
        assert_eq!(best.s, 0.0);
    }

    #[test]
    fn roots_of_products_of_known_factors() {
        // (s - 0.2)(s - 0.5)(s - 0.9), its negative, and one with a root at
        // an end of the interval and one outside it
        for (roots_in, scale) in [(vec![0.2, 0.5, 0.9], 1.0), (vec![0.2, 0.5, 0.9], -3.0)] {
            let mut a = vec![scale];
            for r in &roots_in {
                // multiply by (s - r)
                let mut next = vec![0.0; a.len() + 1];
                for (j, c) in a.iter().enumerate() {
                    next[j + 1] += c;
                    next[j] -= r * c;
                }
                a = next;
            }
            let found = roots(&a);
            assert_eq!(found.len(), 3, "{found:?}");
            for (f, r) in found.iter().zip(&roots_in) {
                assert!((f - r).abs() < 1e-14, "{f} vs {r}");
            }
        }
        // s^2 - 1.44: its root 1.2 lies outside, -1.2 too
        assert!(roots(&[-1.44, 0.0, 1.0]).is_empty());
        // a constant and a linear polynomial
        assert!(roots(&[2.0]).is_empty());
        let r = roots(&[-0.3, 1.0]);
        assert!(r.len() == 1 && (r[0] - 0.3).abs() < 1e-15, "{r:?}");
    }

    #[test]
    fn nearest_critical_points() {
        // p' = (s - 0.2)(s - 0.5)(s - 0.9): p = s^4/4 - 1.6/3 s^3 + 0.73/2 s^2 - 0.09 s
        let a = [0.0, -0.09, 0.365, -1.6 / 3.0, 0.25];
        let b = bern(&a);
        let mut search = Search::default();
        let f = search.nearest_critical(&a, &b, 0.0, 1.0, true).unwrap();
        assert!((f - 0.2).abs() < 1e-14, "{f}");
        let g = search.nearest_critical(&a, &b, 0.0, 1.0, false).unwrap();
        assert!((g - 0.9).abs() < 1e-14, "{g}");
        let mut r = vec![0.0; 5];
        let mut scratch = vec![0.0; 10];
        restrict(&b, 0.3, 0.8, &mut r, &mut scratch);
        let h = search.nearest_critical(&a, &r, 0.3, 0.8, false).unwrap();
        assert!((h - 0.5).abs() < 1e-14, "{h}");
        restrict(&b, 0.55, 0.85, &mut r, &mut scratch);
        assert_eq!(search.nearest_critical(&a, &r, 0.55, 0.85, true), None);
    }

    fn poly() -> impl Strategy<Value = Vec<f64>> {
        prop::collection::vec(-10.0f64..10.0, 1..10)
    }

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: 2000,
            failure_persistence: None,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0xbe25_7e1d),
            ..ProptestConfig::default()
        })]

        /// The minimum is at most every sample and exceeds the best one by
        /// no more than the Lipschitz bound times half the spacing.
        #[test]
        fn minimum_against_dense_sampling(a in poly(), lo in 0.0f64..1.0, w in 0.0f64..1.0) {
            let hi = lo + (1.0 - lo) * w;
            let best = minimum(&a, lo, hi);
            prop_assert!(best.s >= lo && best.s <= hi);
            let n = 20_000;
            let (low, lip) = sampled(&a, lo, hi, n);
            let scale = a.iter().map(|c| c.abs()).sum::<f64>();
            let rounding = 1e-13 * scale;
            prop_assert!(best.value <= low + rounding, "{best:?} above the sample minimum {low}");
            let spacing = (hi - lo) / n as f64;
            prop_assert!(best.value >= low - lip * spacing / 2.0 - rounding,
                "{best:?} below the samples' bound");
            // the value is the polynomial's at the reported place
            prop_assert!((best.value - value(&a, best.s)).abs() <= rounding);
        }

        /// A polynomial with a known interior minimum: `k (s - m)^2 (1 +
        /// c (s - m)^2) + d` with `c >= 0` has its minimum d at m alone.
        #[test]
        fn known_minimum(m in 0.0f64..1.0, k in 0.01f64..100.0, c in 0.0f64..10.0, d in -5.0f64..5.0) {
            // expand in powers of s: (s - m)^2 = s^2 - 2 m s + m^2
            let q = [m * m, -2.0 * m, 1.0];
            let mut q2 = [0.0; 5];
            for i in 0..3 { for j in 0..3 { q2[i + j] += q[i] * q[j]; } }
            let mut a = [0.0; 5];
            for i in 0..3 { a[i] += k * q[i]; }
            for i in 0..5 { a[i] += k * c * q2[i]; }
            a[0] += d;
            let best = minimum(&a, 0.0, 1.0);
            prop_assert!((best.value - d).abs() <= 1e-13 * (1.0 + k * (1.0 + c)), "{best:?}");
            // a simple root of p': located by Newton to rounding
            prop_assert!((best.s - m).abs() <= 1e-13 * (1.0 + c), "{best:?} vs {m}");
        }

        /// Roots of p' put in by hand are found, nearest first, from both ends.
        #[test]
        fn critical_points_in_order(mut roots in prop::collection::vec(0.02f64..0.98, 1..5)) {
            roots.sort_by(f64::total_cmp);
            roots.dedup_by(|x, y| (*x - *y).abs() < 0.02);
            // p' = prod (s - r_i); p = its antiderivative
            let mut d = vec![1.0];
            for &r in &roots {
                let mut next = vec![0.0; d.len() + 1];
                for (i, &c) in d.iter().enumerate() {
                    next[i + 1] += c;
                    next[i] -= r * c;
                }
                d = next;
            }
            let mut a = vec![0.0; d.len() + 1];
            for (i, &c) in d.iter().enumerate() {
                a[i + 1] = c / (i + 1) as f64;
            }
            let b = bern(&a);
            let mut search = Search::default();
            let first = search.nearest_critical(&a, &b, 0.0, 1.0, true).unwrap();
            prop_assert!((first - roots[0]).abs() < 1e-12, "{first} vs {roots:?}");
            let last = search.nearest_critical(&a, &b, 0.0, 1.0, false).unwrap();
            prop_assert!((last - roots[roots.len() - 1]).abs() < 1e-12, "{last} vs {roots:?}");
        }
    }
}
