//! One continuation step's linear algebra: the bordered solve, the
//! corrector, the tangent and the step along it, with their state and
//! workspace.

use super::output::PathReport;
use super::path::Path;
use crate::linear::{all_finite, dot, norm_inf, FactorError, Inertia};
use crate::options::PalcOptions;
use crate::problem::LinearSystem;

/// A point of the branch with its tangent and inertia.
#[derive(Clone, Debug)]
pub(super) struct State {
    pub(super) x: Vec<f64>,
    pub(super) lambda: f64,
    pub(super) tx: Vec<f64>,
    pub(super) tl: f64,
    pub(super) inertia: Inertia,
    /// The inertia of `H` on the tangent space of the path problem's
    /// constraint, if it has one ([`super::Path::constraint`]).
    pub(super) restricted: Option<Inertia>,
    pub(super) iterations: usize,
}

impl State {
    pub(super) fn new(n: usize) -> State {
        State {
            x: vec![0.0; n],
            lambda: 0.0,
            tx: vec![0.0; n],
            tl: 0.0,
            inertia: Inertia::default(),
            restricted: None,
            iterations: 0,
        }
    }

    /// `<t, z - z_self>_theta`: how far `z` lies from this point along
    /// its tangent `t`.
    pub(super) fn along_tangent(&self, theta2: f64, z: &State) -> f64 {
        self.tx
            .iter()
            .zip(&z.x)
            .zip(&self.x)
            .map(|((t, x), b)| t * (x - b))
            .sum::<f64>()
            + theta2 * self.tl * (z.lambda - self.lambda)
    }
}

/// Evaluation buffers and elimination scratch.
#[derive(Clone, Debug)]
pub(super) struct Work {
    pub(super) theta2: f64,
    pub(super) g: Vec<f64>,
    pub(super) gl: Vec<f64>,
    /// `H^-1 g_lambda` at the current factorisation.
    pub(super) w: Vec<f64>,
    pub(super) rx: Vec<f64>,
    pub(super) dx: Vec<f64>,
    pub(super) r: Vec<f64>,
    pub(super) hx: Vec<f64>,
    pub(super) start: Vec<f64>,
    /// The constraint's gradient and scratch for its restricted inertia.
    pub(super) cx: Vec<f64>,
    pub(super) cw: Vec<f64>,
    pub(super) cr: Vec<f64>,
}

impl Work {
    /// Zeroed buffers for `n` unknowns and the load weight `theta`.
    pub(super) fn new(n: usize, theta: f64) -> Work {
        let z = || vec![0.0; n];
        Work {
            theta2: theta * theta,
            g: z(),
            gl: z(),
            w: z(),
            rx: z(),
            dx: z(),
            r: z(),
            hx: z(),
            start: z(),
            cx: z(),
            cw: z(),
            cr: z(),
        }
    }
}

/// Why a corrector (or a step) failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Failure {
    NonFinite,
    Singular,
    NotConverged,
    TooFar,
    Turned,
    Events,
}

/// The constraint row of a corrector solve.
#[derive(Clone, Copy)]
pub(super) enum Row<'a> {
    /// `<t_base, z - z_base>_theta = ds`.
    Arclength { base: &'a State, ds: f64 },
    /// `lambda = value`.
    Lambda(f64),
}

/// The border of a tangent solve.
#[derive(Clone, Copy)]
pub(super) enum Border<'a> {
    /// `<t_prev, t>_theta > 0`.
    Tangent(&'a State),
    /// `sign(t_l) = sign`.
    Lambda(f64),
}

/// `||a - b||_theta` for states `(ax, al)`, `(bx, bl)`.
pub(super) fn distance(theta2: f64, ax: &[f64], al: f64, bx: &[f64], bl: f64) -> f64 {
    let s: f64 = ax.iter().zip(bx).map(|(a, b)| (a - b) * (a - b)).sum();
    (s + theta2 * (al - bl) * (al - bl)).sqrt()
}

/// Solves `[H g_l; c^T cl] (dx, dl) = (rx, rc)` (`c = 0` when `None`) with
/// `H` factorised in `p` and `ws.w = H^-1 g_l`: block elimination and one
/// step of iterative refinement. Reads `ws.rx`, leaves `dx` in `ws.dx`,
/// returns `dl`.
pub(super) fn bordered_solve<P: LinearSystem + ?Sized>(
    p: &mut P,
    ws: &mut Work,
    c: Option<&[f64]>,
    cl: f64,
    rc: f64,
) -> f64 {
    let dotc = |v: &[f64]| c.map_or(0.0, |c| dot(c, v));
    ws.dx.copy_from_slice(&ws.rx);
    p.solve(&mut ws.dx);
    let den = cl - dotc(&ws.w);
    let dl = (rc - dotc(&ws.dx)) / den;
    for (d, w) in ws.dx.iter_mut().zip(&ws.w) {
        *d -= w * dl;
    }
    p.apply(&ws.dx, &mut ws.hx);
    for i in 0..ws.r.len() {
        ws.r[i] = ws.rx[i] - ws.hx[i] - ws.gl[i] * dl;
    }
    let rr = rc - dotc(&ws.dx) - cl * dl;
    p.solve(&mut ws.r);
    let ddl = (rr - dotc(&ws.r)) / den;
    for ((d, r), w) in ws.dx.iter_mut().zip(&ws.r).zip(&ws.w) {
        *d += r - w * ddl;
    }
    dl + ddl
}

