//! The coupled finger as a Newton problem in scaled unknowns.
//!
//! The tip-load potential couples the elements through the chain
//! kinematics; its gradient and Hessian are assembled exactly from the
//! per-element end kernels. With `Fr_j = R(theta_j)^T F` (the load in
//! element j's frame) and `Q_j = tip - p_j`:
//!
//! - `d(F.tip)/dK_j = Fr_j . De_j + (F . J Q_j) grad eta_j`
//! - block `jj`: `Fr_j . D2e_j + (F . J Q_j) D2eta_j - (F . Q_j) grad eta_j grad eta_j^T`
//! - block `jk`, `j < k`: `grad eta_j w_k^T`, `w_k = (J^T Fr_k) . De_k - (F . Q_k) grad eta_k`
//!
//! where `J` rotates by +90 degrees and `e = (Xe, Ze)`. So the Hessian is
//! block diagonal plus a rank-one semiseparable coupling (block `kj` is
//! `-w_k u_j^T` with `u_j = grad eta_j`), which fpc-newton's
//! [`Semiseparable`] stores in `O(N)` and factorises and solves in `O(N)`
//! (block LDL^T along the chain, two scalar recurrences; its inertia gives
//! the stability). No `4N x 4N` matrix exists on the solve path.

use fpc_newton::{
    Energy, FactorError, Gradient, Hessian, Inertia, LinearSystem, PivotKind, Semiseparable, GROUP,
};

use crate::coefficients::Coefficients;
use crate::element;
use crate::element::packed::HessianGroups;
use crate::model::{ElementModel, EnergyScalars, Vector};

use super::assembly::{self, LoadTerms, Terms, Work};
use super::load::Load;
use super::problem::FingerCore;
use super::straighten;

/// The coupled finger: all elements plus the tip-load chain, with exact
/// gradient and structured Hessian. It reuses its buffers, so evaluations
/// do not allocate.
pub(crate) struct Chain<'a, M: ElementModel> {
    pub finger: &'a FingerCore<M>,
    scalars: EnergyScalars,
    f: [f64; 2],
    /// The buffers, the scaled Hessian of the last evaluation (and its
    /// factorisation) and the start's memo.
    b: ChainParts<M>,
    pub tip: [f64; 2],
    /// Evaluate the chain geometry even without a tip load (bordered solves
    /// need the tip and its gradient).
    pub force_chain: bool,
    /// Evaluate in Newton's own unknowns, the spec's `straighten`
    /// statements applied (src/finger/straighten.rs), instead of the
    /// scaled unknowns.
    pub straight: bool,
    /// Set by a cold solve from its unloaded start: the next Hessian
    /// evaluation takes the element pass from [`StartMemo`] when that was
    /// made at the same point, and keeps its own there otherwise.
    pub from_start: bool,
}

/// The element pass (energies, gradients and Hessian blocks, in groups)
/// of the Hessian at a cold solve's start. Cold solves of a batch share
/// their start (the unloaded equilibrium at the scene's pressure) and
/// differ in the tip load alone, which this pass does not see; so the
/// first Newton iteration of every cold solve after the first takes it
/// instead of evaluating the element kernels again. It is the same
/// arithmetic on the same numbers, so the solves stay bit for bit what
/// they were.
struct StartMemo {
    /// The point (Newton's unknowns), empty while nothing is kept.
    y: Vec<f64>,
    straight: bool,
    scalars: EnergyScalars,
    groups: HessianGroups,
}

impl StartMemo {
    /// Nothing kept.
    fn empty() -> StartMemo {
        StartMemo {
            y: Vec::new(),
            straight: false,
            scalars: Load::unloaded().scalars(),
            groups: HessianGroups::default(),
        }
    }

