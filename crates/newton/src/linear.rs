//! What a factorisation reports: the inertia of the matrix, or why it
//! could not be factorised.

/// Counts of positive and negative eigenvalues (Sylvester's inertia; a
/// successful factorisation has no zero eigenvalue).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Inertia {
    /// Positive eigenvalues.
    pub positive: usize,
    /// Negative eigenvalues.
    pub negative: usize,
}

impl Inertia {
    /// True when every eigenvalue is positive.
    pub fn is_positive_definite(&self) -> bool {
        self.negative == 0
    }
}

/// Why a matrix could not be factorised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FactorError {
    /// A Cholesky pivot was not positive: the matrix is not positive
    /// definite (row `index`, 0-based).
    #[error("not positive definite (pivot {index})")]
    NotPositiveDefinite {
        /// Row of the failing pivot.
        index: usize,
    },
    /// A pivot was (numerically) zero: the matrix is singular, or its
    /// leading block `block` is.
    #[error("singular (block {block})")]
    Singular {
        /// The block (or row) whose pivot vanished.
        block: usize,
    },
    /// An entry, or a quantity computed from them, was not finite.
    #[error("non-finite entry (block {block})")]
    NonFinite {
        /// The block where it showed.
        block: usize,
    },
    /// The eigenvalue iteration of a pivot did not converge.
    #[error("no convergence (block {block})")]
    NoConvergence {
        /// The block.
        block: usize,
    },
}

/// `max_i |v_i|` (0 for an empty slice; NaN entries propagate as NaN).
///
/// Branch-free, in four running maxima and one running NaN test, so that
/// it vectorises (a loop that returns at the first NaN, or folds one
/// maximum after the other, does not). The largest of numbers does not
/// depend on the order they are compared in, so this is the value of the
/// element-by-element loop, bit for bit.
pub(crate) fn norm_inf(v: &[f64]) -> f64 {
    let mut m = [0.0f64; 4];
    let mut nan = false;
    let mut chunks = v.chunks_exact(4);
    for c in &mut chunks {
        for (mi, x) in m.iter_mut().zip(c) {
            let a = x.abs();
            nan |= a.is_nan();
            *mi = if a > *mi { a } else { *mi };
        }
    }
    for (mi, x) in m.iter_mut().zip(chunks.remainder()) {
        let a = x.abs();
        nan |= a.is_nan();
        *mi = if a > *mi { a } else { *mi };
    }
    if nan {
        return f64::NAN;
    }
    m.into_iter().fold(0.0, |a, b| if b > a { b } else { a })
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub(crate) fn all_finite(v: &[f64]) -> bool {
    // Branch-free OR of per-element tests: vectorises (an integer
    // reduction), unlike a short-circuiting `all` or a float sum.
    let mut bad = false;
    for &x in v {
        bad |= !x.is_finite();
    }
    !bad
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vector_helpers() {
        assert_eq!(norm_inf(&[1.0, -3.0, 2.0]), 3.0);
        assert!(norm_inf(&[1.0, f64::NAN]).is_nan());
        assert!(norm_inf(&[f64::NAN, 1.0]).is_nan());
        assert_eq!(norm_inf(&[]), 0.0);
        assert_eq!(norm_inf(&[-0.0, 0.0]).to_bits(), 0.0f64.to_bits());
        // every length and position of the largest entry and of a NaN
        // (the four running maxima and the tail)
        for n in 1..=11 {
            for at in 0..n {
                let mut v: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
                v[at] = -5.0;
                assert_eq!(norm_inf(&v), 5.0, "n {n}, at {at}");
                v[at] = f64::NAN;
                assert!(norm_inf(&v).is_nan(), "n {n}, NaN at {at}");
                v[at] = f64::NEG_INFINITY;
                assert_eq!(norm_inf(&v), f64::INFINITY, "n {n}, -inf at {at}");
            }
        }
        assert_eq!(dot(&[1.0, 2.0], &[3.0, -1.0]), 1.0);
        assert!(all_finite(&[1.0, 2.0]));
        assert!(!all_finite(&[1.0, f64::INFINITY]));
        assert!(!all_finite(&[f64::NAN]));
    }
}
