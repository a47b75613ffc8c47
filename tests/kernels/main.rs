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
use fpc::model::shear::Shear;
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
        $check::<Shear>($($arg),*);
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
    /// The transverse shear strain gamma_xz at local `x` and its gradient
    /// (linear in the unknowns); zero for the models without shear.
    fn gamma_xz(_k: &Self::Coeffs, _x: f64) -> (f64, Self::Coeffs) {
        (0.0, Self::Coeffs::zero())
    }
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

/// The shear-deformable element: the paper's u, v, the section rotation
/// th = 2 c2 x and the mid-plane w = c2 x^2 + g0 x, so
/// eps_x = u' + w'^2 / 2 - z th' = a1 + 3 a3 x^2 + (2 c2 x + g0)^2 / 2 - 2 z c2,
/// eps_y = b1, gamma_xz = w' - th = g0 (unknowns a1, a3, b1, c2, g0).
impl Fields for Shear {
    fn typical() -> [f64; 5] {
        [0.05, 2e-5, 0.05, 0.03, 0.02]
    }

    fn typical_at(l: f64) -> [f64; 5] {
        [0.05, 0.05 / (l * l), 0.05, 0.03 * 13.75 / l, 0.02]
    }

    fn eps_x(k: &[f64; 5], x: f64, z: f64) -> (f64, [f64; 5]) {
        let [a1, a3, _, c2, g0] = *k;
        let slope = 2.0 * c2 * x + g0;
        (
            a1 + 3.0 * a3 * x * x + 0.5 * slope * slope - 2.0 * z * c2,
            [1.0, 3.0 * x * x, 0.0, 2.0 * x * slope - 2.0 * z, slope],
        )
    }

    fn eps_x_gradient_magnitude(k: &[f64; 5], x: f64, z: f64) -> [f64; 5] {
        let slope = 2.0 * k[3].abs() * x.abs() + k[4].abs();
        [
            1.0,
            3.0 * x * x,
            0.0,
            2.0 * x.abs() * slope + 2.0 * z.abs(),
            slope,
        ]
    }

    fn eps_x_hessian(_: &[f64; 5], x: f64, _: f64, i: usize, j: usize) -> (f64, f64) {
        // slope^2 / 2 with slope = 2 c2 x + g0
        let v = match (i, j) {
            (3, 3) => 4.0 * x * x,
            (3, 4) | (4, 3) => 2.0 * x,
            (4, 4) => 1.0,
            _ => 0.0,
        };
        (v, v.abs())
    }

    fn eps_y(k: &[f64; 5], _: f64, _: f64) -> (f64, [f64; 5], [f64; 5]) {
        (k[2], [0.0, 0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0, 0.0])
    }

    fn eps_y_hessian(_: &[f64; 5], _: f64, _: f64, _: usize, _: usize) -> (f64, f64) {
        (0.0, 0.0)
    }

    fn shape(k: &[f64; 5], x: f64) -> [[f64; 3]; 2] {
        let [a1, a3, _, c2, g0] = *k;
        [
            [
                x + a1 * x + a3 * x.powi(3),
                1.0 + a1 + 3.0 * a3 * x * x,
                6.0 * a3 * x,
            ],
            [c2 * x * x + g0 * x, 2.0 * c2 * x + g0, 2.0 * c2],
        ]
    }

    fn shape_gradients(_: &[f64; 5], x: f64) -> [[f64; 5]; 4] {
        [
            [x, x.powi(3), 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, x * x, x],
            [1.0, 3.0 * x * x, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 2.0 * x, 1.0],
        ]
    }

    fn gamma_xz(k: &[f64; 5], _: f64) -> (f64, [f64; 5]) {
        (k[4], [0.0, 0.0, 0.0, 0.0, 1.0])
    }
}

// ---------------------------------------------------------------------------
// The energy densities of docs/model.md section 4 (the same for every
// model: the families' laws in the strains).