    /// True when it was made at `y` (bit for bit), in the same unknowns
    /// and with the same energy scalars.
    fn holds(&self, y: &[f64], straight: bool, scalars: &EnergyScalars) -> bool {
        self.straight == straight
            && self.scalars.to_values().map(f64::to_bits) == scalars.to_values().map(f64::to_bits)
            && !self.y.is_empty()
            && self.y.len() == y.len()
            && self
                .y
                .iter()
                .zip(y)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

/// A chain's buffers without its finger, kept between solvers
/// ([`Chain::take_parts`], [`Chain::with_parts`]).
pub(crate) struct ChainParts<M: ElementModel> {
    /// Each element's raw unknowns.
    k: Vec<M::Coeffs>,
    /// The gradients of each element's end point and slope (the gradient
    /// pass's).
    end_g: Vec<[M::Coeffs; 3]>,
    /// (cos, sin) of each element frame's angle theta_i.
    rot: Vec<[f64; 2]>,
    q: Vec<[f64; 2]>,
    /// The element pass's potentials, with gradients, with Hessians (in
    /// groups of elements).
    ev: Vec<f64>,
    eg: Vec<(f64, M::Coeffs)>,
    groups: HessianGroups,
    /// Two scaled Hessians: `matrices[active]` holds the last
    /// factorisation, which `solve` uses; a Hessian evaluation fills the
    /// other one and marks it `staged`, and the next `factor` makes it the
    /// active one ([`Hessian::stages_hessian`]: Newton may evaluate a
    /// step's landing with its Hessian and still take chord steps with the
    /// factorisation before it).
    matrices: [Semiseparable; 2],
    active: usize,
    staged: bool,
    memo: StartMemo,
    /// The assembly's lanes.
    work: Work,
}

impl<M: ElementModel> ChainParts<M> {
    /// Buffers for `n` elements (none allocated for 0).
    fn new(n: usize) -> ChainParts<M> {
        ChainParts {
            k: vec![M::Coeffs::zero(); n],
            end_g: vec![[M::Coeffs::zero(); 3]; n],
            rot: vec![[1.0, 0.0]; n],
            q: vec![[0.0; 2]; n],
            ev: vec![0.0; n],
            eg: vec![(0.0, M::Coeffs::zero()); n],
            groups: HessianGroups::new::<M>(n),
            matrices: [0; 2].map(|_| Semiseparable::new(M::Coeffs::LEN, n)),
            active: 0,
            staged: false,
            memo: StartMemo::empty(),
            work: Work::new(M::Coeffs::LEN),
        }
    }

    /// The number of elements they are for.
    pub fn len(&self) -> usize {
        self.k.len()
    }

    /// The Hessian of the last evaluation (staged or factorised).
    fn latest(&self) -> &Semiseparable {
        &self.matrices[self.active ^ usize::from(self.staged)]
    }

    /// The Hessian of the last evaluation, made the active matrix (the
    /// factorisation before it is dropped).
    fn promote(&mut self) -> &mut Semiseparable {
        self.active ^= usize::from(std::mem::take(&mut self.staged));
        &mut self.matrices[self.active]
    }
}

impl<'a, M: ElementModel> Chain<'a, M> {
    /// The problem for `finger` with no load (see [`Chain::set_load`]).
    pub fn new(finger: &'a FingerCore<M>) -> Chain<'a, M> {
        Chain::with_parts(finger, None)
    }

    /// [`Chain::new`], in `parts` when they are for as many elements
    /// (every buffer is written before it is read, so their contents do
    /// not matter).
    pub fn with_parts(finger: &'a FingerCore<M>, parts: Option<ChainParts<M>>) -> Chain<'a, M> {
        let n = finger.len();
        Chain {
            finger,
            scalars: Load::unloaded().scalars(),
            f: [0.0, 0.0],
            b: parts
                .filter(|p| p.len() == n)
                .unwrap_or_else(|| ChainParts::new(n)),
            tip: [0.0, 0.0],
            force_chain: false,
            straight: false,
            from_start: false,
        }
    }

    /// Moves the buffers out, leaving empty ones (the chain is unusable
    /// afterwards).
    pub fn take_parts(&mut self) -> ChainParts<M> {
        std::mem::replace(&mut self.b, ChainParts::new(0))
    }

    /// Sets pressure and tip load.
    pub fn set_load(&mut self, load: &Load) {
        self.scalars = load.scalars();
        self.f = [load.fx, load.fz];
    }

    /// True when the chain geometry is needed (a tip load acts, or a
    /// bordered solve needs the tip and its gradient).
    fn loaded(&self) -> bool {
        self.force_chain || self.f[0] != 0.0 || self.f[1] != 0.0
    }

    /// Scaled gradient of `w . tip` from the geometry of the last
    /// gradient/Hessian evaluation.
    pub fn tip_gradient_scaled(&self, w: [f64; 2], out: &mut [f64]) {
        let n = M::Coeffs::LEN;
        for (j, e) in self.finger.elements.iter().enumerate() {
            let [c, s] = self.b.rot[j];
            let wr = [c * w[0] + s * w[1], -s * w[0] + c * w[1]];
            let qj = self.b.q[j];
            let wjq = -w[0] * qj[1] + w[1] * qj[0];
            let eg = e.end_derivatives(&self.b.k[j]).0;
            let sj = &self.finger.unscale[j];
            for a in 0..n {
                out[n * j + a] = (wr[0] * eg[0][a] + wr[1] * eg[1][a] + wjq * eg[2][a]) * sj[a];
            }
        }
    }

    fn unscale_into(&mut self, y: &[f64]) {
        let n = M::Coeffs::LEN;
        for (i, (k, s)) in self.b.k.iter_mut().zip(&self.finger.unscale).enumerate() {
            let k = k.as_mut();
            k.copy_from_slice(&y[n * i..n * i + n]);
            if self.straight {
                straighten::from_newton::<M>(k);
            }
            for j in 0..n {
                k[j] *= s[j];
            }
        }
    }

    /// Frames (as rotations, from the elements' end tangents) and the
    /// vectors from each element's end to the tip.
    fn chain_geometry(&mut self) {
        let b = &mut self.b;
        let (k, rot, q) = (&b.k, &mut b.rot, &mut b.q);
        let p = element::walk::walk(
            &self.finger.elements,
            |i| k[i],
            |i, _, r, end| {
                rot[i] = r;
                q[i] = end; // the end for now
            },
        );
        for qi in q.iter_mut() {
            *qi = [p[0] - qi[0], p[1] - qi[1]];
        }
        self.tip = p;
    }
}

impl<M: ElementModel> Energy for Chain<'_, M> {
    fn dim(&self) -> usize {
        M::Coeffs::LEN * self.b.k.len()
    }

    fn energy(&mut self, y: &[f64]) -> f64 {
        self.unscale_into(y);
        let core = self.finger;
        core.lanes.eval::<element::packed::Value>(
            &core.elements,
            &self.b.k,
            &self.scalars,
            &mut self.b.ev,
        );
        let mut v = 0.0;
        for vi in &self.b.ev {
            v += vi;
        }
        if self.loaded() {
            let k = &self.b.k;
            let p = element::walk::walk(&self.finger.elements, |i| k[i], |_, _, _, _| {});
            v -= self.f[0] * p[0] + self.f[1] * p[1];
        }
        v
    }
}

impl<M: ElementModel> Gradient for Chain<'_, M> {
    fn gradient(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        self.unscale_into(y);
        let n = M::Coeffs::LEN;
        let loaded = self.loaded();
        let mut v = 0.0;
        let core = self.finger;
        core.lanes.eval::<element::packed::Gradient>(
            &core.elements,
            &self.b.k,
            &self.scalars,
            &mut self.b.eg,
        );
        for (i, e) in core.elements.iter().enumerate() {
            let (vi, gi) = self.b.eg[i];
            v += vi;
            g[n * i..n * i + n].copy_from_slice(gi.as_ref());
            if loaded {
                self.b.end_g[i] = e.end_derivatives(&self.b.k[i]).0;
            }
        }
        if loaded {
            self.chain_geometry();
            let [fx, fz] = self.f;
            v -= fx * self.tip[0] + fz * self.tip[1];
            for j in 0..self.b.k.len() {
                let [c, s] = self.b.rot[j];
                let fr = [c * fx + s * fz, -s * fx + c * fz];
                let qj = self.b.q[j];
                let fjq = -fx * qj[1] + fz * qj[0];
                let eg = &self.b.end_g[j];
                for a in 0..n {
                    g[n * j + a] -= fr[0] * eg[0][a] + fr[1] * eg[1][a] + fjq * eg[2][a];
                }
            }
        }
        for (i, s) in self.finger.unscale.iter().enumerate() {
            for j in 0..n {
                g[n * i + j] *= s[j];
            }
            if self.straight {
                straighten::pull_back::<M, f64>(&y[n * i..n * i + n], &mut g[n * i..n * i + n]);
            }
        }
        v
    }
}

impl<M: ElementModel> LinearSystem for Chain<'_, M> {
    fn diagonal_range(&self) -> (f64, f64) {
        self.b.latest().diagonal_range()
    }
    /// (A failure on a non-finite entry is already reported as
    /// `FactorError::NonFinite` by the factorisation.)
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.b.promote().factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.b.matrices[self.b.active].solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.b.latest().apply(x, out)
    }
}

