//! Derivative strategies for the same Newton solve (prints a table; not criterion).
//!
//! ```sh
//! cargo bench --bench derivatives
//! ```
//!
//! One problem: the default actuator (eps0 = 0.25), N = 8 equal elements,
//! tip load (Fx, Fz) = (0.939782, 0.521707) N, no pressure, Newton from the
//! unloaded equilibrium, in the solver's scaled unknowns
//! `y = (a1, a3 L^2, b1, c2 L)` per element. One `fpc_newton::Newton`
//! configuration (the one `fpc::finger::Solver` uses: `gtol = 1e-11` times the
//! stiffness scale, at most 60 iterations) minimises the total potential
//! energy given three ways:
//!
//! - **generated**: the build-time generated straight-line kernels with the
//!   exactly differentiated chain: the library's own Newton problem in the
//!   scaled unknowns (`Finger::problem`), which reuses its buffers and
//!   condenses the local unknowns like the solver;
//! - **dual**: the same energy written once, generically over a
//!   `num_dual::DualNum` type: element energies by tensor Gauss-Legendre
//!   quadrature of the energy densities over the elements' blocks (the
//!   library's, `fpc::actuator::element_blocks`; exact: linear density 3
//!   x-points by 2 z-points,
//!   prestressed 6 by 3, gas volume 2 by 1), and the chain tip potential
//!   with `atan2`/`sin_cos` in the dual type. Derivatives by
//!   `num_dual::hessian` (`Dual2SVec64`): per element with 4 unknowns
//!   (using the block-diagonal structure), plus the tip potential over all
//!   4N unknowns. Energies at line-search trial points are the same
//!   generic code in `f64`.
//! - **dual (whole)**: the same, but `num_dual::hessian` of the total
//!   energy over all 4N unknowns at once (no structure used), for
//!   reference;
//! - **FD**: the generated value kernels only (`Finger::energy`),
//!   gradient by central differences (2n energies, step 1e-6 in scaled
//!   units), Hessian by central second differences of the energy (step
//!   1e-4; 2n + 2n(n-1) energies).
//!
//! Every result is judged the same way: the residual is the inf-norm of the
//! EXACT generated scaled gradient at the returned point, over the
//! stiffness scale (what `fpc` reports as `residual_norm`).
//!
//! Before timing, the dual and FD gradients and Hessians are compared with
//! the generated ones at a random point (a correctness check of both).

use std::time::{Duration, Instant};

use fpc::actuator::{element_blocks, ElementBlocks};
use fpc::{Actuator, Coefficients, Finger, Load, Partition, SolveOptions};
use fpc_newton::{Dense, DenseHessian, Energy, Gradient, Hessian, Newton, NewtonOptions, Report};
use nalgebra::SVector;
use num_dual::{Dual2SVec64, DualNum, DualSVec64};

const N: usize = 8;
const DIM: usize = 4 * N;
const EPS0: f64 = 0.25;
const FX: f64 = 0.939782;
const FZ: f64 = 0.521707;
/// `SolveOptions::default().rtol`, the relative residual the library solves to.
const RTOL: f64 = 1e-11;

// ------------------------------------------------------------ quadrature

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton's method on P_n).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let legendre = |x: f64| {
        let (mut p0, mut p1) = (1.0, x);
        for j in 2..=n {
            let j = j as f64;
            let p2 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p0) / j;
            p0 = p1;
            p1 = p2;
        }
        (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
    };
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre(x);
                let dx = p / dp;
                x -= dx;
                if dx.abs() < 1e-17 {
                    break;
                }
            }
            let (_, dp) = legendre(x);
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Tensor rule on [x0, x1] x [z0, z1]: `(x^2, 2 z, weight * width)` per point.
fn tensor(nx: usize, nz: usize, b: (f64, f64, f64, f64, f64)) -> Vec<[f64; 3]> {
    let (x0, x1, z0, z1, width) = b;
    let (cx, hx) = (0.5 * (x0 + x1), 0.5 * (x1 - x0));
    let (cz, hz) = (0.5 * (z0 + z1), 0.5 * (z1 - z0));
    let mut out = Vec::with_capacity(nx * nz);
    for &(tx, wx) in &gauss_legendre(nx) {
        for &(tz, wz) in &gauss_legendre(nz) {
            let x = cx + hx * tx;
            let z = cz + hz * tz;
            out.push([x * x, 2.0 * z, hx * wx * hz * wz * width]);
        }
    }
    out
}

