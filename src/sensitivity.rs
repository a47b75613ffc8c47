//! Exact sensitivities of an equilibrium with respect to design and load
//! parameters (docs/model.md, "Sensitivities").
//!
//! At an equilibrium `grad Pi(K*, p) = 0` the implicit function theorem
//! gives `dK/dp = -H^-1 d(grad Pi)/dp`, with `H` the Hessian the solver
//! factorises anyway (the chain's [`fpc_newton::Semiseparable`]): one
//! factorisation, then one `O(N)` solve per parameter. The right-hand
//! sides are exact:
//!
//! - an actuator parameter moves the blocks (`src/blocks.rs`,
//!   [`element_block_tangents`]); each integral family's energy is linear
//!   in its moments, so `d(grad Pi)/dp` is the model's own gradient kernel
//!   evaluated at the moments' derivative, which the generated
//!   `*_dmoments` kernels add up box by box ([`ElementModel::add_linear_tangent`], ...);
//! - the pressure and `kappa` enter through `kp = kappa P`, which
//!   multiplies the gas family ([`ElementModel::scalars_tangent`]);
//! - a tip force `F` enters through `-F . tip`: `d(grad Pi)/dF = -grad tip`.
//!
//! A target solve ([`crate::Solver::solve_target`]) adds the load factor
//! `lambda` and the target equation `c = w . tip - target = 0`; its
//! sensitivities solve the bordered system
//! `[[H, g_lambda], [c_x^T, c_lambda]] (dK, dlambda) = -(dg/dp, dc/dp)` by
//! block elimination on the same factorisation.
//!
//! Everything runs in the solver's scaled unknowns
//! ([`Finger::unknown_scales`]); `dK/dp` is returned in raw coefficients.

use std::fmt;

use fpc_newton::{Hessian, LinearSystem, PivotKind, Termination};

use crate::actuator::{Actuator, ActuatorParams, Material, RibLayout};
use crate::blocks::{
    element_block_tangent_into, element_blocks, ActuatorTangent, ElementBlocks, Partition,
};
use crate::element::Element;
use crate::error::{InputError, SolveError};
use crate::finger::{Chain, Coefficients, Finger, FingerCore, Load, Solution, TargetProblem};
use crate::model::{
    ElementModel, EnergyScalars, GasParams, LinearParams, PrestressedParams, Vector,
};

/// A linear lamina with its own material table (`actuator.<layer>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Lamina {
    /// The constraining layer, `actuator.cl`.
    Cl,
    /// The regular EMC, `actuator.emc`.
    Emc,
    /// The fluidic layer (and the ribs), `actuator.fluidic`.
    Fluidic,
}

impl Lamina {
    /// Every lamina, top to bottom.
    pub const ALL: [Lamina; 3] = [Lamina::Cl, Lamina::Emc, Lamina::Fluidic];

    /// The scene table's name (`cl`, `emc`, `fluidic`).
    pub fn name(self) -> &'static str {
        match self {
            Lamina::Cl => "cl",
            Lamina::Emc => "emc",
            Lamina::Fluidic => "fluidic",
        }
    }
}

/// An elastic constant of a lamina's material: `e`, `nu` of an isotropic
/// material, `e1`, `e2`, `nu12` of an orthotropic one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Elastic {
    /// Young's modulus of an isotropic material (MPa).
    E,
    /// Poisson's ratio of an isotropic material.
    Nu,
    /// Young's modulus along X of an orthotropic material (MPa).
    E1,
    /// Young's modulus along Y of an orthotropic material (MPa).
    E2,
    /// Major Poisson's ratio of an orthotropic material.
    Nu12,
}

impl Elastic {
    /// Every constant, isotropic first.
    pub const ALL: [Elastic; 5] = [
        Elastic::E,
        Elastic::Nu,
        Elastic::E1,
        Elastic::E2,
        Elastic::Nu12,
    ];

