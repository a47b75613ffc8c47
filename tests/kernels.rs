//! The generated element kernels against methods written here, independently
//! of the generator, from docs/model.md sections 3-4:
//!
//! - tensor Gauss-Legendre quadrature of the energy densities (values, and
//!   the chain-rule derivatives of the densities);
//! - central finite differences with Richardson extrapolation;
//! - the closed-form element end and end slope;
//! - an element energy assembled from the laminate description (cross
//!   section by cross section, not box by box as the library does);
//! - physical closed forms at K = 0.
//!
//! Random inputs come from a seeded xorshift generator, so every run checks
//! the same cases. Each test prints its worst error (`--nocapture`).

use fpc::kernels::{
    end_hessian, end_value, gas_gradient, gas_hessian, gas_moments, gas_value, linear_gradient,
    linear_hessian, linear_moments, linear_value, prestressed_gradient, prestressed_hessian,
    prestressed_moments, prestressed_value, upper_index, GAS_MOMENTS, LINEAR_MOMENTS,
    PRESTRESSED_MOMENTS,
};
use fpc::{element_blocks, Actuator, Element, Partition};
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::OnceLock;

// ---------------------------------------------------------------------------
// Deterministic random numbers (xorshift64*).

struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Two sorted draws in [lo, hi], at least `gap` apart.
    fn interval(&mut self, lo: f64, hi: f64, gap: f64) -> (f64, f64) {
        loop {
            let (a, b) = (self.range(lo, hi), self.range(lo, hi));
            let (a, b) = if a < b { (a, b) } else { (b, a) };
            if b - a >= gap {
                return (a, b);
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Gauss-Legendre rules on [-1, 1], by Newton's method on P_n.

fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    assert!(n >= 2);
    let legendre = |x: f64| {
        // (P_n(x), P_n'(x))
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
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
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

/// Nodes and weights of an n-point rule mapped to [a, b] (the rules on
/// [-1, 1] are computed once).
fn rule(n: usize, a: f64, b: f64) -> Vec<(f64, f64)> {
    static RULES: OnceLock<Vec<Vec<(f64, f64)>>> = OnceLock::new();
    let rules = RULES.get_or_init(|| {
        (0..=NX.max(NZ))
            .map(|n| if n < 2 { Vec::new() } else { gauss_legendre(n) })
            .collect()
    });
    let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
    rules[n].iter().map(|&(t, w)| (c + h * t, h * w)).collect()
}

/// x: 8 points (exact to degree 15; the densities reach degree 10 in x).
const NX: usize = 8;
/// z: 4 points (exact to degree 7; the densities reach degree 5 in z).
const NZ: usize = 4;

#[test]
fn gauss_legendre_rules_are_exact() {
    for n in [NZ, NX] {
        for deg in 0..2 * n {
            let got: f64 = rule(n, -0.7, 2.3)
                .iter()
                .map(|(x, w)| w * x.powi(deg as i32))
                .sum();
            let want =
                (2.3f64.powi(deg as i32 + 1) - (-0.7f64).powi(deg as i32 + 1)) / (deg as f64 + 1.0);
            assert!(
                (got - want).abs() <= 1e-14 * want.abs().max(1.0),
                "n={n} deg={deg}: {got} vs {want}"
            );
        }
    }
}

// ---------------------------------------------------------------------------
// The model, written from docs/model.md section 4.

type K = [f64; 4];

/// eps_x = a1 + (3 a3 + 2 c2^2) x^2 - 2 z c2.
fn eps_x(k: &K, x: f64, z: f64) -> f64 {
    let [a1, a3, _, c2] = *k;
    a1 + (3.0 * a3 + 2.0 * c2 * c2) * x * x - 2.0 * z * c2
}

/// d eps_x / d K_i.
fn d_eps_x(k: &K, x: f64, z: f64) -> [f64; 4] {
    let c2 = k[3];
    [1.0, 3.0 * x * x, 0.0, 4.0 * c2 * x * x - 2.0 * z]
}

/// |d eps_x / d K_i| with each term by absolute value.
fn d_eps_x_magnitude(k: &K, x: f64, z: f64) -> [f64; 4] {
    [
        1.0,
        3.0 * x * x,
        0.0,
        4.0 * k[3].abs() * x * x + 2.0 * z.abs(),
    ]
}

/// d eps_y / d K_i (eps_y = b1).
const D_EPS_Y: [f64; 4] = [0.0, 0.0, 1.0, 0.0];

/// An energy (or volume) density W(eps_x, eps_y) with its derivatives.
#[derive(Debug, Clone, Copy)]
enum Density {
    Linear { q11: f64, q12: f64, q22: f64 },
    Prestressed { eps0: f64, p: [f64; 4], q22: f64 },
    Gas,
}

/// W, W_e, W_y, W_ee, W_ey, W_yy (e = eps_x, y = eps_y).
struct Jet {
    f: f64,
    fe: f64,
    fy: f64,
    fee: f64,
    fey: f64,
    fyy: f64,
}

/// psi(s) = p1/2 s^2 - p2/3 s^3 + p3/4 s^4 - p4/5 s^5 and its first two derivatives.
fn psi(p: &[f64; 4], s: f64) -> (f64, f64, f64) {
    let [p1, p2, p3, p4] = *p;
    (
        p1 / 2.0 * s.powi(2) - p2 / 3.0 * s.powi(3) + p3 / 4.0 * s.powi(4) - p4 / 5.0 * s.powi(5),
        p1 * s - p2 * s.powi(2) + p3 * s.powi(3) - p4 * s.powi(4),
        p1 - 2.0 * p2 * s + 3.0 * p3 * s.powi(2) - 4.0 * p4 * s.powi(3),
    )
}

impl Density {
    fn jet(&self, e: f64, y: f64) -> Jet {
        match *self {
            Density::Linear { q11, q12, q22 } => Jet {
                f: 0.5 * q11 * e * e + q12 * e * y + 0.5 * q22 * y * y,
                fe: q11 * e + q12 * y,
                fy: q12 * e + q22 * y,
                fee: q11,
                fey: q12,
                fyy: q22,
            },
            Density::Prestressed { eps0, p, q22 } => {
                let (s0, s1, s2) = psi(&p, eps0 + e);
                Jet {
                    f: s0 + 0.5 * q22 * y * y,
                    fe: s1,
                    fy: q22 * y,
                    fee: s2,
                    fey: 0.0,
                    fyy: q22,
                }
            }
            Density::Gas => Jet {
                f: (1.0 + e) * (1.0 + y),
                fe: 1.0 + y,
                fy: 1.0 + e,
                fee: 0.0,
                fey: 1.0,
                fyy: 0.0,
            },
        }
    }

    /// The density and its derivatives with every monomial (in eps0,
    /// eps_x, eps_y) taken by absolute value: the size of the terms whose
    /// rounding an expanded kernel accumulates, the scale of its errors.
    fn magnitude_jet(&self, e: f64, y: f64) -> Jet {
        let (e, y) = (e.abs(), y.abs());
        match *self {
            Density::Linear { q11, q12, q22 } => {
                let (q11, q12, q22) = (q11.abs(), q12.abs(), q22.abs());
                Jet {
                    f: 0.5 * q11 * e * e + q12 * e * y + 0.5 * q22 * y * y,
                    fe: q11 * e + q12 * y,
                    fy: q12 * e + q22 * y,
                    fee: q11,
                    fey: q12,
                    fyy: q22,
                }
            }
            Density::Prestressed { eps0, p, q22 } => {
                let s = eps0.abs() + e;
                let p = p.map(f64::abs);
                Jet {
                    f: p[0] / 2.0 * s.powi(2)
                        + p[1] / 3.0 * s.powi(3)
                        + p[2] / 4.0 * s.powi(4)
                        + p[3] / 5.0 * s.powi(5)
                        + 0.5 * q22.abs() * y * y,
                    fe: p[0] * s + p[1] * s.powi(2) + p[2] * s.powi(3) + p[3] * s.powi(4),
                    fy: q22.abs() * y,
                    fee: p[0] + 2.0 * p[1] * s + 3.0 * p[2] * s.powi(2) + 4.0 * p[3] * s.powi(3),
                    fey: 0.0,
                    fyy: q22.abs(),
                }
            }
            Density::Gas => Jet {
                f: (1.0 + e) * (1.0 + y),
                fe: 1.0 + y,
                fy: 1.0 + e,
                fee: 0.0,
                fey: 1.0,
                fyy: 0.0,
            },
        }
    }

    fn kind(&self) -> usize {
        match self {
            Density::Linear { .. } => 0,
            Density::Prestressed { .. } => 1,
            Density::Gas => 2,
        }
    }
}

const KIND_NAMES: [&str; 3] = ["linear", "prestressed", "gas"];

/// x in [x0, x1], y in [0, width], z in [z0, z1].
#[derive(Debug, Clone, Copy)]
struct Bx {
    x0: f64,
    x1: f64,
    z0: f64,
    z1: f64,
    width: f64,
}

/// A box's integral of W, its gradient and full Hessian in K, and of the
/// magnitude density (times |width|).
struct Quad {
    v: f64,
    g: [f64; 4],
    h: [[f64; 4]; 4],
    mag: f64,
    /// Integrals of the absolute terms of the gradient and Hessian densities.
    gmag: [f64; 4],
    hmag: [[f64; 4]; 4],
}

impl Quad {
    fn zero() -> Quad {
        Quad {
            v: 0.0,
            g: [0.0; 4],
            h: [[0.0; 4]; 4],
            mag: 0.0,
            gmag: [0.0; 4],
            hmag: [[0.0; 4]; 4],
        }
    }

    /// self += c * other (magnitudes add with |c|).
    fn add_scaled(&mut self, c: f64, o: &Quad) {
        self.v += c * o.v;
        self.mag += c.abs() * o.mag;
        for i in 0..4 {
            self.g[i] += c * o.g[i];
            self.gmag[i] += c.abs() * o.gmag[i];
            for j in 0..4 {
                self.h[i][j] += c * o.h[i][j];
                self.hmag[i][j] += c.abs() * o.hmag[i][j];
            }
        }
    }

    fn add(&mut self, o: &Quad) {
        self.add_scaled(1.0, o);
    }
}

fn quad(d: &Density, b: &Bx, k: &K) -> Quad {
    let mut q = Quad::zero();
    let ey = k[2];
    for &(x, wx) in &rule(NX, b.x0, b.x1) {
        for &(z, wz) in &rule(NZ, b.z0, b.z1) {
            let w = wx * wz * b.width;
            let e = eps_x(k, x, z);
            let de = d_eps_x(k, x, z);
            let j = d.jet(e, ey);
            let jm = d.magnitude_jet(e, ey);
            let dem = d_eps_x_magnitude(k, x, z);
            q.v += w * j.f;
            q.mag += w.abs() * jm.f;
            for i in 0..4 {
                q.g[i] += w * (j.fe * de[i] + j.fy * D_EPS_Y[i]);
                q.gmag[i] += w.abs() * (jm.fe * dem[i] + jm.fy * D_EPS_Y[i]);
                for l in 0..4 {
                    let mut hil = j.fee * de[i] * de[l]
                        + j.fey * (de[i] * D_EPS_Y[l] + D_EPS_Y[i] * de[l])
                        + j.fyy * D_EPS_Y[i] * D_EPS_Y[l];
                    let mut mil = jm.fee * dem[i] * dem[l]
                        + jm.fey * (dem[i] * D_EPS_Y[l] + D_EPS_Y[i] * dem[l])
                        + jm.fyy * D_EPS_Y[i] * D_EPS_Y[l];
                    if i == 3 && l == 3 {
                        // d^2 eps_x / d c2^2 = 4 x^2
                        hil += j.fe * 4.0 * x * x;
                        mil += jm.fe * 4.0 * x * x;
                    }
                    q.h[i][l] += w * hil;
                    q.hmag[i][l] += w.abs() * mil;
                }
            }
        }
    }
    q
}

// ---------------------------------------------------------------------------
// Dispatch to the generated kernels (moment arrays as slices).

fn moments_len(kind: usize) -> usize {
    [LINEAR_MOMENTS, PRESTRESSED_MOMENTS, GAS_MOMENTS][kind]
}

fn add_moments(d: &Density, b: &Bx, m: &mut [f64]) {
    match *d {
        Density::Linear { q11, q12, q22 } => linear_moments(
            m.try_into().unwrap(),
            b.x0,
            b.x1,
            b.width,
            b.z0,
            b.z1,
            q11,
            q12,
            q22,
        ),
        Density::Prestressed { eps0, p, q22 } => prestressed_moments(
            m.try_into().unwrap(),
            b.x0,
            b.x1,
            b.width,
            b.z0,
            b.z1,
            eps0,
            p[0],
            p[1],
            p[2],
            p[3],
            q22,
        ),
        Density::Gas => gas_moments(m.try_into().unwrap(), b.x0, b.x1, b.width, b.z0, b.z1),
    }
}

fn moments_of(d: &Density, boxes: &[Bx]) -> Vec<f64> {
    let mut m = vec![0.0; moments_len(d.kind())];
    for b in boxes {
        add_moments(d, b, &mut m);
    }
    m
}

fn k_value(kind: usize, k: &K, m: &[f64]) -> f64 {
    match kind {
        0 => linear_value(k, m.try_into().unwrap()),
        1 => prestressed_value(k, m.try_into().unwrap()),
        _ => gas_value(k, m.try_into().unwrap()),
    }
}

fn k_gradient(kind: usize, k: &K, m: &[f64]) -> (f64, [f64; 4]) {
    match kind {
        0 => linear_gradient(k, m.try_into().unwrap()),
        1 => prestressed_gradient(k, m.try_into().unwrap()),
        _ => gas_gradient(k, m.try_into().unwrap()),
    }
}

fn k_hessian(kind: usize, k: &K, m: &[f64]) -> (f64, [f64; 4], [f64; 10]) {
    match kind {
        0 => linear_hessian(k, m.try_into().unwrap()),
        1 => prestressed_hessian(k, m.try_into().unwrap()),
        _ => gas_hessian(k, m.try_into().unwrap()),
    }
}

fn full(h: &[f64; 10]) -> [[f64; 4]; 4] {
    let mut f = [[0.0; 4]; 4];
    for (i, row) in f.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            *e = h[upper_index(i, j)];
        }
    }
    f
}

// ---------------------------------------------------------------------------
// Random inputs in realistic ranges.

/// Typical sizes of a1, a3, b1, c2 (a3 such that 3 a3 x^2 ~ 0.05 at x = 30).
const TYPICAL: K = [0.05, 2e-5, 0.05, 0.03];

fn random_k(rng: &mut Rng) -> K {
    [
        rng.range(-0.05, 0.05),
        rng.range(-2e-5, 2e-5),
        rng.range(-0.05, 0.05),
        rng.range(-0.03, 0.03),
    ]
}

fn random_box(rng: &mut Rng) -> Bx {
    let (x0, x1) = rng.interval(0.0, 30.0, 0.0);
    let (z0, z1) = rng.interval(-4.1, 4.1, 0.0);
    let width = rng.range(-30.0, 30.0);
    Bx {
        x0,
        x1,
        z0,
        z1,
        width,
    }
}

fn random_density(kind: usize, rng: &mut Rng) -> Density {
    match kind {
        0 => {
            let q11 = rng.range(0.5, 400.0);
            let q22 = rng.range(0.5, 400.0);
            let q12 = rng.range(-0.5, 0.5) * (q11 * q22).sqrt();
            Density::Linear { q11, q12, q22 }
        }
        1 => {
            let paper = [1.598, 2.306, 2.29, 0.698];
            let mut p = [0.0; 4];
            for (pi, base) in p.iter_mut().zip(paper) {
                *pi = base * rng.range(0.7, 1.3);
            }
            Density::Prestressed {
                eps0: rng.range(0.0, 0.6),
                p,
                q22: rng.range(1.0, 400.0),
            }
        }
        _ => Density::Gas,
    }
}

// ---------------------------------------------------------------------------
// 1. Quadrature and linearity of the moments.

#[test]
fn values_match_gauss_legendre_quadrature() {
    let mut rng = Rng::new(1);
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        let (mut worst_value, mut worst_mag) = (0.0f64, 0.0f64);
        for case in 0..300 {
            let d = random_density(kind, &mut rng);
            let b = random_box(&mut rng);
            let k = random_k(&mut rng);
            let got = k_value(kind, &k, &moments_of(&d, &[b]));
            let q = quad(&d, &b, &k);
            let rel = (got - q.v).abs() / q.v.abs();
            worst_value = worst_value.max(rel);
            worst_mag = worst_mag.max((got - q.v).abs() / q.mag);
            assert!(
                rel <= 1e-12,
                "{} case {case}: kernel {got:e}, quadrature {:e}, relative {rel:e}\n{d:?}\n{b:?}\nK = {k:?}",
                name,
                q.v
            );
        }
        eprintln!(
            "{}: worst relative error vs quadrature {worst_value:e} ({worst_mag:e} of the term magnitude)",
            name
        );
    }
}

#[test]
fn moments_are_linear_in_blocks() {
    let mut rng = Rng::new(2);
    let (mut worst_sum, mut worst_cancel, mut worst_split) = (0.0f64, 0.0f64, 0.0f64);
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        for case in 0..200 {
            let k = random_k(&mut rng);
            // two blocks of different material accumulate into one array
            let (d1, d2) = (
                random_density(kind, &mut rng),
                random_density(kind, &mut rng),
            );
            let (b1, b2) = (random_box(&mut rng), random_box(&mut rng));
            let mut m = vec![0.0; moments_len(kind)];
            add_moments(&d1, &b1, &mut m);
            add_moments(&d2, &b2, &mut m);
            let v1 = k_value(kind, &k, &moments_of(&d1, &[b1]));
            let v2 = k_value(kind, &k, &moments_of(&d2, &[b2]));
            let both = k_value(kind, &k, &m);
            let rel = (both - (v1 + v2)).abs() / (v1.abs() + v2.abs());
            worst_sum = worst_sum.max(rel);
            assert!(
                rel <= 1e-12,
                "{} case {case}: two blocks {both:e}, sum {:e}",
                name,
                v1 + v2
            );

            // the same block with the opposite width cancels it
            let neg = Bx {
                width: -b1.width,
                ..b1
            };
            let cancel = k_value(kind, &k, &moments_of(&d1, &[b1, neg]));
            let rel = cancel.abs() / v1.abs();
            worst_cancel = worst_cancel.max(rel);
            assert!(
                rel <= 1e-12,
                "{} case {case}: +w and -w leave {cancel:e} (block {v1:e})",
                name
            );

            // splitting a box in x and in z does not change the total
            let xm = rng.range(b1.x0, b1.x1);
            let zm = rng.range(b1.z0, b1.z1);
            let parts = [
                Bx {
                    x1: xm,
                    z1: zm,
                    ..b1
                },
                Bx {
                    x0: xm,
                    z1: zm,
                    ..b1
                },
                Bx {
                    x1: xm,
                    z0: zm,
                    ..b1
                },
                Bx {
                    x0: xm,
                    z0: zm,
                    ..b1
                },
            ];
            let split = k_value(kind, &k, &moments_of(&d1, &parts));
            let scale = quad(&d1, &b1, &k).mag;
            let rel = (split - v1).abs() / scale;
            worst_split = worst_split.max(rel);
            assert!(
                rel <= 1e-12,
                "{} case {case}: split {split:e}, whole {v1:e}",
                name
            );
        }
    }
    eprintln!(
        "linearity: worst two-block {worst_sum:e}, cancellation {worst_cancel:e}, split {worst_split:e}"
    );
}