/// One element as quadrature points with their material constants.
#[derive(Clone)]
struct QuadElement {
    len: f64,
    /// raw = scaled * s
    s: [f64; 4],
    /// `[x^2, 2z, w q11/2, w q12, w q22/2]`
    linear: Vec<[f64; 5]>,
    /// `[x^2, 2z, w, eps0, p0/2, -p1/3, p2/4, -p3/5, q22/2]`
    prestressed: Vec<[f64; 9]>,
    /// `[x^2, 2z, w]`
    gas: Vec<[f64; 3]>,
}

impl QuadElement {
    fn new(b: &ElementBlocks) -> QuadElement {
        let l = b.length;
        let mut linear = Vec::new();
        for blk in &b.linear {
            for [x2, tz, w] in tensor(3, 2, (blk.x0, blk.x1, blk.z0, blk.z1, blk.width)) {
                linear.push([x2, tz, 0.5 * w * blk.q11, w * blk.q12, 0.5 * w * blk.q22]);
            }
        }
        let mut prestressed = Vec::new();
        for blk in &b.prestressed {
            for [x2, tz, w] in tensor(6, 3, (blk.x0, blk.x1, blk.z0, blk.z1, blk.width)) {
                let p = [blk.p1, blk.p2, blk.p3, blk.p4];
                prestressed.push([
                    x2,
                    tz,
                    w,
                    blk.eps0,
                    p[0] / 2.0,
                    -p[1] / 3.0,
                    p[2] / 4.0,
                    -p[3] / 5.0,
                    0.5 * blk.q22,
                ]);
            }
        }
        let mut gas = Vec::new();
        for blk in &b.gas {
            gas.extend(tensor(2, 1, (blk.x0, blk.x1, blk.z0, blk.z1, blk.width)));
        }
        QuadElement {
            len: l,
            s: [1.0, 1.0 / (l * l), 1.0, 1.0 / l],
            linear,
            prestressed,
            gas,
        }
    }

    fn points(&self) -> usize {
        self.linear.len() + self.prestressed.len() + self.gas.len()
    }
}

// ------------------------------------------------------------ the energy, generic

/// Element energy `Psi_e - kp V_e` at scaled unknowns `y` (any dual type).
fn element_energy<D: DualNum<Primitive = f64> + Copy>(q: &QuadElement, y: [D; 4], kp: f64) -> D {
    let a1 = y[0] * q.s[0];
    let a3 = y[1] * q.s[1];
    let b1 = y[2] * q.s[2];
    let c2 = y[3] * q.s[3];
    let atom = a3 * 3.0 + c2 * c2 * 2.0;
    let bb = b1 * b1;
    let mut v = D::from(0.0);
    for &[x2, tz, h11, q12, h22] in &q.linear {
        let ex = a1 + atom * x2 - c2 * tz;
        v += ex * (ex * h11 + b1 * q12) + bb * h22;
    }
    for &[x2, tz, w, eps0, c2p, c3p, c4p, c5p, h22] in &q.prestressed {
        let s = a1 + atom * x2 - c2 * tz + eps0;
        let psi = s * s * (((s * c5p + c4p) * s + c3p) * s + c2p);
        v += (psi + bb * h22) * w;
    }
    if kp != 0.0 {
        let mut vol = D::from(0.0);
        let one_b = b1 + 1.0;
        for &[x2, tz, w] in &q.gas {
            let ex = a1 + atom * x2 - c2 * tz;
            vol += (ex + 1.0) * one_b * w;
        }
        v -= vol * kp;
    }
    v
}

/// Tip potential `-(F . tip)` of the chain at scaled unknowns `y` (4N of them).
fn tip_potential<D: DualNum<Primitive = f64> + Copy>(q: &[QuadElement], y: &[D], f: [f64; 2]) -> D {
    let mut theta = D::from(0.0);
    let mut px = D::from(0.0);
    let mut pz = D::from(0.0);
    for (i, e) in q.iter().enumerate() {
        let l = e.len;
        let a1 = y[4 * i] * e.s[0];
        let a3 = y[4 * i + 1] * e.s[1];
        let c2 = y[4 * i + 3] * e.s[3];
        let xe = (a1 + 1.0) * l + a3 * (l * l * l);
        let ze = c2 * (l * l);
        let eta = (c2 * (2.0 * l)).atan2(a1 + 1.0 + a3 * (3.0 * l * l));
        let (sn, cs) = theta.sin_cos();
        px += cs * xe - sn * ze;
        pz += sn * xe + cs * ze;
        theta += eta;
    }
    -(px * f[0] + pz * f[1])
}

