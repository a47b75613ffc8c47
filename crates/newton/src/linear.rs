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
