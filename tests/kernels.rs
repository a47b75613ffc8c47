//! The generated element models against methods written here, independently
//! of the generator, from docs/model.md sections 3-4:
//!
//! - tensor Gauss-Legendre quadrature of the energy densities (values, and
//!   the chain-rule derivatives of the densities);
//! - central finite differences with Richardson extrapolation;
//! - the closed-form element end and end slope, mid-plane, tangent,
//!   strain and curvature;
//! - the prestressed law in closed form;
//! - an element energy assembled from the laminate description (cross
//!   section by cross section, not box by box as the library does);
//! - physical closed forms at K = 0.
//!
//! Everything goes through the [`ElementModel`] trait (moments built with
//! `add_linear`, `add_prestressed`, `add_gas`; `energy`, `gradient`,
//! `hessian`, `family_hessian`, the point kernels and the law) or the
//! public finger API. The checks are generic over the model; what a check
//! needs to know of a model beyond the trait, its displacement fields and
//! the typical sizes of its unknowns, is written by hand in an
//! `impl Fields` ([`Fields`] for [`Ccm`] below). A new model is one more
//! `impl Fields` and one more line in [`for_each_model!`].
//!
//! Random inputs come from fastrand with fixed seeds, so every run checks
//! the same cases. Each test prints its worst error (`--nocapture`).

use fpc::model::ccm::Ccm;
use fpc::model::quad::Quad as QuadModel;
use fpc::model::{
    upper_index, EnergyScalars, GasParams, LinearParams, PrestressedParams, PsiParams, Vector,
};
use fpc::model::{ElementModel, Energy, Kinematics, ModelCore};
use fpc::{Actuator, Coefficients, Finger, Load, ModelId, Partition};
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::OnceLock;

// ---------------------------------------------------------------------------
// The models checked here.

/// Runs the generic check `$check::<M>($args)` for every model with
/// hand-written [`Fields`]: adding a model is one line here.
macro_rules! for_each_model {
    ($check:ident $(, $arg:expr)*) => {{
        $check::<Ccm>($($arg),*);
        $check::<QuadModel>($($arg),*);
    }};
}

fn push_name<M: ElementModel>(names: &mut Vec<&'static str>) {
    names.push(M::NAME);
}

#[test]
fn every_generated_model_is_checked() {
    let mut names = Vec::new();
    for_each_model!(push_name, &mut names);
    assert_eq!(
        names,
        ModelId::names(),
        "every generated model needs an `impl Fields` and a line in `for_each_model!`"
    );
}

/// The run-time id of model `M`.
fn model_id<M: ElementModel>() -> ModelId {
    ModelId::from_name(M::NAME).unwrap_or_else(|| panic!("no ModelId for {}", M::NAME))
}

/// Number of unknowns of model `M`.
fn len<M: ElementModel>() -> usize {
    M::Coeffs::LEN
}

// ---------------------------------------------------------------------------
// Deterministic random numbers (fastrand, seeded).