/// Newton on `g = 0` plus `row`, from the guess in `out`; on success `H`
/// is factorised at the converged point (inertia in `out`), `ws.g`, `ws.gl`
/// and `ws.w` hold the evaluation there. `max_dist`: largest distance of an
/// iterate from the guess.
pub(super) fn correct<P: Path + ?Sized>(
    p: &mut P,
    o: &PalcOptions,
    ws: &mut Work,
    row: Row<'_>,
    out: &mut State,
    max_dist: f64,
    rep: &mut PathReport,
) -> Result<(), Failure> {
    ws.start.copy_from_slice(&out.x);
    let l_start = out.lambda;
    let mut k = 0usize;
    loop {
        if !(out.lambda.is_finite() && all_finite(&out.x)) {
            return Err(Failure::NonFinite);
        }
        rep.evaluations += 1;
        if !p.eval(&out.x, out.lambda, &mut ws.g, &mut ws.gl)
            || !all_finite(&ws.g)
            || !all_finite(&ws.gl)
        {
            return Err(Failure::NonFinite);
        }
        rep.factorizations += 1;
        out.inertia = crate::problem::factor_cholesky_first(p).map_err(|e| match e {
            FactorError::NonFinite { .. } => Failure::NonFinite,
            _ => Failure::Singular,
        })?;
        ws.w.copy_from_slice(&ws.gl);
        p.solve(&mut ws.w);
        if !all_finite(&ws.w) {
            return Err(Failure::Singular);
        }
        if norm_inf(&ws.g) <= o.gtol {
            out.iterations = k;
            return Ok(());
        }
        if k >= o.max_corrector_iterations {
            return Err(Failure::NotConverged);
        }
        for (r, g) in ws.rx.iter_mut().zip(&ws.g) {
            *r = -g;
        }
        let dl = match row {
            Row::Arclength { base, ds } => {
                let res = base.along_tangent(ws.theta2, out) - ds;
                bordered_solve(p, ws, Some(&base.tx), ws.theta2 * base.tl, -res)
            }
            Row::Lambda(value) => bordered_solve(p, ws, None, 1.0, value - out.lambda),
        };
        if !(dl.is_finite() && all_finite(&ws.dx)) {
            return Err(Failure::Singular);
        }
        for (x, d) in out.x.iter_mut().zip(&ws.dx) {
            *x += d;
        }
        out.lambda += dl;
        if let Row::Lambda(value) = row {
            // keep the prescribed load exact
            out.lambda = value;
        }
        k += 1;
        rep.corrector_iterations += 1;
        if distance(ws.theta2, &out.x, out.lambda, &ws.start, l_start) > max_dist {
            return Err(Failure::TooFar);
        }
    }
}

/// The unit tangent at the point `correct` just converged to (its
/// factorisation and `ws.w` current), oriented by `border`.
pub(super) fn tangent<P: LinearSystem + ?Sized>(
    p: &mut P,
    ws: &mut Work,
    border: Border<'_>,
    out: &mut State,
) -> Result<(), Failure> {
    ws.rx.fill(0.0);
    let mu = match border {
        Border::Tangent(prev) => bordered_solve(p, ws, Some(&prev.tx), ws.theta2 * prev.tl, 1.0),
        Border::Lambda(sign) => bordered_solve(p, ws, None, 1.0, sign),
    };
    let norm = (dot(&ws.dx, &ws.dx) + ws.theta2 * mu * mu).sqrt();
    if !(norm.is_finite() && norm > 0.0) {
        return Err(Failure::Singular);
    }
    for (t, d) in out.tx.iter_mut().zip(&ws.dx) {
        *t = d / norm;
    }
    out.tl = mu / norm;
    Ok(())
}

/// Corrector at pseudo-arclength `s` along the step from `base` (Euler
/// predictor, then [`correct`] and [`tangent`]) into `out`.
pub(super) fn step_to<P: Path + ?Sized>(
    p: &mut P,
    o: &PalcOptions,
    ws: &mut Work,
    base: &State,
    s: f64,
    out: &mut State,
    rep: &mut PathReport,
) -> Result<(), Failure> {
    for ((x, b), t) in out.x.iter_mut().zip(&base.x).zip(&base.tx) {
        *x = b + s * t;
    }
    out.lambda = base.lambda + s * base.tl;
    let max_dist = o.max_correction * s.abs().max(o.event_tol);
    correct(p, o, ws, Row::Arclength { base, ds: s }, out, max_dist, rep)?;
    tangent(p, ws, Border::Tangent(base), out)
}
