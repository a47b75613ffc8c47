//! The implicit-function-theorem core of the finger sensitivities: the
//! Hessian at the equilibrium, the bordered system of a target solve, and
//! the right-hand sides of every parameter.

use fpc_newton::{Hessian, LinearSystem, PivotKind, Termination};

use crate::actuator::Actuator;
use crate::actuator::{element_block_tangent_into, element_blocks, ActuatorTangent};
use crate::coefficients::Coefficients;
use crate::element::Element;
use crate::element::ElementBlocks;
use crate::error::InputError;
use crate::field::Field;
use crate::finger::{Chain, FingerCore, Load, TargetProblem};
use crate::model::{
    ElementModel, EnergyScalars, GasParams, LinearParams, PrestressedParams, Vector,
};
use crate::partition::Partition;
use crate::solve_error::SolveError;

use super::params::Param;
use super::record::{Sensitivities, Sensitivity};

/// Largest relative residual `||grad Pi||_inf / stiffness` accepted as an
/// equilibrium (the solver's default tolerance is 1e-11).
pub const EQUILIBRIUM_TOLERANCE: f64 = 1e-6;

/// Largest target residual accepted, relative to the finger's length.
pub const TARGET_TOLERANCE: f64 = 1e-6;

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

fn inconsistent(field: impl Into<Field>, rule: String) -> SolveError {
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
            Field::key("solution.coefficients"),
            format!(
                "must hold one set of {n} coefficients per element ({ne}); it holds {} of {}",
                k.elements(),
                k.per_element()
            ),
        ));
    }
    if let Some(&value) = k.as_slice().iter().find(|v| !v.is_finite()) {
        return Err(InputError::NotFinite {
            field: Field::key("solution.coefficients"),
            value,
        }
        .into());
    }
    let (load, target) = match req.state {
        State::Load(l) => (*l, None),
        State::Target { problem, lambda } => {
            crate::error::finite(Field::key("target.lambda"), lambda)?;
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
            Field::key("actuator"),
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
            Field::key("solution"),
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
                    Field::key("solution"),
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
                let (vi, mut gk) = M::scalars_tangent(el.moments(), &kis[i], &scalars, &ds);
                el.hold(&mut gk);
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
/// once for all parameters ([`Tangents::add_linear_tangents`](crate::model::Tangents::add_linear_tangents), ...);
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
        plane_strain: false,
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
                let Some((v, mut gk)) = M::family_gradient(&dms[q], f, &kis[i]) else {
                    continue;
                };
                core.elements[i].hold(&mut gk);
                ep[r] += w * v;
                for a in 0..n {
                    rhs[r][n * i + a] -= w * gk[a] * s[a];
                }
            }
        }
    }
}
