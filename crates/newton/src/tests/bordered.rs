//! Tests of the bordered (displacement-controlled) Newton solve.

use super::*;

/// `E = 1/2 x^T A x + sum w_i x_i^4/4 - lambda b^T x`, target
/// `c = e^T x - t`.
struct BorderedQQ {
    q: QuadQuartic,
    e: Vec<f64>,
    t: f64,
}

impl DenseBorderedProblem for BorderedQQ {
    fn dim(&self) -> usize {
        self.q.n
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
        let n = self.q.n;
        for i in 0..n {
            out.g[i] = self.q.ax(x, i) + self.q.w[i] * x[i].powi(3) - lambda * self.q.b[i];
            out.g_lambda[i] = -self.q.b[i];
            out.c_x[i] = self.e[i];
        }
        h.copy_from_slice(&self.q.a);
        for i in 0..n {
            h[i * (n + 1)] += 3.0 * self.q.w[i] * x[i] * x[i];
        }
        out.c = (0..n).map(|i| self.e[i] * x[i]).sum::<f64>() - self.t;
        out.c_lambda = 0.0;
        true
    }
}

/// Plain energy of [`BorderedQQ`] at a fixed lambda.
struct AtLoad<'a>(&'a BorderedQQ, f64);

impl Energy for AtLoad<'_> {
    fn dim(&self) -> usize {
        self.0.q.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        let mut q = self.0.q.clone();
        q.b.iter_mut().for_each(|b| *b *= self.1);
        q.energy(x)
    }
}
impl Gradient for AtLoad<'_> {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let mut q = self.0.q.clone();
        q.b.iter_mut().for_each(|b| *b *= self.1);
        q.gradient(x, g)
    }
}
impl DenseHessian for AtLoad<'_> {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let mut q = self.0.q.clone();
        q.b.iter_mut().for_each(|b| *b *= self.1);
        q.hessian(x, g, h)
    }
}

#[test]
fn bordered_linear_matches_closed_form() {
    let mut rng = Lcg::new(21);
    for &n in &[1usize, 4, 12] {
        let q = QuadQuartic::random(n, false, &mut rng);
        let e: Vec<f64> = (0..n).map(|_| rng.sym()).collect();
        let mut p = Dense::bordered(BorderedQQ { q, e, t: 0.7 });
        let mut x = vec![0.0; n];
        let mut lambda = 0.0;
        let mut newton = BorderedNewton::new(n, NewtonOptions::default()).unwrap();
        let r = newton.solve(&mut p, &mut x, &mut lambda);
        assert!(r.converged(), "n = {n}: {r}");
        assert_eq!(r.iterations, 1, "linear problem: one step");
        let p = &p.problem;
        // Closed form: x = lambda A^{-1} b, e^T x = t.
        let z = lu_solve(n, &p.q.a, &p.q.b);
        let ez: f64 = (0..n).map(|i| p.e[i] * z[i]).sum();
        let lam = p.t / ez;
        assert!(
            (lambda - lam).abs() < 1e-9 * (1.0 + lam.abs()),
            "n = {n}: {lambda} vs {lam}"
        );
        for i in 0..n {
            assert!((x[i] - lam * z[i]).abs() < 1e-9 * (1.0 + (lam * z[i]).abs()));
        }
    }
}

#[test]
fn bordered_nonlinear_agrees_with_plain_newton() {
    let mut rng = Lcg::new(5);
    let n = 8;
    let q = QuadQuartic::random(n, true, &mut rng);
    let e: Vec<f64> = (0..n).map(|i| if i == n - 1 { 1.0 } else { 0.1 }).collect();
    let mut p = Dense::bordered(BorderedQQ { q, e, t: 2.5 });
    let mut x = vec![0.0; n];
    let mut lambda = 0.0;
    let mut newton = BorderedNewton::new(n, NewtonOptions::default()).unwrap();
    let r = newton.solve(&mut p, &mut x, &mut lambda);
    assert!(r.converged(), "{r}");
    assert_eq!(r.energy_evals, 0);
    assert!(r.hessian_evals > r.iterations);
    // Feed lambda back into plain minimisation from a cold start.
    let p = &p.problem;
    let mut y = vec![0.0; n];
    let rr = Newton::new(n, NewtonOptions::default())
        .minimize(&mut Dense::new(AtLoad(p, lambda)), &mut y);
    assert!(rr.converged(), "{rr}");
    let c: f64 = (0..n).map(|i| p.e[i] * y[i]).sum::<f64>() - p.t;
    assert!(c.abs() < 1e-8, "target residual {c}");
    assert!(max_abs_diff(&x, &y) < 1e-8);
}

