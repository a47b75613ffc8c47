//! The element model: the runtime trait that generated code implements.
//!
//! Every `energy-spec/*.spec` becomes a module here (`ccm`, ...) whose
//! model type implements [`ElementModel`] (build.rs, `crates/modelgen`).
//! The rest of the library is generic over the trait and never calls a
//! generated function by name: the unknowns, their scaling, which of them
//! are local to an element, how the energies combine, the end kinematics,
//! the mid-plane and the material law all come from the spec.
//! [`ModelId`] names the generated models at run time (`--model NAME`,
//! `[model] name = ...`).

use std::fmt::Debug;
use std::ops::{Index, IndexMut};

pub use crate::lanes::{Lane, LaneScalar};

/// A fixed-size vector of `f64`: an element's unknowns, or the upper
/// triangle of its Hessian.
pub trait Vector:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + AsRef<[f64]>
    + AsMut<[f64]>
    + Index<usize, Output = f64>
    + IndexMut<usize>
{
    /// Number of entries.
    const LEN: usize;
    /// All zero.
    fn zero() -> Self;
    /// Entry `i` is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self;
}

impl<const N: usize> Vector for [f64; N] {
    const LEN: usize = N;
    fn zero() -> Self {
        [0.0; N]
    }
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
        std::array::from_fn(f)
    }
}

/// An element model generated from an energy spec: its [`ModelCore`] (the
/// unknowns and names), its [`Energy`], its [`Kinematics`] and the
/// [`Tangents`] the sensitivities use. The generated models implement the
/// four; a caller bounds on the ones it uses (the validity checks need
/// only [`Kinematics`]), or on this trait for all of them.
pub trait ElementModel: Energy + Kinematics + Tangents {}

impl<M: Energy + Kinematics + Tangents> ElementModel for M {}

/// What a spec says of its unknowns beyond the energy: those of the
/// strain across the width (`across ...;`), which plane strain holds at
/// zero, and the changes of Newton's unknowns (`straighten ...;`).
/// Generated into `models.rs`, beside the model's own module.
pub trait Across {
    /// The positions of the unknowns across the width.
    const ACROSS: &'static [usize];
    /// `(t, s, c)`: Newton solves for `y_t = scaled_t + c scaled_s^2` in
    /// place of the scaled unknown `t` (src/finger/straighten.rs).
    const STRAIGHTEN: &'static [(usize, usize, f64)];
}

/// What every part of a model shares: the unknowns, their scaling, the
/// names. Hessians are upper triangles, row by row ([`upper_index`]).
pub trait ModelCore: Copy + Debug + Default + PartialEq + Send + Sync + Across + 'static {
    /// The element's unknowns.
    type Coeffs: Vector;
    /// The upper triangle of a Hessian over the unknowns.
    type Upper: Vector;
    /// Block moments of every integral of the energy, summed per element.
    type Moments: Clone + Debug + PartialEq + Send + Sync + 'static;

    /// The model's name (lower case; `--model NAME`).
    const NAME: &'static str;
    /// The spec it was generated from, relative to the repository.
    const SPEC_PATH: &'static str;
    /// The spec's header comment.
    const DESCRIPTION: &'static str;
    /// Names of the unknowns, in order.
    const UNKNOWNS: &'static [&'static str];
    /// Positions of the unknowns that couple only within their element.
    const LOCAL: &'static [usize];
    /// The integral families, in [`Energy::family_hessian`]'s order.
    const FAMILIES: &'static [&'static str];
    /// The degree in `x` of the mid-plane (the generator checks that the
    /// spec's `point midplane(x)` is a polynomial in `x`).
    const MIDPLANE_DEGREE: usize;

    /// The raw value of one unit of each scaled unknown (`raw = scaled * unscale`)
    /// for an element of length `length`.
    fn unscale(length: f64) -> Self::Coeffs;
}

