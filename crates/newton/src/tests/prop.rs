//! Property tests: Newton on random convex energies, Cholesky on random SPD matrices.

use super::*;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// On random convex quadratic + quartic energies, Newton converges
    /// and, when it reports convergence, the gradient recomputed
    /// independently is within gtol.
    #[test]
    fn newton_gradient_within_gtol(seed in any::<u64>(), n in 1usize..14, scale in 0.1f64..10.0) {
        let mut rng = Lcg::new(seed);
        let mut q = QuadQuartic::random(n, true, &mut rng);
        q.b.iter_mut().for_each(|b| *b *= scale);
        let mut x: Vec<f64> = (0..n).map(|_| 2.0 * rng.sym()).collect();
        let opts = NewtonOptions::default();
        let r = Newton::new(n, opts).minimize(&mut Dense::new(&mut q), &mut x);
        prop_assert!(r.converged(), "{}", r);
        let mut g = vec![0.0; n];
        q.gradient(&x, &mut g);
        let gn = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        prop_assert!(gn <= opts.gtol, "|g| = {}", gn);
        prop_assert_eq!(gn, r.residual_norm);
    }

    /// Cholesky + solve residual on random SPD matrices, both kernels.
    #[test]
    fn cholesky_residual(seed in any::<u64>(), n in 1usize..40) {
        let mut rng = Lcg::new(seed);
        let q = QuadQuartic::random(n, false, &mut rng);
        let mut l = q.a.clone();
        cholesky_in_place(n, &mut l).unwrap();
        let mut x = q.b.clone();
        cholesky_solve(n, &l, &mut x);
        let mut lp = q.a.clone();
        crate::dense::cholesky_portable(n, &mut lp).unwrap();
        let mut xp = q.b.clone();
        crate::dense::cholesky_solve_portable(n, &lp, &mut xp);
        let amax = q.a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (xx, tag) in [(&x, "kernel"), (&xp, "portable")] {
            let xmax = xx.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for i in 0..n {
                let r = q.ax(xx, i) - q.b[i];
                // Condition number of A = B B^T + 0.1 I can reach ~1e3 n.
                prop_assert!(r.abs() <= 1e-13 * n as f64 * amax * xmax.max(1.0), "{} row {}: {}", tag, i, r);
            }
        }
    }
}