// ---------------------------------------------------------------------------
// 2. Derivatives.

/// 5-point central difference (Richardson-extrapolated) of f along e_i.
fn fd<T, F>(f: F, k: &K, i: usize, h: f64) -> T
where
    F: Fn(&K) -> T,
    T: Combine,
{
    let at = |t: f64| {
        let mut kk = *k;
        kk[i] += t * h;
        f(&kk)
    };
    T::combine(
        &[
            (8.0, at(1.0)),
            (-8.0, at(-1.0)),
            (-1.0, at(2.0)),
            (1.0, at(-2.0)),
        ],
        12.0 * h,
    )
}

trait Combine: Sized {
    fn combine(terms: &[(f64, Self)], div: f64) -> Self;
}

impl Combine for f64 {
    fn combine(terms: &[(f64, f64)], div: f64) -> f64 {
        terms.iter().map(|(c, v)| c * v).sum::<f64>() / div
    }
}

impl Combine for [f64; 4] {
    fn combine(terms: &[(f64, [f64; 4])], div: f64) -> [f64; 4] {
        let mut out = [0.0; 4];
        for (c, v) in terms {
            for (o, x) in out.iter_mut().zip(v) {
                *o += c * x;
            }
        }
        out.map(|o| o / div)
    }
}

/// Step of the finite differences, as a fraction of each unknown's typical
/// size. The 5-point stencil's truncation error grows as step^4 (about 1e-9
/// of the energy scale at 1e-3 for the degree-10 prestressed kernel) and
/// its rounding error as 1/step; 3e-4 keeps both near 1e-11.
const FD_STEP: f64 = 3e-4;

