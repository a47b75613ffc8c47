//! Property tests for `fpc-symbolic`.
//!
//! Every result of the library is checked against an independent method
//! written here, never against another path through the library:
//!
//! - random expression trees ([`T`]) are rendered as text for the parser and
//!   evaluated by this file's own evaluator, in `f64` and in hyper-dual
//!   numbers ([`Hd`], exact first and second derivatives by forward mode);
//! - derivatives are also checked by Richardson-extrapolated central
//!   differences of that evaluator;
//! - integrals by composite Gauss-Legendre quadrature whose nodes are
//!   computed here by Newton's method on Legendre polynomials;
//! - emitted Rust by a small interpreter for the straight-line subset the
//!   emitter produces (parsed with `syn`), which also counts the operations
//!   actually written in the code.
//!
//! All property runs are seeded (`RngSeed::Fixed`) and write no persistence
//! files; case counts are kept small so the file runs in seconds in debug.

use std::collections::HashSet;
use std::ops::{Add, Div, Mul, Neg, Sub};

use fpc_symbolic::codegen::{format_file, generate, GenError};
use fpc_symbolic::emit::{tree_ops, Emitter};
use fpc_symbolic::spec::parse_spec;
use fpc_symbolic::{Arena, Expr, ExprId, Node, Poly, Rational, Sym};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};
use quote::quote;

// ---------------------------------------------------------------------------
// configuration

fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(0x5eed_f00d_2024),
        max_shrink_iters: 2048,
        ..Config::default()
    }
}

// ---------------------------------------------------------------------------
// numbers: f64 and hyper-dual numbers v + a e1 + b e2 + ab e1 e2 (e1^2 = e2^2 = 0)

trait Num:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    fn c(v: f64) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn sqrt(self) -> Self;
    /// `atan2(self, x)`
    fn atan2(self, x: Self) -> Self;
}

impl Num for f64 {
    fn c(v: f64) -> f64 {
        v
    }
    fn sin(self) -> f64 {
        f64::sin(self)
    }
    fn cos(self) -> f64 {
        f64::cos(self)
    }
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
    fn atan2(self, x: f64) -> f64 {
        f64::atan2(self, x)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Hd {
    v: f64,
    a: f64,
    b: f64,
    ab: f64,
}

impl Hd {
    fn var(v: f64, a: f64, b: f64) -> Hd {
        Hd { v, a, b, ab: 0.0 }
    }
    /// `f(self)` given `f`, `f'` and `f''` at `self.v`.
    fn chain(self, f: f64, f1: f64, f2: f64) -> Hd {
        Hd {
            v: f,
            a: f1 * self.a,
            b: f1 * self.b,
            ab: f1 * self.ab + f2 * self.a * self.b,
        }
    }
}

impl Add for Hd {
    type Output = Hd;
    fn add(self, o: Hd) -> Hd {
        Hd {
            v: self.v + o.v,
            a: self.a + o.a,
            b: self.b + o.b,
            ab: self.ab + o.ab,
        }
    }
}

impl Sub for Hd {
    type Output = Hd;
    fn sub(self, o: Hd) -> Hd {
        self + (-o)
    }
}

impl Neg for Hd {
    type Output = Hd;
    fn neg(self) -> Hd {
        Hd {
            v: -self.v,
            a: -self.a,
            b: -self.b,
            ab: -self.ab,
        }
    }
}

impl Mul for Hd {
    type Output = Hd;
    fn mul(self, o: Hd) -> Hd {
        Hd {
            v: self.v * o.v,
            a: self.v * o.a + self.a * o.v,
            b: self.v * o.b + self.b * o.v,
            ab: self.v * o.ab + self.a * o.b + self.b * o.a + self.ab * o.v,
        }
    }
}

impl Div for Hd {
    type Output = Hd;
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: Hd) -> Hd {
        let v = o.v;
        self * o.chain(1.0 / v, -1.0 / (v * v), 2.0 / (v * v * v))
    }
}

impl Num for Hd {
    fn c(v: f64) -> Hd {
        Hd::var(v, 0.0, 0.0)
    }
    fn sin(self) -> Hd {
        let (s, c) = self.v.sin_cos();
        self.chain(s, c, -s)
    }
    fn cos(self) -> Hd {
        let (s, c) = self.v.sin_cos();
        self.chain(c, -s, -c)
    }
    fn sqrt(self) -> Hd {
        let r = self.v.sqrt();
        self.chain(r, 0.5 / r, -0.25 / (r * self.v))
    }
    fn atan2(self, x: Hd) -> Hd {
        let y = self;
        let r2 = x.v * x.v + y.v * y.v;
        let r4 = r2 * r2;
        let (fy, fx) = (x.v / r2, -y.v / r2);
        let fyy = -2.0 * x.v * y.v / r4;
        let fxx = 2.0 * x.v * y.v / r4;
        let fxy = (y.v * y.v - x.v * x.v) / r4;
        Hd {
            v: y.v.atan2(x.v),
            a: fy * y.a + fx * x.a,
            b: fy * y.b + fx * x.b,
            ab: fy * y.ab
                + fx * x.ab
                + fyy * y.a * y.b
                + fxx * x.a * x.b
                + fxy * (y.a * x.b + x.a * y.b),
        }
    }
}

// ---------------------------------------------------------------------------
// the test's own expression trees

/// Symbol names; a tree's `Var(i)` is `NAMES[i]`.
const NAMES: [&str; 5] = ["x", "y", "z", "a", "b"];

#[derive(Debug, Clone)]
enum T {
    /// p/q with q > 0
    Num(i64, i64),
    Var(usize),
    Add(Box<T>, Box<T>),
    Sub(Box<T>, Box<T>),
    Mul(Box<T>, Box<T>),
    Neg(Box<T>),
    Pow(Box<T>, u32),
    Sin(Box<T>),
    Cos(Box<T>),
    /// sqrt(1 + a^2)
    SqrtPos(Box<T>),
    /// a / (1 + b^2)
    DivPos(Box<T>, Box<T>),
    /// atan2(1 + a^2, b): away from the branch cut and the origin
    Atan2Up(Box<T>, Box<T>),
    /// atan2(a, 1 + b^2)
    Atan2Right(Box<T>, Box<T>),
}

fn bx(t: T) -> Box<T> {
    Box::new(t)
}

impl T {
    /// Fully parenthesised text form.
    fn text(&self) -> String {
        match self {
            T::Num(p, 1) if *p < 0 => format!("({p})"),
            T::Num(p, 1) => format!("{p}"),
            T::Num(p, q) => format!("({p}/{q})"),
            T::Var(i) => NAMES[*i].to_string(),
            T::Add(a, b) => format!("({} + {})", a.text(), b.text()),
            T::Sub(a, b) => format!("({} - {})", a.text(), b.text()),
            T::Mul(a, b) => format!("({}*{})", a.text(), b.text()),
            T::Neg(a) => format!("(-{})", a.text()),
            T::Pow(a, k) => format!("({})^{k}", a.text()),
            T::Sin(a) => format!("sin({})", a.text()),
            T::Cos(a) => format!("cos({})", a.text()),
            T::SqrtPos(a) => format!("sqrt(1 + ({})^2)", a.text()),
            T::DivPos(a, b) => format!("({}/(1 + ({})^2))", a.text(), b.text()),
            T::Atan2Up(a, b) => format!("atan2(1 + ({})^2, {})", a.text(), b.text()),
            T::Atan2Right(a, b) => format!("atan2({}, 1 + ({})^2)", a.text(), b.text()),
        }
    }

    fn eval<N: Num>(&self, v: &[N]) -> N {
        let one = N::c(1.0);
        match self {
            T::Num(p, q) => N::c(*p as f64 / *q as f64),
            T::Var(i) => v[*i],
            T::Add(a, b) => a.eval(v) + b.eval(v),
            T::Sub(a, b) => a.eval(v) - b.eval(v),
            T::Mul(a, b) => a.eval(v) * b.eval(v),
            T::Neg(a) => -a.eval(v),
            T::Pow(a, k) => {
                let b = a.eval(v);
                (0..*k).fold(one, |acc, _| acc * b)
            }
            T::Sin(a) => a.eval(v).sin(),
            T::Cos(a) => a.eval(v).cos(),
            T::SqrtPos(a) => {
                let x = a.eval(v);
                (one + x * x).sqrt()
            }
            T::DivPos(a, b) => {
                let d = b.eval(v);
                a.eval(v) / (one + d * d)
            }
            T::Atan2Up(a, b) => {
                let y = a.eval(v);
                (one + y * y).atan2(b.eval(v))
            }
            T::Atan2Right(a, b) => {
                let x = b.eval(v);
                a.eval(v).atan2(one + x * x)
            }
        }
    }

    /// An upper bound of |value| (and of the sum of the absolute values of
    /// the terms any expansion of the tree can produce) at the point.
    fn bound(&self, v: &[f64]) -> f64 {
        match self {
            T::Num(p, q) => (*p as f64 / *q as f64).abs(),
            T::Var(i) => v[*i].abs(),
            T::Add(a, b) | T::Sub(a, b) => a.bound(v) + b.bound(v),
            T::Mul(a, b) => a.bound(v) * b.bound(v),
            T::Neg(a) => a.bound(v),
            T::Pow(a, k) => a.bound(v).powi(*k as i32),
            T::Sin(_) | T::Cos(_) => 1.0,
            T::SqrtPos(a) => 1.0 + a.bound(v),
            T::DivPos(a, b) => a.bound(v) * (1.0 + b.bound(v).powi(2)),
            T::Atan2Up(..) | T::Atan2Right(..) => std::f64::consts::PI,
        }
    }

