//! Exact sensitivities of an equilibrium with respect to design and load
//! parameters (docs/model.md, "Sensitivities").
//!
//! At an equilibrium `grad Pi(K*, p) = 0` the implicit function theorem
//! gives `dK/dp = -H^-1 d(grad Pi)/dp`, with `H` the Hessian the solver
//! factorises anyway (the chain's [`fpc_newton::Semiseparable`]): one
//! factorisation, then one `O(N)` solve per parameter. The right-hand
//! sides are exact:
//!
//! - an actuator parameter moves the blocks (`src/actuator/tangent.rs`,
//!   `element_block_tangents`); each integral family's energy is linear
//!   in its moments, so `d(grad Pi)/dp` is the model's own gradient kernel
//!   evaluated at the moments' derivative, which the generated
//!   `*_dmoments` kernels add up box by box ([`crate::model::Tangents::add_linear_tangents`], ...);
//! - the pressure and `kappa` enter through `kp = kappa P`, which
//!   multiplies the gas family ([`crate::model::Tangents::scalars_tangent`]);
//! - a tip force `F` enters through `-F . tip`: `d(grad Pi)/dF = -grad tip`.
//!
//! A target solve ([`crate::finger::Solver::solve_target`]) adds the load factor
//! `lambda` and the target equation `c = w . tip - target = 0`; its
//! sensitivities solve the bordered system
//! `[[H, g_lambda], [c_x^T, c_lambda]] (dK, dlambda) = -(dg/dp, dc/dp)` by
//! block elimination on the same factorisation.
//!
//! Everything runs in the solver's scaled unknowns
//! ([`Finger::unknown_scales`]); `dK/dp` is returned in raw coefficients.

mod compute;
mod covariance;
mod envelope;
mod gripper;
mod midplane;
mod params;
mod record;

use compute::{compute, Request, State};
pub use compute::{EQUILIBRIUM_TOLERANCE, TARGET_TOLERANCE};
pub use covariance::Covariance;
pub use envelope::{EnvelopeSensitivities, EnvelopeSensitivity, ENVELOPE_STATIONARITY};
pub use gripper::{
    GeometrySensitivity, GraspKind, GraspSensitivities, GraspSensitivity, GripperParam,
    SizeSensitivity,
};
pub(crate) use midplane::{points_and_tangents, radius_rows, shape_sites, site_at, Site};
pub use params::Param;
pub use record::{Sensitivities, Sensitivity};

use crate::actuator::Actuator;
use crate::finger::{CoreVisitor, Finger, FingerCore, Load, Solution, TargetProblem};
use crate::model::ElementModel;
use crate::solve_error::SolveError;

/// The sensitivities of a request, with the finger's typed core.
struct Compute<'a>(&'a Request<'a>);

impl CoreVisitor for Compute<'_> {
    type Output = Result<Sensitivities, SolveError>;
    fn visit<M: ElementModel>(self, core: &FingerCore<M>) -> Self::Output {
        compute(core, self.0)
    }
}

impl Finger {
    /// The sensitivities of the equilibrium `solution` under `load` with
    /// respect to `params`: d(tip, end angle, energy, K)/dp by the implicit
    /// function theorem, one factorisation of the Hessian and one solve per
    /// parameter. `actuator` must be the one the finger was built from
    /// (checked: its blocks must give the finger's moments, with or without
    /// ribs); [`Param::Target`] is not a parameter here.
    pub fn sensitivities(
        &self,
        actuator: &Actuator,
        solution: &Solution,
        load: &Load,
        params: &[Param],
    ) -> Result<Sensitivities, SolveError> {
        self.visit_core(Compute(&Request {
            actuator,
            coefficients: &solution.coefficients,
            state: State::Load(load),
            params,
        }))
    }

    /// The sensitivities of a target solve's equilibrium ([`crate::finger::Solver::solve_target`]
    /// returned `solution` and `lambda`): the load factor moves with the
    /// parameters to keep the target, so every derivative, d(lambda)/dp
    /// included, comes from the bordered system
    /// `[[H, g_lambda], [c_x^T, c_lambda]]`. [`Param::Fx`] and [`Param::Fz`]
    /// are the fixed part of the load (`problem.base`), [`Param::Target`]
    /// the target value.
    pub fn target_sensitivities(
        &self,
        actuator: &Actuator,
        solution: &Solution,
        problem: &TargetProblem,
        lambda: f64,
        params: &[Param],
    ) -> Result<Sensitivities, SolveError> {
        self.visit_core(Compute(&Request {
            actuator,
            coefficients: &solution.coefficients,
            state: State::Target { problem, lambda },
            params,
        }))
    }
}