/// One dof past a limit point in load: `E = x^4/4 - x^2/2 - lambda x`,
/// target `x = t` with `t` where `E'' < 0`. Displacement control passes
/// where load control cannot.
#[test]
fn bordered_passes_limit_point() {
    struct Snap {
        t: f64,
    }
    impl DenseBorderedProblem for Snap {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
            out.g[0] = x[0].powi(3) - x[0] - lambda;
            h[0] = 3.0 * x[0] * x[0] - 1.0;
            out.g_lambda[0] = -1.0;
            out.c = x[0] - self.t;
            out.c_x[0] = 1.0;
            out.c_lambda = 0.0;
            true
        }
    }
    for &t in &[-0.3, 0.2, 0.5, 1.5] {
        let mut x = [0.9];
        let mut lambda = 0.0;
        let r = BorderedNewton::new(1, NewtonOptions::default())
            .unwrap()
            .solve(&mut Dense::bordered(Snap { t }), &mut x, &mut lambda);
        assert!(r.converged(), "t = {t}: {r}");
        assert!((x[0] - t).abs() < 1e-12);
        assert!((lambda - (t * t * t - t)).abs() < 1e-12);
    }
}

#[test]
fn bordered_singular_and_nonfinite() {
    // c depends on nothing: the bordered Jacobian is singular (H is not).
    struct Flat;
    impl DenseBorderedProblem for Flat {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], _lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
            out.g[0] = x[0] - 1.0;
            h[0] = 1.0;
            out.g_lambda[0] = 0.0;
            out.c = 1.0;
            out.c_x[0] = 0.0;
            out.c_lambda = 0.0;
            true
        }
    }
    let mut x = [0.0];
    let mut lambda = 0.0;
    let mut newton = BorderedNewton::new(1, NewtonOptions::default()).unwrap();
    let mut flat = Dense::bordered(Flat);
    let r = newton.solve(&mut flat, &mut x, &mut lambda);
    assert_eq!(r.reason, Termination::Singular);
    // H itself was factorised: the step, not H, was singular.
    assert_eq!(
        newton.last_inertia(),
        Some(Inertia {
            positive: 1,
            negative: 0
        })
    );
    let mut lambda = f64::NAN;
    let r = newton.solve(&mut flat, &mut x, &mut lambda);
    assert_eq!(r.reason, Termination::NonFinite);
    assert_eq!(newton.last_inertia(), None);

    // A singular H (a zero pivot) is Singular even where the bordered
    // Jacobian is not: `E = x^3/3 - lambda x`, target x = 0, where E'' = 0
    // but [[0, -1], [1, 0]] is regular.
    struct Inflection;
    impl DenseBorderedProblem for Inflection {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
            out.g[0] = x[0] * x[0] - lambda;
            h[0] = 2.0 * x[0];
            out.g_lambda[0] = -1.0;
            out.c = x[0];
            out.c_x[0] = 1.0;
            out.c_lambda = 0.0;
            true
        }
    }
    let mut x = [0.0];
    let mut lambda = 0.5;
    let r = newton.solve(&mut Dense::bordered(Inflection), &mut x, &mut lambda);
    assert_eq!(r.reason, Termination::Singular, "{r}");
    assert_eq!((x[0], lambda), (0.0, 0.5), "the start is kept");
    assert_eq!(newton.last_inertia(), None);
}

/// A non-finite Hessian (with a finite residual) ends a bordered solve as
/// `NonFinite`, not `Singular`, and leaves the start unchanged.
#[test]
fn bordered_nonfinite_hessian_is_reported() {
    struct InfH;
    impl DenseBorderedProblem for InfH {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
            out.g[0] = x[0] - lambda;
            h[0] = f64::INFINITY;
            out.g_lambda[0] = -1.0;
            out.c = x[0] - 1.0;
            out.c_x[0] = 1.0;
            out.c_lambda = 0.0;
            true
        }
    }
    let mut p = Dense::bordered(InfH);
    let mut solver = BorderedNewton::new(1, NewtonOptions::default()).unwrap();
    let (mut x, mut lambda) = ([0.0], 0.0);
    let rep = solver.solve(&mut p, &mut x, &mut lambda);
    assert_eq!(rep.reason, Termination::NonFinite, "{rep:?}");
    assert_eq!((x[0], lambda), (0.0, 0.0));
    assert!(solver.last_inertia().is_none());
}