    /// log2 of a bound on the numerators and denominators of the exact
    /// numbers folding or expanding the tree can make (constants count as
    /// max(|p|, q), variables as 2 to cover multinomial coefficients).
    fn size_bits(&self) -> f64 {
        fn size(t: &T) -> f64 {
            match t {
                T::Num(p, q) => p.unsigned_abs().max(q.unsigned_abs()).max(1) as f64,
                T::Var(_) => 2.0,
                T::Add(a, b) | T::Sub(a, b) => size(a) + size(b),
                T::Mul(a, b) => size(a) * size(b),
                T::Neg(a) | T::Sin(a) | T::Cos(a) => size(a),
                T::Pow(a, k) => size(a).powi(*k as i32),
                T::SqrtPos(a) => 1.0 + size(a).powi(2),
                T::DivPos(a, b) | T::Atan2Up(a, b) | T::Atan2Right(a, b) => {
                    size(a).max(1.0 + size(b).powi(2)) * (1.0 + size(b).powi(2))
                }
            }
        }
        size(self).log2()
    }

    /// The largest bound of an argument of a function node (or of a divisor).
    fn max_arg(&self, v: &[f64]) -> f64 {
        match self {
            T::Num(..) | T::Var(_) => 0.0,
            T::Add(a, b) | T::Sub(a, b) | T::Mul(a, b) => a.max_arg(v).max(b.max_arg(v)),
            T::Neg(a) | T::Pow(a, _) => a.max_arg(v),
            T::Sin(a) | T::Cos(a) | T::SqrtPos(a) => a.bound(v).max(a.max_arg(v)),
            T::DivPos(a, b) => a.max_arg(v).max(b.bound(v)).max(b.max_arg(v)),
            T::Atan2Up(a, b) | T::Atan2Right(a, b) => a
                .bound(v)
                .max(b.bound(v))
                .max(a.max_arg(v))
                .max(b.max_arg(v)),
        }
    }

    /// Polynomial degree; for function nodes a growth measure of the same kind.
    fn degree(&self) -> u32 {
        match self {
            T::Num(..) => 0,
            T::Var(_) => 1,
            T::Add(a, b) | T::Sub(a, b) => a.degree().max(b.degree()),
            T::Mul(a, b) => a.degree() + b.degree(),
            T::Neg(a) => a.degree(),
            T::Pow(a, k) => a.degree() * k,
            T::Sin(a) | T::Cos(a) => 2 * a.degree(),
            T::SqrtPos(a) => 2 * a.degree(),
            T::DivPos(a, b) | T::Atan2Up(a, b) | T::Atan2Right(a, b) => a.degree() + 2 * b.degree(),
        }
    }

    /// The same tree built through the arena's constructors (mirroring what
    /// the parser does for the text form).
    fn build(&self, a: &mut Arena) -> ExprId {
        use fpc_symbolic::Func;
        let one_plus_sq = |a: &mut Arena, t: &T| {
            let e = t.build(a);
            let sq = a.pow(e, 2).unwrap();
            let one = a.int(1);
            a.add2(one, sq).unwrap()
        };
        match self {
            T::Num(p, q) => a.num(Rational::new(*p as i128, *q as i128).unwrap()),
            T::Var(i) => a.var(NAMES[*i]),
            T::Add(l, r) => {
                let (l, r) = (l.build(a), r.build(a));
                a.add2(l, r).unwrap()
            }
            T::Sub(l, r) => {
                let (l, r) = (l.build(a), r.build(a));
                a.sub(l, r).unwrap()
            }
            T::Mul(l, r) => {
                let (l, r) = (l.build(a), r.build(a));
                a.mul2(l, r).unwrap()
            }
            T::Neg(l) => {
                let l = l.build(a);
                a.neg(l).unwrap()
            }
            T::Pow(l, k) => {
                let l = l.build(a);
                a.pow(l, *k as i32).unwrap()
            }
            T::Sin(l) => {
                let l = l.build(a);
                a.func(Func::Sin, &[l]).unwrap()
            }
            T::Cos(l) => {
                let l = l.build(a);
                a.func(Func::Cos, &[l]).unwrap()
            }
            T::SqrtPos(l) => {
                let s = one_plus_sq(a, l);
                a.func(Func::Sqrt, &[s]).unwrap()
            }
            T::DivPos(l, r) => {
                let l = l.build(a);
                let d = one_plus_sq(a, r);
                a.div(l, d).unwrap()
            }
            T::Atan2Up(l, r) => {
                let y = one_plus_sq(a, l);
                let x = r.build(a);
                a.func(Func::Atan2, &[y, x]).unwrap()
            }
            T::Atan2Right(l, r) => {
                let y = l.build(a);
                let x = one_plus_sq(a, r);
                a.func(Func::Atan2, &[y, x]).unwrap()
            }
        }
    }

