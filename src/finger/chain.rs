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
//! where `J` rotates by +90 degrees and `e = (Xe, Ze)`. The unknowns the
//! model declares local do not enter the end kernels, so they couple only
//! within their element's diagonal block and are condensed out before the
//! factorisation ([`Chain::solve_shifted`]).

use fpc_newton::{Energy, Gradient, Hessian};

use crate::model::{upper_index, ElementModel, EnergyScalars, Vector};

use super::problem::FingerCore;
use super::Load;

/// Largest number of unknowns per element the condensation handles.
const MAX_UNKNOWNS: usize = 8;

/// Copies the lower triangle of a column-major `n x n` matrix to its upper triangle.
pub(crate) fn fill_upper(n: usize, h: &mut [f64]) {
    for j in 0..n {
        for i in j + 1..n {
            h[j + n * i] = h[i + n * j];
        }
    }
}

/// The coupled finger: all elements plus the tip-load chain, with exact
/// gradient and Hessian (the lower triangle only, which is all Newton
/// reads). It reuses its buffers, so evaluations do not allocate.
pub(crate) struct Chain<'a, M: ElementModel> {
    pub finger: &'a FingerCore<M>,
    scalars: EnergyScalars,
    f: [f64; 2],
    k: Vec<M::Coeffs>,
    end_g: Vec<[M::Coeffs; 3]>,
    end_h: Vec<[M::Upper; 3]>,
    /// (cos, sin) of each element frame's angle theta_i.
    rot: Vec<[f64; 2]>,
    q: Vec<[f64; 2]>,
    u: Vec<M::Coeffs>,
    w: Vec<M::Coeffs>,
    blk: Vec<M::Upper>,
    pub tip: [f64; 2],
    /// Evaluate the chain geometry even without a tip load (bordered solves
    /// need the tip and its gradient).
    pub force_chain: bool,
    /// Condensed Newton system (lower triangle) and its right-hand side.
    red: Vec<f64>,
    rg: Vec<f64>,
    /// Per element: the factorised local block and the coupling rows to
    /// the kept unknowns, for the back substitution.
    local_l: Vec<[f64; MAX_UNKNOWNS * MAX_UNKNOWNS]>,
    local_c: Vec<[f64; MAX_UNKNOWNS * MAX_UNKNOWNS]>,
}

/// Positions of the kept (chain) unknowns of model `M`, in order.
fn kept<M: ElementModel>() -> impl Iterator<Item = usize> {
    (0..M::Coeffs::LEN).filter(|i| !M::LOCAL.contains(i))
}

impl<'a, M: ElementModel> Chain<'a, M> {
    /// The problem for `finger` with no load (see [`Chain::set_load`]).
    pub fn new(finger: &'a FingerCore<M>) -> Chain<'a, M> {
        const { assert!(M::Coeffs::LEN <= MAX_UNKNOWNS) };
        let n = finger.len();
        Chain {
            finger,
            scalars: Load::unloaded().scalars(),
            f: [0.0, 0.0],
            k: vec![M::Coeffs::zero(); n],
            end_g: vec![[M::Coeffs::zero(); 3]; n],
            end_h: vec![[M::Upper::zero(); 3]; n],
            rot: vec![[1.0, 0.0]; n],
            q: vec![[0.0; 2]; n],
            u: vec![M::Coeffs::zero(); n],
            w: vec![M::Coeffs::zero(); n],
            blk: vec![M::Upper::zero(); n],
            tip: [0.0, 0.0],
            force_chain: false,
            red: Vec::new(),
            rg: Vec::new(),
            local_l: vec![[0.0; MAX_UNKNOWNS * MAX_UNKNOWNS]; n],
            local_c: vec![[0.0; MAX_UNKNOWNS * MAX_UNKNOWNS]; n],
        }
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
        for j in 0..self.k.len() {
            let [c, s] = self.rot[j];
            let wr = [c * w[0] + s * w[1], -s * w[0] + c * w[1]];
            let qj = self.q[j];
            let wjq = -w[0] * qj[1] + w[1] * qj[0];
            let eg = &self.end_g[j];
            let sj = &self.finger.unscale[j];
            for a in 0..n {
                out[n * j + a] = (wr[0] * eg[0][a] + wr[1] * eg[1][a] + wjq * eg[2][a]) * sj[a];
            }
        }
    }

    fn unscale_into(&mut self, y: &[f64]) {
        let n = M::Coeffs::LEN;
        for (i, (k, s)) in self.k.iter_mut().zip(&self.finger.unscale).enumerate() {
            for j in 0..n {
                k[j] = y[n * i + j] * s[j];
            }
        }
    }

    /// Frames (as rotations, from the elements' end tangents) and the
    /// vectors from each element's end to the tip.
    fn chain_geometry(&mut self) {
        let n = self.k.len();
        let (mut c, mut s) = (1.0, 0.0);
        let mut p = [0.0, 0.0];
        for i in 0..n {
            self.rot[i] = [c, s];
            let [xe, ze, ce, se] = self.finger.elements[i].frame(&self.k[i]);
            p[0] += c * xe - s * ze;
            p[1] += s * xe + c * ze;
            self.q[i] = p; // p_i for now
            (c, s) = (c * ce - s * se, s * ce + c * se);
        }
        for i in 0..n {
            self.q[i] = [p[0] - self.q[i][0], p[1] - self.q[i][1]];
        }
        self.tip = p;
    }
}

impl<M: ElementModel> Energy for Chain<'_, M> {
    fn dim(&self) -> usize {
        M::Coeffs::LEN * self.k.len()
    }