struct Rng(fastrand::Rng);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(fastrand::Rng::with_seed(seed))
    }

    fn next_u64(&mut self) -> u64 {
        self.0.u64(..)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        self.0.f64()
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

    /// Each unknown uniform in [-size, size].
    fn within<C: Vector>(&mut self, size: &C) -> C {
        C::from_fn(|i| self.range(-size[i], size[i]))
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

/// x: 8 points (exact to degree 15; the CCM's densities reach degree 10 in x).
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
// The kinematics of each model, written by hand from docs/model.md section 4.

/// What the checks need to know of a model beyond the trait: its
/// displacement fields (as the strains, mid-plane and their derivatives
/// they give) and the typical sizes of its unknowns, written here by hand.
trait Fields: ElementModel {
    /// Typical size of each unknown on elements up to 30 mm: random states
    /// are drawn within it, finite-difference steps and error scales
    /// follow it.
    fn typical() -> Self::Coeffs;
    /// Typical size of each unknown on an element of length `l`.
    fn typical_at(l: f64) -> Self::Coeffs;
    /// The axial strain eps_x at (x, z) and its gradient in the unknowns.
    fn eps_x(k: &Self::Coeffs, x: f64, z: f64) -> (f64, Self::Coeffs);
    /// The gradient of eps_x with each of its terms by absolute value.
    fn eps_x_gradient_magnitude(k: &Self::Coeffs, x: f64, z: f64) -> Self::Coeffs;
    /// d^2 eps_x / dK_i dK_j, and the same with its terms by absolute value.
    fn eps_x_hessian(k: &Self::Coeffs, x: f64, z: f64, i: usize, j: usize) -> (f64, f64);
    /// The transverse strain eps_y and its gradient (the gradient's terms
    /// by absolute value are the last value).
    fn eps_y(k: &Self::Coeffs, x: f64, z: f64) -> (f64, Self::Coeffs, Self::Coeffs);
    /// d^2 eps_y / dK_i dK_j, and the same by absolute value.
    fn eps_y_hessian(k: &Self::Coeffs, x: f64, z: f64, i: usize, j: usize) -> (f64, f64);
    /// The mid-plane X = x + u, Z = w at local `x`, with their first two
    /// derivatives in x: `[[X, X', X''], [Z, Z', Z'']]`.
    fn shape(k: &Self::Coeffs, x: f64) -> [[f64; 3]; 2];
    /// Gradients in the unknowns of `[X, Z, X', Z']` at local `x`.
    fn shape_gradients(k: &Self::Coeffs, x: f64) -> [Self::Coeffs; 4];
}

/// The paper's element: u = a1 x + a3 x^3, v = b1 y, w = c2 x^2 (Eq. 4),
/// eps_x = u' + w'^2 / 2 - z w'' = a1 + (3 a3 + 2 c2^2) x^2 - 2 z c2,
/// eps_y = b1 (Eq. 5).
impl Fields for Ccm {
    /// a1, b1 and c2 of a few percent; a3 such that 3 a3 x^2 ~ 0.05 at x = 30.
    fn typical() -> [f64; 4] {
        [0.05, 2e-5, 0.05, 0.03]
    }

    /// a3's scale moves the end as much as a1's; c2 curls a 13.75 mm element
    /// by a few percent.
    fn typical_at(l: f64) -> [f64; 4] {
        [0.05, 0.05 / (l * l), 0.05, 0.03 * 13.75 / l]
    }

    fn eps_x(k: &[f64; 4], x: f64, z: f64) -> (f64, [f64; 4]) {
        let [a1, a3, _, c2] = *k;
        (
            a1 + (3.0 * a3 + 2.0 * c2 * c2) * x * x - 2.0 * z * c2,
            [1.0, 3.0 * x * x, 0.0, 4.0 * c2 * x * x - 2.0 * z],
        )
    }

    fn eps_x_gradient_magnitude(k: &[f64; 4], x: f64, z: f64) -> [f64; 4] {
        [
            1.0,
            3.0 * x * x,
            0.0,
            4.0 * k[3].abs() * x * x + 2.0 * z.abs(),
        ]
    }

    fn eps_x_hessian(_: &[f64; 4], x: f64, _: f64, i: usize, j: usize) -> (f64, f64) {
        // d^2 eps_x / d c2^2 = 4 x^2, nothing else
        if i == 3 && j == 3 {
            (4.0 * x * x, 4.0 * x * x)
        } else {
            (0.0, 0.0)
        }
    }

    fn eps_y(k: &[f64; 4], _: f64, _: f64) -> (f64, [f64; 4], [f64; 4]) {
        (k[2], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 1.0, 0.0])
    }

    fn eps_y_hessian(_: &[f64; 4], _: f64, _: f64, _: usize, _: usize) -> (f64, f64) {
        (0.0, 0.0)
    }

    fn shape(k: &[f64; 4], x: f64) -> [[f64; 3]; 2] {
        let [a1, a3, _, c2] = *k;
        [
            [
                x + a1 * x + a3 * x.powi(3),
                1.0 + a1 + 3.0 * a3 * x * x,
                6.0 * a3 * x,
            ],
            [c2 * x * x, 2.0 * c2 * x, 2.0 * c2],
        ]
    }

    fn shape_gradients(_: &[f64; 4], x: f64) -> [[f64; 4]; 4] {
        [
            [x, x.powi(3), 0.0, 0.0],
            [0.0, 0.0, 0.0, x * x],
            [1.0, 3.0 * x * x, 0.0, 0.0],
            [0.0, 0.0, 0.0, 2.0 * x],
        ]
    }
}

/// The richer membrane: u = a1 x + a2 x^2 + a3 x^3, v = b1 y, w = c2 x^2,
/// eps_x = a1 + 2 a2 x + (3 a3 + 2 c2^2) x^2 - 2 z c2, eps_y = b1
/// (unknowns a1, a2, a3, b1, c2).
impl Fields for QuadModel {
    fn typical() -> [f64; 5] {
        [0.05, 1e-3, 2e-5, 0.05, 0.03]
    }

    fn typical_at(l: f64) -> [f64; 5] {
        [0.05, 0.05 / l, 0.05 / (l * l), 0.05, 0.03 * 13.75 / l]
    }

    fn eps_x(k: &[f64; 5], x: f64, z: f64) -> (f64, [f64; 5]) {
        let [a1, a2, a3, _, c2] = *k;
        (
            a1 + 2.0 * a2 * x + (3.0 * a3 + 2.0 * c2 * c2) * x * x - 2.0 * z * c2,
            [1.0, 2.0 * x, 3.0 * x * x, 0.0, 4.0 * c2 * x * x - 2.0 * z],
        )
    }

    fn eps_x_gradient_magnitude(k: &[f64; 5], x: f64, z: f64) -> [f64; 5] {
        [
            1.0,
            2.0 * x.abs(),
            3.0 * x * x,
            0.0,
            4.0 * k[4].abs() * x * x + 2.0 * z.abs(),
        ]
    }

    fn eps_x_hessian(_: &[f64; 5], x: f64, _: f64, i: usize, j: usize) -> (f64, f64) {
        // d^2 eps_x / d c2^2 = 4 x^2, nothing else
        if i == 4 && j == 4 {
            (4.0 * x * x, 4.0 * x * x)
        } else {
            (0.0, 0.0)
        }
    }

    fn eps_y(k: &[f64; 5], _: f64, _: f64) -> (f64, [f64; 5], [f64; 5]) {
        (k[3], [0.0, 0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0, 0.0])
    }

    fn eps_y_hessian(_: &[f64; 5], _: f64, _: f64, _: usize, _: usize) -> (f64, f64) {
        (0.0, 0.0)
    }

    fn shape(k: &[f64; 5], x: f64) -> [[f64; 3]; 2] {
        let [a1, a2, a3, _, c2] = *k;
        [
            [
                x + a1 * x + a2 * x * x + a3 * x.powi(3),
                1.0 + a1 + 2.0 * a2 * x + 3.0 * a3 * x * x,
                2.0 * a2 + 6.0 * a3 * x,
            ],
            [c2 * x * x, 2.0 * c2 * x, 2.0 * c2],
        ]
    }

    fn shape_gradients(_: &[f64; 5], x: f64) -> [[f64; 5]; 4] {
        [
            [x, x * x, x.powi(3), 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, x * x],
            [1.0, 2.0 * x, 3.0 * x * x, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, 2.0 * x],
        ]
    }
}

// ---------------------------------------------------------------------------
// The energy densities of docs/model.md section 4 (the same for every
// model: the families' laws in the strains).

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

/// psi(s) = p1/2 s^2 - p2/3 s^3 + p3/4 s^4 - p4/5 s^5 and its first two
/// derivatives (the paper's law, `p = [p1, p2, p3, p4]`).
fn psi(p: &[f64; 4], s: f64) -> (f64, f64, f64) {
    let [p1, p2, p3, p4] = *p;
    (
        p1 / 2.0 * s.powi(2) - p2 / 3.0 * s.powi(3) + p3 / 4.0 * s.powi(4) - p4 / 5.0 * s.powi(5),
        p1 * s - p2 * s.powi(2) + p3 * s.powi(3) - p4 * s.powi(4),
        p1 - 2.0 * p2 * s + 3.0 * p3 * s.powi(2) - 4.0 * p4 * s.powi(3),
    )
}

/// The same with every term by absolute value.
fn psi_magnitude(p: &[f64; 4], s: f64) -> (f64, f64, f64) {
    let s = s.abs();
    let p = p.map(f64::abs);
    (
        p[0] / 2.0 * s.powi(2)
            + p[1] / 3.0 * s.powi(3)
            + p[2] / 4.0 * s.powi(4)
            + p[3] / 5.0 * s.powi(5),
        p[0] * s + p[1] * s.powi(2) + p[2] * s.powi(3) + p[3] * s.powi(4),
        p[0] + 2.0 * p[1] * s + 3.0 * p[2] * s.powi(2) + 4.0 * p[3] * s.powi(3),
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
                let (s0, s1, s2) = psi_magnitude(&p, eps0.abs() + e);
                Jet {
                    f: s0 + 0.5 * q22.abs() * y * y,
                    fe: s1,
                    fy: q22.abs() * y,
                    fee: s2,
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
}

/// The integral families by kind (the test's numbering).
const KIND_NAMES: [&str; 3] = ["linear", "prestressed", "gas"];

/// Position of kind `kind` in `M::FAMILIES` (family_hessian's argument).
fn family<M: ElementModel>(kind: usize) -> usize {
    M::FAMILIES
        .iter()
        .position(|f| *f == KIND_NAMES[kind])
        .unwrap_or_else(|| panic!("{} has no family {}", M::NAME, KIND_NAMES[kind]))
}

#[test]
fn every_family_is_known() {
    fn check<M: ElementModel>() {
        let mut known: Vec<&str> = M::FAMILIES.to_vec();
        known.sort_unstable();
        let mut want = KIND_NAMES.to_vec();
        want.sort_unstable();
        assert_eq!(known, want, "{}: families {:?}", M::NAME, M::FAMILIES);
        let m = M::zero_moments();
        assert!(M::family_hessian(&m, M::FAMILIES.len(), &M::Coeffs::zero()).is_none());
    }
    for_each_model!(check);
}

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
    g: Vec<f64>,
    h: Vec<Vec<f64>>,
    mag: f64,
    /// Integrals of the absolute terms of the gradient and Hessian densities.
    gmag: Vec<f64>,
    hmag: Vec<Vec<f64>>,
}

impl Quad {
    fn zero(n: usize) -> Quad {
        Quad {
            v: 0.0,
            g: vec![0.0; n],
            h: vec![vec![0.0; n]; n],
            mag: 0.0,
            gmag: vec![0.0; n],
            hmag: vec![vec![0.0; n]; n],
        }
    }

    /// self += c * other (magnitudes add with |c|).
    fn add_scaled(&mut self, c: f64, o: &Quad) {
        self.v += c * o.v;
        self.mag += c.abs() * o.mag;
        for i in 0..self.g.len() {
            self.g[i] += c * o.g[i];
            self.gmag[i] += c.abs() * o.gmag[i];
            for j in 0..self.g.len() {
                self.h[i][j] += c * o.h[i][j];
                self.hmag[i][j] += c.abs() * o.hmag[i][j];
            }
        }
    }

    fn add(&mut self, o: &Quad) {
        self.add_scaled(1.0, o);
    }
}

/// Tensor Gauss-Legendre quadrature of density `d` over box `b` at `k`,
/// through model `M`'s hand-written strains.
fn quad<M: Fields>(d: &Density, b: &Bx, k: &M::Coeffs) -> Quad {
    let n = len::<M>();
    let mut q = Quad::zero(n);
    for &(x, wx) in &rule(NX, b.x0, b.x1) {
        for &(z, wz) in &rule(NZ, b.z0, b.z1) {
            let w = wx * wz * b.width;
            let (e, de) = M::eps_x(k, x, z);
            let dem = M::eps_x_gradient_magnitude(k, x, z);
            let (ey, dy, dym) = M::eps_y(k, x, z);
            let j = d.jet(e, ey);
            let jm = d.magnitude_jet(e, ey);
            q.v += w * j.f;
            q.mag += w.abs() * jm.f;
            for i in 0..n {
                q.g[i] += w * (j.fe * de[i] + j.fy * dy[i]);
                q.gmag[i] += w.abs() * (jm.fe * dem[i] + jm.fy * dym[i]);
                for l in 0..n {
                    let (hx, hxm) = M::eps_x_hessian(k, x, z, i, l);
                    let (hy, hym) = M::eps_y_hessian(k, x, z, i, l);
                    let hil = j.fee * de[i] * de[l]
                        + j.fey * (de[i] * dy[l] + dy[i] * de[l])
                        + j.fyy * dy[i] * dy[l]
                        + j.fe * hx
                        + j.fy * hy;
                    let mil = jm.fee * dem[i] * dem[l]
                        + jm.fey * (dem[i] * dym[l] + dym[i] * dem[l])
                        + jm.fyy * dym[i] * dym[l]
                        + jm.fe * hxm
                        + jm.fy * hym;
                    q.h[i][l] += w * hil;
                    q.hmag[i][l] += w.abs() * mil;
                }
            }
        }
    }
    q
}

// ---------------------------------------------------------------------------
// The generated model through its trait.

/// Adds box `b` of density `d` to the moments, through the family's
/// parameter struct.
fn add_block<M: ElementModel>(d: &Density, b: &Bx, m: &mut M::Moments) {
    match *d {
        Density::Linear { q11, q12, q22 } => M::add_linear(
            m,
            &LinearParams {
                x0: b.x0,
                x1: b.x1,
                width: b.width,
                z0: b.z0,
                z1: b.z1,
                q11,
                q12,
                q22,
            },
        ),
        Density::Prestressed { eps0, p, q22 } => M::add_prestressed(
            m,
            &PrestressedParams {
                x0: b.x0,
                x1: b.x1,
                width: b.width,
                z0: b.z0,
                z1: b.z1,
                eps0,
                p1: p[0],
                p2: p[1],
                p3: p[2],
                p4: p[3],
                q22,
            },
        ),
        Density::Gas => M::add_gas(
            m,
            &GasParams {
                x0: b.x0,
                x1: b.x1,
                width: b.width,
                z0: b.z0,
                z1: b.z1,
            },
        ),
    }
}

fn moments_of<M: ElementModel>(d: &Density, boxes: &[Bx]) -> M::Moments {
    let mut m = M::zero_moments();
    for b in boxes {
        add_block::<M>(d, b, &mut m);
    }
    m
}

/// The element potential is `Psi - kp V` (docs/model.md Eq. 16): the
/// coefficient of each kind.
fn coefficient(kind: usize, kp: f64) -> f64 {
    if kind == 2 {
        -kp
    } else {
        1.0
    }
}

/// The scalars under which the potential of moments holding kind `kind`
/// alone is that family's integral (kp = -1 for the gas volume).
fn alone(kind: usize) -> EnergyScalars {
    EnergyScalars {
        kp: if kind == 2 { -1.0 } else { 0.0 },
    }
}

/// The value kernel of kind `kind` (moments of that kind alone).
fn k_value<M: ElementModel>(kind: usize, k: &M::Coeffs, m: &M::Moments) -> f64 {
    M::energy(m, k, &alone(kind))
}

/// The gradient kernel of kind `kind` (moments of that kind alone).
fn k_gradient<M: ElementModel>(kind: usize, k: &M::Coeffs, m: &M::Moments) -> (f64, M::Coeffs) {
    M::gradient(m, k, &alone(kind))
}

/// The family's own kernel.
fn k_family<M: ElementModel>(
    kind: usize,
    k: &M::Coeffs,
    m: &M::Moments,
) -> (f64, M::Coeffs, M::Upper) {
    M::family_hessian(m, family::<M>(kind), k).expect("family in range")
}

/// The full matrix of an upper triangle.
fn full(n: usize, h: &[f64]) -> Vec<Vec<f64>> {
    assert_eq!(h.len(), n * (n + 1) / 2);
    (0..n)
        .map(|i| (0..n).map(|j| h[upper_index(n, i, j)]).collect())
        .collect()
}

// ---------------------------------------------------------------------------
// Random inputs in realistic ranges.

fn random_k<M: Fields>(rng: &mut Rng) -> M::Coeffs {
    rng.within(&M::typical())
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

/// The paper's law, [p1, p2, p3, p4].
const PAPER_PSI: [f64; 4] = [1.598, 2.306, 2.29, 0.698];

/// The paper's law with each constant scaled by a random factor in [0.7, 1.3].
fn random_law(rng: &mut Rng) -> [f64; 4] {
    let mut p = [0.0; 4];
    for (pi, base) in p.iter_mut().zip(PAPER_PSI) {
        *pi = base * rng.range(0.7, 1.3);
    }
    p
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
            let p = random_law(rng);
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

fn values_vs_quadrature<M: Fields>() {
    let mut rng = Rng::new(1);
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        let (mut worst_value, mut worst_mag) = (0.0f64, 0.0f64);
        for case in 0..300 {
            let d = random_density(kind, &mut rng);
            let b = random_box(&mut rng);
            let k = random_k::<M>(&mut rng);
            let m = moments_of::<M>(&d, &[b]);
            let got = k_value::<M>(kind, &k, &m);
            let q = quad::<M>(&d, &b, &k);
            let rel = (got - q.v).abs() / q.v.abs();
            worst_value = worst_value.max(rel);
            worst_mag = worst_mag.max((got - q.v).abs() / q.mag);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: kernel {got:e}, quadrature {:e}, relative {rel:e}\n{d:?}\n{b:?}\nK = {k:?}",
                M::NAME,
                q.v
            );
            // the family's own kernel gives the same value
            let fam = k_family::<M>(kind, &k, &m).0;
            let rel = (fam - q.v).abs() / q.v.abs();
            worst_value = worst_value.max(rel);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: family kernel {fam:e}, quadrature {:e}",
                M::NAME,
                q.v
            );
        }
        eprintln!(
            "{} {name}: worst relative error vs quadrature {worst_value:e} ({worst_mag:e} of the term magnitude)",
            M::NAME
        );
    }
}

#[test]
fn values_match_gauss_legendre_quadrature() {
    for_each_model!(values_vs_quadrature);
}

fn linearity<M: Fields>() {
    let mut rng = Rng::new(2);
    let (mut worst_sum, mut worst_cancel, mut worst_split) = (0.0f64, 0.0f64, 0.0f64);
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        for case in 0..200 {
            let k = random_k::<M>(&mut rng);
            // two blocks of different material accumulate into one set of moments
            let (d1, d2) = (
                random_density(kind, &mut rng),
                random_density(kind, &mut rng),
            );
            let (b1, b2) = (random_box(&mut rng), random_box(&mut rng));
            let mut m = M::zero_moments();
            add_block::<M>(&d1, &b1, &mut m);
            add_block::<M>(&d2, &b2, &mut m);
            let v1 = k_value::<M>(kind, &k, &moments_of::<M>(&d1, &[b1]));
            let v2 = k_value::<M>(kind, &k, &moments_of::<M>(&d2, &[b2]));
            let both = k_value::<M>(kind, &k, &m);
            let rel = (both - (v1 + v2)).abs() / (v1.abs() + v2.abs());
            worst_sum = worst_sum.max(rel);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: two blocks {both:e}, sum {:e}",
                M::NAME,
                v1 + v2
            );

            // the same block with the opposite width cancels it
            let neg = Bx {
                width: -b1.width,
                ..b1
            };
            let cancel = k_value::<M>(kind, &k, &moments_of::<M>(&d1, &[b1, neg]));
            let rel = cancel.abs() / v1.abs();
            worst_cancel = worst_cancel.max(rel);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: +w and -w leave {cancel:e} (block {v1:e})",
                M::NAME
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
            let split = k_value::<M>(kind, &k, &moments_of::<M>(&d1, &parts));
            let scale = quad::<M>(&d1, &b1, &k).mag;
            let rel = (split - v1).abs() / scale;
            worst_split = worst_split.max(rel);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: split {split:e}, whole {v1:e}",
                M::NAME
            );
        }
    }
    eprintln!(
        "{} linearity: worst two-block {worst_sum:e}, cancellation {worst_cancel:e}, split {worst_split:e}",
        M::NAME
    );
}