/// A random scene for a kernel: 1 to 3 blocks of random material.
fn random_scene(kind: usize, rng: &mut Rng) -> Vec<f64> {
    let mut m = vec![0.0; moments_len(kind)];
    let n = 1 + (rng.next_u64() % 3) as usize;
    for _ in 0..n {
        let d = random_density(kind, rng);
        let b = random_box(rng);
        add_moments(&d, &b, &mut m);
    }
    m
}

#[test]
fn derivatives_match_finite_differences() {
    let mut rng = Rng::new(3);
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        let (mut worst_g, mut worst_h, mut worst_variant) = (0.0f64, 0.0f64, 0.0f64);
        for case in 0..60 {
            let m = random_scene(kind, &mut rng);
            let k = random_k(&mut rng);
            let v = k_value(kind, &k, &m);
            let (vg, g) = k_gradient(kind, &k, &m);
            let (vh, gh, hu) = k_hessian(kind, &k, &m);
            let h = full(&hu);

            // the three variants agree
            let gscale = (0..4).fold(0.0f64, |s, i| s.max(g[i].abs() * TYPICAL[i]));
            let scale = v.abs().max(gscale);
            let mut variant = (vg - v).abs().max((vh - v).abs()) / scale;
            for i in 0..4 {
                variant = variant.max((gh[i] - g[i]).abs() * TYPICAL[i] / scale);
            }
            worst_variant = worst_variant.max(variant);
            assert!(
                variant <= 1e-14,
                "{} case {case}: value/gradient/hessian variants differ by {variant:e}",
                name
            );

            // gradient: finite differences of the value; errors are measured
            // as the change of the value over a typical step, over the
            // energy scale
            for i in 0..4 {
                let d = fd(|kk| k_value(kind, kk, &m), &k, i, FD_STEP * TYPICAL[i]);
                let err = (d - g[i]).abs() * TYPICAL[i] / scale;
                worst_g = worst_g.max(err);
                assert!(
                    err <= 1e-9,
                    "{} case {case}: dV/dK[{i}] kernel {:e}, finite difference {d:e} (error {err:e})",
                    name,
                    g[i]
                );
            }
            // Hessian: finite differences of the gradient, full 4x4
            for j in 0..4 {
                let col = fd(|kk| k_gradient(kind, kk, &m).1, &k, j, FD_STEP * TYPICAL[j]);
                for i in 0..4 {
                    let err = (col[i] - h[i][j]).abs() * TYPICAL[i] * TYPICAL[j] / scale;
                    worst_h = worst_h.max(err);
                    assert!(
                        err <= 1e-9,
                        "{} case {case}: H[{i}][{j}] kernel {:e}, finite difference {:e} (error {err:e})",
                        name,
                        h[i][j],
                        col[i]
                    );
                }
            }
        }
        eprintln!(
            "{}: worst FD gradient error {worst_g:e}, FD Hessian {worst_h:e}, variants {worst_variant:e}",
            name
        );
    }
}