    fn energy(&mut self, y: &[f64]) -> f64 {
        self.unscale_into(y);
        let mut v = 0.0;
        for (e, k) in self.finger.elements.iter().zip(&self.k) {
            v += e.energy(k, &self.scalars);
        }
        if self.loaded() {
            let mut p = [0.0, 0.0];
            let (mut c, mut s) = (1.0, 0.0);
            for (e, k) in self.finger.elements.iter().zip(&self.k) {
                let [xe, ze, ce, se] = e.frame(k);
                p[0] += c * xe - s * ze;
                p[1] += s * xe + c * ze;
                (c, s) = (c * ce - s * se, s * ce + c * se);
            }
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
        for (i, e) in self.finger.elements.iter().enumerate() {
            let (vi, gi) = e.gradient(&self.k[i], &self.scalars);
            v += vi;
            g[n * i..n * i + n].copy_from_slice(gi.as_ref());
            if loaded {
                self.end_g[i] = e.end_gradient(&self.k[i]).1;
            }
        }
        if loaded {
            self.chain_geometry();
            let [fx, fz] = self.f;
            v -= fx * self.tip[0] + fz * self.tip[1];
            for j in 0..self.k.len() {
                let [c, s] = self.rot[j];
                let fr = [c * fx + s * fz, -s * fx + c * fz];
                let qj = self.q[j];
                let fjq = -fx * qj[1] + fz * qj[0];
                let eg = &self.end_g[j];
                for a in 0..n {
                    g[n * j + a] -= fr[0] * eg[0][a] + fr[1] * eg[1][a] + fjq * eg[2][a];
                }
            }
        }
        for (i, s) in self.finger.unscale.iter().enumerate() {
            for j in 0..n {
                g[n * i + j] *= s[j];
            }
        }
        v
    }
}

/// In-place Cholesky of the leading `m x m` block of a row-major
/// `MAX_UNKNOWNS`-strided matrix; false unless positive definite.
fn small_cholesky(a: &mut [f64; MAX_UNKNOWNS * MAX_UNKNOWNS], m: usize) -> bool {
    for j in 0..m {
        let mut d = a[j * MAX_UNKNOWNS + j];
        for k in 0..j {
            d -= a[j * MAX_UNKNOWNS + k] * a[j * MAX_UNKNOWNS + k];
        }
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        a[j * MAX_UNKNOWNS + j] = d;
        for i in j + 1..m {
            let mut v = a[i * MAX_UNKNOWNS + j];
            for k in 0..j {
                v -= a[i * MAX_UNKNOWNS + k] * a[j * MAX_UNKNOWNS + k];
            }
            a[i * MAX_UNKNOWNS + j] = v / d;
        }
    }
    true
}

/// Solves `L L^T x = b` in place for the factor of [`small_cholesky`].
fn small_solve(l: &[f64; MAX_UNKNOWNS * MAX_UNKNOWNS], m: usize, b: &mut [f64]) {
    for i in 0..m {
        let mut v = b[i];
        for k in 0..i {
            v -= l[i * MAX_UNKNOWNS + k] * b[k];
        }
        b[i] = v / l[i * MAX_UNKNOWNS + i];
    }
    for i in (0..m).rev() {
        let mut v = b[i];
        for k in i + 1..m {
            v -= l[k * MAX_UNKNOWNS + i] * b[k];
        }
        b[i] = v / l[i * MAX_UNKNOWNS + i];
    }
}

impl<M: ElementModel> Hessian for Chain<'_, M> {
    /// Condenses the model's local unknowns out of the Newton system: they
    /// couple only within their own element's block (the chain terms do
    /// not involve them), so eliminating them leaves a smaller Cholesky.
    fn solve_shifted(&mut self, h: &[f64], g: &[f64], tau: f64, p: &mut [f64]) -> Option<bool> {
        let nl = M::LOCAL.len();
        if nl == 0 {
            return None;
        }
        let n = M::Coeffs::LEN;
        let nk = n - nl;
        let ne = self.k.len();
        let (dim, m) = (n * ne, nk * ne);
        if m > fpc_newton::AUTO_DENSE_MAX_DIM {
            return None; // faer's factorisation wins at this size
        }
        let keep: [usize; MAX_UNKNOWNS] = {
            let mut kk = [0; MAX_UNKNOWNS];
            for (t, i) in kept::<M>().enumerate() {
                kk[t] = i;
            }
            kk
        };
        // read an entry of the (lower-triangle) Hessian
        let at = |r: usize, c: usize| {
            if r >= c {
                h[r + dim * c]
            } else {
                h[c + dim * r]
            }
        };
        self.red.resize(m * m, 0.0);
        self.rg.resize(m, 0.0);
        // per element: factor the shifted local block, and X = L^-1 B_lc
        for e in 0..ne {
            let base = n * e;
            let l = &mut self.local_l[e];
            for (a, &ia) in M::LOCAL.iter().enumerate() {
                for (b, &ib) in M::LOCAL.iter().enumerate().take(a + 1) {
                    l[a * MAX_UNKNOWNS + b] =
                        at(base + ia, base + ib) + if a == b { tau } else { 0.0 };
                }
            }
            if !small_cholesky(l, nl) {
                return Some(false);
            }
            // column t of B_lc (local rows, kept column t), then solved by L
            let c = &mut self.local_c[e];
            for t in 0..nk {
                let mut col = [0.0; MAX_UNKNOWNS];
                for (a, &ia) in M::LOCAL.iter().enumerate() {
                    col[a] = at(base + ia, base + keep[t]);
                }
                // forward substitution only: y = L^-1 col
                for i in 0..nl {
                    let mut v = col[i];
                    for k in 0..i {
                        v -= l[i * MAX_UNKNOWNS + k] * col[k];
                    }
                    col[i] = v / l[i * MAX_UNKNOWNS + i];
                }
                for a in 0..nl {
                    c[a * MAX_UNKNOWNS + t] = col[a];
                }
            }
        }
        for col in 0..m {
            let (ec, tc) = (col / nk, col % nk);
            let jc = n * ec + keep[tc];
            // L^-1 g_l for this element
            let mut gl = [0.0; MAX_UNKNOWNS];
            for (a, &ia) in M::LOCAL.iter().enumerate() {
                gl[a] = g[n * ec + ia];
            }
            let l = &self.local_l[ec];
            for i in 0..nl {
                let mut v = gl[i];
                for k in 0..i {
                    v -= l[i * MAX_UNKNOWNS + k] * gl[k];
                }
                gl[i] = v / l[i * MAX_UNKNOWNS + i];
            }
            let c = &self.local_c[ec];
            let mut corr = 0.0;
            for a in 0..nl {
                corr += c[a * MAX_UNKNOWNS + tc] * gl[a];
            }
            self.rg[col] = g[jc] - corr;
            let src = &h[dim * jc..dim * (jc + 1)];
            let out = &mut self.red[m * col..m * (col + 1)];
            // the diagonal block: Schur complement of the local unknowns
            for (r, o) in out.iter_mut().enumerate().take(nk * ec + nk).skip(col) {
                let tr = r % nk;
                let mut s = 0.0;
                for a in 0..nl {
                    s += c[a * MAX_UNKNOWNS + tr] * c[a * MAX_UNKNOWNS + tc];
                }
                *o = src[n * ec + keep[tr]] - s;
            }
            out[col] += tau;
            // blocks below: local unknowns do not couple across elements
            for er in ec + 1..ne {
                for t in 0..nk {
                    out[nk * er + t] = src[n * er + keep[t]];
                }
            }
        }
        if fpc_newton::cholesky_in_place(m, &mut self.red).is_err() {
            return Some(false);
        }
        for v in self.rg.iter_mut() {
            *v = -*v;
        }
        fpc_newton::cholesky_solve(m, &self.red, &mut self.rg);
        // back substitution: B_ll p_l = -g_l - B_lc p_c
        for e in 0..ne {
            let base = n * e;
            let mut rhs = [0.0; MAX_UNKNOWNS];
            for t in 0..nk {
                p[base + keep[t]] = self.rg[nk * e + t];
            }
            for (a, &ia) in M::LOCAL.iter().enumerate() {
                let mut v = -g[base + ia];
                for t in 0..nk {
                    v -= at(base + ia, base + keep[t]) * p[base + keep[t]];
                }
                rhs[a] = v;
            }
            small_solve(&self.local_l[e], nl, &mut rhs);
            for (a, &ia) in M::LOCAL.iter().enumerate() {
                p[base + ia] = rhs[a];
            }
        }
        Some(true)
    }

