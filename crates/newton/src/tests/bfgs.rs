//! Tests of BFGS against Newton.

use super::*;

#[test]
fn bfgs_matches_newton() {
    let mut rng = Lcg::new(77);
    for &n in &[2usize, 10] {
        let mut xn = rosenbrock_start(n);
        let mut xb = rosenbrock_start(n);
        assert!(Newton::new(n, NewtonOptions::default())
            .minimize(&mut Dense::new(Rosenbrock { n }), &mut xn)
            .converged());
        let rb = Bfgs::new(n, bfgs_tight()).minimize(&mut Rosenbrock { n }, &mut xb);
        assert!(rb.converged(), "n = {n}: {rb}");
        assert_eq!(rb.hessian_evals, 0);
        assert!(max_abs_diff(&xn, &xb) < 1e-6, "n = {n}");
    }
    for _ in 0..3 {
        let n = 8;
        let mut q = QuadQuartic::random(n, true, &mut rng);
        let mut xn = vec![0.0; n];
        let mut xb = vec![0.0; n];
        assert!(Newton::new(n, NewtonOptions::default())
            .minimize(&mut Dense::new(&mut q), &mut xn)
            .converged());
        let rb = Bfgs::new(n, bfgs_tight()).minimize(&mut q, &mut xb);
        assert!(rb.converged(), "{rb}");
        assert!(max_abs_diff(&xn, &xb) < 1e-6);
    }
}

#[test]
fn bfgs_max_iterations() {
    let mut x = rosenbrock_start(2);
    let r = Bfgs::new(2, BfgsOptions::default().with_max_iter(2))
        .minimize(&mut Rosenbrock { n: 2 }, &mut x);
    assert_eq!(r.reason, Termination::MaxIterations);
    assert_eq!(r.iterations, 2);
}