#[test]
fn moments_are_linear_in_blocks() {
    for_each_model!(linearity);
}

// ---------------------------------------------------------------------------
// 2. Derivatives.

/// 5-point central difference (Richardson-extrapolated) of `f` along e_i.
fn fd_vec<C: Vector>(f: impl Fn(&C) -> Vec<f64>, k: &C, i: usize, h: f64) -> Vec<f64> {
    let at = |t: f64| {
        let mut kk = *k;
        kk[i] += t * h;
        f(&kk)
    };
    let terms = [
        (8.0, at(1.0)),
        (-8.0, at(-1.0)),
        (-1.0, at(2.0)),
        (1.0, at(-2.0)),
    ];
    let mut out = vec![0.0; terms[0].1.len()];
    for (c, v) in &terms {
        for (o, x) in out.iter_mut().zip(v) {
            *o += c * x;
        }
    }
    out.iter().map(|o| o / (12.0 * h)).collect()
}

/// The same for a scalar function.
fn fd<C: Vector>(f: impl Fn(&C) -> f64, k: &C, i: usize, h: f64) -> f64 {
    fd_vec(|kk| vec![f(kk)], k, i, h)[0]
}

/// 5-point central difference in a scalar argument.
fn fd1(f: impl Fn(f64) -> f64, s: f64, h: f64) -> f64 {
    (8.0 * (f(s + h) - f(s - h)) - (f(s + 2.0 * h) - f(s - 2.0 * h))) / (12.0 * h)
}

