//! Tests of load continuation.

use super::*;

/// `sum_i cosh(x_i - t) + kappa/2 sum (x_{i+1} - x_i)^2 + s/2 |x|^2 ...`:
/// minimiser `x_i = t`. Newton's step is at most ~1 per iteration far from
/// it (`-tanh`), so a cold start at large `t` needs many iterations.
struct CoshChain {
    n: usize,
    t: f64,
    kappa: f64,
}

impl Energy for CoshChain {
    fn dim(&self) -> usize {
        self.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        let mut f = 0.0;
        for i in 0..self.n {
            f += (x[i] - self.t).cosh();
            if i + 1 < self.n {
                f += 0.5 * self.kappa * (x[i + 1] - x[i]).powi(2);
            }
        }
        f
    }
}
impl Gradient for CoshChain {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let n = self.n;
        for i in 0..n {
            g[i] = (x[i] - self.t).sinh();
        }
        for i in 0..n - 1 {
            let d = self.kappa * (x[i + 1] - x[i]);
            g[i + 1] += d;
            g[i] -= d;
        }
        self.energy(x)
    }
}
impl DenseHessian for CoshChain {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let n = self.n;
        h.fill(0.0);
        for i in 0..n {
            h[i * (n + 1)] = (x[i] - self.t).cosh();
        }
        for i in 0..n - 1 {
            let k = self.kappa;
            h[i * (n + 1)] += k;
            h[(i + 1) * (n + 1)] += k;
            h[i + (i + 1) * n] -= k;
            h[(i + 1) + i * n] -= k;
        }
        self.gradient(x, g)
    }
}

#[test]
fn continuation_succeeds_where_cold_start_fails() {
    let n = 4;
    let opts = NewtonOptions {
        max_iter: 8,
        ..Default::default()
    };
    let mut newton = Newton::new(n, opts);
    let mut p = Dense::new(CoshChain {
        n,
        t: 0.0,
        kappa: 0.5,
    });

    // Cold start at t = 20 fails within 8 iterations.
    p.problem.t = 20.0;
    let mut x = vec![0.0; n];
    let cold = newton.minimize(&mut p, &mut x);
    assert_eq!(cold.reason, Termination::MaxIterations);

    // Continuation with a deliberately too-large first step.
    let copts = ContinuationOptions {
        initial_step: 12.0,
        min_step: 1e-3,
        max_step: 20.0,
        ..Default::default()
    };
    let mut x = vec![0.0; n];
    let rep = continuation(0.0, 20.0, &mut x, &copts, |t, x| {
        p.problem.t = t;
        newton.minimize(&mut p, x)
    });
    assert!(rep.complete, "{rep:?}");
    assert_eq!(rep.reached, 20.0);
    assert!(
        rep.rejected > 0,
        "the first 12-unit step must fail: {rep:?}"
    );
    assert!(rep.last.converged());
    assert!(max_abs_diff(&x, &[20.0; 4]) < 1e-9);
    assert!(rep.newton_iterations > 0);

    // Back down (reverse direction), without predictor.
    let copts = ContinuationOptions {
        predictor: false,
        ..copts
    };
    let rep = continuation(20.0, 0.0, &mut x, &copts, |t, x| {
        p.problem.t = t;
        newton.minimize(&mut p, x)
    });
    assert!(rep.complete, "{rep:?}");
    assert!(max_abs_diff(&x, &[0.0; 4]) < 1e-9);
}

#[test]
fn continuation_stops_incomplete_and_restores_state() {
    let n = 2;
    let mut newton = Newton::new(
        n,
        NewtonOptions {
            max_iter: 8,
            ..Default::default()
        },
    );
    let mut p = Dense::new(CoshChain {
        n,
        t: 0.0,
        kappa: 0.0,
    });
    // Beyond t = 5 the "solver" refuses: the driver must stop at <= 5.
    let copts = ContinuationOptions {
        initial_step: 1.0,
        min_step: 0.01,
        max_step: 2.0,
        ..Default::default()
    };
    let mut x = vec![0.0; n];
    let mut calls = 0;
    let rep = continuation(0.0, 10.0, &mut x, &copts, |t, x| {
        calls += 1;
        p.problem.t = t;
        let r = newton.minimize(&mut p, x);
        if t > 5.0 {
            x.iter_mut().for_each(|v| *v = f64::NAN);
            Report {
                reason: Termination::NonFinite,
                ..r
            }
        } else {
            r
        }
    });
    assert!(!rep.complete);
    assert!(rep.reached <= 5.0 && rep.reached > 4.9, "{rep:?}");
    assert!(rep.rejected > 0);
    assert_eq!(rep.steps + rep.rejected, calls);
    assert!(
        max_abs_diff(&x, &[rep.reached; 2]) < 1e-9,
        "x restored to the last accepted state"
    );

    // max_steps bounds the attempts.
    let mut x = vec![0.0; n];
    let three = ContinuationOptions {
        max_steps: 3,
        ..copts
    };
    let rep = continuation(0.0, 10.0, &mut x, &three, |t, x| {
        p.problem.t = t;
        newton.minimize(&mut p, x)
    });
    assert!(!rep.complete);
    assert_eq!(rep.steps + rep.rejected, 3);

    // Invalid input: nothing is called.
    let rep = continuation(0.0, f64::NAN, &mut x, &copts, |_, _| unreachable!());
    assert_eq!(rep.last.reason, Termination::InvalidInput);
    let bad = ContinuationOptions {
        shrink: 2.0,
        ..Default::default()
    };
    let rep = continuation(0.0, 1.0, &mut x, &bad, |_, _| unreachable!());
    assert!(!rep.complete);

    // from == to: a single solve.
    let mut x = vec![0.3; n];
    let rep = continuation(0.3, 0.3, &mut x, &copts, |t, x| {
        p.problem.t = t;
        newton.minimize(&mut p, x)
    });
    assert!(rep.complete && rep.steps == 1);
}