/// Total potential energy at scaled unknowns `y` (4N of them).
fn total_energy<D: DualNum<Primitive = f64> + Copy>(
    q: &[QuadElement],
    y: &[D],
    kp: f64,
    f: [f64; 2],
) -> D {
    let mut v = D::from(0.0);
    for (i, e) in q.iter().enumerate() {
        v += element_energy(e, [y[4 * i], y[4 * i + 1], y[4 * i + 2], y[4 * i + 3]], kp);
    }
    if f != [0.0, 0.0] {
        v += tip_potential(q, y, f);
    }
    v
}

// ------------------------------------------------------------ (b) dual numbers

/// The finger as a Newton problem with num-dual derivatives.
struct DualProblem {
    q: Vec<QuadElement>,
    kp: f64,
    f: [f64; 2],
    /// `num_dual::hessian` over all 4N unknowns at once (no structure).
    whole: bool,
}

impl Energy for DualProblem {
    fn dim(&self) -> usize {
        DIM
    }
    fn energy(&mut self, y: &[f64]) -> f64 {
        total_energy::<f64>(&self.q, y, self.kp, self.f)
    }
}

impl Gradient for DualProblem {
    fn gradient(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        let (q, kp, f) = (&self.q, self.kp, self.f);
        if self.whole {
            let (v, gr) = num_dual::gradient(
                |v: SVector<DualSVec64<DIM>, DIM>| total_energy(q, v.as_slice(), kp, f),
                &SVector::<f64, DIM>::from_column_slice(y),
            );
            g.copy_from_slice(gr.as_slice());
            return v;
        }
        let mut v = 0.0;
        for (i, e) in q.iter().enumerate() {
            let (vi, gi) = num_dual::gradient(
                |v: SVector<DualSVec64<4>, 4>| element_energy(e, [v[0], v[1], v[2], v[3]], kp),
                &SVector::<f64, 4>::from_column_slice(&y[4 * i..4 * i + 4]),
            );
            v += vi;
            g[4 * i..4 * i + 4].copy_from_slice(gi.as_slice());
        }
        if f != [0.0, 0.0] {
            let (vt, gt) = num_dual::gradient(
                |v: SVector<DualSVec64<DIM>, DIM>| tip_potential(q, v.as_slice(), f),
                &SVector::<f64, DIM>::from_column_slice(y),
            );
            v += vt;
            for (gi, ti) in g.iter_mut().zip(gt.iter()) {
                *gi += ti;
            }
        }
        v
    }
}

impl DenseHessian for DualProblem {
    fn hessian(&mut self, y: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let (q, kp, f) = (&self.q, self.kp, self.f);
        if self.whole {
            let (v, gr, hm) = num_dual::hessian(
                |v: SVector<Dual2SVec64<DIM>, DIM>| total_energy(q, v.as_slice(), kp, f),
                &SVector::<f64, DIM>::from_column_slice(y),
            );
            g.copy_from_slice(gr.as_slice());
            h.copy_from_slice(hm.as_slice()); // column-major, like nalgebra
            return v;
        }
        h.fill(0.0);
        let mut v = 0.0;
        for (i, e) in q.iter().enumerate() {
            let (vi, gi, hi) = num_dual::hessian(
                |v: SVector<Dual2SVec64<4>, 4>| element_energy(e, [v[0], v[1], v[2], v[3]], kp),
                &SVector::<f64, 4>::from_column_slice(&y[4 * i..4 * i + 4]),
            );
            v += vi;
            g[4 * i..4 * i + 4].copy_from_slice(gi.as_slice());
            for b in 0..4 {
                for a in 0..4 {
                    h[(4 * i + a) + DIM * (4 * i + b)] = hi[(a, b)];
                }
            }
        }
        if f != [0.0, 0.0] {
            let (vt, gt, ht) = num_dual::hessian(
                |v: SVector<Dual2SVec64<DIM>, DIM>| tip_potential(q, v.as_slice(), f),
                &SVector::<f64, DIM>::from_column_slice(y),
            );
            v += vt;
            for (gi, ti) in g.iter_mut().zip(gt.iter()) {
                *gi += ti;
            }
            for (hi, ti) in h.iter_mut().zip(ht.as_slice()) {
                *hi += ti;
            }
        }
        v
    }
}