impl<M: ElementModel> Chain<'_, M> {
    /// The inertia of the kept Hessian (its negative eigenvalues count the
    /// stability), without a factorisation to solve with
    /// ([`Semiseparable::inertia`]); `None` where the symmetric
    /// factorisation fails (a singular pivot, say).
    pub(crate) fn inertia(&mut self) -> Option<Inertia> {
        self.b.promote().inertia(0.0).ok()
    }
}

impl<M: ElementModel> Hessian for Chain<'_, M> {
    fn stages_hessian(&self) -> bool {
        true
    }

    fn hessian(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        self.unscale_into(y);
        let loaded = self.loaded();
        let core = self.finger;
        let from_start = std::mem::take(&mut self.from_start) && loaded;
        let from_memo = from_start && self.b.memo.holds(y, self.straight, &self.scalars);
        if !from_memo {
            // the element pass, several elements per instruction
            let b = &mut self.b;
            core.lanes
                .hessian_groups(&core.elements, &b.k, &self.scalars, &mut b.groups);
            if from_start {
                let m = &mut b.memo;
                m.y.clear();
                m.y.extend_from_slice(y);
                m.straight = self.straight;
                m.scalars = self.scalars;
                m.groups.clone_from(&b.groups);
            }
        }
        // (filled beside the factorised matrix)
        let m = self.b.active ^ 1;
        self.b.staged = true;
        if loaded {
            self.chain_geometry();
        } else {
            self.b.matrices[m].clear_coupling();
        }
        // each element's block and coupling vectors: the load's terms,
        // then scaled and straightened where the unknowns are (a group of
        // elements at a time, each lane an element's own arithmetic)
        let b = &mut self.b;
        let load = loaded.then(|| LoadTerms {
            force: self.f,
            rot: &b.rot,
            q: &b.q,
        });
        let terms = Terms::<M> {
            // (the memo's pass is read where it is kept)
            groups: if from_memo { &b.memo.groups } else { &b.groups },
            k: &b.k,
            unscale: &core.unscale_groups,
            lengths: &core.length_groups,
            load,
            straight: self.straight,
        };
        // the potentials summed element by element
        let mut v = 0.0;
        for i in 0..core.len() {
            v += terms.groups.v[i / GROUP].0[i % GROUP];
        }
        if loaded {
            let [fx, fz] = self.f;
            v -= fx * self.tip[0] + fz * self.tip[1];
        }
        let width = core.lanes.width();
        assembly::assemble(&terms, y, g, &mut b.matrices[m], width, &mut b.work);
        v
    }
}