/// Step of the finite differences, as a fraction of each unknown's typical
/// size. The 5-point stencil's truncation error grows as step^4 (about 1e-9
/// of the energy scale at 1e-3 for the CCM's degree-10 prestressed kernel)
/// and its rounding error as 1/step; 3e-4 keeps both near 1e-11.
const FD_STEP: f64 = 3e-4;

/// A random scene for a family: 1 to 3 blocks of random material.
fn random_scene<M: ElementModel>(kind: usize, rng: &mut Rng) -> M::Moments {
    let mut m = M::zero_moments();
    let n = 1 + (rng.next_u64() % 3) as usize;
    for _ in 0..n {
        let d = random_density(kind, rng);
        let b = random_box(rng);
        add_block::<M>(&d, &b, &mut m);
    }
    m
}

fn derivatives_vs_fd<M: Fields>() {
    let mut rng = Rng::new(3);
    let n = len::<M>();
    let typical = M::typical();
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        let (mut worst_g, mut worst_h, mut worst_variant) = (0.0f64, 0.0f64, 0.0f64);
        for case in 0..60 {
            let m = random_scene::<M>(kind, &mut rng);
            let k = random_k::<M>(&mut rng);
            let v = k_value::<M>(kind, &k, &m);
            let (vg, g) = k_gradient::<M>(kind, &k, &m);
            let (vh, gh, hu) = M::hessian(&m, &k, &alone(kind));
            let (vf, gf, hf) = k_family::<M>(kind, &k, &m);
            let h = full(n, hf.as_ref());

            // the value, gradient and Hessian variants and the family's own
            // kernel agree
            let gscale = (0..n).fold(0.0f64, |s, i| s.max(g[i].abs() * typical[i]));
            let scale = v.abs().max(gscale);
            let mut variant = (vg - v).abs().max((vh - v).abs()).max((vf - v).abs()) / scale;
            for i in 0..n {
                let d = (gh[i] - g[i]).abs().max((gf[i] - g[i]).abs());
                variant = variant.max(d * typical[i] / scale);
                for j in 0..n {
                    let hij = hu[upper_index(n, i, j)];
                    let d = (hij - h[i][j]).abs() * typical[i] * typical[j] / scale;
                    variant = variant.max(d);
                }
            }
            worst_variant = worst_variant.max(variant);
            assert!(
                variant <= 1e-14,
                "{} {name} case {case}: value/gradient/hessian/family variants differ by {variant:e}",
                M::NAME
            );

            // gradient: finite differences of the value; errors are measured
            // as the change of the value over a typical step, over the
            // energy scale
            for i in 0..n {
                let d = fd(|kk| k_value::<M>(kind, kk, &m), &k, i, FD_STEP * typical[i]);
                let err = (d - g[i]).abs() * typical[i] / scale;
                worst_g = worst_g.max(err);
                assert!(
                    err <= 1e-9,
                    "{} {name} case {case}: dV/dK[{i}] kernel {:e}, finite difference {d:e} (error {err:e})",
                    M::NAME,
                    g[i]
                );
            }
            // Hessian: finite differences of the gradient, full n x n
            for j in 0..n {
                let col = fd_vec(
                    |kk| k_gradient::<M>(kind, kk, &m).1.as_ref().to_vec(),
                    &k,
                    j,
                    FD_STEP * typical[j],
                );
                for i in 0..n {
                    let err = (col[i] - h[i][j]).abs() * typical[i] * typical[j] / scale;
                    worst_h = worst_h.max(err);
                    assert!(
                        err <= 1e-9,
                        "{} {name} case {case}: H[{i}][{j}] kernel {:e}, finite difference {:e} (error {err:e})",
                        M::NAME,
                        h[i][j],
                        col[i]
                    );
                }
            }
        }
        eprintln!(
            "{} {name}: worst FD gradient error {worst_g:e}, FD Hessian {worst_h:e}, variants {worst_variant:e}",
            M::NAME
        );
    }
}

#[test]
fn derivatives_match_finite_differences() {
    for_each_model!(derivatives_vs_fd);
}

/// The element potential of moments holding every family is the
/// families' sum with the potential's coefficients (1, 1, -kp), in all
/// three variants.
fn potential_combines_families<M: Fields>() {
    let mut rng = Rng::new(7);
    let n = len::<M>();
    let mut worst = 0.0f64;
    for case in 0..100 {
        let mut m = M::zero_moments();
        for kind in 0..3 {
            for _ in 0..1 + (rng.next_u64() % 3) {
                let d = random_density(kind, &mut rng);
                let b = random_box(&mut rng);
                add_block::<M>(&d, &b, &mut m);
            }
        }
        let k = random_k::<M>(&mut rng);
        // kappa P from 0 to 2.5 * 400 kPa, exactly zero in a quarter of the cases
        let kp = if case % 4 == 0 {
            0.0
        } else {
            rng.range(0.0, 1.0)
        };
        let s = EnergyScalars { kp };
        let mut want = Quad::zero(n);
        for kind in 0..3 {
            let (v, g, h) = k_family::<M>(kind, &k, &m);
            let c = coefficient(kind, kp);
            want.v += c * v;
            want.mag += (c * v).abs();
            for i in 0..n {
                want.g[i] += c * g[i];
                want.gmag[i] += (c * g[i]).abs();
                for j in 0..n {
                    let hij = h.as_ref()[upper_index(n, i, j)];
                    want.h[i][j] += c * hij;
                    want.hmag[i][j] += (c * hij).abs();
                }
            }
        }
        let v = M::energy(&m, &k, &s);
        let (vg, g) = M::gradient(&m, &k, &s);
        let (vh, gh, hu) = M::hessian(&m, &k, &s);
        for (what, got) in [
            ("value", v),
            ("gradient variant", vg),
            ("Hessian variant", vh),
        ] {
            let err = (got - want.v).abs() / want.mag;
            worst = worst.max(err);
            assert!(
                err <= 1e-14,
                "{} case {case} kp {kp}: {what} {got:e} vs the families' {:e} ({err:e})",
                M::NAME,
                want.v
            );
        }
        for i in 0..n {
            for (what, got) in [("gradient", g[i]), ("Hessian variant's gradient", gh[i])] {
                if want.gmag[i] == 0.0 {
                    assert_eq!(got, 0.0, "{} case {case}: {what}[{i}]", M::NAME);
                    continue;
                }
                let err = (got - want.g[i]).abs() / want.gmag[i].max(1e-300);
                worst = worst.max(err);
                assert!(
                    err <= 1e-14,
                    "{} case {case} kp {kp}: {what}[{i}] {got:e} vs {:e}",
                    M::NAME,
                    want.g[i]
                );
            }
            for j in 0..n {
                let got = hu[upper_index(n, i, j)];
                if want.hmag[i][j] == 0.0 {
                    assert_eq!(got, 0.0, "{} case {case}: H[{i}][{j}]", M::NAME);
                    continue;
                }
                let err = (got - want.h[i][j]).abs() / want.hmag[i][j];
                worst = worst.max(err);
                assert!(
                    err <= 1e-14,
                    "{} case {case} kp {kp}: H[{i}][{j}] {got:e} vs {:e}",
                    M::NAME,
                    want.h[i][j]
                );
            }
        }
    }
    eprintln!(
        "{}: element potential vs the sum of its families: worst {worst:e} of the term magnitude",
        M::NAME
    );
}

#[test]
fn element_potential_is_the_sum_of_its_families() {
    for_each_model!(potential_combines_families);
}

fn derivatives_vs_density_quadrature<M: Fields>() {
    let mut rng = Rng::new(4);
    let n = len::<M>();
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        let (mut worst_g, mut worst_h) = ((0.0f64, 0.0f64), (0.0f64, 0.0f64));
        for case in 0..150 {
            let d = random_density(kind, &mut rng);
            let b = random_box(&mut rng);
            let k = random_k::<M>(&mut rng);
            let m = moments_of::<M>(&d, &[b]);
            let (_, g, hu) = k_family::<M>(kind, &k, &m);
            let h = full(n, hu.as_ref());
            let q = quad::<M>(&d, &b, &k);
            // Errors over the integral of the absolute terms of each
            // entry's density (exact zeros must be exact); the relative
            // error per entry is reported too.
            let mut entries: Vec<(String, f64, f64, f64, bool)> = Vec::new();
            for i in 0..n {
                entries.push((format!("gradient[{i}]"), g[i], q.g[i], q.gmag[i], true));
                for (j, (hij, (qh, qm))) in
                    h[i].iter().zip(q.h[i].iter().zip(&q.hmag[i])).enumerate()
                {
                    entries.push((format!("H[{i}][{j}]"), *hij, *qh, *qm, false));
                }
            }
            for (entry, got, want, mag, is_grad) in entries {
                if mag == 0.0 {
                    assert_eq!(got, 0.0, "{} {name} case {case}: {entry}", M::NAME);
                    continue;
                }
                let err = (got - want).abs() / mag;
                let worst = if is_grad { &mut worst_g } else { &mut worst_h };
                worst.0 = worst.0.max(err);
                worst.1 = worst.1.max((got - want).abs() / want.abs().max(1e-6 * mag));
                assert!(
                    err <= 1e-12,
                    "{} {name} case {case}: {entry} kernel {got:e}, quadrature {want:e} ({err:e} of the term magnitude {mag:e})",
                    M::NAME
                );
            }
        }
        eprintln!(
            "{} {name}: worst error vs quadrature of density derivatives (of term magnitude / relative): gradient {:e} / {:e}, Hessian {:e} / {:e}",
            M::NAME, worst_g.0, worst_g.1, worst_h.0, worst_h.1
        );
    }
}

