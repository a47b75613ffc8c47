//! Property tests: Newton on random convex energies.

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

}