    /// The scene key's last part (`e`, `nu`, `e1`, `e2`, `nu12`).
    pub fn name(self) -> &'static str {
        match self {
            Elastic::E => "e",
            Elastic::Nu => "nu",
            Elastic::E1 => "e1",
            Elastic::E2 => "e2",
            Elastic::Nu12 => "nu12",
        }
    }

    /// The constant's value in `material`, if it has it.
    pub fn value(self, material: &Material) -> Option<f64> {
        match (material, self) {
            (Material::Isotropic(m), Elastic::E) => Some(m.e),
            (Material::Isotropic(m), Elastic::Nu) => Some(m.nu),
            (Material::Orthotropic(m), Elastic::E1) => Some(m.e1),
            (Material::Orthotropic(m), Elastic::E2) => Some(m.e2),
            (Material::Orthotropic(m), Elastic::Nu12) => Some(m.nu12),
            _ => None,
        }
    }

    fn slot(self, material: &mut Material) -> Option<&mut f64> {
        match (material, self) {
            (Material::Isotropic(m), Elastic::E) => Some(&mut m.e),
            (Material::Isotropic(m), Elastic::Nu) => Some(&mut m.nu),
            (Material::Orthotropic(m), Elastic::E1) => Some(&mut m.e1),
            (Material::Orthotropic(m), Elastic::E2) => Some(&mut m.e2),
            (Material::Orthotropic(m), Elastic::Nu12) => Some(&mut m.nu12),
            _ => None,
        }
    }
}

/// An actuator parameter the blocks depend on smoothly, named by its scene
/// key ([`ActuatorParam::name`]). Not covered: the lengths `lx` and `cx`,
/// and the rib layout's `w1` and `t`, which move element boundaries or the
/// clipping of a rib (and at the paper's layout the last rib ends exactly
/// at the channel's end, where the blocks are not differentiable).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ActuatorParam {
    /// `actuator.pemc.eps0`, the prestrain.
    Eps0,
    /// `actuator.pemc.e2` (MPa), the prestressed layer's Y modulus (its Q22).
    PemcE2,
    /// `actuator.pemc.p1` (MPa), the psi law's coefficients.
    PsiP1,
    /// `actuator.pemc.p2` (MPa).
    PsiP2,
    /// `actuator.pemc.p3` (MPa).
    PsiP3,
    /// `actuator.pemc.p4` (MPa).
    PsiP4,
    /// `actuator.geometry.h` (mm), the total thickness H.
    H,
    /// `actuator.geometry.h1` (mm): the CL / EMC interface.
    H1,
    /// `actuator.geometry.h2` (mm): the EMC / fluidic interface.
    H2,
    /// `actuator.geometry.h3` (mm): the fluidic / PEMC interface is at -h3.
    H3,
    /// `actuator.geometry.ly` (mm), the width.
    Ly,
    /// `actuator.channel.cy` (mm), the channel's width.
    ChannelCy,
    /// `actuator.channel.h3a` (mm): the channel's top at z = h3a.
    ChannelH3a,
    /// `actuator.channel.h3b` (mm): the channel's bottom at z = -h3b.
    ChannelH3b,
    /// `actuator.<layer>.<constant>`: an elastic constant of a linear lamina.
    Elastic(Lamina, Elastic),
    /// `actuator.ribs.w2` (mm): the transverse ribs' half width (paper layout).
    RibsW2,
}

const ELASTIC_NAMES: [[&str; 5]; 3] = [
    [
        "actuator.cl.e",
        "actuator.cl.nu",
        "actuator.cl.e1",
        "actuator.cl.e2",
        "actuator.cl.nu12",
    ],
    [
        "actuator.emc.e",
        "actuator.emc.nu",
        "actuator.emc.e1",
        "actuator.emc.e2",
        "actuator.emc.nu12",
    ],
    [
        "actuator.fluidic.e",
        "actuator.fluidic.nu",
        "actuator.fluidic.e1",
        "actuator.fluidic.e2",
        "actuator.fluidic.nu12",
    ],
];

impl ActuatorParam {
    /// Every actuator parameter (elastic constants of both kinds).
    pub fn all() -> Vec<ActuatorParam> {
        let mut v = vec![
            ActuatorParam::Eps0,
            ActuatorParam::PemcE2,
            ActuatorParam::PsiP1,
            ActuatorParam::PsiP2,
            ActuatorParam::PsiP3,
            ActuatorParam::PsiP4,
            ActuatorParam::H,
            ActuatorParam::H1,
            ActuatorParam::H2,
            ActuatorParam::H3,
            ActuatorParam::Ly,
            ActuatorParam::ChannelCy,
            ActuatorParam::ChannelH3a,
            ActuatorParam::ChannelH3b,
        ];
        for l in Lamina::ALL {
            for k in Elastic::ALL {
                v.push(ActuatorParam::Elastic(l, k));
            }
        }
        v.push(ActuatorParam::RibsW2);
        v
    }

    /// The parameters `actuator` has (its materials' constants, `w2` only
    /// with the paper's rib layout).
    pub fn for_actuator(actuator: &Actuator) -> Vec<ActuatorParam> {
        ActuatorParam::all()
            .into_iter()
            .filter(|p| p.value(actuator).is_some())
            .collect()
    }