#[test]
fn derivatives_match_quadrature_of_density_derivatives() {
    for_each_model!(derivatives_vs_density_quadrature);
}

// ---------------------------------------------------------------------------
// 3. The prestressed law.

fn psi_vs_fd<M: ElementModel>() {
    let mut rng = Rng::new(8);
    let mut worst = 0.0f64;
    for case in 0..200 {
        let p = random_law(&mut rng);
        let law = PsiParams {
            p1: p[0],
            p2: p[1],
            p3: p[2],
            p4: p[3],
        };
        let s = rng.range(-0.3, 0.9);
        let got = M::psi(s, &law);
        // psi' and psi'' against finite differences of psi and psi'; errors
        // over the magnitude of the derivative's terms
        let (_, m1, m2) = psi_magnitude(&p, s);
        let h = 1e-4;
        for (o, fd_value, mag) in [
            (1, fd1(|t| M::psi(t, &law)[0], s, h), m1),
            (2, fd1(|t| M::psi(t, &law)[1], s, h), m2),
        ] {
            let err = (got[o] - fd_value).abs() / mag.max(1e-300);
            worst = worst.max(err);
            assert!(
                err <= 1e-10,
                "{} case {case}: psi derivative {o} at s = {s}: {:e} vs finite difference {fd_value:e} ({err:e})",
                M::NAME,
                got[o]
            );
        }
    }
    eprintln!(
        "{}: psi', psi'' vs finite differences: worst {worst:e} of the term magnitude",
        M::NAME
    );
}

#[test]
fn psi_derivatives_match_finite_differences() {
    for_each_model!(psi_vs_fd);
}

#[test]
fn ccm_psi_is_the_papers_law() {
    // the default constants are the paper's fit
    assert_eq!(PsiParams::default().to_array(), PAPER_PSI);
    let mut rng = Rng::new(9);
    let mut worst = 0.0f64;
    for case in 0..300 {
        let p = if case == 0 {
            PAPER_PSI
        } else {
            random_law(&mut rng)
        };
        let law = PsiParams {
            p1: p[0],
            p2: p[1],
            p3: p[2],
            p4: p[3],
        };
        let s = if case < 2 { 0.0 } else { rng.range(-0.3, 0.9) };
        let got = Ccm::psi(s, &law);
        let (w0, w1, w2) = psi(&p, s);
        let (m0, m1, m2) = psi_magnitude(&p, s);
        for (o, want, mag) in [(0, w0, m0), (1, w1, m1), (2, w2, m2)] {
            if mag == 0.0 {
                assert_eq!(got[o], 0.0, "case {case}: psi[{o}] at s = 0");
                continue;
            }
            let err = (got[o] - want).abs() / mag;
            worst = worst.max(err);
            assert!(
                err <= 1e-14,
                "case {case}: psi[{o}]({s}) = {:e}, closed form {want:e} ({err:e})",
                got[o]
            );
        }
    }
    // at rest the tangent modulus is p1, exactly
    assert_eq!(Ccm::psi(0.0, &PsiParams::default()), [0.0, 0.0, 1.598]);
    eprintln!("ccm psi vs the paper's law in closed form: worst {worst:e} of the term magnitude");
}

// ---------------------------------------------------------------------------
// 4. Point kernels: mid-plane, tangent, strain, curvature; scaling.

fn point_kernels_vs_closed_forms<M: Fields>() {
    let mut rng = Rng::new(10);
    let n = len::<M>();
    let (mut worst_p, mut worst_t, mut worst_s, mut worst_c, mut worst_fd) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for case in 0..400 {
        let l = rng.range(1.0, 110.0);
        let k: M::Coeffs = rng.within(&M::typical_at(l));
        let x = if case % 10 == 0 {
            0.0
        } else {
            rng.range(0.0, l)
        };
        let z = rng.range(-4.1, 4.1);
        let [[xx, dxx, ddxx], [zz, dzz, ddzz]] = M::shape(&k, x);
        let label = format!("{} case {case} L={l} x={x} z={z} K={k:?}", M::NAME);

        // mid-plane [X, Z] = [x + u, w], on the scale of the element
        let got = M::midplane(&k, x);
        for (o, want) in [xx, zz].into_iter().enumerate() {
            let err = (got[o] - want).abs() / want.abs().max(l);
            worst_p = worst_p.max(err);
            assert!(
                err <= 1e-14,
                "{label}: midplane[{o}] {:e}, closed form {want:e}",
                got[o]
            );
        }
        // tangent [X', Z']
        let got = M::tangent(&k, x);
        for (o, want) in [dxx, dzz].into_iter().enumerate() {
            let err = (got[o] - want).abs() / want.abs().max(1.0);
            worst_t = worst_t.max(err);
            assert!(
                err <= 1e-14,
                "{label}: tangent[{o}] {:e}, closed form {want:e}",
                got[o]
            );
        }
        // the tangent is the mid-plane's derivative in x
        let hx = 1e-3 * l;
        for (o, &t_o) in got.iter().enumerate() {
            let d = fd1(|t| M::midplane(&k, t)[o], x, hx);
            let err = (d - t_o).abs() / t_o.abs().max(1.0);
            worst_fd = worst_fd.max(err);
            assert!(
                err <= 1e-9,
                "{label}: tangent[{o}] {t_o:e}, finite difference of the mid-plane {d:e}"
            );
        }
        // axial strain eps_x; scale: its terms by absolute value
        let (want, _) = M::eps_x(&k, x, z);
        let dm = M::eps_x_gradient_magnitude(&k, x, z);
        let scale = (0..n).map(|i| (dm[i] * k[i]).abs()).sum::<f64>();
        let got = M::strain(&k, x, z);
        let err = (got - want).abs() / scale.max(f64::MIN_POSITIVE);
        worst_s = worst_s.max(err);
        assert!(
            err <= 1e-14,
            "{label}: strain {got:e}, closed form {want:e}"
        );
        // curvature (X' Z'' - Z' X'') / (X'^2 + Z'^2)^(3/2)
        let r3 = (dxx * dxx + dzz * dzz).powf(1.5);
        let want = (dxx * ddzz - dzz * ddxx) / r3;
        let scale = ((dxx * ddzz).abs() + (dzz * ddxx).abs()) / r3;
        let got = M::curvature(&k, x);
        if scale == 0.0 {
            assert_eq!(got, 0.0, "{label}: curvature of a straight element");
        } else {
            let err = (got - want).abs() / scale;
            worst_c = worst_c.max(err);
            assert!(
                err <= 1e-13,
                "{label}: curvature {got:e}, closed form {want:e} ({err:e})"
            );
        }
    }
    // the straight element: flat, unit tangent, no strain, no curvature
    let zero = M::Coeffs::zero();
    for x in [0.0, 1.0, 13.75, 110.0] {
        assert_eq!(M::midplane(&zero, x), [x, 0.0], "{}", M::NAME);
        assert_eq!(M::tangent(&zero, x), [1.0, 0.0], "{}", M::NAME);
        assert_eq!(M::strain(&zero, x, 2.0), 0.0, "{}", M::NAME);
        assert_eq!(M::curvature(&zero, x), 0.0, "{}", M::NAME);
    }
    eprintln!(
        "{}: point kernels vs closed forms: worst mid-plane {worst_p:e}, tangent {worst_t:e}, strain {worst_s:e}, curvature {worst_c:e}; tangent vs FD of the mid-plane {worst_fd:e}",
        M::NAME
    );
}

#[test]
fn midplane_tangent_strain_and_curvature_match_closed_forms() {
    for_each_model!(point_kernels_vs_closed_forms);
}