/// The element's energy: its moments built box by box, the potential with
/// its gradient and Hessian, the families alone, the prestressed law.
pub trait Energy: ModelCore {
    /// Moments of an element without blocks.
    fn zero_moments() -> Self::Moments;
    /// Adds a linear lamina's box.
    fn add_linear(m: &mut Self::Moments, p: &LinearParams);
    /// Adds a box of the prestressed layer.
    fn add_prestressed(m: &mut Self::Moments, p: &PrestressedParams);
    /// Adds a box of the gas volume.
    fn add_gas(m: &mut Self::Moments, p: &GasParams);
    /// The element's potential.
    fn energy(m: &Self::Moments, k: &Self::Coeffs, s: &EnergyScalars) -> f64;
    /// Potential and gradient.
    fn gradient(m: &Self::Moments, k: &Self::Coeffs, s: &EnergyScalars) -> (f64, Self::Coeffs);
    /// Potential, gradient and Hessian.
    fn hessian(
        m: &Self::Moments,
        k: &Self::Coeffs,
        s: &EnergyScalars,
    ) -> (f64, Self::Coeffs, Self::Upper);
    /// The moments of several elements side by side, one per lane
    /// ([`crate::lanes`]).
    type MomentLanes<L: Lane>: Clone + Debug + Send + Sync;
    /// Lane `l` holds `m[l]`'s moments; lanes past the end of `m` repeat
    /// its last element. `m` must not be empty.
    fn moment_lanes<L: Lane>(m: &[&Self::Moments]) -> Self::MomentLanes<L>;
    /// [`Energy::energy`] of up to `L::WIDTH` elements at once: element
    /// `l` has the moments of lane `l` of `m` and the unknowns `k[l]`, and
    /// its result goes to `out[l]`, bit for bit the scalar one.
    fn energy_lanes<L: Lane>(
        m: &Self::MomentLanes<L>,
        k: &[Self::Coeffs],
        s: &EnergyScalars,
        out: &mut [f64],
    ) where
        f64: LaneScalar<L>;
    /// [`Energy::gradient`] of up to `L::WIDTH` elements at once (as
    /// [`Energy::energy_lanes`]).
    fn gradient_lanes<L: Lane>(
        m: &Self::MomentLanes<L>,
        k: &[Self::Coeffs],
        s: &EnergyScalars,
        out: &mut [(f64, Self::Coeffs)],
    ) where
        f64: LaneScalar<L>;
    /// [`Energy::hessian`] of up to `L::WIDTH` elements at once, left in
    /// lanes and handed to `put` as the value, the gradient's `LEN` entries
    /// and the upper triangle's: lane `l` of each is element `l`'s, bit for
    /// bit the scalar result (lanes past the end of `k` repeat its last
    /// element). False, without calling `put`, for no elements.
    fn hessian_lane_major<L: Lane>(
        m: &Self::MomentLanes<L>,
        k: &[Self::Coeffs],
        s: &EnergyScalars,
        put: impl FnOnce(&L, &[L], &[L]),
    ) -> bool
    where
        f64: LaneScalar<L>;
    /// One integral family alone (`None` past the last family).
    fn family_hessian(
        m: &Self::Moments,
        family: usize,
        k: &Self::Coeffs,
    ) -> Option<(f64, Self::Coeffs, Self::Upper)>;
    /// The prestressed law: `[psi, psi', psi'']` at strain `s`.
    fn psi(s: f64, p: &PsiParams) -> [f64; 3];
}

/// The element's kinematics, in the runtime's order whatever the spec's:
/// `end` is `[Xe, Ze, eta]` (the element's end in its own frame and the end
/// tangent's angle), `frame` is `[Xe, Ze, dx, dz]` (the end and an
/// unnormalised end tangent), `midplane` `[X, Z]` and `tangent` `[dx, dz]`
/// at a local coordinate `x`.
pub trait Kinematics: ModelCore {
    /// `[Xe, Ze, eta]`.
    fn end(k: &Self::Coeffs, length: f64) -> [f64; 3];
    /// `[Xe, Ze, eta]` and their gradients.
    fn end_gradient(k: &Self::Coeffs, length: f64) -> ([f64; 3], [Self::Coeffs; 3]);
    /// `[Xe, Ze, eta]`, their gradients and Hessians.
    #[allow(clippy::type_complexity)]
    fn end_hessian(
        k: &Self::Coeffs,
        length: f64,
    ) -> ([f64; 3], [Self::Coeffs; 3], [Self::Upper; 3]);
    /// The gradients and Hessians of `[Xe, Ze, eta]`, without the values
    /// (the chain's Hessian needs no `atan2`).
    #[allow(clippy::type_complexity)]
    fn end_derivatives(k: &Self::Coeffs, length: f64) -> ([Self::Coeffs; 3], [Self::Upper; 3]);
    /// [`Kinematics::end_derivatives`] of several elements at once, lane
    /// `l` element `l`'s (unknowns `k`, `LEN` lanes, and length): the
    /// gradients of `[Xe, Ze, eta]` one after the other into `g` (`3 LEN`
    /// entries), their Hessians into `h`, bit for bit the scalar ones.
    fn end_derivatives_lanes<L: Lane>(k: &[L], length: L, g: &mut [L], h: &mut [L])
    where
        f64: LaneScalar<L>;
    /// `[Xe, Ze, dx, dz]`.
    fn frame(k: &Self::Coeffs, length: f64) -> [f64; 4];
    /// The mid-plane point at local `x`, in the element's frame.
    fn midplane(k: &Self::Coeffs, x: f64) -> [f64; 2];
    /// The mid-plane as a polynomial curve in local `x`: `out[j] = [X_j,
    /// Z_j]`, the coefficients of `x^j`, so that `midplane(k, x) = sum_j
    /// out[j] x^j`. Fills the first [`ModelCore::MIDPLANE_DEGREE`]` + 1`
    /// entries of `out` (all of a shorter slice).
    fn midplane_coefficients(k: &Self::Coeffs, out: &mut [[f64; 2]]);
    /// The mid-plane's tangent `(dX/dx, dZ/dx)` at local `x`.
    fn tangent(k: &Self::Coeffs, x: f64) -> [f64; 2];
    /// Axial strain at local `x` and height `z`.
    fn strain(k: &Self::Coeffs, x: f64, z: f64) -> f64;
    /// Signed curvature of the mid-plane at local `x` (1/mm; negative curls
    /// towards -Z).
    fn curvature(k: &Self::Coeffs, x: f64) -> f64;
}