// ------------------------------------------------------------ (a) generated

/// The finger as a Newton problem in the solver's scaled unknowns
/// (`raw = scaled * Finger::unknown_scales()`), through the public
/// raw-coefficient API.
struct Generated<'a> {
    finger: &'a Finger,
    load: Load,
    /// raw value of one scaled unit, per unknown
    s: Vec<f64>,
}

impl<'a> Generated<'a> {
    fn new(finger: &'a Finger, load: Load) -> Generated<'a> {
        Generated {
            finger,
            load,
            s: finger.unknown_scales(),
        }
    }

    fn raw(&self, y: &[f64]) -> Coefficients {
        let values = y.iter().zip(&self.s).map(|(y, s)| y * s).collect();
        Coefficients::new(self.finger.unknowns_per_element(), values).unwrap()
    }

    fn scaled(&self, k: &Coefficients) -> Vec<f64> {
        k.as_slice()
            .iter()
            .zip(&self.s)
            .map(|(k, s)| k / s)
            .collect()
    }
}

impl Energy for Generated<'_> {
    fn dim(&self) -> usize {
        self.s.len()
    }
    fn energy(&mut self, y: &[f64]) -> f64 {
        self.finger.energy(&self.load, &self.raw(y)).unwrap()
    }
}

impl Gradient for Generated<'_> {
    fn gradient(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        let (v, gr) = self.finger.gradient(&self.load, &self.raw(y)).unwrap();
        for ((g, gr), s) in g.iter_mut().zip(gr).zip(&self.s) {
            *g = gr * s;
        }
        v
    }
}

impl DenseHessian for Generated<'_> {
    fn hessian(&mut self, y: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let n = self.s.len();
        let (v, gr, hr) = self.finger.hessian(&self.load, &self.raw(y)).unwrap();
        for i in 0..n {
            g[i] = gr[i] * self.s[i];
        }
        // the full symmetric matrix, column-major
        for j in 0..n {
            for i in 0..n {
                h[i + n * j] = hr[i + n * j] * self.s[i] * self.s[j];
            }
        }
        v
    }
}

// ------------------------------------------------------------ (c) finite differences

/// The generated energy with central-difference derivatives.
struct FdProblem<'a> {
    chain: Generated<'a>,
    /// gradient step (scaled units)
    hg: f64,
    /// Hessian step (scaled units)
    hh: f64,
    x: Vec<f64>,
}

impl Energy for FdProblem<'_> {
    fn dim(&self) -> usize {
        self.chain.dim()
    }
    fn energy(&mut self, y: &[f64]) -> f64 {
        self.chain.energy(y)
    }
}

impl FdProblem<'_> {
    fn fd_gradient(&mut self, y: &[f64], g: &mut [f64]) {
        let h = self.hg;
        self.x.copy_from_slice(y);
        for i in 0..y.len() {
            self.x[i] = y[i] + h;
            let fp = self.chain.energy(&self.x);
            self.x[i] = y[i] - h;
            let fm = self.chain.energy(&self.x);
            self.x[i] = y[i];
            g[i] = (fp - fm) / (2.0 * h);
        }
    }
}

impl Gradient for FdProblem<'_> {
    fn gradient(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        self.fd_gradient(y, g);
        self.chain.energy(y)
    }
}