/// The mid-plane's polynomial coefficients against the mid-plane point
/// kernel: `sum_j c_j x^j` evaluated here (Horner) equals `midplane(k, x)`
/// to rounding at random states and points, inside and beyond the element.
fn midplane_polynomial_vs_point_kernel<M: Fields>() {
    let mut rng = Rng::new(12);
    let d = M::MIDPLANE_DEGREE;
    let mut c = vec![[f64::NAN; 2]; d + 2];
    let mut worst = 0.0f64;
    for case in 0..2000 {
        let l = rng.range(1.0, 110.0);
        // typical states, and large ones (every coefficient matters)
        let k: M::Coeffs = if case % 4 == 3 {
            M::Coeffs::from_fn(|_| rng.range(-2.0, 2.0))
        } else {
            rng.within(&M::typical_at(l))
        };
        c.iter_mut().for_each(|e| *e = [f64::NAN; 2]);
        M::midplane_coefficients(&k, &mut c);
        assert!(
            c[d + 1][0].is_nan(),
            "{}: wrote beyond MIDPLANE_DEGREE + 1 entries",
            M::NAME
        );
        let x = rng.range(-0.5 * l, 1.5 * l);
        let want = M::midplane(&k, x);
        for o in 0..2 {
            let got = c[..=d].iter().rev().fold(0.0, |acc, cj| acc * x + cj[o]);
            // rounding scale: the terms by absolute value
            let scale = c[..=d]
                .iter()
                .enumerate()
                .map(|(j, cj)| (cj[o] * x.powi(j as i32)).abs())
                .sum::<f64>()
                .max(l);
            let err = (got - want[o]).abs() / scale;
            worst = worst.max(err);
            assert!(
                err <= 4.0 * f64::EPSILON,
                "{} case {case}: polynomial[{o}]({x}) = {got:e}, point kernel {:e} (K = {k:?})",
                M::NAME,
                want[o]
            );
        }
    }
    // the straight, unstrained element is X = x, Z = 0
    M::midplane_coefficients(&M::Coeffs::zero(), &mut c);
    for (j, cj) in c[..=d].iter().enumerate() {
        assert_eq!(
            *cj,
            if j == 1 { [1.0, 0.0] } else { [0.0, 0.0] },
            "{}",
            M::NAME
        );
    }
    // a shorter slice gets the lowest powers only
    let mut short = [[f64::NAN; 2]; 1];
    M::midplane_coefficients(&M::Coeffs::zero(), &mut short);
    assert_eq!(short, [[0.0, 0.0]]);
    eprintln!(
        "{}: mid-plane polynomial (degree {d}) vs point kernel: worst {worst:e} of the term magnitude",
        M::NAME
    );
}

#[test]
fn midplane_polynomial_matches_the_point_kernel() {
    for_each_model!(midplane_polynomial_vs_point_kernel);
}