#[test]
fn derivatives_match_quadrature_of_density_derivatives() {
    let mut rng = Rng::new(4);
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        let (mut worst_g, mut worst_h) = ((0.0f64, 0.0f64), (0.0f64, 0.0f64));
        for case in 0..150 {
            let d = random_density(kind, &mut rng);
            let b = random_box(&mut rng);
            let k = random_k(&mut rng);
            let m = moments_of(&d, &[b]);
            let (_, g, hu) = k_hessian(kind, &k, &m);
            let h = full(&hu);
            let q = quad(&d, &b, &k);
            // Errors over the integral of the absolute terms of each
            // entry's density (exact zeros must be exact); the relative
            // error per entry is reported too.
            let mut entries: Vec<(String, f64, f64, f64, bool)> = Vec::new();
            for i in 0..4 {
                entries.push((format!("gradient[{i}]"), g[i], q.g[i], q.gmag[i], true));
                for (j, (hij, (qh, qm))) in
                    h[i].iter().zip(q.h[i].iter().zip(&q.hmag[i])).enumerate()
                {
                    entries.push((format!("H[{i}][{j}]"), *hij, *qh, *qm, false));
                }
            }
            for (entry, got, want, mag, is_grad) in entries {
                if mag == 0.0 {
                    assert_eq!(got, 0.0, "{name} case {case}: {entry}");
                    continue;
                }
                let err = (got - want).abs() / mag;
                let worst = if is_grad { &mut worst_g } else { &mut worst_h };
                worst.0 = worst.0.max(err);
                worst.1 = worst.1.max((got - want).abs() / want.abs().max(1e-6 * mag));
                assert!(
                    err <= 1e-12,
                    "{name} case {case}: {entry} kernel {got:e}, quadrature {want:e} ({err:e} of the term magnitude {mag:e})",
                );
            }
        }
        eprintln!(
            "{}: worst error vs quadrature of density derivatives (of term magnitude / relative): gradient {:e} / {:e}, Hessian {:e} / {:e}",
            name, worst_g.0, worst_g.1, worst_h.0, worst_h.1
        );
    }
}