    /// The tree with `Var(i)` replaced by `by`.
    fn subst(&self, i: usize, by: &T) -> T {
        let s = |t: &T| bx(t.subst(i, by));
        match self {
            T::Var(j) if *j == i => by.clone(),
            T::Num(..) | T::Var(_) => self.clone(),
            T::Add(a, b) => T::Add(s(a), s(b)),
            T::Sub(a, b) => T::Sub(s(a), s(b)),
            T::Mul(a, b) => T::Mul(s(a), s(b)),
            T::Neg(a) => T::Neg(s(a)),
            T::Pow(a, k) => T::Pow(s(a), *k),
            T::Sin(a) => T::Sin(s(a)),
            T::Cos(a) => T::Cos(s(a)),
            T::SqrtPos(a) => T::SqrtPos(s(a)),
            T::DivPos(a, b) => T::DivPos(s(a), s(b)),
            T::Atan2Up(a, b) => T::Atan2Up(s(a), s(b)),
            T::Atan2Right(a, b) => T::Atan2Right(s(a), s(b)),
        }
    }
}

// ---------------------------------------------------------------------------
// strategies

fn leaf(vars: &'static [usize]) -> BoxedStrategy<T> {
    prop_oneof![
        3 => prop::sample::select(vars).prop_map(T::Var),
        2 => (-6i64..=6, 1i64..=4).prop_map(|(p, q)| T::Num(p, q)),
    ]
    .boxed()
}

/// Polynomial trees (+, -, *, unary -, ^0..=4) of bounded degree.
fn poly_tree(vars: &'static [usize], depth: u32, max_degree: u32) -> BoxedStrategy<T> {
    poly_over(leaf(vars), depth, max_degree)
}

fn poly_over(leaves: BoxedStrategy<T>, depth: u32, max_degree: u32) -> BoxedStrategy<T> {
    leaves
        .prop_recursive(depth, 24, 2, |inner| {
            prop_oneof![
                3 => (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Add(bx(a), bx(b))),
                2 => (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Sub(bx(a), bx(b))),
                3 => (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Mul(bx(a), bx(b))),
                1 => inner.clone().prop_map(|a| T::Neg(bx(a))),
                2 => (inner, 0u32..=4).prop_map(|(a, k)| T::Pow(bx(a), k)),
            ]
        })
        .prop_filter("degree bound", move |t| t.degree() <= max_degree)
        .prop_filter("exact numbers fit", |t| t.size_bits() <= 40.0)
        .boxed()
}

/// Trees with sin, cos, sqrt of positive arguments, atan2 away from its
/// singularities and division by expressions at least 1 in magnitude.
fn fun_tree(vars: &'static [usize]) -> BoxedStrategy<T> {
    leaf(vars)
        .prop_recursive(4, 20, 2, |inner| {
            prop_oneof![
                3 => (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Add(bx(a), bx(b))),
                1 => (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Sub(bx(a), bx(b))),
                3 => (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Mul(bx(a), bx(b))),
                1 => inner.clone().prop_map(|a| T::Neg(bx(a))),
                1 => (inner.clone(), 0u32..=3).prop_map(|(a, k)| T::Pow(bx(a), k)),
                1 => inner.clone().prop_map(|a| T::Sin(bx(a))),
                1 => inner.clone().prop_map(|a| T::Cos(bx(a))),
                1 => inner.clone().prop_map(|a| T::SqrtPos(bx(a))),
                1 => (inner.clone(), inner.clone()).prop_map(|(a, b)| T::DivPos(bx(a), bx(b))),
                1 => (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Atan2Up(bx(a), bx(b))),
                1 => (inner.clone(), inner).prop_map(|(a, b)| T::Atan2Right(bx(a), bx(b))),
            ]
        })
        .prop_filter("growth bound", |t| {
            t.degree() <= 8
                && t.bound(&[1.5; 5]) <= 1e3
                && t.max_arg(&[1.5; 5]) <= 10.0
                && t.size_bits() <= 40.0
        })
        .boxed()
}

const XYZ: &[usize] = &[0, 1, 2];
const YZ: &[usize] = &[1, 2];
const AB: &[usize] = &[3, 4];
const XYZAB: &[usize] = &[0, 1, 2, 3, 4];

fn point() -> impl Strategy<Value = [f64; 5]> {
    prop::array::uniform5(-1.5f64..1.5)
}

// ---------------------------------------------------------------------------
// helpers

/// The value of a symbol of arena `a` at `pt` (by name).
fn value_of(a: &Arena, s: Sym, pt: &[f64]) -> Option<f64> {
    NAMES.iter().position(|n| *n == a.name(s)).map(|i| pt[i])
}

fn eval_at(a: &Arena, e: ExprId, pt: &[f64]) -> f64 {
    a.eval(e, &|s| value_of(a, s, pt)).unwrap()
}

fn poly_at(a: &Arena, p: &Poly, pt: &[f64]) -> f64 {
    p.eval(&|s| value_of(a, s, pt).unwrap())
}

fn abs_point(pt: &[f64]) -> Vec<f64> {
    pt.iter().map(|v| v.abs()).collect()
}

fn check_close(what: &str, got: f64, want: f64, tol: f64) -> Result<(), TestCaseError> {
    prop_assert!(
        got.is_finite() && (got - want).abs() <= tol,
        "{what}: got {got:e}, want {want:e}, |diff| {:e} > tol {tol:e}",
        (got - want).abs()
    );
    Ok(())
}

/// Gauss-Legendre nodes and weights on [-1, 1] by Newton's method on P_n.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    // P_n(x) and P_n'(x) by the three-term recurrence
    let legendre = |x: f64| {
        let (mut p0, mut p1) = (1.0, x);
        for k in 1..n {
            let k = k as f64;
            let p2 = ((2.0 * k + 1.0) * x * p1 - k * p0) / (k + 1.0);
            p0 = p1;
            p1 = p2;
        }
        let dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
        (p1, dp)
    };
    (1..=n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre(x);
                let dx = p / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, dp) = legendre(x);
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Composite Gauss-Legendre quadrature of `f` over [lo, hi] (signed).
fn quad<N: Num>(rule: &[(f64, f64)], panels: usize, lo: f64, hi: f64, f: impl Fn(f64) -> N) -> N {
    let h = (hi - lo) / panels as f64;
    let mut acc = N::c(0.0);
    for p in 0..panels {
        let mid = lo + (p as f64 + 0.5) * h;
        for &(x, w) in rule {
            acc = acc + N::c(w * h / 2.0) * f(mid + x * h / 2.0);
        }
    }
    acc
}

#[test]
fn gauss_legendre_rule_is_exact_to_degree_2n_minus_1() {
    for n in [4, 8, 10] {
        let rule = gauss_legendre(n);
        let wsum: f64 = rule.iter().map(|r| r.1).sum();
        assert!((wsum - 2.0).abs() < 1e-14);
        for k in 0..2 * n as i32 {
            let got = quad(&rule, 1, -1.0, 1.0, |x| x.powi(k));
            let want = if k % 2 == 1 {
                0.0
            } else {
                2.0 / (k as f64 + 1.0)
            };
            assert!((got - want).abs() < 1e-13, "n {n} k {k}: {got} vs {want}");
        }
    }
}

#[test]
fn hyper_dual_numbers_agree_with_known_derivatives() {
    // d/dx and d2/dx2 of sin(x) * sqrt(1 + x^2) / (1 + x^2) + atan2(x, 2)
    let f = |x: Hd| {
        let one = Hd::c(1.0);
        x.sin() * (one + x * x).sqrt() / (one + x * x) + x.atan2(Hd::c(2.0))
    };
    let x0: f64 = 0.7;
    let r = f(Hd::var(x0, 1.0, 1.0));
    let g = |x: f64| x.sin() / (1.0 + x * x).sqrt() + x.atan2(2.0);
    let h = 1e-4;
    let d1 = (g(x0 + h) - g(x0 - h)) / (2.0 * h);
    let d2 = (g(x0 + h) - 2.0 * g(x0) + g(x0 - h)) / (h * h);
    assert!((r.v - g(x0)).abs() < 1e-15);
    assert!((r.a - d1).abs() < 1e-7, "{} {d1}", r.a);
    assert!((r.ab - d2).abs() < 1e-5, "{} {d2}", r.ab);
}

// ---------------------------------------------------------------------------
// 1. expansion, Horner form, text round trip

fn check_polynomial_forms(t: &T, pt: &[f64; 5], last_mask: u8) -> Result<(), TestCaseError> {
    let want = t.eval::<f64>(pt);
    let tol = 1e-9 * t.bound(&abs_point(pt)) + 1e-300;
    let mut a = Arena::new();
    let text = t.text();
    let e = a.parse(&text).unwrap();
    check_close("canonical DAG", eval_at(&a, e, pt), want, tol)?;

    let p = a.expand(e).unwrap();
    check_close("expand", poly_at(&a, &p, pt), want, tol)?;
    let last: Vec<Sym> = (0..3)
        .filter(|i| last_mask & (1 << i) != 0)
        .filter_map(|i| a.find_symbol(NAMES[i]))
        .collect();
    let h = a.horner(&p, &last).unwrap();
    check_close("horner", eval_at(&a, h, pt), want, tol)?;
    let back = a.from_poly(&p).unwrap();
    check_close("from_poly", eval_at(&a, back, pt), want, tol)?;

    // text round trips, in the same arena: the same node (parsing may
    // intern the literals of the text, but a second parse adds nothing)
    for id in [e, h, back] {
        let shown = a.show(id).to_string();
        let again = a.parse(&shown).unwrap();
        prop_assert_eq!(again, id, "`{}` shown as `{}`", text, shown);
        let n = a.len();
        prop_assert_eq!(a.parse(&shown).unwrap(), id);
        prop_assert_eq!(a.len(), n);
    }

    // the owned Expr wrapper
    let named: Vec<(&str, f64)> = NAMES.iter().copied().zip(pt.iter().copied()).collect();
    let ex: Expr = text.parse().unwrap();
    check_close("Expr::eval", ex.eval(&named).unwrap(), want, tol)?;
    // (the text orders terms by creation in its own arena, so compare values)
    let ex2: Expr = ex.to_string().parse().unwrap();
    check_close("Expr text round trip", ex2.eval(&named).unwrap(), want, tol)?;
    check_close(
        "Expr::expand",
        ex.expand().unwrap().eval(&named).unwrap(),
        want,
        tol,
    )?;
    Ok(())
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn expand_and_horner_match_direct_evaluation(
        t in poly_tree(XYZ, 4, 8),
        pt in point(),
        last_mask in 0u8..8,
    ) {
        check_polynomial_forms(&t, &pt, last_mask)?;
    }

    #[test]
    fn api_construction_parse_and_text_agree(t in fun_tree(XYZ), pt in point()) {
        // building through the constructors twice, and parsing the text,
        // all give the same node without growing the arena
        let mut a = Arena::new();
        let e1 = t.build(&mut a);
        let n = a.len();
        let e2 = t.build(&mut a);
        prop_assert_eq!(e1, e2);
        prop_assert_eq!(a.len(), n);
        // the parser builds the same node (interning at most the literals
        // of the text on the way)
        let e3 = a.parse(&t.text()).unwrap();
        prop_assert_eq!(e1, e3);
        let n = a.len();
        prop_assert_eq!(a.parse(&t.text()).unwrap(), e1);
        prop_assert_eq!(t.build(&mut a), e1);
        prop_assert_eq!(a.len(), n);
        let shown = a.show(e1).to_string();
        let e4 = a.parse(&shown).unwrap();
        prop_assert_eq!(e4, e1, "shown as `{}`", shown);
        let want = t.eval::<f64>(&pt);
        let tol = 1e-9 * (1.0 + t.bound(&abs_point(&pt)));
        check_close("eval", eval_at(&a, e1, &pt), want, tol)?;
    }
}

/// A regression case for the flattening of sums: when like terms of a
/// multiple of a sum add up to coefficient 1, the sum must be flattened into
/// the surrounding sum (else `x + y + z` has two forms and does not cancel).
#[test]
fn sums_stay_flat_when_a_multiple_of_a_sum_collapses() {
    let mut a = Arena::new();
    let e = a.parse("(2*(x + y) + z) - (x + y)").unwrap();
    let flat = a.parse("x + y + z").unwrap();
    assert_eq!(e, flat, "{}", a.show(e));
    let z = a.parse("(2*(x + y) + z) - (x + y) - x - y").unwrap();
    assert_eq!(a.show(z).to_string(), "z");
    // through the n-ary constructor too
    let s = a.parse("x + y").unwrap();
    let two = a.int(2);
    let two_s = a.mul2(two, s).unwrap();
    let minus_s = a.neg(s).unwrap();
    let zz = a.var("z");
    let sum = a.add(&[two_s, zz, minus_s]).unwrap();
    assert_eq!(sum, flat);
    for id in [e, sum] {
        if let Node::Add(ts) = a.node(id) {
            for t in ts {
                assert!(!matches!(a.node(*t), Node::Add(_)));
            }
        }
    }
}

// ---------------------------------------------------------------------------
// 2. differentiation

/// Richardson-extrapolated central difference of `f` at 0, with an error
/// estimate (the change from the extrapolation at twice the step).
fn richardson1(f: impl Fn(f64) -> f64, h: f64) -> (f64, f64) {
    let d = |h: f64| (f(h) - f(-h)) / (2.0 * h);
    let r = |h: f64| (4.0 * d(h / 2.0) - d(h)) / 3.0;
    (r(h), (r(h) - r(2.0 * h)).abs())
}

/// Richardson-extrapolated mixed second difference of `f` at (0, 0), with an
/// error estimate.
fn richardson2(f: impl Fn(f64, f64) -> f64, h: f64) -> (f64, f64) {
    let d = |h: f64| (f(h, h) - f(h, -h) - f(-h, h) + f(-h, -h)) / (4.0 * h * h);
    let r = |h: f64| (4.0 * d(h / 2.0) - d(h)) / 3.0;
    (r(h), (r(h) - r(2.0 * h)).abs())
}

fn check_derivatives(t: &T, pt: &[f64; 5]) -> Result<(), TestCaseError> {
    let mut a = Arena::new();
    let text = t.text();
    let e = a.parse(&text).unwrap();
    let m = 1.0 + t.bound(&abs_point(pt));
    let g = 1.0 + f64::from(t.degree());
    let f64_at = |i: usize, di: f64, j: usize, dj: f64| {
        let mut v = *pt;
        v[i] += di;
        v[j] += dj;
        t.eval::<f64>(&v)
    };
    for (i, ni) in NAMES.iter().enumerate().take(3) {
        let si = a.symbol(ni);
        let d = a.diff(e, si).unwrap();
        let got = eval_at(&a, d, pt);
        let hd: Vec<Hd> = (0..5)
            .map(|k| Hd::var(pt[k], f64::from(k == i), 0.0))
            .collect();
        let want = t.eval(&hd).a;
        check_close(&format!("d/d{ni} of {text}"), got, want, 1e-9 * m * g)?;
        let (fd, err) = richardson1(|h| f64_at(i, h, i, 0.0), 1e-3);
        let what = format!("FD d/d{ni} of {text}");
        check_close(&what, got, fd, 1e-6 * m * g + 10.0 * err)?;
        for (j, nj) in NAMES.iter().enumerate().take(3).skip(i) {
            let sj = a.symbol(nj);
            let d2 = a.diff(d, sj).unwrap();
            let got2 = eval_at(&a, d2, pt);
            let hd: Vec<Hd> = (0..5)
                .map(|k| Hd::var(pt[k], f64::from(k == i), f64::from(k == j)))
                .collect();
            let want2 = t.eval(&hd).ab;
            let what = format!("d2/d{ni}d{nj} of {text}");
            check_close(&what, got2, want2, 1e-9 * m * g * g)?;
            let (fd2, err2) = richardson2(|hi, hj| f64_at(i, hi, j, hj), 4e-3);
            check_close(
                &format!("FD {what}"),
                got2,
                fd2,
                1e-5 * m * g * g + 10.0 * err2,
            )?;
        }
    }
    // the text operators d(e, x, 2) and at(e, x, v)
    let dxx = a.parse(&format!("d({text}, x, 2)")).unwrap();
    let hd: Vec<Hd> = (0..5)
        .map(|k| Hd::var(pt[k], f64::from(k == 0), f64::from(k == 0)))
        .collect();
    check_close(
        "d(e, x, 2)",
        eval_at(&a, dxx, pt),
        t.eval(&hd).ab,
        1e-9 * m * g * g,
    )?;
    Ok(())
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn derivatives_match_forward_mode_and_finite_differences(
        t in fun_tree(XYZ),
        pt in point(),
    ) {
        check_derivatives(&t, &pt)?;
    }

    #[test]
    fn polynomial_derivatives_match(t in poly_tree(XYZ, 4, 8), pt in point()) {
        check_derivatives(&t, &pt)?;
    }

    #[test]
    fn substitution_matches_composition(
        t in fun_tree(XYZ),
        q in poly_tree(YZ, 2, 3),
        pt in point(),
    ) {
        // at(t, x, q) and Arena::subst1 against evaluating t at x = q(y, z)
        let mut a = Arena::new();
        let composed = t.subst(0, &q);
        prop_assume!(composed.size_bits() <= 60.0);
        let want = composed.eval::<f64>(&pt);
        let tol = 1e-9 * (1.0 + composed.bound(&abs_point(&pt)));
        let e = a.parse(&format!("at({}, x, {})", t.text(), q.text())).unwrap();
        check_close("at(e, x, q)", eval_at(&a, e, &pt), want, tol)?;
        let te = a.parse(&t.text()).unwrap();
        let qe = a.parse(&q.text()).unwrap();
        let x = a.symbol("x");
        let s = a.subst1(te, x, qe).unwrap();
        check_close("subst1", eval_at(&a, s, &pt), want, tol)?;
        prop_assert!(!a.free_symbols(s).contains(&x));
    }
}

// ---------------------------------------------------------------------------
// 3. exact integration

fn poly_scale(a: &Arena, p: &Poly, pt: &[f64]) -> f64 {
    p.terms()
        .map(|(m, c)| {
            m.iter().fold(c.to_f64().abs(), |acc, (s, e)| {
                acc * value_of(a, *s, pt).unwrap().abs().powi(*e as i32)
            })
        })
        .sum()
}

fn check_integral(t: &T, lo: &T, hi: &T, pt: &[f64; 5]) -> Result<(), TestCaseError> {
    let rule = gauss_legendre(10);
    let mut a = Arena::new();
    let e = a.parse(&t.text()).unwrap();
    let p = a.expand(e).unwrap();
    let x = a.symbol("x");
    let le = a.parse(&lo.text()).unwrap();
    let he = a.parse(&hi.text()).unwrap();
    let (lp, hp) = (a.expand(le).unwrap(), a.expand(he).unwrap());

    // symbolic bounds in y and z, evaluated afterwards; the exact result may
    // outgrow i128 only when the estimate of its numbers is large
    let deg = f64::from(p.degree_in(x)) + 2.0;
    let big = t.size_bits() + deg * lo.size_bits().max(hi.size_bits()).max(3.0) > 60.0;
    let i = match p.integrate(x, &lp, &hp) {
        Err(_) if big => return Ok(()),
        r => r.unwrap(),
    };
    prop_assert_eq!(i.degree_in(x), 0);
    let (l, h) = (lo.eval::<f64>(pt), hi.eval::<f64>(pt));
    let f = |xv: f64| {
        let mut v = *pt;
        v[0] = xv;
        v
    };
    let want = quad(&rule, 2, l, h, |xv| t.eval::<f64>(&f(xv)));
    let fabs = quad(&rule, 2, l, h, |xv| t.bound(&abs_point(&f(xv)))).abs();
    // the bounds themselves are rounded when evaluated for the quadrature
    let fmax = t.bound(&abs_point(&f(l.abs().max(h.abs()))));
    let bounds = fmax * (lo.bound(&abs_point(pt)) + hi.bound(&abs_point(pt)));
    let tol = 1e-9 * (poly_scale(&a, &i, pt) + fabs + bounds) + 1e-300;
    check_close(
        "integral over [lo(y,z), hi(y,z)]",
        poly_at(&a, &i, pt),
        want,
        tol,
    )?;

    // the Expr wrapper with the bounds as text
    let ex: Expr = t.text().parse().unwrap();
    let ie = ex.integrate("x", &lo.text(), &hi.text()).unwrap();
    let named: Vec<(&str, f64)> = NAMES.iter().copied().zip(pt.iter().copied()).collect();
    check_close("Expr::integrate", ie.eval(&named).unwrap(), want, tol)?;

    // bounds as fresh symbols u (lower) and w (upper); iterate over y too
    let (u, w) = (a.symbol("u"), a.symbol("w"));
    let (y, z) = (a.symbol("y"), a.symbol("z"));
    let j = p.integrate(x, &Poly::var(u), &Poly::var(w)).unwrap();
    let (uv, wv) = (pt[3], pt[4]);
    let at_uw = |s: Sym| match a.name(s) {
        "u" => uv,
        "w" => wv,
        n => pt[NAMES.iter().position(|k| *k == n).unwrap()],
    };
    let want_j = quad(&rule, 2, uv, wv, |xv| t.eval::<f64>(&f(xv)));
    let j_scale: f64 = j
        .terms()
        .map(|(m, c)| {
            m.iter().fold(c.to_f64().abs(), |acc, (s, e)| {
                acc * at_uw(*s).abs().powi(*e as i32)
            })
        })
        .sum();
    check_close(
        "integral over [u, w]",
        j.eval(&at_uw),
        want_j,
        1e-9 * j_scale + 1e-300,
    )?;

    // fundamental theorem: d/dw of the integral is the integrand at x = w,
    // and -d/du is the integrand at x = u
    let fw = t.eval::<f64>(&f(wv));
    let fu = t.eval::<f64>(&f(uv));
    let ftol = |xv: f64| 1e-10 * (1.0 + t.bound(&abs_point(&f(xv))));
    check_close(
        "d/dw integral",
        j.diff(w).unwrap().eval(&at_uw),
        fw,
        ftol(wv),
    )?;
    check_close(
        "-d/du integral",
        -j.diff(u).unwrap().eval(&at_uw),
        fu,
        ftol(uv),
    )?;

    // a second, iterated integration over y in [-1, z]: a 2-D box integral
    let k = j
        .integrate(y, &Poly::constant(Rational::int(-1)), &Poly::var(z))
        .unwrap();
    let want_k = quad(&rule, 2, -1.0, pt[2], |yv| {
        quad(&rule, 2, uv, wv, |xv| {
            let mut v = *pt;
            v[0] = xv;
            v[1] = yv;
            t.eval::<f64>(&v)
        })
    });
    let k_abs = quad(&rule, 2, -1.0, pt[2], |yv| {
        quad(&rule, 2, uv, wv, |xv| {
            let mut v = abs_point(pt);
            v[0] = xv.abs();
            v[1] = yv.abs();
            t.bound(&v)
        })
        .abs()
    })
    .abs();
    let k_scale: f64 = k
        .terms()
        .map(|(m, c)| {
            m.iter().fold(c.to_f64().abs(), |acc, (s, e)| {
                acc * at_uw(*s).abs().powi(*e as i32)
            })
        })
        .sum();
    prop_assert_eq!(k.degree_in(y), 0);
    check_close(
        "iterated integral",
        k.eval(&at_uw),
        want_k,
        1e-9 * (k_scale + k_abs),
    )?;
    Ok(())
}

proptest! {
    #![proptest_config(config(48))]

    #[test]
    fn integrals_match_gauss_legendre_quadrature(
        t in poly_tree(XYZ, 4, 8),
        lo in poly_tree(YZ, 2, 3),
        hi in poly_tree(YZ, 2, 3),
        pt in point(),
    ) {
        check_integral(&t, &lo, &hi, &pt)?;
    }
}

// ---------------------------------------------------------------------------
// 4. expansion in chosen variables with factored coefficients

/// Opaque coefficient functions of `a` and `b` (not polynomials).
fn opaque() -> BoxedStrategy<T> {
    let p = || poly_tree(AB, 2, 3);
    prop_oneof![
        p().prop_map(|q| T::Sin(bx(q))),
        p().prop_map(|q| T::SqrtPos(bx(q))),
        p().prop_map(|q| T::DivPos(bx(T::Num(1, 1)), bx(q))),
    ]
    .boxed()
}

fn expand_in_tree() -> BoxedStrategy<T> {
    let leaves = prop_oneof![
        4 => leaf(XYZAB),
        1 => opaque(),
    ]
    .boxed();
    poly_over(leaves, 4, 8)
}

/// Sums of (coefficient in a, b) * (small polynomial in x, y, z), multiplied
/// and raised to powers: like monomials with different coefficients make
/// multi-term coefficients, which products must freeze into atoms.
fn structured_expand_in_tree() -> BoxedStrategy<T> {
    let coef = poly_over(prop_oneof![3 => leaf(AB), 1 => opaque()].boxed(), 2, 3);
    // few distinct monomials, so that like monomials meet often
    let mono = prop_oneof![
        Just(T::Num(1, 1)),
        Just(T::Var(0)),
        Just(T::Var(1)),
        Just(T::Mul(bx(T::Var(0)), bx(T::Var(1)))),
        Just(T::Pow(bx(T::Var(0)), 2)),
        poly_tree(XYZ, 1, 2),
    ];
    let sum = prop::collection::vec((coef, mono), 1..4)
        .prop_map(|ts| {
            ts.into_iter()
                .map(|(c, m)| T::Mul(bx(c), bx(m)))
                .reduce(|a, b| T::Add(bx(a), bx(b)))
                .unwrap()
        })
        .boxed();
    prop_oneof![
        sum.clone(),
        (sum.clone(), sum.clone()).prop_map(|(a, b)| T::Mul(bx(a), bx(b))),
        (sum.clone(), 2u32..=3).prop_map(|(a, k)| T::Pow(bx(a), k)),
        (sum.clone(), sum.clone(), sum)
            .prop_map(|(a, b, c)| T::Mul(bx(T::Add(bx(a), bx(b))), bx(c))),
    ]
    .boxed()
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn expand_in_sums_back_to_the_expression(
        t in prop_oneof![expand_in_tree(), structured_expand_in_tree()],
        var_mask in 1u8..8,
        pt in point(),
    ) {
        let mut a = Arena::new();
        let e = a.parse(&t.text()).unwrap();
        let vars: Vec<Sym> = (0..3)
            .filter(|i| var_mask & (1 << i) != 0)
            .map(|i| a.symbol(NAMES[i]))
            .collect();
        let is_var = |s: Sym| vars.contains(&s);
        let m = a.expand_in(e, &is_var).unwrap();
        let mut sum = 0.0;
        for (mono, lc) in &m {
            prop_assert!(!lc.is_zero());
            for (s, k) in mono {
                prop_assert!(vars.contains(s), "monomial in a non-variable");
                prop_assert!(*k > 0);
            }
            let c = lc.to_expr(&mut a).unwrap();
            prop_assert!(
                a.free_symbols(c).iter().all(|s| !vars.contains(s)),
                "coefficient `{}` depends on a variable", a.show(c)
            );
            let mono_v: f64 = mono
                .iter()
                .map(|(s, k)| value_of(&a, *s, &pt).unwrap().powi(*k as i32))
                .product();
            sum += eval_at(&a, c, &pt) * mono_v;
        }
        let want = t.eval::<f64>(&pt);
        let tol = 1e-9 * (1.0 + t.bound(&abs_point(&pt)));
        check_close("sum of expand_in terms", sum, want, tol)?;
    }
}

// ---------------------------------------------------------------------------
// 5. hash-consing and common-subexpression emission, with an interpreter
//    for the emitted straight-line Rust

mod rust_subset {
    //! Evaluates the straight-line Rust the generator emits: `let`
    //! statements, `m[i] += e;`, arithmetic, `.sin() .cos() .sqrt()
    //! .atan2()`, indexing, arrays and tuples; and counts its operations.