    /// The scene key (`actuator.pemc.eps0`, `actuator.cl.e`, ...).
    pub fn name(self) -> &'static str {
        match self {
            ActuatorParam::Eps0 => "actuator.pemc.eps0",
            ActuatorParam::PemcE2 => "actuator.pemc.e2",
            ActuatorParam::PsiP1 => "actuator.pemc.p1",
            ActuatorParam::PsiP2 => "actuator.pemc.p2",
            ActuatorParam::PsiP3 => "actuator.pemc.p3",
            ActuatorParam::PsiP4 => "actuator.pemc.p4",
            ActuatorParam::H => "actuator.geometry.h",
            ActuatorParam::H1 => "actuator.geometry.h1",
            ActuatorParam::H2 => "actuator.geometry.h2",
            ActuatorParam::H3 => "actuator.geometry.h3",
            ActuatorParam::Ly => "actuator.geometry.ly",
            ActuatorParam::ChannelCy => "actuator.channel.cy",
            ActuatorParam::ChannelH3a => "actuator.channel.h3a",
            ActuatorParam::ChannelH3b => "actuator.channel.h3b",
            ActuatorParam::Elastic(l, k) => ELASTIC_NAMES[l as usize][k as usize],
            ActuatorParam::RibsW2 => "actuator.ribs.w2",
        }
    }

    /// The parameter's value in `actuator` (`None`: it has no such
    /// parameter, as `e1` of an isotropic layer).
    pub fn value(self, actuator: &Actuator) -> Option<f64> {
        let p = actuator.params();
        let g = &p.geometry;
        let c = &p.channel;
        let law = &p.pemc.law;
        Some(match self {
            ActuatorParam::Eps0 => p.pemc.eps0,
            ActuatorParam::PemcE2 => p.pemc.e2,
            ActuatorParam::PsiP1 => law.p1,
            ActuatorParam::PsiP2 => law.p2,
            ActuatorParam::PsiP3 => law.p3,
            ActuatorParam::PsiP4 => law.p4,
            ActuatorParam::H => g.h,
            ActuatorParam::H1 => g.h1,
            ActuatorParam::H2 => g.h2,
            ActuatorParam::H3 => g.h3,
            ActuatorParam::Ly => g.ly,
            ActuatorParam::ChannelCy => c.cy,
            ActuatorParam::ChannelH3a => c.h3a,
            ActuatorParam::ChannelH3b => c.h3b,
            ActuatorParam::Elastic(l, k) => k.value(material(p, l))?,
            ActuatorParam::RibsW2 => match p.ribs {
                RibLayout::Paper { w2, .. } => w2,
                _ => return None,
            },
        })
    }

    /// `actuator` with this parameter set to `value`, validated again.
    pub fn with_value(self, actuator: &Actuator, value: f64) -> Result<Actuator, InputError> {
        let mut p = actuator.params().clone();
        let missing = || InputError::Inconsistent {
            field: self.name().into(),
            rule: "the actuator has no such parameter".into(),
        };
        let slot: &mut f64 = match self {
            ActuatorParam::Eps0 => &mut p.pemc.eps0,
            ActuatorParam::PemcE2 => &mut p.pemc.e2,
            ActuatorParam::PsiP1 => &mut p.pemc.law.p1,
            ActuatorParam::PsiP2 => &mut p.pemc.law.p2,
            ActuatorParam::PsiP3 => &mut p.pemc.law.p3,
            ActuatorParam::PsiP4 => &mut p.pemc.law.p4,
            ActuatorParam::H => &mut p.geometry.h,
            ActuatorParam::H1 => &mut p.geometry.h1,
            ActuatorParam::H2 => &mut p.geometry.h2,
            ActuatorParam::H3 => &mut p.geometry.h3,
            ActuatorParam::Ly => &mut p.geometry.ly,
            ActuatorParam::ChannelCy => &mut p.channel.cy,
            ActuatorParam::ChannelH3a => &mut p.channel.h3a,
            ActuatorParam::ChannelH3b => &mut p.channel.h3b,
            ActuatorParam::Elastic(l, k) => {
                let m = match l {
                    Lamina::Cl => &mut p.cl,
                    Lamina::Emc => &mut p.emc,
                    Lamina::Fluidic => &mut p.fluidic,
                };
                k.slot(m).ok_or_else(missing)?
            }
            ActuatorParam::RibsW2 => match &mut p.ribs {
                RibLayout::Paper { w2, .. } => w2,
                _ => return Err(missing()),
            },
        };
        *slot = value;
        Actuator::new(p)
    }
}

