//! The restricted inertia against eigenvalues of `Z^T H Z`, and
//! `BorderedNewton::last_restricted_inertia`.

use super::chain::*;
use super::*;

// ------------------------------------------------------ restricted inertia

/// A [`Semiseparable`] as a [`LinearSystem`].
struct Semi(Semiseparable);

impl LinearSystem for Semi {
    fn diagonal_range(&self) -> (f64, f64) {
        self.0.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.0.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.0.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.0.apply(x, out)
    }
}

#[test]
fn restricted_inertia_matches_the_reduced_hessian() {
    let mut rng = fastrand::Rng::with_seed(99);
    let mut checked = 0;
    for trial in 0..400 {
        let n = 2 + trial % 11;
        // H = Q diag(d) Q^T with eigenvalues of both signs, some small
        let q = random_orthogonal(n, &mut rng);
        let d: Vec<f64> = (0..n)
            .map(|_| {
                let v = 2.0 * rng.f64() - 1.0;
                if rng.f64() < 0.2 {
                    1e-6 * v
                } else {
                    v
                }
            })
            .collect();
        let mut a = vec![0.0; n * n];
        for c in 0..n {
            for r in 0..n {
                a[r + n * c] = (0..n).map(|j| q[r + n * j] * d[j] * q[c + n * j]).sum();
            }
        }
        let c: Vec<f64> = (0..n).map(|_| 2.0 * rng.f64() - 1.0).collect();
        let mut m = DenseMatrix::new(n);
        m.matrix_mut().copy_from_slice(&a);
        let mut work = vec![0.0; 2 * n];
        let inertia = m.factor(0.0, PivotKind::Symmetric).unwrap();
        let r = restricted_inertia(&mut m, inertia, &c, &mut work).unwrap();
        let red = reduce(n, &a, &null_basis(&c));
        let neg = negative_eigenvalues(n - 1, &red).unwrap();
        assert_eq!(r.negative, neg, "trial {trial}, n = {n}, d = {d:?}");
        assert_eq!(r.positive, n - 1 - neg);
        // the same through factor_restricted_inertia
        assert_eq!(factor_restricted_inertia(&mut m, &c, &mut work), Ok(r));
        checked += 1;
    }
    assert_eq!(checked, 400);

    // structured: random semiseparable matrices against their dense form
    for trial in 0..60 {
        let (bn, nb) = (1 + trial % 4, 2 + trial % 5);
        let dim = bn * nb;
        let mut s = Semiseparable::new(bn, nb);
        for k in 0..nb {
            let mut blk = vec![0.0; bn * bn];
            for j in 0..bn {
                for i in j..bn {
                    let v = 2.0 * rng.f64() - 1.0;
                    blk[i + bn * j] = v;
                    blk[j + bn * i] = v;
                }
            }
            s.set_block(k, &blk);
            let (mut u, mut w) = (vec![0.0; bn], vec![0.0; bn]);
            for i in 0..bn {
                u[i] = 2.0 * rng.f64() - 1.0;
                w[i] = 0.5 * (2.0 * rng.f64() - 1.0);
            }
            s.set_coupling(k, &u, &w);
        }
        let mut a = vec![0.0; dim * dim];
        s.dense(&mut a);
        let c: Vec<f64> = (0..dim).map(|_| 2.0 * rng.f64() - 1.0).collect();
        let mut work = vec![0.0; 2 * dim];
        let mut semi = Semi(s);
        let Ok(r) = factor_restricted_inertia(&mut semi, &c, &mut work) else {
            continue;
        };
        let neg = negative_eigenvalues(dim - 1, &reduce(dim, &a, &null_basis(&c))).unwrap();
        assert_eq!(r.negative, neg, "structured trial {trial}");
        assert_eq!(r.positive, dim - 1 - neg);
    }

    // H singular but the bordered matrix regular: an error, documented
    let mut m = DenseMatrix::new(2);
    m.matrix_mut().copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
    let mut work = [0.0; 4];
    assert!(matches!(
        factor_restricted_inertia(&mut m, &[1.0, 0.0], &mut work),
        Err(RestrictedInertiaError::Hessian(
            FactorError::Singular { .. }
        ))
    ));
}

#[test]
fn bordered_newton_restricted_inertia_of_a_tip_controlled_chain() {
    // Controlling the tip rotation s_N: H is indefinite at small s_N (the
    // double well's maximum), but positive definite on s_N = const, so the
    // controlled equilibrium is stable although H is not.
    for (n, blocks, seed) in [(3, 6, 5), (2, 8, 6), (1, 16, 3)] {
        let m = chain(n, blocks, seed);
        let dim = m.size();
        let mut p = Dense::bordered(TipTarget {
            m: m.clone(),
            t: 0.0,
        });
        let mut bn = BorderedNewton::new(dim, NewtonOptions::default()).unwrap();
        let (mut x, mut lambda) = (vec![0.0; dim], 0.0);
        let mut indefinite = 0;
        for t in [0.05, 0.1, 0.2, 0.4, 0.8, 1.6] {
            p.problem.t = t;
            let r = bn.solve(&mut p, &mut x, &mut lambda);
            assert!(r.converged(), "{r}");
            let restricted = bn.last_restricted_inertia(&mut p).unwrap();
            // against Z^T H Z at the returned point
            let mut mm = m.clone();
            mm.lambda = lambda;
            mm.sweep(&x);
            let mut h = vec![0.0; dim * dim];
            mm.dense(&x, &mut h);
            let red = reduce(dim, &h, &null_basis(&m.arm));
            let neg = negative_eigenvalues(dim - 1, &red).unwrap();
            assert_eq!(restricted.negative, neg, "t = {t}");
            assert_eq!(restricted.positive, dim - 1 - neg);
            assert_eq!(restricted.negative, 0, "t = {t}");
            indefinite += usize::from(negative_eigenvalues(dim, &h).unwrap() > 0);
        }
        assert!(indefinite > 0, "{n} x {blocks}: H itself was indefinite");
    }
}