// ---------------------------------------------------------------------------
// 3. End kinematics.

/// docs/model.md Eqs. 11, 13 with decision D2.
fn end_closed_form(k: &K, l: f64) -> [f64; 3] {
    let [a1, a3, _, c2] = *k;
    [
        (1.0 + a1) * l + a3 * l.powi(3),
        c2 * l * l,
        (2.0 * c2 * l).atan2(1.0 + a1 + 3.0 * a3 * l * l),
    ]
}

/// Gradient of (Xe, Ze, eta), differentiated by hand.
fn end_gradient_closed_form(k: &K, l: f64) -> [[f64; 4]; 3] {
    let [a1, a3, _, c2] = *k;
    let (x, y) = (1.0 + a1 + 3.0 * a3 * l * l, 2.0 * c2 * l);
    let r2 = x * x + y * y;
    // d atan2(y, x) = (x dy - y dx) / r2; dx = (1, 3 L^2, 0, 0), dy = (0, 0, 0, 2 L)
    [
        [l, l.powi(3), 0.0, 0.0],
        [0.0, 0.0, 0.0, l * l],
        [-y / r2, -3.0 * l * l * y / r2, 0.0, 2.0 * l * x / r2],
    ]
}

fn random_end_case(rng: &mut Rng) -> (K, f64) {
    let l = rng.range(1.0, 110.0);
    let k = [
        rng.range(-0.05, 0.05),
        rng.range(-1.0, 1.0) * 0.05 / (l * l),
        rng.range(-0.05, 0.05),
        rng.range(-1.0, 1.0) * 0.03 * 13.75 / l,
    ];
    (k, l)
}

fn check_end(k: &K, l: f64, label: &str, worst: &mut [f64; 4]) {
    let v = end_value(k, l);
    let (vh, g, hu) = end_hessian(k, l);
    let want = end_closed_form(k, l);
    let want_g = end_gradient_closed_form(k, l);
    // typical sizes: a3's scale is the one that moves the end by ~ a1's
    let typ = [0.05, 0.05 / (l * l), 0.05, 0.03 * 13.75 / l];
    for o in 0..3 {
        let scale = want[o].abs().max(if o == 2 { 1.0 } else { l });
        let err = (v[o] - want[o]).abs().max((vh[o] - want[o]).abs()) / scale;
        worst[0] = worst[0].max(err);
        assert!(
            err <= 1e-14,
            "{label}: end[{o}] kernel {:e}, closed form {:e}",
            v[o],
            want[o]
        );
        // gradient scale: the output's change over typical steps
        let gscale = (0..4).fold(0.0f64, |s, i| s.max(want_g[o][i].abs() * typ[i]));
        for i in 0..4 {
            let err = (g[o][i] - want_g[o][i]).abs() * typ[i] / gscale.max(1e-300);
            worst[1] = worst[1].max(err);
            assert!(
                err <= 1e-13,
                "{label}: d end[{o}]/dK[{i}] kernel {:e}, closed form {:e}",
                g[o][i],
                want_g[o][i]
            );
            let d = fd(|kk| end_value(kk, l)[o], k, i, FD_STEP * typ[i]);
            let err = (d - g[o][i]).abs() * typ[i] / gscale.max(1e-300);
            worst[2] = worst[2].max(err);
            assert!(
                err <= 1e-9,
                "{label}: d end[{o}]/dK[{i}] kernel {:e}, finite difference {d:e}",
                g[o][i]
            );
        }
        let h = full(&hu[o]);
        for j in 0..4 {
            let col = fd(|kk| end_hessian(kk, l).1[o], k, j, FD_STEP * typ[j]);
            for i in 0..4 {
                let err = (col[i] - h[i][j]).abs() * typ[i] * typ[j] / scale;
                worst[3] = worst[3].max(err);
                assert!(
                    err <= 1e-9,
                    "{label}: d2 end[{o}]/dK[{i}]dK[{j}] kernel {:e}, finite difference {:e}",
                    h[i][j],
                    col[i]
                );
            }
        }
    }
}