fn material(p: &ActuatorParams, l: Lamina) -> &Material {
    match l {
        Lamina::Cl => &p.cl,
        Lamina::Emc => &p.emc,
        Lamina::Fluidic => &p.fluidic,
    }
}

/// A parameter of a sensitivity: of the actuator, of the load, or the
/// target of a target solve. Named by its scene key ([`Param::name`]);
/// derivatives are per unit of that key (the pressure per kPa).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Param {
    /// An actuator parameter.
    Actuator(ActuatorParam),
    /// `load.pressure_kpa`: the channel pressure, per kPa.
    Pressure,
    /// `load.kappa`: the pressure factor.
    Kappa,
    /// `load.fx` (N): the tip force along X (for a target solve, the fixed
    /// part of the load, `base.fx`).
    Fx,
    /// `load.fz` (N): the tip force along Z (`base.fz` for a target solve).
    Fz,
    /// `target.value` (mm): the target of a target solve.
    Target,
}

impl Param {
    /// The load's parameters.
    pub const LOAD: [Param; 4] = [Param::Pressure, Param::Kappa, Param::Fx, Param::Fz];

    /// Every parameter `actuator` and a load have (actuator parameters,
    /// then the load's; not [`Param::Target`]).
    pub fn all(actuator: &Actuator) -> Vec<Param> {
        let mut v: Vec<Param> = ActuatorParam::for_actuator(actuator)
            .into_iter()
            .map(Param::Actuator)
            .collect();
        v.extend(Param::LOAD);
        v
    }

    /// The scene key (`actuator.pemc.eps0`, `load.pressure_kpa`, ...;
    /// `target.value` for the target).
    pub fn name(self) -> &'static str {
        match self {
            Param::Actuator(a) => a.name(),
            Param::Pressure => "load.pressure_kpa",
            Param::Kappa => "load.kappa",
            Param::Fx => "load.fx",
            Param::Fz => "load.fz",
            Param::Target => "target.value",
        }
    }

    /// The parameter of a name ([`Param::name`]).
    pub fn from_name(name: &str) -> Option<Param> {
        ActuatorParam::all()
            .into_iter()
            .map(Param::Actuator)
            .chain(Param::LOAD)
            .chain([Param::Target])
            .find(|p| p.name() == name)
    }

    /// The parameter's value (in its key's unit) for an actuator and a load
    /// (and, for [`Param::Target`], a target problem).
    pub fn value(
        self,
        actuator: &Actuator,
        load: &Load,
        target: Option<&TargetProblem>,
    ) -> Option<f64> {
        match self {
            Param::Actuator(a) => a.value(actuator),
            Param::Pressure => Some(load.pressure * 1e3),
            Param::Kappa => Some(load.kappa),
            Param::Fx => Some(load.fx),
            Param::Fz => Some(load.fz),
            Param::Target => target.map(|t| t.target),
        }
    }

    /// `load` with this load parameter set to `value` (`None` for an
    /// actuator parameter or the target).
    pub fn load_with(self, load: &Load, value: f64) -> Option<Load> {
        let mut l = *load;
        match self {
            Param::Pressure => l.pressure = value * 1e-3,
            Param::Kappa => l.kappa = value,
            Param::Fx => l.fx = value,
            Param::Fz => l.fz = value,
            Param::Actuator(_) | Param::Target => return None,
        }
        Some(l)
    }
}

impl fmt::Display for Param {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for Param {
    /// The scene key.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// The derivatives of an equilibrium's outputs with respect to one
/// parameter, per unit of the parameter's key.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Sensitivity {
    /// The parameter.
    pub param: Param,
    /// Its value at the equilibrium (in its key's unit).
    pub value: f64,
    /// d(tip X, tip Z)/dp (mm per unit).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// d(end angle)/dp (rad per unit).
    #[serde(rename = "end_angle_rad")]
    pub end_angle: f64,
    /// d(Pi)/dp (N mm per unit), the total potential's total derivative.
    #[serde(rename = "energy_nmm")]
    pub energy: f64,
    /// d(lambda)/dp for a target solve (`None` otherwise).
    pub lambda: Option<f64>,
    /// dK/dp: the derivative of the raw element unknowns.
    pub coefficients: Coefficients,
}

/// The sensitivities of one equilibrium ([`Finger::sensitivities`],
/// [`Finger::target_sensitivities`]), one row per parameter asked for, in
/// that order.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Sensitivities {
    /// Tip position (X, Z) at the equilibrium (mm).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// End angle at the equilibrium (rad).
    #[serde(rename = "end_angle_rad")]
    pub end_angle: f64,
    /// Total potential at the equilibrium (N mm).
    #[serde(rename = "energy_nmm")]
    pub energy: f64,
    /// The load factor of a target solve (`None` otherwise).
    pub lambda: Option<f64>,
    /// One row per parameter.
    pub rows: Vec<Sensitivity>,
}

