//! A covariance of parameters ([`Covariance`]) and the first-order
//! propagation through sensitivities it carries: `sigma_y^2 = g^T C g`
//! with `g = dy/dp`. A scene's `[calibration]` table is checked into one
//! (`crate::scene`); a scene's solve and `fpc paper`'s study bands
//! propagate it.

use super::params::Param;

/// A checked covariance: the parameters it is over, in the table's order,
/// and the symmetric positive semi-definite matrix (built by
/// [`crate::scene::Scene`] from a `[calibration]` table, which checks it).
#[derive(Debug, Clone, PartialEq)]
pub struct Covariance {
    params: Vec<Param>,
    matrix: Vec<Vec<f64>>,
}

impl Covariance {
    /// A covariance the caller has checked (square, as large as `params`,
    /// symmetric positive semi-definite).
    pub(crate) fn checked(params: Vec<Param>, matrix: Vec<Vec<f64>>) -> Covariance {
        Covariance { params, matrix }
    }

    /// The parameters, in the table's order.
    pub fn params(&self) -> &[Param] {
        &self.params
    }

    /// The matrix, one row per parameter.
    pub fn matrix(&self) -> &[Vec<f64>] {
        &self.matrix
    }

    /// The standard deviation of parameter `i` (the root of its variance).
    pub fn standard_error(&self, i: usize) -> f64 {
        self.matrix[i][i].max(0.0).sqrt()
    }

    /// `g^T C g` as a standard deviation, for `g` the derivatives of one
    /// output along [`Covariance::params`] in order; clamped at zero (a
    /// semi-definite `C` may give a tiny negative by round-off).
    pub fn sigma(&self, g: &[f64]) -> f64 {
        let mut v = 0.0;
        for (i, gi) in g.iter().enumerate() {
            for (j, gj) in g.iter().enumerate() {
                v += gi * self.matrix[i][j] * gj;
            }
        }
        v.max(0.0).sqrt()
    }
}