#[test]
fn end_kinematics_match_closed_forms_and_finite_differences() {
    let mut rng = Rng::new(5);
    let mut worst = [0.0f64; 4];
    for case in 0..200 {
        let (k, l) = random_end_case(&mut rng);
        check_end(&k, l, &format!("case {case} L={l} K={k:?}"), &mut worst);

        // eta is the direction of the mid-plane's tangent at x = L
        let [a1, a3, _, c2] = k;
        let shape = |x: f64| ((1.0 + a1) * x + a3 * x.powi(3), c2 * x * x);
        let hh = 1e-4 * l;
        let (p, q) = (shape(l + hh), shape(l - hh));
        let eta_fd = (p.1 - q.1).atan2(p.0 - q.0);
        let err = (end_value(&k, l)[2] - eta_fd).abs();
        assert!(err <= 1e-9, "case {case}: eta vs mid-plane tangent {err:e}");
    }
    eprintln!(
        "end: worst value {:e}, gradient vs closed form {:e}, vs FD {:e}, Hessian vs FD {:e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

#[test]
fn end_slope_is_right_past_ninety_degrees() {
    let mut worst = [0.0f64; 4];
    let l = 13.75;
    // 1 + a1 + 3 a3 L^2 < 0: the end points backwards
    for (c2, lo, hi) in [(0.02, FRAC_PI_2, PI), (-0.02, -PI, -FRAC_PI_2)] {
        let k = [-0.5, -0.3 / (l * l), 0.01, c2];
        let x = 1.0 + k[0] + 3.0 * k[1] * l * l;
        assert!(x < 0.0);
        let eta = end_value(&k, l)[2];
        assert!(
            eta > lo && eta < hi,
            "eta = {eta} for c2 = {c2}, should lie in ({lo}, {hi})"
        );
        let want = PI.copysign(c2) - (2.0 * c2 * l / -x).atan();
        assert!((eta - want).abs() <= 1e-14, "eta {eta} vs {want}");
        check_end(&k, l, &format!("past 90 degrees, c2 = {c2}"), &mut worst);
    }
    // exactly 90 degrees: dX/dx = 0 at the end
    let k = [-0.4, -0.6 / (3.0 * l * l), 0.0, 0.01];
    let eta = end_value(&k, l)[2];
    assert!((eta - FRAC_PI_2).abs() <= 1e-12, "eta = {eta}");
    check_end(&k, l, "at 90 degrees", &mut worst);
    eprintln!(
        "end past 90 degrees: worst value {:e}, gradient {:e}, FD gradient {:e}, FD Hessian {:e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

// ---------------------------------------------------------------------------
// 4. Element energy from the laminate description of docs/model.md section 3.

/// The default finger, from docs/model.md's numbers (not from the library).
mod paper {
    pub const LX: f64 = 110.0;
    pub const LY: f64 = 31.75;
    pub const H: f64 = 8.2;
    pub const H1: f64 = 3.7;
    pub const H2: f64 = 1.8;
    pub const H3: f64 = 2.2;
    pub const CX: f64 = 105.0;
    pub const CY: f64 = 26.0;
    pub const H3A: f64 = 0.8;
    pub const H3B: f64 = 1.2;
    /// Longitudinal rib: width t over the whole channel.
    pub const T: f64 = 2.0;
    /// Transverse ribs: t long, centred at k w1, total width 2 w2.
    pub const W1: f64 = 8.0;
    pub const W2: f64 = 6.0;
    pub const PSI: [f64; 4] = [1.598, 2.306, 2.29, 0.698];
    pub const PEMC_E2: f64 = 250.0;

    /// (Q11, Q12, Q22) of an isotropic material.
    pub fn iso(e: f64, nu: f64) -> (f64, f64, f64) {
        let d = 1.0 - nu * nu;
        (e / d, nu * e / d, e / d)
    }

    /// (Q11, Q12, Q22) of an orthotropic material.
    pub fn ortho(e1: f64, e2: f64, nu12: f64) -> (f64, f64, f64) {
        let d = 1.0 - nu12 * nu12 * e2 / e1;
        (e1 / d, nu12 * e2 / d, e2 / d)
    }

    /// Total rib width at X_ref (inside the channel).
    pub fn rib_width(x: f64) -> f64 {
        let mut w = if x < CX { T } else { 0.0 };
        let mut k = 1.0;
        while k * W1 + T / 2.0 <= CX {
            if (x - k * W1).abs() < T / 2.0 {
                w += 2.0 * W2;
            }
            k += 1.0;
        }
        w
    }

    /// X_ref where the fluidic cross-section changes.
    pub fn breakpoints() -> Vec<f64> {
        let mut b = vec![0.0, CX];
        let mut k = 1.0;
        while k * W1 + T / 2.0 <= CX {
            b.push(k * W1 - T / 2.0);
            b.push(k * W1 + T / 2.0);
            k += 1.0;
        }
        b
    }
}

/// (Psi, V) of the element [start, start + len] at K, integrating the
/// laminate cross-section by cross-section over pieces of constant section.
fn laminate_energy(start: f64, len: f64, eps0: f64, k: &K) -> (Quad, Quad) {
    use paper::*;
    let (cl, emc, fl) = (iso(305.0, 0.43), ortho(1.5, 250.0, 0.0), iso(1.2, 0.48));
    let lin = |q: (f64, f64, f64)| Density::Linear {
        q11: q.0,
        q12: q.1,
        q22: q.2,
    };
    let pemc = Density::Prestressed {
        eps0,
        p: PSI,
        q22: PEMC_E2,
    };
    let end = start + len;
    let mut cuts = vec![start, end];
    cuts.extend(breakpoints().into_iter().filter(|&b| b > start && b < end));
    cuts.sort_by(f64::total_cmp);

    let (mut psi_total, mut vol) = (Quad::zero(), Quad::zero());
    for w in cuts.windows(2) {
        let (a, b) = (w[0] - start, w[1] - start);
        let mid = 0.5 * (w[0] + w[1]);
        let in_channel = mid < CX;
        let ribs = if in_channel { rib_width(mid) } else { 0.0 };
        let fl_mid_width = if in_channel { LY - CY + ribs } else { LY };
        let gas_width = if in_channel { CY - ribs } else { 0.0 };
        let piece = |z0: f64, z1: f64, width: f64, d: Density| {
            quad(
                &d,
                &Bx {
                    x0: a,
                    x1: b,
                    z0,
                    z1,
                    width,
                },
                k,
            )
        };
        psi_total.add(&piece(H1, H / 2.0, LY, lin(cl)));
        psi_total.add(&piece(H2, H1, LY, lin(emc)));
        psi_total.add(&piece(H3A, H2, LY, lin(fl)));
        psi_total.add(&piece(-H3B, H3A, fl_mid_width, lin(fl)));
        psi_total.add(&piece(-H3, -H3B, LY, lin(fl)));
        psi_total.add(&piece(-H / 2.0, -H3, LY, pemc));
        if gas_width > 0.0 {
            vol.add(&piece(-H3B, H3A, gas_width, Density::Gas));
        }
    }
    (psi_total, vol)
}

const N: usize = 8;

/// `got` against `want = (value, magnitude)`: the error over the integral of
/// the absolute terms of the density (a zero magnitude needs an exact zero).
fn against_magnitude(name: &str, got: f64, want: (f64, f64), tol: f64, worst: &mut f64) {
    let (value, mag) = want;
    if mag == 0.0 {
        assert_eq!(got, 0.0, "{name}: expected an exact zero");
        return;
    }
    let err = (got - value).abs() / mag;
    *worst = worst.max(err);
    assert!(
        err <= tol,
        "{name}: {got:e} vs {value:e} ({err:e} of {mag:e})"
    );
}

fn paper_elements(eps0: f64) -> Vec<Element> {
    let act = Actuator::paper(eps0).expect("paper actuator");
    let part = Partition::equal(act.geometry().lx, N).expect("partition");
    element_blocks(&act, &part, true)
        .iter()
        .map(Element::from_blocks)
        .collect()
}

#[test]
fn element_energy_matches_laminate_quadrature() {
    let mut rng = Rng::new(6);
    let len = paper::LX / N as f64;
    #[derive(Default)]
    struct Worst {
        psi: f64,
        v: f64,
        pi: f64,
        g: f64,
        h: f64,
    }
    let mut worst = Worst::default();
    // Actuator::paper(0.25) is the default actuator; the other two are the
    // paper's other samples
    for eps0 in [0.25, 0.15, 0.4] {
        for (i, el) in paper_elements(eps0).iter().enumerate() {
            assert_eq!(el.length(), len);
            for case in 0..8 {
                let k = if case == 0 {
                    [0.0; 4]
                } else {
                    [
                        rng.range(-0.05, 0.05),
                        rng.range(-1.0, 1.0) * 0.05 / (len * len),
                        rng.range(-0.05, 0.05),
                        rng.range(-0.03, 0.03),
                    ]
                };
                // kappa P from 0 to 2.5 * 400 kPa
                let kp = if case % 2 == 0 {
                    0.0
                } else {
                    rng.range(0.0, 1.0)
                };
                let (psi, gas) = laminate_energy(i as f64 * len, len, eps0, &k);
                let (psi_want, v_want) = (psi.v, gas.v);
                let mut pi_want = Quad::zero();
                pi_want.add(&psi);
                pi_want.add_scaled(-kp, &gas);
                let label = format!("eps0 {eps0} element {i} K={k:?} kp={kp}");

                let rel = (el.strain_energy(&k) - psi_want).abs() / psi_want.abs();
                worst.psi = worst.psi.max(rel);
                assert!(
                    rel <= 1e-11,
                    "{label}: Psi {} vs {psi_want} ({rel:e})",
                    el.strain_energy(&k)
                );

                if v_want == 0.0 {
                    assert_eq!(el.gas_volume(&k), 0.0, "{label}: element without channel");
                } else {
                    let rel = (el.gas_volume(&k) - v_want).abs() / v_want.abs();
                    worst.v = worst.v.max(rel);
                    assert!(
                        rel <= 1e-11,
                        "{label}: V {} vs {v_want} ({rel:e})",
                        el.gas_volume(&k)
                    );
                }

                let pi = el.energy(&k, kp);
                let rel = (pi - pi_want.v).abs() / pi_want.mag;
                worst.pi = worst.pi.max(rel);
                assert!(rel <= 1e-11, "{label}: Pi {pi} vs {} ({rel:e})", pi_want.v);

                // gradient and Hessian, each entry against the integral of
                // its density's absolute terms
                let (vg, g) = el.gradient(&k, kp);
                let (vh, gh, hu) = el.hessian(&k, kp);
                assert!((vg - pi).abs() <= 1e-14 * pi_want.mag, "{label}");
                assert!((vh - pi).abs() <= 1e-14 * pi_want.mag, "{label}");
                let h = full(&hu);
                for r in 0..4 {
                    assert!((gh[r] - g[r]).abs() <= 1e-14 * pi_want.gmag[r], "{label}");
                    let name = format!("{label}: gradient[{r}]");
                    let want = (pi_want.g[r], pi_want.gmag[r]);
                    against_magnitude(&name, g[r], want, 1e-11, &mut worst.g);
                    for (c, &hrc) in h[r].iter().enumerate() {
                        let name = format!("{label}: H[{r}][{c}]");
                        let want = (pi_want.h[r][c], pi_want.hmag[r][c]);
                        against_magnitude(&name, hrc, want, 1e-11, &mut worst.h);
                    }
                }
            }
        }
    }
    eprintln!(
        "element vs laminate quadrature: worst relative Psi {:e}, V {:e}; of the term magnitude: Pi {:e}, gradient {:e}, Hessian {:e}",
        worst.psi, worst.v, worst.pi, worst.g, worst.h
    );
}

// ---------------------------------------------------------------------------
// 5. Physical sanity at K = 0.

#[test]
fn unstressed_finger_has_zero_energy_and_gradient_and_is_stable() {
    for el in paper_elements(0.0) {
        let k = [0.0; 4];
        let (v, g, hu) = el.hessian(&k, 0.0);
        assert_eq!(el.strain_energy(&k), 0.0);
        assert_eq!(v, 0.0);
        assert_eq!(g, [0.0; 4]);
        // positive definite Hessian (Cholesky)
        let h = full(&hu);
        let mut l = [[0.0f64; 4]; 4];
        for i in 0..4 {
            for j in 0..=i {
                let s: f64 = h[i][j] - (0..j).map(|m| l[i][m] * l[j][m]).sum::<f64>();
                if i == j {
                    assert!(s > 0.0, "Hessian at rest not positive definite: {h:?}");
                    l[i][i] = s.sqrt();
                } else {
                    l[i][j] = s / l[j][j];
                }
            }
        }
    }
}

#[test]
fn prestrain_gradient_at_rest_matches_closed_form() {
    use paper::*;
    let len = LX / N as f64;
    let (z0, z1) = (-H / 2.0, -H3);
    let mut worst = 0.0f64;
    for eps0 in [0.15, 0.25, 0.4] {
        let (_, stress, _) = psi(&PSI, eps0);
        assert!(stress > 0.0);
        // d Psi/dK at K = 0: psi'(eps0) times the integral of d eps_x/dK
        // over the prestressed layer: (1, 3 x^2, 0, -2 z)
        let area = LY * (z1 - z0);
        let want = [
            stress * area * len,
            stress * area * len.powi(3),
            0.0,
            stress * LY * len * (z0 * z0 - z1 * z1),
        ];
        for (i, el) in paper_elements(eps0).iter().enumerate() {
            let (_, g) = el.gradient(&[0.0; 4], 0.0);
            // stretched prestressed layer: shortening (a1 < 0) and curling
            // towards -Z (c2 < 0) both lower the energy
            assert!(g[0] > 0.0 && g[3] > 0.0, "element {i}: {g:?}");
            for j in 0..4 {
                let err = (g[j] - want[j]).abs() / want[0].abs().max(want[j].abs());
                worst = worst.max(err);
                assert!(
                    err <= 1e-13,
                    "eps0 {eps0} element {i}: dPsi/dK[{j}] = {}, closed form {}",
                    g[j],
                    want[j]
                );
            }
        }
    }
    eprintln!("prestrain gradient at rest: worst relative error {worst:e}");
}

#[test]
fn gas_volume_at_rest_is_channel_minus_ribs() {
    use paper::*;
    let len = LX / N as f64;
    let height = H3A + H3B;
    let elements = paper_elements(0.25);
    let mut total = 0.0;
    let mut worst = 0.0f64;
    for (i, el) in elements.iter().enumerate() {
        let (s, e) = (i as f64 * len, (i + 1) as f64 * len);
        let overlap = |a: f64, b: f64| (b.min(e) - a.max(s)).max(0.0);
        let mut area = CY * overlap(0.0, CX) - T * overlap(0.0, CX);
        let mut k = 1.0;
        while k * W1 + T / 2.0 <= CX {
            area -= 2.0 * W2 * overlap(k * W1 - T / 2.0, k * W1 + T / 2.0);
            k += 1.0;
        }
        let want = area * height;
        let got = el.gas_volume(&[0.0; 4]);
        let err = (got - want).abs() / want.abs().max(1.0);
        worst = worst.max(err);
        assert!(
            err <= 1e-13,
            "element {i}: V = {got}, channel minus ribs {want}"
        );
        total += got;

        // pressure flattens: dV/dc2 = (gas width * length) (z0^2 - z1^2) > 0
        // over z in [-h3b, h3a], and dV/da1 = V at rest
        let (_, g, _) = el.gas_hessian(&[0.0; 4]);
        let want_c2 = area * (H3B * H3B - H3A * H3A);
        assert!(
            (g[0] - want).abs() <= 1e-12 * want.abs().max(1.0),
            "element {i}: {g:?}"
        );
        assert!(
            (g[3] - want_c2).abs() <= 1e-12 * want.abs().max(1.0),
            "element {i}: {g:?}"
        );
        if want > 0.0 {
            assert!(g[3] > 0.0);
        }
    }
    // 2 mm x (26 x 105 - 2 x 105 - 13 x 12 x 2) mm^2
    let all = height * (CY * CX - T * CX - 13.0 * 2.0 * W2 * T);
    assert!((total - all).abs() <= 1e-12 * all, "total {total} vs {all}");
    eprintln!("gas volume at rest: worst relative error {worst:e}, total {total} mm^3");
}