impl Sensitivities {
    /// The row of a parameter.
    pub fn get(&self, param: Param) -> Option<&Sensitivity> {
        self.rows.iter().find(|r| r.param == param)
    }
}

/// Largest relative residual `||grad Pi||_inf / stiffness` accepted as an
/// equilibrium (the solver's default tolerance is 1e-11).
pub const EQUILIBRIUM_TOLERANCE: f64 = 1e-6;

/// Largest target residual accepted, relative to the finger's length.
pub const TARGET_TOLERANCE: f64 = 1e-6;

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
        self.core().sensitivities(&Request {
            actuator,
            coefficients: &solution.coefficients,
            state: State::Load(load),
            params,
        })
    }

    /// The sensitivities of a target solve's equilibrium ([`crate::Solver::solve_target`]
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
        self.core().sensitivities(&Request {
            actuator,
            coefficients: &solution.coefficients,
            state: State::Target { problem, lambda },
            params,
        })
    }
}

/// What [`Finger::sensitivities`] hands to the model's core.
pub(crate) struct Request<'a> {
    pub actuator: &'a Actuator,
    pub coefficients: &'a Coefficients,
    pub state: State<'a>,
    pub params: &'a [Param],
}

/// The equilibrium's kind.
#[derive(Clone, Copy)]
pub(crate) enum State<'a> {
    Load(&'a Load),
    Target {
        problem: &'a TargetProblem,
        lambda: f64,
    },
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn inconsistent(field: &str, rule: String) -> SolveError {
    SolveError::Input(InputError::Inconsistent {
        field: field.into(),
        rule,
    })
}

/// The border of a target solve: `g_lambda`, `c_x` (scaled), `c_lambda`,
/// and `b = H^-1 g_lambda` with the Schur complement `c_lambda - c_x . b`.
struct Border {
    g_lambda: Vec<f64>,
    c_x: Vec<f64>,
    c_lambda: f64,
    b: Vec<f64>,
    schur: f64,
}

/// `x = H^-1 r` with one step of iterative refinement.
fn solve_refined<M: ElementModel>(
    chain: &mut Chain<'_, M>,
    r: &[f64],
    x: &mut [f64],
    e: &mut [f64],
) {
    x.copy_from_slice(r);
    chain.solve(x);
    chain.apply(x, e);
    for (ei, ri) in e.iter_mut().zip(r) {
        *ei = ri - *ei;
    }
    chain.solve(e);
    for (xi, ei) in x.iter_mut().zip(e.iter()) {
        *xi += ei;
    }
}

/// `(dy, dlambda)` solving `H dy + g_lambda dl = r1`, `c_x . dy + c_lambda dl = r2`
/// by block elimination, refined once on the whole bordered system.
fn solve_bordered<M: ElementModel>(
    chain: &mut Chain<'_, M>,
    border: &Border,
    r1: &[f64],
    r2: f64,
    dy: &mut [f64],
    e: &mut [f64],
    scratch: &mut [f64],
) -> f64 {
    let eliminate =
        |chain: &mut Chain<'_, M>, r1: &[f64], r2: f64, x: &mut [f64], e: &mut [f64]| {
            solve_refined(chain, r1, x, e);
            let dl = (r2 - dot(&border.c_x, x)) / border.schur;
            for (xi, bi) in x.iter_mut().zip(&border.b) {
                *xi -= bi * dl;
            }
            dl
        };
    let mut dl = eliminate(chain, r1, r2, dy, e);
    // residual of the whole system, then one correction
    chain.apply(dy, scratch);
    for i in 0..scratch.len() {
        scratch[i] = r1[i] - scratch[i] - border.g_lambda[i] * dl;
    }
    let e2 = r2 - dot(&border.c_x, dy) - border.c_lambda * dl;
    let res = scratch.to_vec();
    let mut corr = vec![0.0; dy.len()];
    let ddl = eliminate(chain, &res, e2, &mut corr, e);
    for (yi, ci) in dy.iter_mut().zip(&corr) {
        *yi += ci;
    }
    dl += ddl;
    dl
}