/// The finger's energy and gradient in raw unknowns (the scaled chain's,
/// unscaled).
pub(crate) fn gradient<M: ElementModel>(
    core: &FingerCore<M>,
    load: &Load,
    k: &Coefficients,
) -> (f64, Vec<f64>) {
    let mut chain = Chain::new(core);
    chain.set_load(load);
    let y = core.scaled(k.as_slice());
    let mut g = vec![0.0; y.len()];
    let v = fpc_newton::Gradient::gradient(&mut chain, &y, &mut g);
    let n = M::Coeffs::LEN;
    for (i, gi) in g.iter_mut().enumerate() {
        *gi /= core.unscale[i / n][i % n];
    }
    (v, g)
}

/// The finger's energy, gradient and dense (column-major) Hessian in raw
/// unknowns.
pub(crate) fn hessian<M: ElementModel>(
    core: &FingerCore<M>,
    load: &Load,
    k: &Coefficients,
) -> (f64, Vec<f64>, Vec<f64>) {
    let mut chain = Chain::new(core);
    chain.set_load(load);
    let y = core.scaled(k.as_slice());
    let dim = y.len();
    let mut g = vec![0.0; dim];
    let mut h = vec![0.0; dim * dim];
    let v = fpc_newton::Hessian::hessian(&mut chain, &y, &mut g);
    chain.b.latest().dense(&mut h);
    let n = M::Coeffs::LEN;
    let s = |i: usize| core.unscale[i / n][i % n];
    for i in 0..dim {
        g[i] /= s(i);
        for j in 0..dim {
            h[i + dim * j] /= s(i) * s(j);
        }
    }
    (v, g, h)
}

/// The chain as a boxed Newton problem at `load`.
pub(crate) fn problem<'a, M: ElementModel>(
    core: &'a FingerCore<M>,
    load: &Load,
) -> Box<dyn fpc_newton::Hessian + 'a> {
    let mut chain = Chain::new(core);
    chain.set_load(load);
    Box::new(chain)
}