impl DenseHessian for FdProblem<'_> {
    fn hessian(&mut self, y: &[f64], g: &mut [f64], hm: &mut [f64]) -> f64 {
        let n = y.len();
        let f0 = self.chain.energy(y);
        self.fd_gradient(y, g);
        let h = self.hh;
        self.x.copy_from_slice(y);
        for i in 0..n {
            self.x[i] = y[i] + h;
            let fp = self.chain.energy(&self.x);
            self.x[i] = y[i] - h;
            let fm = self.chain.energy(&self.x);
            self.x[i] = y[i];
            hm[i + n * i] = (fp - 2.0 * f0 + fm) / (h * h);
            for j in 0..i {
                let corner = |si: f64, sj: f64, x: &mut [f64], c: &mut Generated| {
                    x[i] = y[i] + si * h;
                    x[j] = y[j] + sj * h;
                    let v = c.energy(x);
                    x[i] = y[i];
                    x[j] = y[j];
                    v
                };
                let fpp = corner(1.0, 1.0, &mut self.x, &mut self.chain);
                let fpm = corner(1.0, -1.0, &mut self.x, &mut self.chain);
                let fmp = corner(-1.0, 1.0, &mut self.x, &mut self.chain);
                let fmm = corner(-1.0, -1.0, &mut self.x, &mut self.chain);
                let hij = (fpp - fpm - fmp + fmm) / (4.0 * h * h);
                hm[i + n * j] = hij;
                hm[j + n * i] = hij;
            }
        }
        f0
    }
}

// ------------------------------------------------------------ harness

struct Run {
    name: &'static str,
    median: Duration,
    reps: usize,
    report: Report,
    y: Vec<f64>,
    per_hessian: Duration,
}

fn median(mut t: Vec<Duration>) -> Duration {
    t.sort();
    t[t.len() / 2]
}

/// Median wall time of full Newton solves from `y0`, repeated until
/// `budget` is spent (at least `min_reps`, at most `max_reps` solves), and
/// of single Hessian evaluations at `y0`.
fn time_solves<P: Hessian>(
    name: &'static str,
    p: &mut P,
    opts: NewtonOptions,
    y0: &[f64],
    budget: Duration,
    min_reps: usize,
    max_reps: usize,
) -> Run {
    let n = y0.len();
    let mut newton = Newton::new(n, opts);
    let mut y = y0.to_vec();
    let report = newton.minimize(p, &mut y); // warm-up, and the result
    let mut times = Vec::new();
    let start = Instant::now();
    let mut yt = y0.to_vec();
    while times.len() < max_reps && (times.len() < min_reps || start.elapsed() < budget) {
        yt.copy_from_slice(y0);
        let t = Instant::now();
        let r = newton.minimize(p, std::hint::black_box(&mut yt));
        times.push(t.elapsed());
        assert_eq!(r.iterations, report.iterations, "{name}: not repeatable");
    }
    let mut g = vec![0.0; n];
    let mut ht = Vec::new();
    let start = Instant::now();
    while ht.len() < 5 || (ht.len() < 1000 && start.elapsed() < budget / 4) {
        let t = Instant::now();
        p.hessian(std::hint::black_box(y0), &mut g);
        ht.push(t.elapsed());
    }
    Run {
        name,
        reps: times.len(),
        median: median(times),
        report,
        y,
        per_hessian: median(ht),
    }
}

fn fmt_time(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s >= 1e-3 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.1} µs", s * 1e6)
    }
}

/// max |a - b| / max |b|
fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let num = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    let den = b.iter().map(|x| x.abs()).fold(0.0, f64::max);
    num / den
}

/// max over entries with |b| above 1e-8 max|b| of |a - b| / |b|
fn rel_diff_entrywise(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().map(|x| x.abs()).fold(0.0, f64::max);
    a.iter()
        .zip(b)
        .filter(|(_, y)| y.abs() > 1e-8 * scale)
        .map(|(x, y)| ((x - y) / y).abs())
        .fold(0.0, f64::max)
}