/// The sensitivities for model `M` (the body of [`Finger::sensitivities`]
/// and [`Finger::target_sensitivities`]).
pub(crate) fn compute<M: ElementModel>(
    core: &FingerCore<M>,
    req: &Request<'_>,
) -> Result<Sensitivities, SolveError> {
    let n = M::Coeffs::LEN;
    let ne = core.len();
    let act = req.actuator;
    let k = req.coefficients;
    if k.elements() != ne || k.per_element() != n {
        return Err(inconsistent(
            "solution.coefficients",
            format!(
                "must hold one set of {n} coefficients per element ({ne}); it holds {} of {}",
                k.elements(),
                k.per_element()
            ),
        ));
    }
    if let Some(&value) = k.as_slice().iter().find(|v| !v.is_finite()) {
        return Err(InputError::NotFinite {
            field: "solution.coefficients".into(),
            value,
        }
        .into());
    }
    let (load, target) = match req.state {
        State::Load(l) => (*l, None),
        State::Target { problem, lambda } => {
            crate::error::finite("target.lambda", lambda)?;
            (problem.load_at(lambda), Some((problem, lambda)))
        }
    };
    load.validate()?;
    let base = target.map_or(load, |(p, _)| p.base);
    // the parameters, checked before any work
    let mut tangents = Vec::with_capacity(req.params.len());
    for &p in req.params {
        tangents.push(match p {
            Param::Actuator(a) => Some(ActuatorTangent::of(act, a)?),
            Param::Target if target.is_none() => {
                return Err(inconsistent(
                    p.name(),
                    "is a parameter of target solves only (Finger::target_sensitivities)".into(),
                ))
            }
            _ => None,
        });
    }

    // the finger's blocks, from the actuator (which must be the finger's)
    let mismatch = || {
        inconsistent(
            "actuator",
            "is not the actuator this finger was built from (its blocks do not give the finger's moments)"
                .into(),
        )
    };
    let part =
        Partition::custom(core.lengths.clone(), act.geometry().lx).map_err(|_| mismatch())?;
    let matches = |ribs: bool| {
        let blocks = element_blocks(act, &part, ribs);
        let same = blocks.len() == ne
            && blocks
                .iter()
                .zip(&core.elements)
                .all(|(b, e)| Element::<M>::from_blocks(b).moments() == e.moments());
        same.then_some((blocks, ribs))
    };
    let (blocks, ribs) = matches(true)
        .or_else(|| matches(false))
        .ok_or_else(mismatch)?;

    // the Hessian at the equilibrium, with the chain geometry
    let y = core.scaled(k.as_slice());
    let dim = y.len();
    let mut chain = Chain::new(core);
    chain.set_load(&load);
    chain.force_chain = true;
    let mut g = vec![0.0; dim];
    let energy = chain.hessian(&y, &mut g);
    let residual = g.iter().fold(0.0f64, |m, v| m.max(v.abs())) / core.stiffness;
    if residual.is_nan() || residual > EQUILIBRIUM_TOLERANCE {
        return Err(inconsistent(
            "solution",
            format!(
                "is not an equilibrium of this load (relative residual {residual:.3e} > {EQUILIBRIUM_TOLERANCE:e})"
            ),
        ));
    }
    let tip = chain.tip;
    let mut tx = vec![0.0; dim];
    let mut tz = vec![0.0; dim];
    chain.tip_gradient_scaled([1.0, 0.0], &mut tx);
    chain.tip_gradient_scaled([0.0, 1.0], &mut tz);
    let mut ga = vec![0.0; dim];
    let mut end_angle = 0.0;
    let mut kis = Vec::with_capacity(ne);
    for (i, e) in core.elements.iter().enumerate() {
        let ki = FingerCore::<M>::element_coeffs(k.as_slice(), i);
        let (v, eg) = e.end_gradient(&ki);
        end_angle += v[2];
        let s = &core.unscale[i];
        for a in 0..n {
            ga[n * i + a] = eg[2][a] * s[a];
        }
        kis.push(ki);
    }
    // a singular Hessian (or bordered system) has no sensitivities
    let singular = || SolveError::NotConverged {
        reason: Termination::Singular,
        iterations: 0,
        relative_residual: residual,
        element: None,
        last: k.clone(),
    };
    // Cholesky pivots at a stable equilibrium, symmetric ones otherwise
    // (past a limit point of a target solve the Hessian is indefinite)
    if chain.factor(0.0, PivotKind::Cholesky).is_err() {
        chain
            .factor(0.0, PivotKind::Symmetric)
            .map_err(|_| singular())?;
    }

    let mut e = vec![0.0; dim];
    let mut scratch = vec![0.0; dim];
    let border = match target {
        None => None,
        Some((problem, _)) => {
            let w = problem.weights;
            let c = w[0] * tip[0] + w[1] * tip[1] - problem.target;
            let length: f64 = core.lengths.iter().sum();
            if c.is_nan() || c.abs() > TARGET_TOLERANCE * length {
                return Err(inconsistent(
                    "solution",
                    format!("does not meet the target (w . tip - target = {c:.3e} mm)"),
                ));
            }
            let d = problem.direction;
            let g_lambda: Vec<f64> = (0..dim).map(|i| -(d[0] * tx[i] + d[1] * tz[i])).collect();
            let c_x: Vec<f64> = (0..dim).map(|i| w[0] * tx[i] + w[1] * tz[i]).collect();
            let mut b = vec![0.0; dim];
            solve_refined(&mut chain, &g_lambda, &mut b, &mut e);
            let c_lambda = 0.0;
            let schur = c_lambda - dot(&c_x, &b);
            if schur == 0.0 || !schur.is_finite() {
                return Err(singular());
            }
            Some(Border {
                g_lambda,
                c_x,
                c_lambda,
                b,
                schur,
            })
        }
    };

    // the right-hand sides -d(grad Pi)/dp (scaled), and dPi/dp and dc/dp
    // at fixed K
    let scalars = load.scalars();
    let np = req.params.len();
    let mut rhs = vec![vec![0.0; dim]; np];
    let mut ep = vec![0.0; np];
    let mut cp = vec![0.0; np];
    actuator_rhs::<M>(
        core, act, &part, ribs, &blocks, &tangents, &kis, &scalars, &mut rhs, &mut ep,
    );
    for (r, &param) in req.params.iter().enumerate() {
        let rhs = &mut rhs[r];
        let mut scalar_tangent = |ds: EnergyScalars| {
            let mut v = 0.0;
            for (i, el) in core.elements.iter().enumerate() {
                let (vi, gk) = M::scalars_tangent(el.moments(), &kis[i], &scalars, &ds);
                v += vi;
                let s = &core.unscale[i];
                for a in 0..n {
                    rhs[n * i + a] = -gk[a] * s[a];
                }
            }
            v
        };
        match param {
            Param::Actuator(_) => {}
            Param::Pressure => {
                ep[r] = scalar_tangent(EnergyScalars {
                    kp: load.kappa * 1e-3,
                });
            }
            Param::Kappa => ep[r] = scalar_tangent(EnergyScalars { kp: load.pressure }),
            Param::Fx => {
                rhs.copy_from_slice(&tx);
                ep[r] = -tip[0];
            }
            Param::Fz => {
                rhs.copy_from_slice(&tz);
                ep[r] = -tip[1];
            }
            Param::Target => cp[r] = -1.0,
        }
    }

    // one (refined) solve per parameter
    let mut rows = Vec::with_capacity(np);
    let mut dy = vec![0.0; dim];
    for (r, &param) in req.params.iter().enumerate() {
        let dl = match &border {
            None => {
                solve_refined(&mut chain, &rhs[r], &mut dy, &mut e);
                None
            }
            Some(bd) => Some(solve_bordered(
                &mut chain,
                bd,
                &rhs[r],
                -cp[r],
                &mut dy,
                &mut e,
                &mut scratch,
            )),
        };
        let mut d_energy = ep[r];
        if let (Some(dl), Some((problem, _))) = (dl, target) {
            let d = problem.direction;
            d_energy -= (d[0] * tip[0] + d[1] * tip[1]) * dl;
        }
        let raw: Vec<f64> = dy
            .iter()
            .enumerate()
            .map(|(i, v)| v * core.unscale[i / n][i % n])
            .collect();
        rows.push(Sensitivity {
            param,
            value: param
                .value(act, &base, target.map(|t| t.0))
                .unwrap_or(f64::NAN),
            tip: [dot(&tx, &dy), dot(&tz, &dy)],
            end_angle: dot(&ga, &dy),
            energy: d_energy,
            lambda: dl,
            coefficients: Coefficients::new(n, raw).map_err(SolveError::Input)?,
        });
    }
    Ok(Sensitivities {
        tip,
        end_angle,
        energy,
        lambda: target.map(|t| t.1),
        rows,
    })
}

