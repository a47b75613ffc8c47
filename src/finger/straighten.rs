//! Newton's own unknowns: the spec's `straighten t by c*s^2;` statements
//! (docs/model.md section 4.2). In an element's scaled unknowns `x` Newton
//! solves for `y` with `y_t = x_t + c x_s^2` (every other entry equal), so
//! a parabolic valley of the energy, `x_t` following `-c x_s^2`, becomes a
//! straight one; the equilibria are the same points.
//!
//! With `x = T(y)` (`x_t = y_t - c y_s^2`) and `J = dx/dy = I + j e_t
//! e_s^T`, `j = -2 c y_s`, the energy's derivatives in `y` are `J^T g` and
//! `J^T H J + g_t (-2 c) e_s e_s^T`. `J` acts within an element, so the
//! chain's coupling vectors transform the same way and the structured
//! Hessian keeps its form. No unknown is both a target and a source (the
//! spec parser checks), so the statements apply one after another.

use crate::lanes::{Lane, LaneScalar};
use crate::model::{upper_index, ModelCore, Vector};

/// `x` to Newton's `y`, element by element (`values` holds whole
/// elements).
pub(crate) fn to_newton<M: ModelCore>(values: &mut [f64]) {
    for e in values.chunks_mut(M::Coeffs::LEN) {
        for &(t, s, c) in M::STRAIGHTEN {
            e[t] += c * e[s] * e[s];
        }
    }
}

/// Whether `x` (whole elements) has a finite `y`.
pub(crate) fn representable<M: ModelCore>(values: &[f64]) -> bool {
    values.chunks(M::Coeffs::LEN).all(|e| {
        M::STRAIGHTEN
            .iter()
            .all(|&(t, s, c)| (e[t] + c * e[s] * e[s]).is_finite())
    })
}

/// Newton's `y` back to `x` (the exact inverse of [`to_newton`]).
pub(crate) fn from_newton<M: ModelCore>(values: &mut [f64]) {
    for e in values.chunks_mut(M::Coeffs::LEN) {
        for &(t, s, c) in M::STRAIGHTEN {
            e[t] -= c * e[s] * e[s];
        }
    }
}

/// `-2 c`, the factor of `J`'s entry (`f64` arithmetic where the lane
/// code's bounds would make `-2.0 * c` ambiguous).
#[inline(always)]
fn minus_twice(c: f64) -> f64 {
    -2.0 * c
}

/// `J^T v` for one element at Newton's `y` (a gradient or a coupling
/// vector in `x`, in place); on [`Lane`]s, for several elements at once.
#[inline(always)]
pub(crate) fn pull_back<M: ModelCore, L: Lane>(y: &[L], v: &mut [L])
where
    f64: LaneScalar<L>,
{
    for &(t, s, c) in M::STRAIGHTEN {
        v[s] += minus_twice(c) * y[s] * v[t];
    }
}

/// One element's scaled Hessian block (column-major, `LEN x LEN`) in `x`
/// to `y`: `J^T H J` plus the curvature of `T` times the gradient `g`
/// (the element's gradient in `x`, before [`pull_back`]).
#[inline(always)]
pub(crate) fn block<M: ModelCore, L: Lane>(y: &[L], g: &[L], h: &mut [L])
where
    f64: LaneScalar<L>,
{
    let n = M::Coeffs::LEN;
    for &(t, s, c) in M::STRAIGHTEN {
        let j = minus_twice(c) * y[s];
        // H J: column s gains j times column t
        for a in 0..n {
            h[a + n * s] += j * h[a + n * t];
        }
        // J^T (H J): row s gains j times row t
        for b in 0..n {
            h[s + n * b] += j * h[t + n * b];
        }
        h[s + n * s] += minus_twice(c) * g[t];
    }
}

/// One element's block as Newton sees it: `upper` (the Hessian in raw
/// unknowns, upper triangle) scaled by `s` on both sides into `h` (full,
/// column-major), then, where the unknowns are `straight`, carried to
/// Newton's `y` by [`block`] (`g` the element's scaled gradient in `x`).
#[inline(always)]
pub(crate) fn newton_block<M: ModelCore, L: Lane>(
    upper: &[L],
    s: &[L],
    y: &[L],
    g: &[L],
    straight: bool,
    h: &mut [L],
) where
    f64: LaneScalar<L>,
{
    let n = M::Coeffs::LEN;
    for b in 0..n {
        for a in 0..n {
            h[a + n * b] = upper[upper_index(n, a, b)] * (s[a] * s[b]);
        }
    }
    if straight {
        block::<M, L>(y, g, h);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ccm::Ccm;
    use crate::model::Across;

    /// A smooth test function of four unknowns with a parabolic valley.
    fn f(x: &[f64]) -> f64 {
        let v = x[1] + 2.0 / 3.0 * x[3] * x[3];
        3.0 * v * v + x[0] * x[0] * (1.0 + x[3]) + 0.5 * x[2] * x[2] + (x[3] - 0.4).powi(4) + x[1]
    }

    fn in_y(y: &[f64]) -> f64 {
        let mut x = y.to_vec();
        from_newton::<Ccm>(&mut x);
        f(&x)
    }

    /// Central differences of `fun` at `p`: gradient and Hessian.
    fn differences(fun: &dyn Fn(&[f64]) -> f64, p: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let n = p.len();
        let h = 1e-4;
        let at = |d: &[(usize, f64)]| {
            let mut q = p.to_vec();
            for &(i, v) in d {
                q[i] += v;
            }
            fun(&q)
        };
        let g = (0..n)
            .map(|i| (at(&[(i, h)]) - at(&[(i, -h)])) / (2.0 * h))
            .collect();
        let mut hess = vec![0.0; n * n];
        for a in 0..n {
            for b in 0..n {
                hess[a + n * b] =
                    (at(&[(a, h), (b, h)]) - at(&[(a, h), (b, -h)]) - at(&[(a, -h), (b, h)])
                        + at(&[(a, -h), (b, -h)]))
                        / (4.0 * h * h);
            }
        }
        (g, hess)
    }

    #[test]
    fn the_change_of_unknowns_is_exact_and_its_derivatives_match_differences() {
        assert!(!Ccm::STRAIGHTEN.is_empty());
        let x = [0.3, -0.2, 0.1, -0.7];
        let mut y = x;
        to_newton::<Ccm>(&mut y);
        let mut back = y;
        from_newton::<Ccm>(&mut back);
        for i in 0..4 {
            assert!((back[i] - x[i]).abs() <= 1e-15, "{back:?}");
        }
        // derivatives in x, by differences, carried to y ...
        let (gx, mut h) = differences(&f, &x);
        let mut gy = gx.clone();
        block::<Ccm, f64>(&y, &gx, &mut h);
        pull_back::<Ccm, f64>(&y, &mut gy);
        // ... equal the differences of f(T(y)) in y
        let (gy_ref, hy_ref) = differences(&in_y, &y);
        for i in 0..4 {
            assert!((gy[i] - gy_ref[i]).abs() <= 1e-7, "{gy:?} {gy_ref:?}");
        }
        for i in 0..16 {
            assert!((h[i] - hy_ref[i]).abs() <= 1e-5, "{i}: {h:?} {hy_ref:?}");
        }
    }
}