    use std::collections::HashMap;

    use fpc_symbolic::emit::OpCount;
    use syn::{BinOp, Expr, FnArg, Item, Lit, Pat, Stmt, UnOp};

    #[derive(Debug, Clone, PartialEq)]
    pub enum V {
        F(f64),
        A(Vec<V>),
    }

    impl V {
        pub fn f(&self) -> f64 {
            match self {
                V::F(v) => *v,
                V::A(_) => panic!("expected a number, found {self:?}"),
            }
        }
        pub fn at(&self, i: usize) -> &V {
            match self {
                V::A(v) => &v[i],
                V::F(_) => panic!("indexing a number"),
            }
        }
        pub fn floats(&self) -> Vec<f64> {
            match self {
                V::A(v) => v.iter().map(V::f).collect(),
                V::F(_) => panic!("expected an array"),
            }
        }
        pub fn arr(v: &[f64]) -> V {
            V::A(v.iter().map(|x| V::F(*x)).collect())
        }
    }

    pub type Env = HashMap<String, V>;

    fn ident_of(e: &Expr) -> String {
        match e {
            Expr::Path(p) => p.path.get_ident().expect("a plain name").to_string(),
            _ => panic!("expected a name"),
        }
    }

    pub fn expr(e: &Expr, env: &Env) -> V {
        match e {
            Expr::Lit(l) => match &l.lit {
                Lit::Float(f) => V::F(f.base10_parse().unwrap()),
                Lit::Int(i) => V::F(i.base10_parse::<i64>().unwrap() as f64),
                _ => panic!("unsupported literal"),
            },
            Expr::Path(_) => {
                let n = ident_of(e);
                env.get(&n)
                    .unwrap_or_else(|| panic!("unbound `{n}`"))
                    .clone()
            }
            Expr::Paren(p) => expr(&p.expr, env),
            Expr::Group(g) => expr(&g.expr, env),
            Expr::Unary(u) => match u.op {
                UnOp::Neg(_) => V::F(-expr(&u.expr, env).f()),
                _ => panic!("unsupported unary operator"),
            },
            Expr::Binary(b) => {
                let (l, r) = (expr(&b.left, env).f(), expr(&b.right, env).f());
                V::F(match b.op {
                    BinOp::Add(_) => l + r,
                    BinOp::Sub(_) => l - r,
                    BinOp::Mul(_) => l * r,
                    BinOp::Div(_) => l / r,
                    _ => panic!("unsupported binary operator"),
                })
            }
            Expr::MethodCall(m) => {
                let r = expr(&m.receiver, env).f();
                let args: Vec<f64> = m.args.iter().map(|a| expr(a, env).f()).collect();
                V::F(match (m.method.to_string().as_str(), args.as_slice()) {
                    ("sin", []) => r.sin(),
                    ("cos", []) => r.cos(),
                    ("sqrt", []) => r.sqrt(),
                    ("atan2", [x]) => r.atan2(*x),
                    (other, _) => panic!("unsupported method {other}"),
                })
            }
            Expr::Index(ix) => {
                let base = expr(&ix.expr, env);
                let i = expr(&ix.index, env).f() as usize;
                base.at(i).clone()
            }
            Expr::Array(a) => V::A(a.elems.iter().map(|e| expr(e, env)).collect()),
            Expr::Tuple(t) => V::A(t.elems.iter().map(|e| expr(e, env)).collect()),
            _ => panic!("unsupported expression"),
        }
    }