/// The tangents of the energy along the actuator's and the load's
/// parameters (the exact sensitivities' right-hand sides).
pub trait Tangents: Energy {
    /// For each direction `dp[d]` of a linear box's parameters, adds the
    /// derivative of the box's moments along it to `m[d]`:
    /// `m[d] += (d moments / d p) dp[d]`, from one evaluation of the
    /// generated Jacobian (`linear_dmoments`, straight-line code); zero
    /// entries of `dp[d]` cost nothing. A unit `dp` gives one column. The
    /// energy is linear in the moments, so [`Energy::gradient`] at
    /// moments built this way is the gradient's derivative along `dp`.
    fn add_linear_tangents(m: &mut [Self::Moments], p: &LinearParams, dp: &[LinearParams]);
    /// The same for a prestressed box.
    fn add_prestressed_tangents(
        m: &mut [Self::Moments],
        p: &PrestressedParams,
        dp: &[PrestressedParams],
    );
    /// The same for a gas box.
    fn add_gas_tangents(m: &mut [Self::Moments], p: &GasParams, dp: &[GasParams]);
    /// One integral family's value and gradient alone, without its
    /// coefficient (`None` past the last family).
    fn family_gradient(
        m: &Self::Moments,
        family: usize,
        k: &Self::Coeffs,
    ) -> Option<(f64, Self::Coeffs)>;
    /// The coefficient of a family in the energy for the load scalars `s`
    /// (`1` for the strain energies, `-kp` for the gas volume; 0 for a
    /// family the energy leaves out or past the last one): the energy is
    /// `sum_f family_coefficient(f, s) * family f`.
    fn family_coefficient(family: usize, s: &EnergyScalars) -> f64;
    /// The derivative of the potential and its gradient along a change `ds`
    /// of the load scalars (`kp = kappa P`: minus the gas family).
    fn scalars_tangent(
        m: &Self::Moments,
        k: &Self::Coeffs,
        s: &EnergyScalars,
        ds: &EnergyScalars,
    ) -> (f64, Self::Coeffs);
}

/// Index of entry `(i, j)` in the upper-triangle layout for `n` unknowns.
#[inline]
pub const fn upper_index(n: usize, i: usize, j: usize) -> usize {
    let (i, j) = if i <= j { (i, j) } else { (j, i) };
    i * n - i * (i + 1) / 2 + j
}

/// Something done with a model's type (the way [`ModelId::visit`] hands a
/// run-time choice of model to generic code).
pub trait ModelVisitor {
    /// What the visit returns.
    type Output;
    /// Runs with the model `M`.
    fn visit<M: ElementModel>(self) -> Self::Output;
}

/// What a model is, for listings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModelInfo {
    /// Name (lower case).
    pub name: &'static str,
    /// Spec path.
    pub spec: &'static str,
    /// The spec's header comment.
    pub description: &'static str,
    /// Unknown names.
    pub unknowns: &'static [&'static str],
    /// Local unknowns (positions).
    pub local: &'static [usize],
}

struct Info;

impl ModelVisitor for Info {
    type Output = ModelInfo;
    fn visit<M: ElementModel>(self) -> ModelInfo {
        ModelInfo {
            name: M::NAME,
            spec: M::SPEC_PATH,
            description: M::DESCRIPTION,
            unknowns: M::UNKNOWNS,
            local: M::LOCAL,
        }
    }
}

impl ModelId {
    /// Name, spec and unknowns.
    pub fn info(self) -> ModelInfo {
        self.visit(Info)
    }

    /// The model of a name (`ccm`, ...).
    pub fn from_name(name: &str) -> Option<ModelId> {
        ModelId::ALL.iter().copied().find(|m| m.name() == name)
    }

    /// The model of a name, or an input error for `field` that lists the
    /// models.
    pub fn parse(field: impl Into<crate::Field>, name: &str) -> Result<ModelId, crate::InputError> {
        ModelId::from_name(name).ok_or_else(|| crate::InputError::Unrecognised {
            field: field.into(),
            value: name.into(),
            rule: format!("not a model (models: {})", ModelId::names().join(", ")),
        })
    }

    /// Every model's name, for messages.
    pub fn names() -> Vec<&'static str> {
        ModelId::ALL.iter().map(|m| m.name()).collect()
    }
}

impl std::fmt::Display for ModelId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for ModelId {
    /// The model's name (`ccm`, `quad`, ...).
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

include!(concat!(env!("OUT_DIR"), "/models.rs"));
