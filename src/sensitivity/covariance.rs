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
    /// semi-definite `C` may give a tiny negative by round-off). Where the
    /// sum overflows (variances near f64's largest), it is taken again
    /// with `g` and `C` scaled by their largest entries, so the answer is
    /// the standard deviation, not a NaN clamped to zero.
    pub fn sigma(&self, g: &[f64]) -> f64 {
        let quadratic = |gs: f64, cs: f64| {
            let mut v = 0.0;
            for (i, gi) in g.iter().enumerate() {
                for (j, gj) in g.iter().enumerate() {
                    v += gi / gs * (self.matrix[i][j] / cs) * (gj / gs);
                }
            }
            v
        };
        let v = quadratic(1.0, 1.0);
        if v.is_finite() {
            return v.max(0.0).sqrt();
        }
        let largest = |it: &mut dyn Iterator<Item = f64>| it.fold(0.0_f64, |m, x| m.max(x.abs()));
        let gs = largest(&mut g.iter().copied());
        let cs = largest(&mut self.matrix.iter().flatten().copied());
        if gs == 0.0 || cs == 0.0 {
            return 0.0;
        }
        gs * cs.sqrt() * quadratic(gs, cs).max(0.0).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cov(m: [[f64; 2]; 2]) -> Covariance {
        Covariance::checked(vec![Param::Kappa, Param::Kappa], m.map(Vec::from).to_vec())
    }

    /// Variances near f64's largest: the standard deviation by hand
    /// (sqrt(1e308) = 1e154, times |g|'s sum for a fully correlated pair),
    /// where the plain sum overflowed and came out as 0.
    #[test]
    fn variances_near_the_largest_float_keep_their_sigma() {
        let c = cov([[1e308, 1e308], [1e308, 1e308]]);
        let s = c.sigma(&[1.5, 1.5]);
        assert!((s / 3e154 - 1.0).abs() < 1e-14, "{s:e}");
        // anticorrelated derivatives cancel: zero, not NaN
        assert_eq!(c.sigma(&[2.0, -2.0]), 0.0);
        // an ordinary matrix: the plain sum, bit for bit
        let c = cov([[4.0, 1.0], [1.0, 9.0]]);
        let g = [0.3, -0.7];
        let plain =
            (0.3 * 4.0 * 0.3 + 0.3 * 1.0 * -0.7 + -0.7 * 1.0 * 0.3 + -0.7 * 9.0 * -0.7f64).sqrt();
        assert_eq!(c.sigma(&g), plain);
    }
}