    /// Runs a block; returns its tail expression's value.
    pub fn block(b: &syn::Block, env: &mut Env) -> Option<V> {
        let mut out = None;
        for s in &b.stmts {
            match s {
                Stmt::Local(l) => {
                    let Pat::Ident(pi) = &l.pat else {
                        panic!("unsupported pattern")
                    };
                    let init = l.init.as_ref().expect("an initialiser");
                    let v = expr(&init.expr, env);
                    env.insert(pi.ident.to_string(), v);
                }
                Stmt::Expr(Expr::Binary(b), Some(_)) if matches!(b.op, BinOp::AddAssign(_)) => {
                    let Expr::Index(ix) = &*b.left else {
                        panic!("unsupported assignment target")
                    };
                    let name = ident_of(&ix.expr);
                    let i = expr(&ix.index, env).f() as usize;
                    let v = expr(&b.right, env).f();
                    match env.get_mut(&name) {
                        Some(V::A(arr)) => arr[i] = V::F(arr[i].f() + v),
                        _ => panic!("`{name}` is not an array"),
                    }
                }
                Stmt::Expr(e, None) => out = Some(expr(e, env)),
                _ => panic!("unsupported statement"),
            }
        }
        out
    }

    /// Calls function `name` of `file`; returns its value and final environment.
    pub fn call(file: &syn::File, name: &str, args: Vec<V>) -> (Option<V>, Env) {
        let f = file
            .items
            .iter()
            .find_map(|it| match it {
                Item::Fn(f) if f.sig.ident == name => Some(f),
                _ => None,
            })
            .unwrap_or_else(|| panic!("no function {name}"));
        let mut env = Env::new();
        assert_eq!(f.sig.inputs.len(), args.len(), "arity of {name}");
        for (inp, v) in f.sig.inputs.iter().zip(args) {
            let FnArg::Typed(pt) = inp else {
                panic!("receiver")
            };
            let Pat::Ident(pi) = &*pt.pat else {
                panic!("pattern")
            };
            env.insert(pi.ident.to_string(), v);
        }
        let v = block(&f.block, &mut env);
        (v, env)
    }

    /// The value of `const NAME: usize = N;` in `file`.
    pub fn const_usize(file: &syn::File, name: &str) -> usize {
        file.items
            .iter()
            .find_map(|it| match it {
                Item::Const(c) if c.ident == name => Some(expr(&c.expr, &Env::new()).f() as usize),
                _ => None,
            })
            .unwrap_or_else(|| panic!("no const {name}"))
    }

    /// Operations written in an expression (`+=` counts as an addition).
    pub fn count_expr(e: &Expr, c: &mut OpCount) {
        match e {
            Expr::Binary(b) => {
                match b.op {
                    BinOp::Add(_) | BinOp::Sub(_) | BinOp::AddAssign(_) => c.add += 1,
                    BinOp::Mul(_) => c.mul += 1,
                    BinOp::Div(_) => c.div += 1,
                    _ => {}
                }
                if !matches!(b.op, BinOp::AddAssign(_)) {
                    count_expr(&b.left, c);
                }
                count_expr(&b.right, c);
            }
            Expr::Unary(u) => count_expr(&u.expr, c),
            Expr::Paren(p) => count_expr(&p.expr, c),
            Expr::Group(g) => count_expr(&g.expr, c),
            Expr::MethodCall(m) => {
                c.func += 1;
                count_expr(&m.receiver, c);
                for a in &m.args {
                    count_expr(a, c);
                }
            }
            Expr::Array(a) => a.elems.iter().for_each(|e| count_expr(e, c)),
            Expr::Tuple(t) => t.elems.iter().for_each(|e| count_expr(e, c)),
            _ => {}
        }
    }

    pub fn count_block(b: &syn::Block) -> OpCount {
        let mut c = OpCount::default();
        for s in &b.stmts {
            match s {
                Stmt::Local(l) => count_expr(&l.init.as_ref().unwrap().expr, &mut c),
                Stmt::Expr(e, _) => count_expr(e, &mut c),
                _ => {}
            }
        }
        c
    }