fn run() {
    let act = Actuator::paper(EPS0).unwrap();
    let part = Partition::equal(act.geometry().lx, N).unwrap();
    let finger = Finger::new(&act, &part, true);
    let load = Load::unloaded().with_tip_force(FX, FZ);
    let blocks = element_blocks(&act, &part, true);
    let quad: Vec<QuadElement> = blocks.iter().map(QuadElement::new).collect();
    // the dual strategy's scaling is the solver's
    for (q, s) in quad.iter().zip(finger.unknown_scales().chunks_exact(4)) {
        for (a, b) in q.s.iter().zip(s) {
            assert!(
                (a - b).abs() <= 1e-15 * b,
                "scale {a:e} vs the solver's {b:e}"
            );
        }
    }
    let unloaded = finger
        .solve(&Load::unloaded(), &SolveOptions::default().tip_only())
        .unwrap();
    let stiffness = finger.stiffness_scale();
    let convert = Generated::new(&finger, load);
    let y0 = convert.scaled(&unloaded.coefficients);
    let mut exact = finger.problem(&load);
    let opts = NewtonOptions {
        gtol: RTOL * stiffness,
        max_iter: 60,
        ..NewtonOptions::default()
    };

    println!("# Derivative strategies for one Newton solve");
    println!();
    println!(
        "Problem: default actuator eps0 = {EPS0}, N = {N} ({DIM} unknowns, scaled), tip load \
         (Fx, Fz) = ({FX}, {FZ}) N, no pressure, Newton from the unloaded equilibrium; \
         gtol = {RTOL:e} x stiffness scale ({stiffness:.4e} N mm), max_iter 60."
    );
    println!(
        "Quadrature points per element (dual): {} (linear 3x2, prestressed 6x3, gas 2x1 per block).",
        quad.iter().map(QuadElement::points).max().unwrap()
    );
    println!();

    // ---------------- correctness check at a random point
    let mut dual = DualProblem {
        q: quad.clone(),
        kp: load.kappa * load.pressure,
        f: [load.fx, load.fz],
        whole: false,
    };
    let mut dual_whole = DualProblem {
        q: quad.clone(),
        kp: dual.kp,
        f: dual.f,
        whole: true,
    };
    let mut fd = FdProblem {
        chain: Generated::new(&finger, load),
        hg: 1e-6,
        hh: 1e-4,
        x: vec![0.0; DIM],
    };
    println!("## Check at a random point (against the generated kernels)");
    println!();
    println!("| scene | strategy | energy rel. diff | max abs gradient diff / max abs gradient | max abs Hessian diff / max abs Hessian | worst entrywise Hessian rel. diff |");
    println!("|---|---|---|---|---|---|");
    let mut rng = fastrand::Rng::with_seed(0x9e37_79b9);
    let mut rnd = move || 2.0 * rng.f64() - 1.0;
    let yr: Vec<f64> = y0.iter().map(|v| v + 0.02 * rnd()).collect();
    let mut worst_dual: f64 = 0.0;
    for (scene, l) in [
        ("tip load", load),
        ("tip load + 100 kPa", load.with_pressure_kpa(100.0)),
    ] {
        let mut ex = Generated::new(&finger, l);
        let (mut ge, mut he) = (vec![0.0; DIM], vec![0.0; DIM * DIM]);
        let ve = ex.hessian(&yr, &mut ge, &mut he);
        let kp = l.kappa * l.pressure;
        dual.kp = kp;
        dual_whole.kp = kp;
        fd.chain.load = l;
        let strategies: [(&str, &mut dyn DenseHessian); 3] = [
            ("dual", &mut dual),
            ("dual (whole)", &mut dual_whole),
            ("FD", &mut fd),
        ];
        for (name, p) in strategies {
            let (mut g, mut h) = (vec![0.0; DIM], vec![0.0; DIM * DIM]);
            let v = p.hessian(&yr, &mut g, &mut h);
            let (dv, dg, dh, dhe) = (
                ((v - ve) / ve).abs(),
                rel_diff(&g, &ge),
                rel_diff(&h, &he),
                rel_diff_entrywise(&h, &he),
            );
            if name.starts_with("dual") {
                worst_dual = worst_dual.max(dv).max(dg).max(dh);
            }
            println!("| {scene} | {name} | {dv:.2e} | {dg:.2e} | {dh:.2e} | {dhe:.2e} |");
        }
    }
    println!();
    assert!(
        worst_dual < 1e-10,
        "dual and generated derivatives disagree ({worst_dual:e})"
    );
    dual.kp = 0.0;
    dual_whole.kp = 0.0;
    fd.chain.load = load;

    // ---------------- timing
    let budget = Duration::from_secs(3);
    let runs = vec![
        time_solves("generated (a)", &mut exact, opts, &y0, budget, 50, 20_000),
        time_solves(
            "dual (b)",
            &mut Dense::new(&mut dual),
            opts,
            &y0,
            budget,
            5,
            2_000,
        ),
        time_solves(
            "dual, whole 4N (b')",
            &mut Dense::new(&mut dual_whole),
            opts,
            &y0,
            budget,
            3,
            200,
        ),
        time_solves(
            "FD (c)",
            &mut Dense::new(&mut fd),
            opts,
            &y0,
            budget,
            5,
            2_000,
        ),
    ];

    let base = &runs[0];
    let (tip_a, _) = finger.tip(&convert.raw(&base.y)).unwrap();
    let mut gex = vec![0.0; DIM];
    println!(
        "## Newton solves ({} cores available; median over repeated solves)",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    println!();
    println!("| strategy | median / solve | x generated | solves timed | iterations | evals E/G/H | termination | final residual (exact, rel.) | abs tip diff vs (a) (mm) | median / Hessian eval |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut summary = Vec::new();
    for r in &runs {
        exact.gradient(&r.y, &mut gex);
        let res = gex.iter().map(|v| v.abs()).fold(0.0, f64::max) / stiffness;
        let (tip, _) = finger.tip(&convert.raw(&r.y)).unwrap();
        let dtip = ((tip[0] - tip_a[0]).powi(2) + (tip[1] - tip_a[1]).powi(2)).sqrt();
        let ratio = r.median.as_secs_f64() / base.median.as_secs_f64();
        println!(
            "| {} | {} | {:.1} | {} | {} | {}/{}/{} | {:?} | {:.2e} | {:.1e} | {} |",
            r.name,
            fmt_time(r.median),
            ratio,
            r.reps,
            r.report.iterations,
            r.report.energy_evals,
            r.report.gradient_evals,
            r.report.hessian_evals,
            r.report.reason,
            res,
            dtip,
            fmt_time(r.per_hessian),
        );
        summary.push((ratio, res));
    }
    println!();
    // where the time of one dual Hessian evaluation goes
    let time_eval = |f: &mut dyn FnMut()| -> Duration {
        let mut t = Vec::new();
        let start = Instant::now();
        while t.len() < 5 || (t.len() < 10_000 && start.elapsed() < Duration::from_millis(300)) {
            let s = Instant::now();
            f();
            t.push(s.elapsed());
        }
        median(t)
    };
    let (mut g, mut h) = (vec![0.0; DIM], vec![0.0; DIM * DIM]);
    let mut dual_elements = DualProblem {
        q: quad.clone(),
        kp: 0.0,
        f: [0.0, 0.0],
        whole: false,
    };
    let t_de = time_eval(&mut || {
        dual_elements.hessian(std::hint::black_box(&y0), &mut g, &mut h);
    });
    let t_dt = time_eval(&mut || {
        std::hint::black_box(num_dual::hessian(
            |v: SVector<Dual2SVec64<DIM>, DIM>| tip_potential(&quad, v.as_slice(), [FX, FZ]),
            &SVector::<f64, DIM>::from_column_slice(std::hint::black_box(&y0)),
        ));
    });
    let mut unloaded_chain = Generated::new(&finger, Load::unloaded());
    let t_ge = time_eval(&mut || {
        unloaded_chain.hessian(std::hint::black_box(&y0), &mut g, &mut h);
    });
    println!(
        "One dual Hessian evaluation, split: the {N} element energies (Dual2SVec64<4> each) {}, \
         the tip potential (Dual2SVec64<{DIM}>) {}; generated, without the tip load (element \
         kernels only) {}.",
        fmt_time(t_de),
        fmt_time(t_dt),
        fmt_time(t_ge)
    );
    println!();
    let (res_a, (dual_ratio, res_b), (fd_ratio, res_c)) = (summary[0].1, summary[1], summary[3]);
    let verdict = |ok: bool| if ok { "met" } else { "NOT met" };
    println!(
        "Target: generated >= 3x faster than dual numbers at equal or better residual: {:.1}x, residual {:.1e} vs {:.1e} -> {}",
        dual_ratio,
        res_a,
        res_b,
        verdict(dual_ratio >= 3.0 && res_a <= res_b.max(RTOL))
    );
    println!(
        "Target: generated >= 5x faster than finite differences at equal or better residual: {:.1}x, residual {:.1e} vs {:.1e} -> {}",
        fd_ratio,
        res_a,
        res_c,
        verdict(fd_ratio >= 5.0 && res_a <= res_c.max(RTOL))
    );
    println!(
        "(the residual criterion counts a residual within the solver's tolerance {RTOL:e} as equal)"
    );
}

fn main() {
    // `cargo bench` passes `--bench`; nothing to parse. The whole-4N dual
    // numbers (`Dual2SVec64<32>`, ~8 kB each) need a large stack.
    std::thread::Builder::new()
        .stack_size(512 << 20)
        .spawn(run)
        .unwrap()
        .join()
        .unwrap();
}