/// An energy (or volume) density W(eps_x, eps_y) with its derivatives.
#[derive(Debug, Clone, Copy)]
enum Density {
    /// With the transverse shear energy ks g13 gamma^2 / 2.
    Linear {
        q11: f64,
        q12: f64,
        q22: f64,
        g13: f64,
        ks: f64,
    },
    Prestressed {
        eps0: f64,
        p: [f64; 4],
        q22: f64,
        g13: f64,
        ks: f64,
    },
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
    /// ks g13 of the transverse shear energy ks g13 gamma^2 / 2, which
    /// adds to the density in the strains eps_x, eps_y (0 for the gas).
    fn shear_stiffness(&self) -> f64 {
        match *self {
            Density::Linear { g13, ks, .. } | Density::Prestressed { g13, ks, .. } => ks * g13,
            Density::Gas => 0.0,
        }
    }

    fn jet(&self, e: f64, y: f64) -> Jet {
        match *self {
            Density::Linear { q11, q12, q22, .. } => Jet {
                f: 0.5 * q11 * e * e + q12 * e * y + 0.5 * q22 * y * y,
                fe: q11 * e + q12 * y,
                fy: q12 * e + q22 * y,
                fee: q11,
                fey: q12,
                fyy: q22,
            },
            Density::Prestressed { eps0, p, q22, .. } => {
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
            Density::Linear { q11, q12, q22, .. } => {
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
            Density::Prestressed { eps0, p, q22, .. } => {
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
            let (gamma, dg) = M::gamma_xz(k, x);
            let gs = d.shear_stiffness();
            let j = d.jet(e, ey);
            let jm = d.magnitude_jet(e, ey);
            q.v += w * (j.f + 0.5 * gs * gamma * gamma);
            q.mag += w.abs() * (jm.f + 0.5 * gs.abs() * gamma * gamma);
            for i in 0..n {
                q.g[i] += w * (j.fe * de[i] + j.fy * dy[i] + gs * gamma * dg[i]);
                q.gmag[i] +=
                    w.abs() * (jm.fe * dem[i] + jm.fy * dym[i] + gs.abs() * (gamma * dg[i]).abs());
                for l in 0..n {
                    let (hx, hxm) = M::eps_x_hessian(k, x, z, i, l);
                    let (hy, hym) = M::eps_y_hessian(k, x, z, i, l);
                    let hil = j.fee * de[i] * de[l]
                        + j.fey * (de[i] * dy[l] + dy[i] * de[l])
                        + j.fyy * dy[i] * dy[l]
                        + j.fe * hx
                        + j.fy * hy
                        + gs * dg[i] * dg[l];
                    let mil = jm.fee * dem[i] * dem[l]
                        + jm.fey * (dem[i] * dym[l] + dym[i] * dem[l])
                        + jm.fyy * dym[i] * dym[l]
                        + jm.fe * hxm
                        + jm.fy * hym
                        + gs.abs() * (dg[i] * dg[l]).abs();
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
        Density::Linear {
            q11,
            q12,
            q22,
            g13,
            ks,
        } => M::add_linear(
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
                g13,
                ks,
            },
        ),
        Density::Prestressed {
            eps0,
            p,
            q22,
            g13,
            ks,
        } => M::add_prestressed(
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
                g13,
                ks,
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
            Density::Linear {
                q11,
                q12,
                q22,
                g13: rng.range(0.2, 150.0),
                ks: rng.range(0.5, 1.2),
            }
        }
        1 => {
            let p = random_law(rng);
            Density::Prestressed {
                eps0: rng.range(0.0, 0.6),
                p,
                q22: rng.range(1.0, 400.0),
                g13: rng.range(0.2, 150.0),
                ks: rng.range(0.5, 1.2),
            }
        }
        _ => Density::Gas,
    }
}

mod derivatives;
mod ends;
mod energy;
mod moments;
mod points;
mod psi;
mod sanity;

// the finite differences of section 2, shared by the later sections
use derivatives::{fd, fd1, fd_vec, FD_STEP};