    fn hessian(&mut self, y: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        self.unscale_into(y);
        let n = M::Coeffs::LEN;
        let ne = self.k.len();
        let dim = n * ne;
        let loaded = self.loaded();
        let mut v = 0.0;
        // pass 1: element energies and, for the chain, end kinematics
        for (i, e) in self.finger.elements.iter().enumerate() {
            let (vi, gi, hi) = e.hessian(&self.k[i], &self.scalars);
            v += vi;
            g[n * i..n * i + n].copy_from_slice(gi.as_ref());
            self.blk[i] = hi;
            if loaded {
                let (_, eg, eh) = e.end_hessian(&self.k[i]);
                self.end_g[i] = eg;
                self.end_h[i] = eh;
            }
        }
        if loaded {
            self.chain_geometry();
            let [fx, fz] = self.f;
            v -= fx * self.tip[0] + fz * self.tip[1];
            for j in 0..ne {
                let [cs, sn] = self.rot[j];
                let fr = [cs * fx + sn * fz, -sn * fx + cs * fz];
                let qj = self.q[j];
                let fjq = -fx * qj[1] + fz * qj[0]; // F . J Q_j
                let fq = fx * qj[0] + fz * qj[1]; // F . Q_j
                let eg = self.end_g[j];
                let eh = self.end_h[j];
                let blk = &mut self.blk[j];
                for a in 0..n {
                    g[n * j + a] -= fr[0] * eg[0][a] + fr[1] * eg[1][a] + fjq * eg[2][a];
                    for b in a..n {
                        let ab = upper_index(n, a, b);
                        blk[ab] -= fr[0] * eh[0][ab] + fr[1] * eh[1][ab] + fjq * eh[2][ab]
                            - fq * eg[2][a] * eg[2][b];
                    }
                }
                // scaled coupling vectors: u_j = grad eta_j, and
                // w_j = (J^T Fr_j) . De_j - (F . Q_j) grad eta_j, J^T Fr = (Fr_z, -Fr_x)
                let sj = self.finger.unscale[j];
                for a in 0..n {
                    self.u[j][a] = eg[2][a] * sj[a];
                    self.w[j][a] = (fr[1] * eg[0][a] - fr[0] * eg[1][a] - fq * eg[2][a]) * sj[a];
                }
            }
        }
        // pass 2: write the scaled Hessian
        for j in 0..ne {
            let sj = self.finger.unscale[j];
            let blk = &self.blk[j];
            for b in 0..n {
                let col = &mut h[dim * (n * j + b)..dim * (n * j + b + 1)];
                for a in 0..n {
                    col[n * j + a] = blk[upper_index(n, a, b)] * sj[a] * sj[b];
                }
                // lower triangle only (Newton reads no more): row blocks k > j
                let below = &mut col[n * (j + 1)..];
                if loaded {
                    // row block k > column block j: -w_k u_j^T
                    let ub = self.u[j][b];
                    for (dst, w) in below.chunks_exact_mut(n).zip(&self.w[j + 1..]) {
                        for a in 0..n {
                            dst[a] = -w[a] * ub;
                        }
                    }
                } else {
                    below.fill(0.0);
                }
            }
        }
        for (i, s) in self.finger.unscale.iter().enumerate() {
            for a in 0..n {
                g[n * i + a] *= s[a];
            }
        }
        v
    }
}