/// The right-hand sides `-d(grad Pi)/dp` (scaled) and `dPi/dp` at fixed K
/// of the actuator parameters among `tangents` (the others are left as
/// they are). Element by element, each box's moment Jacobian is evaluated
/// once for all parameters ([`ElementModel::add_linear_tangents`], ...);
/// the moments' derivatives then go through the model's own gradient
/// kernels, family by family (a family no parameter moves costs nothing).
#[allow(clippy::too_many_arguments)]
fn actuator_rhs<M: ElementModel>(
    core: &FingerCore<M>,
    act: &Actuator,
    part: &Partition,
    ribs: bool,
    blocks: &[ElementBlocks],
    tangents: &[Option<ActuatorTangent>],
    kis: &[M::Coeffs],
    scalars: &EnergyScalars,
    rhs: &mut [Vec<f64>],
    ep: &mut [f64],
) {
    let n = M::Coeffs::LEN;
    let rows: Vec<(usize, &ActuatorTangent)> = tangents
        .iter()
        .enumerate()
        .filter_map(|(r, t)| t.as_ref().map(|t| (r, t)))
        .collect();
    if rows.is_empty() {
        return;
    }
    let family = |name: &str| M::FAMILIES.iter().position(|f| *f == name);
    let families = [family("linear"), family("prestressed"), family("gas")];
    let weights: Vec<f64> = (0..M::FAMILIES.len())
        .map(|f| M::family_coefficient(f, scalars))
        .collect();
    let nonzero = |v: &[f64]| v.iter().any(|&x| x != 0.0);
    let empty = || ElementBlocks {
        length: 0.0,
        linear: Vec::new(),
        prestressed: Vec::new(),
        gas: Vec::new(),
    };
    let mut dblocks: Vec<ElementBlocks> = rows.iter().map(|_| empty()).collect();
    let mut dms = vec![M::zero_moments(); rows.len()];
    // per parameter: which of linear, prestressed, gas it moves here
    let mut touched = vec![[false; 3]; rows.len()];
    let mut lin: Vec<LinearParams> = Vec::with_capacity(rows.len());
    let mut pre: Vec<PrestressedParams> = Vec::with_capacity(rows.len());
    let mut gas: Vec<GasParams> = Vec::with_capacity(rows.len());
    for (i, (b, (&len, &start))) in blocks
        .iter()
        .zip(part.lengths().iter().zip(part.starts()))
        .enumerate()
    {
        for ((_, t), d) in rows.iter().zip(dblocks.iter_mut()) {
            element_block_tangent_into(act, ribs, t, start, len, d);
        }
        for m in dms.iter_mut() {
            *m = M::zero_moments();
        }
        touched.fill([false; 3]);
        for (j, p) in b.linear.iter().enumerate() {
            lin.clear();
            lin.extend(dblocks.iter().map(|d| d.linear[j]));
            let mut any = false;
            for (t, d) in touched.iter_mut().zip(&lin) {
                let moved = nonzero(&d.to_values());
                t[0] |= moved;
                any |= moved;
            }
            if any {
                M::add_linear_tangents(&mut dms, p, &lin);
            }
        }
        for (j, p) in b.prestressed.iter().enumerate() {
            pre.clear();
            pre.extend(dblocks.iter().map(|d| d.prestressed[j]));
            let mut any = false;
            for (t, d) in touched.iter_mut().zip(&pre) {
                let moved = nonzero(&d.to_values());
                t[1] |= moved;
                any |= moved;
            }
            if any {
                M::add_prestressed_tangents(&mut dms, p, &pre);
            }
        }
        for (j, p) in b.gas.iter().enumerate() {
            gas.clear();
            gas.extend(dblocks.iter().map(|d| d.gas[j]));
            let mut any = false;
            for (t, d) in touched.iter_mut().zip(&gas) {
                let moved = nonzero(&d.to_values());
                t[2] |= moved;
                any |= moved;
            }
            if any {
                M::add_gas_tangents(&mut dms, p, &gas);
            }
        }
        let s = &core.unscale[i];
        for (q, &(r, _)) in rows.iter().enumerate() {
            for (f, moved) in families.iter().zip(touched[q]) {
                let Some(f) = *f else { continue };
                let w = weights[f];
                if !moved || w == 0.0 {
                    continue;
                }
                let Some((v, gk)) = M::family_gradient(&dms[q], f, &kis[i]) else {
                    continue;
                };
                ep[r] += w * v;
                for a in 0..n {
                    rhs[r][n * i + a] -= w * gk[a] * s[a];
                }
            }
        }
    }
}
