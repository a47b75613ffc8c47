//! 1-sigma bands on the studies' curves from a covariance of the
//! actuator's parameters (a calibrated scene's `[calibration]` table, as
//! `fpc paper --scene` reads it), by first-order propagation:
//! `sigma_y^2 = g^T C g` with `g = dy/dp` at each point of a curve
//! ([`Covariance::sigma`]).
//!
//! The studies set some parameters themselves: every curve is at its own
//! prestrain (`actuator.pemc.eps0`), and every finger is solved at the
//! default `load.kappa`. A covariance's variance of those does not move
//! the curves; [`BandParams`] propagates the others and says why it leaves
//! these out ([`BandParams::not_propagated`]).
//!
//! Which study has bands, and how each column's are computed
//! ([`EXACT`]), is in docs/calibration.md section 7.

use serde::Serialize;

use crate::actuator::ActuatorParam;
use crate::sensitivity::{Covariance, Param};

/// The method of a column whose band comes from the exact sensitivities
/// (implicit function theorem, src/sensitivity/) of its points.
pub const EXACT: &str = "first_order_exact";

/// The legend entry of a band.
pub(crate) const BAND_LABEL: &str = "± 1 sd (calibration covariance)";

/// A column's band and how it was computed, for a summary.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct BandColumn {
    /// The table column (`radius_mm_sd`).
    pub column: String,
    /// [`EXACT`].
    pub method: &'static str,
}

/// The entries of `columns`, each banded by the exact sensitivities.
pub(crate) fn exact_bands(columns: &[crate::report::Column]) -> Vec<BandColumn> {
    columns
        .iter()
        .map(|c| BandColumn {
            column: c.name.into(),
            method: EXACT,
        })
        .collect()
}

/// A covariance parameter a study does not propagate, and why.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct NotPropagated {
    /// The scene key.
    pub parameter: String,
    /// Why.
    pub reason: &'static str,
}

/// The parameters of a covariance the studies propagate.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BandParams<'a> {
    cov: &'a Covariance,
}

impl<'a> BandParams<'a> {
    pub fn new(cov: &'a Covariance) -> BandParams<'a> {
        BandParams { cov }
    }

    /// Why a parameter is not propagated (`None`: it is).
    fn excluded(p: Param) -> Option<&'static str> {
        match p {
            Param::Actuator(ActuatorParam::Eps0) => {
                Some("each curve of a study is at a prestrain the study sets")
            }
            Param::Kappa => Some("the studies solve every finger at the default load.kappa"),
            _ => None,
        }
    }

    /// The parameters propagated: the covariance's, less those the
    /// studies set themselves.
    pub fn params(&self) -> Vec<Param> {
        self.cov
            .params()
            .iter()
            .copied()
            .filter(|&p| Self::excluded(p).is_none())
            .collect()
    }

    /// The covariance's parameters that are not propagated, with why.
    fn not_propagated(cov: &Covariance) -> Vec<NotPropagated> {
        cov.params()
            .iter()
            .filter_map(|&p| {
                Self::excluded(p).map(|reason| NotPropagated {
                    parameter: p.name(),
                    reason,
                })
            })
            .collect()
    }

    /// The standard deviation of an output whose derivative along each
    /// propagated parameter is `d(p)` (in [`BandParams::params`]' order;
    /// the others count 0).
    pub fn sigma(&self, d: &[f64]) -> f64 {
        let propagated = self.params();
        let g: Vec<f64> = self
            .cov
            .params()
            .iter()
            .map(|p| {
                propagated
                    .iter()
                    .position(|q| q == p)
                    .map_or(0.0, |k| d.get(k).copied().unwrap_or(0.0))
            })
            .collect();
        self.cov.sigma(&g)
    }
}

/// The parameters of `cov` the studies' bands leave out, and why (the
/// prestrain each curve sets, the default `load.kappa`).
pub fn not_propagated(cov: &Covariance) -> Vec<NotPropagated> {
    BandParams::not_propagated(cov)
}