    pub fn count_fn(file: &syn::File, name: &str) -> OpCount {
        file.items
            .iter()
            .find_map(|it| match it {
                Item::Fn(f) if f.sig.ident == name => Some(count_block(&f.block)),
                _ => None,
            })
            .unwrap_or_else(|| panic!("no function {name}"))
    }
}

use rust_subset::V;

/// An upper bound on the operations of code that computes every distinct
/// node of the DAG once (each node's own operations, children excluded).
fn dag_ops_bound(a: &Arena, roots: &[ExprId]) -> u64 {
    let mut seen = HashSet::new();
    let mut stack = roots.to_vec();
    let mut total = 0u64;
    while let Some(n) = stack.pop() {
        if !seen.insert(n) {
            continue;
        }
        total += match a.node(n) {
            Node::Add(ts) => ts.len() as u64 - 1,
            // n - 1 products plus at most one division for negative powers
            Node::Mul(fs) => fs.len() as u64,
            Node::Pow(_, k) => u64::from(k.unsigned_abs()) - 1 + u64::from(*k < 0),
            Node::Fun(..) => 1,
            Node::Num(_) | Node::Sym(_) => 0,
        };
        stack.extend(a.children(n));
    }
    total
}

fn check_emission(t: &T, s: &T, pt: &[f64; 5]) -> Result<(), TestCaseError> {
    // t with x replaced by s: s occurs once per x in t
    let composed = t.subst(0, s);
    prop_assume!(composed.size_bits() <= 60.0);
    let mut a = Arena::new();
    let root = composed.build(&mut a);
    let n = a.len();
    prop_assert_eq!(composed.build(&mut a), root);
    prop_assert_eq!(a.len(), n);
    let se = s.build(&mut a);
    let te = t.build(&mut a);
    let roots = [root, se, te];
    let mut em = Emitter::new(&a, &roots, "t");
    let mut stmts = Vec::new();
    let mut outs = Vec::new();
    for r in roots {
        outs.push(em.expr(r));
        stmts.extend(em.take_statements());
    }
    let tokens = quote! { { #(#stmts)* (#(#outs),*) } };
    let block: syn::Block = syn::parse2(tokens.clone()).unwrap();

    // the code computes the right values
    let mut env: rust_subset::Env = NAMES
        .iter()
        .zip(pt)
        .map(|(n, v)| (n.to_string(), V::F(*v)))
        .collect();
    let got = rust_subset::block(&block, &mut env).unwrap().floats();
    for (k, tree) in [&composed, s, t].into_iter().enumerate() {
        let want = tree.eval::<f64>(pt);
        let tol = 1e-9 * (1.0 + tree.bound(&abs_point(pt)));
        check_close(&format!("emitted root {k} of {tokens}"), got[k], want, tol)?;
    }

    // the reported operation count is what the code does, every distinct
    // node is computed at most once, and sharing never costs operations
    let written = rust_subset::count_block(&block);
    prop_assert_eq!(em.ops(), written, "reported vs written ops in {}", tokens);
    prop_assert!(
        written.total() <= dag_ops_bound(&a, &roots),
        "{} ops written, DAG bound {}: {}",
        written.total(),
        dag_ops_bound(&a, &roots),
        tokens
    );
    let before = tree_ops(&a, &roots);
    prop_assert!(em.ops().total() <= before.total());
    prop_assert!(em.ops().func <= before.func);
    Ok(())
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn emitted_code_is_correct_and_shares_subexpressions(
        t in fun_tree(XYZ),
        s in fun_tree(XYZ),
        pt in point(),
    ) {
        check_emission(&t, &s, &pt)?;
    }

    #[test]
    fn emitted_polynomials_are_correct(
        t in poly_tree(XYZ, 4, 8),
        s in poly_tree(YZ, 3, 3),
        pt in point(),
    ) {
        check_emission(&t, &s, &pt)?;
    }
}

#[test]
fn integer_powers_emit_correctly() {
    // the power cache (squares, odd steps, reciprocals) for every exponent up
    // to 12 in magnitude, of a symbol, a sum and a function call, all in one
    // emitter so powers of a base share their intermediate products
    for base in ["x", "(x + y)", "sin(x)"] {
        let mut a = Arena::new();
        let roots: Vec<ExprId> = (-12i32..=12)
            .map(|k| a.parse(&format!("{base}^({k})")).unwrap())
            .collect();
        let mut em = Emitter::new(&a, &roots, "t");
        let outs: Vec<_> = roots.iter().map(|&r| em.expr(r)).collect();
        let stmts = em.take_statements();
        let block: syn::Block = syn::parse2(quote! { { #(#stmts)* [#(#outs),*] } }).unwrap();
        let (x, y) = (0.9f64, 0.35f64);
        let mut env: rust_subset::Env = [("x", x), ("y", y)]
            .into_iter()
            .map(|(n, v)| (n.to_string(), V::F(v)))
            .collect();
        let got = rust_subset::block(&block, &mut env).unwrap().floats();
        let b = match base {
            "x" => x,
            "(x + y)" => x + y,
            _ => x.sin(),
        };
        for (i, k) in (-12i32..=12).enumerate() {
            let want = b.powi(k);
            assert!(
                (got[i] - want).abs() <= 1e-13 * want.abs(),
                "{base}^{k}: {} vs {want}",
                got[i]
            );
        }
        assert_eq!(em.ops(), rust_subset::count_block(&block), "{base}");
        // the base and each power are computed once
        assert!(em.ops().total() <= dag_ops_bound(&a, &roots), "{base}");
        assert!(
            em.ops().func <= 1 && em.ops().add <= 1,
            "{base}: {:?}",
            em.ops()
        );
    }
}

#[test]
fn repeated_subexpressions_are_emitted_once() {
    // each of these repeats a non-trivial sub-expression; its operation must
    // appear once in the code
    for (src, sub) in [
        ("(x + y)^2", "x + y"),
        ("(x + y)^3 + 1", "x + y"),
        ("sin(x)*y + sin(x)*z", "x.sin()"),
        ("sin(x)^2", "x.sin()"),
        ("z/(x + y) + y/(x + y)", "x + y"),
        ("sqrt(1 + x^2)*x + sqrt(1 + x^2)*y^2", "sqrt"),
    ] {
        let mut a = Arena::new();
        let e = a.parse(src).unwrap();
        let mut em = Emitter::new(&a, &[e], "t");
        let out = em.expr(e);
        let stmts = em.take_statements();
        let code = quote! { #(#stmts)* #out }.to_string().replace(' ', "");
        let sub = sub.replace(' ', "");
        assert_eq!(code.matches(&sub).count(), 1, "{src}: {code}");
    }
}

// ---------------------------------------------------------------------------
// 6. exact rationals

fn gcd_u(mut a: u128, mut b: u128) -> u128 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

fn check_reduced(r: Rational) -> Result<(), TestCaseError> {
    prop_assert!(r.denom() > 0);
    prop_assert_eq!(gcd_u(r.numer().unsigned_abs(), r.denom().unsigned_abs()), 1);
    Ok(())
}

fn special_i128() -> impl Strategy<Value = i128> {
    prop_oneof![
        4 => any::<i128>(),
        1 => Just(i128::MIN),
        1 => Just(i128::MIN + 1),
        1 => Just(i128::MAX),
        1 => Just(i128::MAX / 3),
        1 => Just(i128::MIN / 2),
        1 => Just(0i128),
        1 => Just(1i128),
        1 => Just(-1i128),
        1 => Just(2i128),
        2 => any::<i64>().prop_map(i128::from),
    ]
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn rational_arithmetic_matches_f64(
        n1 in any::<i64>(),
        d1 in any::<i64>().prop_filter("nonzero", |d| *d != 0),
        n2 in any::<i64>(),
        d2 in any::<i64>().prop_filter("nonzero", |d| *d != 0),
    ) {
        let eps = f64::EPSILON;
        let (x, y) = (n1 as f64 / d1 as f64, n2 as f64 / d2 as f64);
        let a = Rational::new(n1.into(), d1.into()).unwrap();
        let b = Rational::new(n2.into(), d2.into()).unwrap();
        check_reduced(a)?;
        check_close("new", a.to_f64(), x, 4.0 * eps * x.abs())?;
        let sum = a.add(b).unwrap();
        check_reduced(sum)?;
        check_close("add", sum.to_f64(), x + y, 8.0 * eps * (x.abs() + y.abs()))?;
        let diff = a.sub(b).unwrap();
        check_close("sub", diff.to_f64(), x - y, 8.0 * eps * (x.abs() + y.abs()))?;
        let prod = a.mul(b).unwrap();
        check_reduced(prod)?;
        check_close("mul", prod.to_f64(), x * y, 8.0 * eps * (x * y).abs())?;
        if n2 != 0 {
            let quot = a.div(b).unwrap();
            check_reduced(quot)?;
            check_close("div", quot.to_f64(), x / y, 8.0 * eps * (x / y).abs())?;
            // exact identities
            prop_assert_eq!(quot.mul(b).unwrap(), a);
        } else {
            prop_assert!(a.div(b).is_err());
        }
        prop_assert_eq!(sum.sub(b).unwrap(), a);
        if (x - y).abs() > 8.0 * eps * (x.abs() + y.abs()) {
            prop_assert_eq!(Some(a.cmp(&b)), x.partial_cmp(&y));
        }
        prop_assert_eq!(a.cmp(&a), std::cmp::Ordering::Equal);
    }

    #[test]
    fn rational_overflow_is_an_error_never_a_panic(
        n1 in special_i128(),
        d1 in special_i128(),
        n2 in special_i128(),
        d2 in special_i128(),
        k in -80i32..80,
    ) {
        // every operation either succeeds with a reduced value close to the
        // f64 result, or reports an error
        let eps = f64::EPSILON;
        let ok = |r: Result<Rational, fpc_symbolic::Overflow>, want: f64, scale: f64|
            -> Result<(), TestCaseError> {
            if let Ok(r) = r {
                check_reduced(r)?;
                check_close("value", r.to_f64(), want, 16.0 * eps * scale + 1e-300)?;
            }
            Ok(())
        };
        let a = Rational::new(n1, d1);
        // only a zero denominator, or a sign normalisation that would negate
        // i128::MIN, fails
        let coprime = gcd_u(n1.unsigned_abs(), d1.unsigned_abs()) == 1;
        let unrepresentable = d1 < 0 && coprime && (n1 == i128::MIN || d1 == i128::MIN);
        prop_assert_eq!(a.is_err(), d1 == 0 || unrepresentable, "{}/{}", n1, d1);
        let x = n1 as f64 / d1 as f64;
        ok(a, x, x.abs())?;
        let b = Rational::new(n2, d2);
        let (Ok(a), Ok(b)) = (a, b) else { return Ok(()); };
        let (x, y) = (a.to_f64(), b.to_f64());
        ok(a.add(b), x + y, x.abs() + y.abs())?;
        ok(a.sub(b), x - y, x.abs() + y.abs())?;
        ok(a.mul(b), x * y, (x * y).abs())?;
        ok(a.neg(), -x, x.abs())?;
        if !b.is_zero() {
            ok(a.div(b), x / y, (x / y).abs())?;
        }
        if !a.is_zero() {
            ok(a.recip(), 1.0 / x, (1.0 / x).abs())?;
        }
        if !(a.is_zero() && k < 0) {
            let want = x.powi(k);
            if want.is_finite() && want != 0.0 {
                ok(a.pow(k), want, want.abs() * f64::from(k.unsigned_abs() + 1))?;
            } else {
                let _ = a.pow(k);
            }
        }
        let _ = a.cmp(&b);
        let _ = a.to_string();
    }
}

#[test]
fn rational_overflow_examples() {
    let third = Rational::int(i128::MAX / 3);
    assert!(third.mul(third).is_err());
    assert!(third.pow(2).is_err());
    assert!(Rational::int(i128::MAX).add(Rational::ONE).is_err());
    assert!(Rational::int(i128::MIN).neg().is_err());
    assert!(Rational::int(i128::MIN).mul(Rational::int(-1)).is_err());
    assert!(Rational::int(i128::MIN).recip().is_err());
    assert!(Rational::new(1, i128::MIN).is_err());
    assert!(Rational::new(i128::MIN, -1).is_err());
    assert_eq!(Rational::new(i128::MIN, i128::MIN).unwrap(), Rational::ONE);
    assert_eq!(Rational::new(0, i128::MIN).unwrap(), Rational::ZERO);
    assert_eq!(
        Rational::new(i128::MIN, 2).unwrap(),
        Rational::int(i128::MIN / 2)
    );
    let half_min = Rational::int(i128::MIN / 2);
    assert_eq!(half_min.add(half_min).unwrap(), Rational::int(i128::MIN));
    assert_eq!(
        Rational::int(i128::MIN).mul(Rational::ONE).unwrap(),
        Rational::int(i128::MIN)
    );
    assert!(Rational::new(1, 3).unwrap().pow(-81).is_err());
    assert!(Rational::from_decimal("1e39").is_none());
    assert!(Rational::from_decimal("1e-39").is_none());
    assert!(Rational::from_decimal("1e99999999999").is_none());
    // the same through the arena: an overflowing fold is an error
    let mut a = Arena::new();
    assert!(a
        .parse("170141183460469231731687303715884105727 + 1")
        .is_err());
    assert!(a.parse("(x^(-2))^1073741824").is_ok());
    assert!(a.parse("d((x^(-2))^1073741824, x)").is_err());
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn decimal_literals_are_exact(mantissa in 0u64..10_000_000_000, frac in 0usize..8, exp in -12i32..12) {
        // digits with a decimal point `frac` places from the right, and an exponent
        let digits = mantissa.to_string();
        let text = if frac > 0 && frac < digits.len() {
            format!("{}.{}e{exp}", &digits[..digits.len() - frac], &digits[digits.len() - frac..])
        } else {
            format!("{digits}e{exp}")
        };
        let r = Rational::from_decimal(&text).unwrap();
        check_reduced(r)?;
        let want: f64 = text.parse().unwrap();
        check_close(&text, r.to_f64(), want, 4.0 * f64::EPSILON * want.abs())?;
    }
}

// ---------------------------------------------------------------------------
// 7. code generation from a spec, run through the interpreter

const SPRING: &str = "\
unknowns a, b;
let e = a + b*x;
integral spring(x0, x1, ks) = 1/2*ks*e^2 over x in [x0, x1];
point tip(l) { y = at(e, x, l); }
";

const PLATE: &str = "\
unknowns a, b, c;
let u = a*x + b*x^2*y;
let s = d(u, x) + 1/2*(c*y)^2 - z*c;
let psi = p1/2*t^2 - p2/3*t^3;
integral plate(x0, x1, w, z0, z1, e0, p1, p2) =
    at(psi, t, e0 + s) + (1 + s)*(1 + b*y) over x in [x0, x1], y in [0, w], z in [z0, z1];
point tip(l, h) {
    X = at(at(x + u, x, l), y, h);
    eta = atan2(at(at(d(u, x), x, l), y, h), 1 + a^2);
    r = sqrt(1 + c^2)*sin(b*l);
}
";

fn generated_file(src: &str) -> syn::File {
    let g = generate(src).unwrap();
    let text = format_file(&g.tokens).unwrap();
    let file: syn::File = syn::parse_file(&text).unwrap();
    // the report's counts are the operations written in each function
    for r in &g.report {
        let written = rust_subset::count_fn(&file, &r.function);
        assert_eq!(written, r.ops_after_cse, "{}: {text}", r.function);
        assert!(
            r.ops_after_cse.total() <= r.ops_before_cse.total(),
            "{}",
            r.function
        );
    }
    file
}

/// Value, gradient and upper-triangle Hessian of `f` over the unknowns, by
/// hyper-dual evaluation.
fn derivs<const N: usize>(k: &[f64; N], f: impl Fn(&[Hd; N]) -> Hd) -> (f64, Vec<f64>, Vec<f64>) {
    let seed = |i: usize, j: usize| -> [Hd; N] {
        std::array::from_fn(|l| Hd::var(k[l], f64::from(l == i), f64::from(l == j)))
    };
    let v = f(&seed(N, N)).v;
    let g = (0..N).map(|i| f(&seed(i, N)).a).collect();
    let mut h = Vec::new();
    for i in 0..N {
        for j in i..N {
            h.push(f(&seed(i, j)).ab);
        }
    }
    (v, g, h)
}

fn check_vec(what: &str, got: &[f64], want: &[f64], tol: f64) -> Result<(), TestCaseError> {
    prop_assert_eq!(got.len(), want.len(), "{}", what);
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        check_close(&format!("{what}[{i}]"), *g, *w, tol * (1.0 + w.abs()))?;
    }
    Ok(())
}

/// Runs `NAME_value`, `NAME_gradient` and `NAME_hessian` and compares them
/// with `want` (value, gradient, upper Hessian).
fn check_energy_kernels(
    file: &syn::File,
    name: &str,
    k: &[f64],
    m: &V,
    want: &(f64, Vec<f64>, Vec<f64>),
    tol: f64,
) -> Result<(), TestCaseError> {
    let ka = V::arr(k);
    let (v, _) = rust_subset::call(file, &format!("{name}_value"), vec![ka.clone(), m.clone()]);
    check_close("value", v.unwrap().f(), want.0, tol * (1.0 + want.0.abs()))?;
    let (g, _) = rust_subset::call(
        file,
        &format!("{name}_gradient"),
        vec![ka.clone(), m.clone()],
    );
    let g = g.unwrap();
    check_close(
        "gradient value",
        g.at(0).f(),
        want.0,
        tol * (1.0 + want.0.abs()),
    )?;
    check_vec("gradient", &g.at(1).floats(), &want.1, tol)?;
    let (h, _) = rust_subset::call(file, &format!("{name}_hessian"), vec![ka, m.clone()]);
    let h = h.unwrap();
    check_close(
        "hessian value",
        h.at(0).f(),
        want.0,
        tol * (1.0 + want.0.abs()),
    )?;
    check_vec("hessian gradient", &h.at(1).floats(), &want.1, tol)?;
    check_vec("hessian", &h.at(2).floats(), &want.2, tol)?;
    Ok(())
}

fn accumulate_moments(file: &syn::File, name: &str, blocks: &[Vec<f64>]) -> V {
    let n = rust_subset::const_usize(file, &format!("{}_MOMENTS", name.to_uppercase()));
    let mut m = V::arr(&vec![0.0; n]);
    for params in blocks {
        let mut args = vec![m];
        args.extend(params.iter().map(|p| V::F(*p)));
        let (_, env) = rust_subset::call(file, &format!("{name}_moments_at"), args);
        m = env["m"].clone();
    }
    m
}

#[test]
fn spring_spec_generates_correct_kernels() {
    let file = generated_file(SPRING);
    let rule = gauss_legendre(4);
    let mut runner = TestRunner::new(config(32));
    let strategy = (
        prop::array::uniform2(-2.0f64..2.0),
        prop::collection::vec((-2.0f64..2.0, -2.0f64..2.0, 0.1f64..10.0), 1..4),
        -3.0f64..3.0,
    );
    runner
        .run(&strategy, |(k, blocks, l)| {
            let blocks: Vec<Vec<f64>> = blocks.iter().map(|&(a, b, s)| vec![a, b, s]).collect();
            let m = accumulate_moments(&file, "spring", &blocks);
            let energy = |u: &[Hd; 2]| {
                let mut acc = Hd::c(0.0);
                for bl in &blocks {
                    acc = acc
                        + quad(&rule, 1, bl[0], bl[1], |x| {
                            let e = u[0] + u[1] * Hd::c(x);
                            Hd::c(0.5 * bl[2]) * e * e
                        });
                }
                acc
            };
            check_energy_kernels(&file, "spring", &k, &m, &derivs(&k, energy), 1e-10)?;
            // the point kernel
            let (v, _) = rust_subset::call(&file, "tip_value", vec![V::arr(&k), V::F(l)]);
            check_vec("tip", &v.unwrap().floats(), &[k[0] + k[1] * l], 1e-12)?;
            let (h, _) = rust_subset::call(&file, "tip_hessian", vec![V::arr(&k), V::F(l)]);
            let h = h.unwrap();
            check_vec("tip grad", &h.at(1).at(0).floats(), &[1.0, l], 1e-12)?;
            check_vec("tip hess", &h.at(2).at(0).floats(), &[0.0; 3], 1e-12)?;
            Ok(())
        })
        .unwrap();
}

/// One output of a point kernel as a function of the unknowns.
type Kinematics<'a> = dyn Fn(&[Hd; 3]) -> Hd + 'a;

/// The density of [`PLATE`], written independently.
fn plate_density<N: Num>(x: f64, y: f64, z: f64, k: &[N; 3], e0: f64, p1: f64, p2: f64) -> N {
    let [a, b, c] = *k;
    let (x, y, z) = (N::c(x), N::c(y), N::c(z));
    let one = N::c(1.0);
    let s = a + N::c(2.0) * b * x * y + N::c(0.5) * (c * y) * (c * y) - z * c;
    let t = N::c(e0) + s;
    let psi = N::c(p1 / 2.0) * t * t - N::c(p2 / 3.0) * t * t * t;
    psi + (one + s) * (one + b * y)
}

#[test]
fn plate_spec_generates_correct_kernels() {
    let file = generated_file(PLATE);
    let rule = gauss_legendre(6);
    let mut runner = TestRunner::new(config(12));
    let block = (
        (-1.0f64..1.0, 0.2f64..2.0),
        prop_oneof![-1.0f64..-0.1, 0.1f64..1.0],
        (-0.5f64..0.5, 0.1f64..1.0),
        (-0.05f64..0.05, 0.0f64..3.0, 0.0f64..3.0),
    )
        .prop_map(|((x0, len), w, (z0, th), (e0, p1, p2))| {
            vec![x0, x0 + len, w, z0, z0 + th, e0, p1, p2]
        });
    let strategy = (
        prop::array::uniform3(-0.5f64..0.5),
        prop::collection::vec(block, 1..3),
        (0.1f64..2.0, -1.0f64..1.0),
    );
    runner
        .run(&strategy, |(k, blocks, (l, h))| {
            let m = accumulate_moments(&file, "plate", &blocks);
            let energy = |u: &[Hd; 3]| {
                let mut acc = Hd::c(0.0);
                for bl in &blocks {
                    let (x0, x1, w, z0, z1, e0, p1, p2) =
                        (bl[0], bl[1], bl[2], bl[3], bl[4], bl[5], bl[6], bl[7]);
                    acc = acc
                        + quad(&rule, 1, z0, z1, |z| {
                            quad(&rule, 1, 0.0, w, |y| {
                                quad(&rule, 1, x0, x1, |x| plate_density(x, y, z, u, e0, p1, p2))
                            })
                        });
                }
                acc
            };
            check_energy_kernels(&file, "plate", &k, &m, &derivs(&k, energy), 1e-9)?;

            // point kernel: values, gradients and Hessians of each output
            let outputs: [&Kinematics<'_>; 3] = [
                &|u| Hd::c(l) + u[0] * Hd::c(l) + u[1] * Hd::c(l * l * h),
                &|u| (u[0] + Hd::c(2.0 * l * h) * u[1]).atan2(Hd::c(1.0) + u[0] * u[0]),
                &|u| (Hd::c(1.0) + u[2] * u[2]).sqrt() * (u[1] * Hd::c(l)).sin(),
            ];
            let args = vec![V::arr(&k), V::F(l), V::F(h)];
            let (v, _) = rust_subset::call(&file, "tip_value", args.clone());
            let (hs, _) = rust_subset::call(&file, "tip_hessian", args);
            let (v, hs) = (v.unwrap(), hs.unwrap());
            for (o, f) in outputs.iter().enumerate() {
                let (want_v, want_g, want_h) = derivs(&k, f);
                check_close("tip value", v.at(o).f(), want_v, 1e-12)?;
                check_close("tip hessian value", hs.at(0).at(o).f(), want_v, 1e-12)?;
                check_vec("tip gradient", &hs.at(1).at(o).floats(), &want_g, 1e-12)?;
                check_vec("tip hessian", &hs.at(2).at(o).floats(), &want_h, 1e-12)?;
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn spec_errors_report_line_and_column() {
    let bad = "unknowns a, b;\nlet e = a + * b;\n";
    let e = parse_spec(bad).unwrap_err();
    assert_eq!((e.line, e.col), (2, 13), "{e}");
    match generate(bad) {
        Err(GenError::Parse(p)) => assert_eq!((p.line, p.col), (2, 13)),
        other => panic!("{other:?}"),
    }
    // a missing `;` is reported at the next token
    let e = parse_spec("unknowns a\nlet e = a;").unwrap_err();
    assert_eq!((e.line, e.col), (2, 1), "{e}");
    // an unbalanced parenthesis at the end of the statement
    let e = parse_spec("unknowns a;\n  let e = (a + 1;").unwrap_err();
    assert_eq!((e.line, e.col), (2, 17), "{e}");
    // algebra failures name the kernel and its line
    let src = "unknowns a;\n\nintegral f(ks) = sin(x)*a over x in [0, ks];";
    match generate(src) {
        Err(GenError::Algebra { kernel, line, .. }) => {
            assert_eq!((kernel.as_str(), line), ("f", 3))
        }
        other => panic!("{other:?}"),
    }
}

/// 1-based (line, column) of char index `i` in `s`.
fn line_col(s: &str, i: usize) -> (usize, usize) {
    let before: Vec<char> = s.chars().take(i).collect();
    let line = 1 + before.iter().filter(|c| **c == '\n').count();
    let col = 1 + before.iter().rev().take_while(|c| **c != '\n').count();
    (line, col)
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn a_stray_character_is_reported_where_it_is(pos in any::<prop::sample::Index>()) {
        // the specs have no comments, so the lexer sees every character
        for spec in [SPRING, PLATE] {
            let n = spec.chars().count();
            let i = pos.index(n + 1);
            let mut s: String = spec.chars().take(i).collect();
            s.push('$');
            s.extend(spec.chars().skip(i));
            let e = parse_spec(&s).unwrap_err();
            prop_assert_eq!((e.line, e.col), line_col(&s, i), "{}", e);
            prop_assert!(e.found.contains('$'));
        }
    }
}

// ---------------------------------------------------------------------------
// 8. parser robustness

const TOKENS: &[&str] = &[
    "x",
    "y",
    "z",
    "a",
    "b",
    "1",
    "2",
    "0",
    "2.5",
    ".5",
    "1e3",
    "1.5e-2",
    "99999999999999999999",
    "+",
    "-",
    "*",
    "/",
    "^",
    "(",
    ")",
    ",",
    ";",
    "=",
    "[",
    "]",
    "{",
    "}",
    ":",
    "sin",
    "cos",
    "sqrt",
    "atan2",
    "d",
    "at",
    "let",
    "unknowns",
    "integral",
    "point",
    "over",
    "in",
    "#c\n",
    "\n",
    "2147483648",
    "-1",
    "^(",
    "0/0",
    "1/0",
];

fn check_parse_roundtrip(src: &str) -> Result<(), TestCaseError> {
    let mut a = Arena::new();
    if let Ok(e) = a.parse(src) {
        // whatever parses shows as text that parses back to the same node
        let shown = a.show(e).to_string();
        let again = a.parse(&shown);
        prop_assert!(again.is_ok(), "`{}` shown as `{}`: {:?}", src, shown, again);
        prop_assert_eq!(again.unwrap(), e, "`{}` shown as `{}`", src, shown);
    }
    Ok(())
}

fn mutate(base: &str, edits: &[(prop::sample::Index, bool, char)]) -> String {
    let mut s: Vec<char> = base.chars().collect();
    for (at, insert, ch) in edits {
        if *insert {
            let i = at.index(s.len() + 1);
            s.insert(i, *ch);
        } else if !s.is_empty() {
            let i = at.index(s.len());
            s.remove(i);
        }
    }
    s.into_iter().collect()
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn parsers_never_panic_on_printable_text(src in "[ -~\n]{0,60}") {
        let mut a = Arena::new();
        let _ = a.parse(&src);
        let _ = parse_spec(&src);
        check_parse_roundtrip(&src)?;
    }

    #[test]
    fn parsers_never_panic_on_token_soup(
        toks in prop::collection::vec(prop::sample::select(TOKENS), 0..40),
    ) {
        let src = toks.join(" ");
        let mut a = Arena::new();
        let _ = a.parse(&src);
        let _ = parse_spec(&src);
        check_parse_roundtrip(&src)?;
        let glued = toks.concat();
        let _ = a.parse(&glued);
        let _ = parse_spec(&glued);
        check_parse_roundtrip(&glued)?;
    }

    #[test]
    fn parse_spec_never_panics_on_mutated_specs(
        edits in prop::collection::vec(
            (any::<prop::sample::Index>(), any::<bool>(),
             prop::sample::select(&['(', ')', ',', ';', '=', '[', ']', '{', '}', '*', '^', '-',
                                    '/', 'x', 'a', ' ', '\n', '0', '9', '.', 'd', '#'][..])),
            1..6,
        ),
    ) {
        for base in [SPRING, PLATE] {
            let s = mutate(base, &edits);
            let _ = parse_spec(&s);
        }
    }
}

proptest! {
    #![proptest_config(config(24))]

    #[test]
    fn generate_never_panics_on_mutated_specs(
        edits in prop::collection::vec(
            (any::<prop::sample::Index>(), any::<bool>(),
             prop::sample::select(&['(', ')', ',', ';', '=', '*', '+', '-', 'x', 'a', 'b', 'k',
                                    ' ', '\n'][..])),
            1..4,
        ),
    ) {
        let s = mutate(SPRING, &edits);
        if let Ok(g) = generate(&s) {
            // a spec that generates gives a Rust file, or says the generator failed
            match format_file(&g.tokens) {
                Ok(_) | Err(GenError::Syntax(_)) => {}
                Err(other) => prop_assert!(false, "{:?}", other),
            }
        }
    }
}