#[test]
fn ccm_constant_curvature_is_twice_c2() {
    // an element with a1 = a3 = 0 bends as w = c2 x^2: curvature at the
    // root 2 c2, and 2 c2 / (1 + 4 c2^2 x^2)^(3/2) along it
    for c2 in [-0.03f64, -1e-4, 1e-4, 0.03] {
        let k = [0.0, 0.0, 0.01, c2];
        for x in [0.0f64, 3.0, 13.75] {
            let want = 2.0 * c2 / (1.0 + 4.0 * c2 * c2 * x * x).powf(1.5);
            let got = Ccm::curvature(&k, x);
            assert!(
                (got - want).abs() <= 2e-15 * want.abs(),
                "c2 {c2}, x {x}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn ccm_unscale_is_the_natural_scaling() {
    let mut rng = Rng::new(11);
    let mut lengths = vec![1e-3, 0.11, 1.0, 5.0, 13.75, 110.0, 1e3];
    lengths.extend((0..50).map(|_| rng.range(0.1, 200.0)));
    for l in lengths {
        let got = Ccm::unscale(l);
        let want = [1.0, 1.0 / (l * l), 1.0, 1.0 / l];
        for i in 0..4 {
            assert!(
                (got[i] - want[i]).abs() <= 1e-15 * want[i],
                "L = {l}: unscale[{i}] = {:e}, want {:e}",
                got[i],
                want[i]
            );
        }
    }
    assert_eq!(Ccm::UNKNOWNS, ["a1", "a3", "b1", "c2"]);
    assert_eq!(Ccm::LOCAL, [2], "b1 couples only within its element");
}

// ---------------------------------------------------------------------------
// 5. End kinematics.

/// docs/model.md Eqs. 11, 13 with decision D2, from the fields:
/// `[X(L), Z(L), atan2(Z'(L), X'(L))]`, and the unnormalised end frame
/// `[X(L), Z(L), X'(L), Z'(L)]`.
fn end_closed_form<M: Fields>(k: &M::Coeffs, l: f64) -> ([f64; 3], [f64; 4]) {
    let [[x, dx, _], [z, dz, _]] = M::shape(k, l);
    ([x, z, dz.atan2(dx)], [x, z, dx, dz])
}

/// Gradient of (Xe, Ze, eta) by the chain rule from the fields' gradients:
/// d atan2(Z', X') = (X' dZ' - Z' dX') / (X'^2 + Z'^2).
fn end_gradient_closed_form<M: Fields>(k: &M::Coeffs, l: f64) -> [Vec<f64>; 3] {
    let n = len::<M>();
    let [[_, dx, _], [_, dz, _]] = M::shape(k, l);
    let [gx, gz, gdx, gdz] = M::shape_gradients(k, l);
    let r2 = dx * dx + dz * dz;
    [
        (0..n).map(|i| gx[i]).collect(),
        (0..n).map(|i| gz[i]).collect(),
        (0..n).map(|i| (dx * gdz[i] - dz * gdx[i]) / r2).collect(),
    ]
}

fn random_end_case<M: Fields>(rng: &mut Rng) -> (M::Coeffs, f64) {
    let l = rng.range(1.0, 110.0);
    let k = rng.within(&M::typical_at(l));
    (k, l)
}

fn check_end<M: Fields>(k: &M::Coeffs, l: f64, label: &str, worst: &mut [f64; 4]) {
    let n = len::<M>();
    let v = M::end(k, l);
    let (vg, gg) = M::end_gradient(k, l);
    let (vh, g, hu) = M::end_hessian(k, l);
    // the values-free kernel the chain's Hessian uses: the same derivatives
    // (hu is checked against finite differences below)
    let (dg, dh) = M::end_derivatives(k, l);
    for o in 0..3 {
        let gs = g[o].as_ref().iter().fold(1e-300f64, |s, x| s.max(x.abs()));
        let hs = hu[o].as_ref().iter().fold(1e-300f64, |s, x| s.max(x.abs()));
        for (a, b) in dg[o].as_ref().iter().zip(g[o].as_ref()) {
            assert!(
                (a - b).abs() <= 1e-14 * gs,
                "{label}: end_derivatives gradient {a:e} vs {b:e}"
            );
        }
        for (a, b) in dh[o].as_ref().iter().zip(hu[o].as_ref()) {
            assert!(
                (a - b).abs() <= 1e-14 * hs,
                "{label}: end_derivatives Hessian {a:e} vs {b:e}"
            );
        }
    }
    let (want, want_frame) = end_closed_form::<M>(k, l);
    let want_g = end_gradient_closed_form::<M>(k, l);
    // typical sizes: a step that moves the end as much as the others
    let typ = M::typical_at(l);

    // the unnormalised end frame [Xe, Ze, X'(L), Z'(L)]
    let frame = M::frame(k, l);
    for o in 0..4 {
        let scale = want_frame[o].abs().max(if o < 2 { l } else { 1.0 });
        let err = (frame[o] - want_frame[o]).abs() / scale;
        worst[0] = worst[0].max(err);
        assert!(
            err <= 1e-14,
            "{label}: frame[{o}] kernel {:e}, closed form {:e}",
            frame[o],
            want_frame[o]
        );
    }
    for o in 0..3 {
        let scale = want[o].abs().max(if o == 2 { 1.0 } else { l });
        let err = (v[o] - want[o])
            .abs()
            .max((vh[o] - want[o]).abs())
            .max((vg[o] - want[o]).abs())
            / scale;
        worst[0] = worst[0].max(err);
        assert!(
            err <= 1e-14,
            "{label}: end[{o}] kernel {:e}, closed form {:e}",
            v[o],
            want[o]
        );
        // gradient scale: the output's change over typical steps
        let gscale = (0..n).fold(0.0f64, |s, i| s.max(want_g[o][i].abs() * typ[i]));
        for i in 0..n {
            let err = (g[o][i] - want_g[o][i]).abs() * typ[i] / gscale.max(1e-300);
            worst[1] = worst[1].max(err);
            assert!(
                err <= 1e-13,
                "{label}: d end[{o}]/dK[{i}] kernel {:e}, closed form {:e}",
                g[o][i],
                want_g[o][i]
            );
            // the gradient-only kernel agrees with the Hessian kernel
            let err = (gg[o][i] - g[o][i]).abs() * typ[i] / gscale.max(1e-300);
            worst[1] = worst[1].max(err);
            assert!(
                err <= 1e-14,
                "{label}: d end[{o}]/dK[{i}] end_gradient {:e}, end_hessian {:e}",
                gg[o][i],
                g[o][i]
            );
            let d = fd(|kk| M::end(kk, l)[o], k, i, FD_STEP * typ[i]);
            let err = (d - g[o][i]).abs() * typ[i] / gscale.max(1e-300);
            worst[2] = worst[2].max(err);
            assert!(
                err <= 1e-9,
                "{label}: d end[{o}]/dK[{i}] kernel {:e}, finite difference {d:e}",
                g[o][i]
            );
        }
        let h = full(n, hu[o].as_ref());
        for j in 0..n {
            let col = fd_vec(
                |kk| M::end_hessian(kk, l).1[o].as_ref().to_vec(),
                k,
                j,
                FD_STEP * typ[j],
            );
            for i in 0..n {
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

fn end_kinematics<M: Fields>() {
    let mut rng = Rng::new(5);
    let mut worst = [0.0f64; 4];
    for case in 0..200 {
        let (k, l) = random_end_case::<M>(&mut rng);
        check_end::<M>(
            &k,
            l,
            &format!("{} case {case} L={l} K={k:?}", M::NAME),
            &mut worst,
        );

        // eta is the direction of the mid-plane's tangent at x = L
        let hh = 1e-4 * l;
        let (p, q) = (M::shape(&k, l + hh), M::shape(&k, l - hh));
        let eta_fd = (p[1][0] - q[1][0]).atan2(p[0][0] - q[0][0]);
        let err = (M::end(&k, l)[2] - eta_fd).abs();
        assert!(
            err <= 1e-9,
            "{} case {case}: eta vs mid-plane tangent {err:e}",
            M::NAME
        );
    }
    eprintln!(
        "{} end: worst value {:e}, gradient vs closed form {:e}, vs FD {:e}, Hessian vs FD {:e}",
        M::NAME,
        worst[0],
        worst[1],
        worst[2],
        worst[3]
    );
}

#[test]
fn end_kinematics_match_closed_forms_and_finite_differences() {
    for_each_model!(end_kinematics);
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
        let eta = Ccm::end(&k, l)[2];
        assert!(
            eta > lo && eta < hi,
            "eta = {eta} for c2 = {c2}, should lie in ({lo}, {hi})"
        );
        let want = PI.copysign(c2) - (2.0 * c2 * l / -x).atan();
        assert!((eta - want).abs() <= 1e-14, "eta {eta} vs {want}");
        check_end::<Ccm>(&k, l, &format!("past 90 degrees, c2 = {c2}"), &mut worst);
    }
    // exactly 90 degrees: dX/dx = 0 at the end
    let k = [-0.4, -0.6 / (3.0 * l * l), 0.0, 0.01];
    let eta = Ccm::end(&k, l)[2];
    assert!((eta - FRAC_PI_2).abs() <= 1e-12, "eta = {eta}");
    check_end::<Ccm>(&k, l, "at 90 degrees", &mut worst);
    eprintln!(
        "end past 90 degrees: worst value {:e}, gradient {:e}, FD gradient {:e}, FD Hessian {:e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

// ---------------------------------------------------------------------------
// 6. Element energy from the laminate description of docs/model.md section 3.

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
fn laminate_energy<M: Fields>(start: f64, len: f64, eps0: f64, k: &M::Coeffs) -> (Quad, Quad) {
    use paper::*;
    let n = self::len::<M>();
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

    let (mut psi_total, mut vol) = (Quad::zero(n), Quad::zero(n));
    for w in cuts.windows(2) {
        let (a, b) = (w[0] - start, w[1] - start);
        let mid = 0.5 * (w[0] + w[1]);
        let in_channel = mid < CX;
        let ribs = if in_channel { rib_width(mid) } else { 0.0 };
        let fl_mid_width = if in_channel { LY - CY + ribs } else { LY };
        let gas_width = if in_channel { CY - ribs } else { 0.0 };
        let piece = |z0: f64, z1: f64, width: f64, d: Density| {
            quad::<M>(
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

/// The paper's finger at prestrain `eps0`, N equal elements, ribs on, with model `M`.
fn paper_finger<M: ElementModel>(eps0: f64) -> Finger {
    let act = Actuator::paper(eps0).expect("paper actuator");
    let part = Partition::equal(act.geometry().lx, N).expect("partition");
    let f = Finger::with_model(model_id::<M>(), &act, &part, true);
    assert_eq!(f.model(), model_id::<M>());
    assert_eq!(f.unknowns_per_element(), len::<M>());
    f
}

/// A load whose runtime scalar is `kp` exactly (kappa = 1).
fn load_kp(kp: f64) -> Load {
    Load {
        pressure: kp,
        kappa: 1.0,
        fx: 0.0,
        fz: 0.0,
    }
}

/// One element's family alone (value, gradient, upper Hessian) through the finger.
fn element_family(f: &Finger, i: usize, kind: usize, k: &[f64]) -> (f64, Vec<f64>, Vec<f64>) {
    let pos = f.model().visit(FamilyPosition(KIND_NAMES[kind]));
    f.element_hessian(i, Some(pos), &Load::unloaded(), k)
        .expect("element and family in range")
}

/// The position of a family in a model's `FAMILIES`, for a run-time model.
struct FamilyPosition(&'static str);

impl fpc::model::ModelVisitor for FamilyPosition {
    type Output = usize;
    fn visit<M: ElementModel>(self) -> usize {
        M::FAMILIES
            .iter()
            .position(|f| *f == self.0)
            .unwrap_or_else(|| panic!("{} has no family {}", M::NAME, self.0))
    }
}

fn laminate_check<M: Fields>() {
    let mut rng = Rng::new(6);
    let n = len::<M>();
    let len = paper::LX / N as f64;
    #[derive(Default)]
    struct Worst {
        psi: f64,
        v: f64,
        pi: f64,
        g: f64,
        h: f64,
        variants: f64,
    }
    let mut worst = Worst::default();
    // Actuator::paper(0.25) is the default actuator; the other two are the
    // paper's other samples
    for eps0 in [0.25, 0.15, 0.4] {
        let finger = paper_finger::<M>(eps0);
        for (i, &l) in finger.element_lengths().iter().enumerate() {
            assert_eq!(l, len, "element {i}");
        }
        for case in 0..8 {
            // every element its own state (the straight finger first)
            let ks: Vec<M::Coeffs> = (0..N)
                .map(|_| {
                    if case == 0 {
                        M::Coeffs::zero()
                    } else {
                        rng.within(&M::typical_at(len))
                    }
                })
                .collect();
            // kappa P from 0 to 2.5 * 400 kPa
            let kp = if case % 2 == 0 {
                0.0
            } else {
                rng.range(0.0, 1.0)
            };
            let load = load_kp(kp);
            let flat: Vec<f64> = ks.iter().flat_map(|k| k.as_ref().to_vec()).collect();
            let coefficients = Coefficients::new(n, flat).expect("coefficients");
            let (mut sum_pi, mut sum_mag) = (0.0, 0.0);
            let mut grads = Vec::new();
            for (i, k) in ks.iter().enumerate() {
                let (psi, gas) = laminate_energy::<M>(i as f64 * len, len, eps0, k);
                let (psi_want, v_want) = (psi.v, gas.v);
                let mut pi_want = Quad::zero(n);
                pi_want.add(&psi);
                pi_want.add_scaled(-kp, &gas);
                let label = format!("{} eps0 {eps0} element {i} K={k:?} kp={kp}", M::NAME);
                let kr = k.as_ref();

                let psi_got =
                    element_family(&finger, i, 0, kr).0 + element_family(&finger, i, 1, kr).0;
                let rel = (psi_got - psi_want).abs() / psi_want.abs();
                worst.psi = worst.psi.max(rel);
                assert!(
                    rel <= 1e-11,
                    "{label}: Psi {psi_got} vs {psi_want} ({rel:e})"
                );

                let v_got = element_family(&finger, i, 2, kr).0;
                if v_want == 0.0 {
                    assert_eq!(v_got, 0.0, "{label}: element without channel");
                } else {
                    let rel = (v_got - v_want).abs() / v_want.abs();
                    worst.v = worst.v.max(rel);
                    assert!(rel <= 1e-11, "{label}: V {v_got} vs {v_want} ({rel:e})");
                }

                let (pi, g, hu) = finger
                    .element_hessian(i, None, &load, kr)
                    .expect("element in range");
                let rel = (pi - pi_want.v).abs() / pi_want.mag;
                worst.pi = worst.pi.max(rel);
                assert!(rel <= 1e-11, "{label}: Pi {pi} vs {} ({rel:e})", pi_want.v);
                sum_pi += pi;
                sum_mag += pi_want.mag;

                // gradient and Hessian, each entry against the integral of
                // its density's absolute terms
                let h = full(n, &hu);
                for r in 0..n {
                    let name = format!("{label}: gradient[{r}]");
                    let want = (pi_want.g[r], pi_want.gmag[r]);
                    against_magnitude(&name, g[r], want, 1e-11, &mut worst.g);
                    for (c, &hrc) in h[r].iter().enumerate() {
                        let name = format!("{label}: H[{r}][{c}]");
                        let want = (pi_want.h[r][c], pi_want.hmag[r][c]);
                        against_magnitude(&name, hrc, want, 1e-11, &mut worst.h);
                    }
                }
                grads.push((g, pi_want.gmag.clone(), label));
            }
            // the finger's value kernels (energy) and gradient kernels
            // (gradient) agree with the elements' Hessian kernels
            let label = format!("{} eps0 {eps0} case {case} kp={kp}", M::NAME);
            let total = finger.energy(&load, &coefficients).expect("valid");
            let err = (total - sum_pi).abs() / sum_mag;
            worst.variants = worst.variants.max(err);
            assert!(err <= 1e-14, "{label}: finger energy {total} vs {sum_pi}");
            let (total_g, g_all) = finger.gradient(&load, &coefficients).expect("valid");
            let err = (total_g - sum_pi).abs() / sum_mag;
            worst.variants = worst.variants.max(err);
            assert!(
                err <= 1e-14,
                "{label}: finger gradient's value {total_g} vs {sum_pi}"
            );
            for (i, (g, gmag, label)) in grads.iter().enumerate() {
                for r in 0..n {
                    let got = g_all[n * i + r];
                    let err = (got - g[r]).abs() / gmag[r].max(f64::MIN_POSITIVE);
                    worst.variants = worst.variants.max(err);
                    assert!(
                        (got - g[r]).abs() <= 1e-14 * gmag[r],
                        "{label}: finger gradient[{r}] {got:e} vs element {:e}",
                        g[r]
                    );
                }
            }
        }
    }
    eprintln!(
        "{} element vs laminate quadrature: worst relative Psi {:e}, V {:e}; of the term magnitude: Pi {:e}, gradient {:e}, Hessian {:e}; finger energy/gradient vs element kernels {:e}",
        M::NAME, worst.psi, worst.v, worst.pi, worst.g, worst.h, worst.variants
    );
}

#[test]
fn element_energy_matches_laminate_quadrature() {
    for_each_model!(laminate_check);
}

// ---------------------------------------------------------------------------
// 7. Physical sanity at K = 0.

fn unstressed<M: ElementModel>() {
    let n = len::<M>();
    let f = paper_finger::<M>(0.0);
    let straight = f.straight();
    // the whole finger: no energy, no force
    assert_eq!(f.energy(&Load::unloaded(), &straight).unwrap(), 0.0);
    let (v, g) = f.gradient(&Load::unloaded(), &straight).unwrap();
    assert_eq!(v, 0.0);
    assert!(g.iter().all(|&gi| gi == 0.0), "{g:?}");
    for i in 0..f.len() {
        let k = straight.element(i);
        let (v, g, hu) = f
            .element_hessian(i, None, &Load::unloaded(), k)
            .expect("element in range");
        let psi = element_family(&f, i, 0, k).0 + element_family(&f, i, 1, k).0;
        assert_eq!(psi, 0.0, "{} element {i}", M::NAME);
        assert_eq!(v, 0.0, "{} element {i}", M::NAME);
        assert!(
            g.iter().all(|&gi| gi == 0.0),
            "{} element {i}: {g:?}",
            M::NAME
        );
        // positive definite Hessian (Cholesky)
        let h = full(n, &hu);
        let mut l = vec![vec![0.0f64; n]; n];
        for i in 0..n {
            for j in 0..=i {
                let s: f64 = h[i][j] - (0..j).map(|m| l[i][m] * l[j][m]).sum::<f64>();
                if i == j {
                    assert!(
                        s > 0.0,
                        "{}: Hessian at rest not positive definite: {h:?}",
                        M::NAME
                    );
                    l[i][i] = s.sqrt();
                } else {
                    l[i][j] = s / l[j][j];
                }
            }
        }
    }
}

#[test]
fn unstressed_finger_has_zero_energy_and_gradient_and_is_stable() {
    for_each_model!(unstressed);
}

#[test]
fn ccm_prestrain_gradient_at_rest_matches_closed_form() {
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
        let f = paper_finger::<Ccm>(eps0);
        let straight = f.straight();
        // the gradient kernels (through the finger) and the Hessian kernels
        let (_, g_all) = f.gradient(&Load::unloaded(), &straight).unwrap();
        for i in 0..f.len() {
            let (_, gh, _) = f
                .element_hessian(i, None, &Load::unloaded(), straight.element(i))
                .unwrap();
            for (what, g) in [("gradient", &g_all[4 * i..4 * i + 4]), ("Hessian", &gh[..])] {
                // stretched prestressed layer: shortening (a1 < 0) and curling
                // towards -Z (c2 < 0) both lower the energy
                assert!(g[0] > 0.0 && g[3] > 0.0, "element {i}: {g:?}");
                for j in 0..4 {
                    let err = (g[j] - want[j]).abs() / want[0].abs().max(want[j].abs());
                    worst = worst.max(err);
                    assert!(
                        err <= 1e-13,
                        "eps0 {eps0} element {i} ({what} kernel): dPsi/dK[{j}] = {}, closed form {}",
                        g[j],
                        want[j]
                    );
                }
            }
        }
    }
    eprintln!("prestrain gradient at rest: worst relative error {worst:e}");
}

/// Gas volume of each element at rest, channel minus ribs (mm^3), and the
/// channel-minus-ribs area in (x, y) of each element (mm^2).
fn gas_at_rest_by_hand() -> Vec<(f64, f64)> {
    use paper::*;
    let len = LX / N as f64;
    let height = H3A + H3B;
    (0..N)
        .map(|i| {
            let (s, e) = (i as f64 * len, (i + 1) as f64 * len);
            let overlap = |a: f64, b: f64| (b.min(e) - a.max(s)).max(0.0);
            let mut area = CY * overlap(0.0, CX) - T * overlap(0.0, CX);
            let mut k = 1.0;
            while k * W1 + T / 2.0 <= CX {
                area -= 2.0 * W2 * overlap(k * W1 - T / 2.0, k * W1 + T / 2.0);
                k += 1.0;
            }
            (area * height, area)
        })
        .collect()
}

fn gas_volume_at_rest<M: ElementModel>() {
    use paper::*;
    let height = H3A + H3B;
    let f = paper_finger::<M>(0.25);
    let zero = M::Coeffs::zero();
    let mut total = 0.0;
    let mut worst = 0.0f64;
    for (i, (want, _)) in gas_at_rest_by_hand().into_iter().enumerate() {
        let got = element_family(&f, i, 2, zero.as_ref()).0;
        let err = (got - want).abs() / want.abs().max(1.0);
        worst = worst.max(err);
        assert!(
            err <= 1e-13,
            "{} element {i}: V = {got}, channel minus ribs {want}",
            M::NAME
        );
        total += got;
    }
    // 2 mm x (26 x 105 - 2 x 105 - 13 x 12 x 2) mm^2
    let all = height * (CY * CX - T * CX - 13.0 * 2.0 * W2 * T);
    assert!(
        (total - all).abs() <= 1e-12 * all,
        "{}: total {total} vs {all}",
        M::NAME
    );
    eprintln!(
        "{} gas volume at rest: worst relative error {worst:e}, total {total} mm^3",
        M::NAME
    );
}

#[test]
fn gas_volume_at_rest_is_channel_minus_ribs() {
    for_each_model!(gas_volume_at_rest);
}

#[test]
fn ccm_gas_volume_gradient_at_rest_matches_closed_form() {
    use paper::*;
    let f = paper_finger::<Ccm>(0.25);
    for (i, (want, area)) in gas_at_rest_by_hand().into_iter().enumerate() {
        // pressure flattens: dV/dc2 = (gas width * length) (z0^2 - z1^2) > 0
        // over z in [-h3b, h3a], and dV/da1 = V at rest
        let (_, g, _) = element_family(&f, i, 2, &[0.0; 4]);
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
}
