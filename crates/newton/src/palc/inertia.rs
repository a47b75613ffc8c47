//! The inertia of a Hessian restricted to a constraint's tangent space
//! (Haynsworth), from a symmetric factorisation.

use crate::linear::{all_finite, dot, FactorError, Inertia};
use crate::problem::LinearSystem;

/// Why the restricted inertia could not be computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum RestrictedInertiaError {
    /// The constraint gradient `c_x` is zero or holds a non-finite entry.
    #[error("constraint gradient is zero or not finite")]
    DegenerateConstraint,
    /// `H` itself could not be factorised with symmetric pivots (in
    /// particular: `H` singular). The Schur-complement route needs `H`
    /// nonsingular, even where the bordered matrix is not singular.
    #[error("the Hessian could not be factorised: {0}")]
    Hessian(FactorError),
    /// The Schur complement `c_x^T H^-1 c_x` is zero, or its sign
    /// contradicts the inertia of `H`: the bordered matrix is (numerically)
    /// singular, i.e. the restricted Hessian has a zero eigenvalue.
    #[error("the bordered matrix is singular (zero restricted eigenvalue)")]
    Singular,
    /// `H^-1 c_x` is not finite.
    #[error("non-finite solve with the Hessian")]
    NonFinite,
}

/// The inertia of `H` restricted to the tangent space `{v : c_x . v = 0}`
/// of a constraint, i.e. of `Z^T H Z` for an orthonormal basis `Z` of that
/// space (dimension `n - 1`), from a symmetric factorisation of `H`.
///
/// `h` must hold a successful factorisation of `H` itself (`tau = 0`,
/// typically [`PivotKind::Symmetric`](crate::PivotKind::Symmetric)) with inertia `inertia`, and `apply`
/// the same `H` (used for one step of iterative refinement of
/// `w = H^-1 c_x`). By Haynsworth's inertia additivity on the bordered
/// matrix `K = [[H, c_x], [c_x^T, 0]]`,
/// `inertia(K) = inertia(H) + inertia(-c_x^T H^-1 c_x)`, and since `K` is
/// congruent to `Z^T H Z` plus a 2 x 2 block with one positive and one
/// negative eigenvalue, the restricted inertia is that of `K` minus one
/// positive and one negative: with `sigma = c_x^T w`, `(p, q - 1)` for
/// `sigma < 0` and `(p - 1, q)` for `sigma > 0`, where `(p, q) = inertia`.
///
/// A nearly singular (but factorised) `H` is fine: the large component of
/// `w` along its near-null vector gives `sigma` the sign of the small
/// eigenvalue, which the restricted count then drops. An `H` singular to
/// the factorisation cannot be used (see
/// [`RestrictedInertiaError::Hessian`] from [`factor_restricted_inertia`]),
/// even when `K` is regular.
///
/// `work` is scratch of length at least `2 n`; nothing is allocated.
///
/// # Panics
/// If `c_x.len() * 2 > work.len()`.
pub fn restricted_inertia<L: LinearSystem + ?Sized>(
    h: &mut L,
    inertia: Inertia,
    c_x: &[f64],
    work: &mut [f64],
) -> Result<Inertia, RestrictedInertiaError> {
    let n = c_x.len();
    assert!(
        work.len() >= 2 * n,
        "restricted_inertia: work.len() must be at least 2 * c_x.len()"
    );
    let (w, r) = work.split_at_mut(n);
    restricted_inertia_with(h, inertia, c_x, w, &mut r[..n])
}

/// [`restricted_inertia`] with the scratch as two vectors of length `n`.
pub(crate) fn restricted_inertia_with<L: LinearSystem + ?Sized>(
    h: &mut L,
    inertia: Inertia,
    c_x: &[f64],
    w: &mut [f64],
    r: &mut [f64],
) -> Result<Inertia, RestrictedInertiaError> {
    if !all_finite(c_x) || c_x.iter().all(|&c| c == 0.0) {
        return Err(RestrictedInertiaError::DegenerateConstraint);
    }
    w.copy_from_slice(c_x);
    h.solve(w);
    // one step of iterative refinement: w += H^-1 (c - H w)
    h.apply(w, r);
    for (ri, ci) in r.iter_mut().zip(c_x) {
        *ri = ci - *ri;
    }
    h.solve(r);
    for (wi, ri) in w.iter_mut().zip(r.iter()) {
        *wi += ri;
    }
    if !all_finite(w) {
        return Err(RestrictedInertiaError::NonFinite);
    }
    let sigma = dot(c_x, w);
    let Inertia { positive, negative } = inertia;
    if sigma < 0.0 && negative > 0 {
        Ok(Inertia {
            positive,
            negative: negative - 1,
        })
    } else if sigma > 0.0 && positive > 0 {
        Ok(Inertia {
            positive: positive - 1,
            negative,
        })
    } else {
        Err(RestrictedInertiaError::Singular)
    }
}

/// Factorises `h` (`H`, symmetric pivots, no shift) and returns its
/// inertia restricted to `{v : c_x . v = 0}` ([`restricted_inertia`]).
/// `Err(Hessian(Singular))` when `H` is singular (the restricted inertia is
/// then not determined by this route, see [`restricted_inertia`]).
///
/// # Panics
/// If `c_x.len() * 2 > work.len()`.
pub fn factor_restricted_inertia<L: LinearSystem + ?Sized>(
    h: &mut L,
    c_x: &[f64],
    work: &mut [f64],
) -> Result<Inertia, RestrictedInertiaError> {
    let inertia =
        crate::problem::factor_cholesky_first(h).map_err(RestrictedInertiaError::Hessian)?;
    restricted_inertia(h, inertia, c_x, work)
}
