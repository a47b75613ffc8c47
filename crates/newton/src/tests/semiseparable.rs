//! Tests of the semiseparable algebra against the dense path.

use super::chain::{ChainModel, Recording, SemiChain, StagedChain};
use super::*;

/// The structured Hessian is the dense one: same entries, same products.
#[test]
fn semiseparable_chain_hessian_is_exact() {
    let mut rng = Lcg::new(3);
    let mut m = ChainModel::random(3, 7, -0.3, 1.0, 0.4, 0.5, &mut rng);
    let dim = m.size();
    let x: Vec<f64> = (0..dim).map(|_| rng.sym()).collect();
    m.sweep(&x);
    let mut hs = Semiseparable::new(3, 7);
    m.structured(&x, &mut hs);
    let (mut hd, mut hr) = (vec![0.0; dim * dim], vec![0.0; dim * dim]);
    m.dense(&x, &mut hd);
    hs.dense(&mut hr);
    assert!(max_abs_diff(&hd, &hr) <= 1e-14 * norm_inf_of(&hd));
    // the dense Hessian is the derivative of the gradient (central
    // differences, exact for the quadratic part)
    let (mut gp, mut gm) = (vec![0.0; dim], vec![0.0; dim]);
    let step = 1e-5;
    for j in 0..dim {
        let mut xp = x.clone();
        xp[j] += step;
        m.gradient(&xp, &mut gp);
        xp[j] -= 2.0 * step;
        m.gradient(&xp, &mut gm);
        for i in 0..dim {
            let fd = (gp[i] - gm[i]) / (2.0 * step);
            assert!(
                (fd - hd[i + j * dim]).abs() <= 1e-7 * (1.0 + fd.abs()),
                "H[{i},{j}] = {} vs {fd}",
                hd[i + j * dim]
            );
        }
    }
    // and the gradient the derivative of the energy
    let mut g = vec![0.0; dim];
    m.gradient(&x, &mut g);
    for j in 0..dim {
        let mut xp = x.clone();
        xp[j] += step;
        let fp = m.energy(&xp);
        xp[j] -= 2.0 * step;
        let fm = m.energy(&xp);
        let fd = (fp - fm) / (2.0 * step);
        assert!((fd - g[j]).abs() <= 1e-7 * (1.0 + fd.abs()), "g[{j}]");
    }
}

/// A semiseparable-backed problem follows the dense path iterate by
/// iterate, from an indefinite start (shifted factorisations).
#[test]
fn semiseparable_newton_iterates_match_dense() {
    let mut rng = Lcg::new(8);
    for (n, blocks) in [(1, 12), (2, 7), (3, 6), (4, 10), (5, 4), (6, 3), (7, 2)] {
        let m = ChainModel::random(n, blocks, -0.5, 1.0, 0.05, 0.5, &mut rng);
        let dim = m.size();
        let start: Vec<f64> = (0..dim).map(|i| 0.05 * (i as f64 * 0.9).sin()).collect();
        assert!(m.negative_eigenvalues_at(&start) > 0, "indefinite start");
        let mut semi = Track::new(SemiChain::new(m.clone()));
        let mut x = start.clone();
        let r = Newton::new(dim, NewtonOptions::default()).minimize(&mut semi, &mut x);
        assert!(r.converged(), "{n} x {blocks}: {r}");
        assert!(r.max_shift > 0.0, "{r}");
        let mut dense = Dense::new(Track::new(m.clone()));
        let mut xd = start.clone();
        let rd = Newton::new(dim, NewtonOptions::default()).minimize(&mut dense, &mut xd);
        // far from the minimum (indefinite H, shifts, backtracking) Newton
        // is not contractive: rounding differences of the two algebras
        // grow by up to ~1e5 before the quadratic phase removes them
        assert_same_path(
            (&semi.iterates, &x, &r),
            (&dense.problem.iterates, &xd, &rd),
            1e-9,
            1e-12,
        );
        assert!(max_abs_diff(&x, &xd) <= 1e-12 * (1.0 + norm_inf_of(&x)));
        // a minimum: the structured factorisation's inertia says so
        assert_eq!(
            semi.p.h.factor(0.0, PivotKind::Symmetric).unwrap().negative,
            0
        );
        assert_eq!(m.negative_eigenvalues_at(&x), 0);
    }
}

/// A problem that stages its Hessians beside the factorisation takes the
/// same iterates bit for bit as one that does not (the landing of a full
/// step is evaluated with its Hessian, not with an energy first), with
/// fewer evaluations in all; from starts near and far, so that landings
/// are accepted, rejected and followed by chord steps.
#[test]
fn staged_hessians_keep_the_iterates_with_fewer_evaluations() {
    let mut rng = Lcg::new(21);
    let (mut fewer, mut chorded, mut rejected) = (0, 0, 0);
    for case in 0..40 {
        let (n, blocks) = [(4, 8), (3, 6), (5, 4), (2, 12)][case % 4];
        let m = ChainModel::random(
            n,
            blocks,
            -0.3 + 0.02 * case as f64,
            1.0,
            0.1,
            0.5,
            &mut rng,
        );
        let dim = m.size();
        let amp = [0.02, 0.3, 1.5, 4.0][case / 10];
        let start: Vec<f64> = (0..dim)
            .map(|i| amp * (i as f64 * 0.7 + case as f64).sin())
            .collect();
        let opts = NewtonOptions {
            gtol: 1e-11,
            ..NewtonOptions::default()
        };
        let mut plain = Track::new(SemiChain::new(m.clone()));
        let mut x = start.clone();
        let r = Newton::new(dim, opts).minimize(&mut plain, &mut x);
        let mut staged = StagedChain::new(m);
        let mut xs = start.clone();
        let rs = Newton::new(dim, opts).minimize(&mut staged, &mut xs);
        assert!(r.converged(), "case {case}: {r}");
        assert_eq!(rs.reason, r.reason, "case {case}");
        assert_eq!(bits(&xs), bits(&x), "case {case}: {rs} against {r}");
        assert_eq!(rs.energy.to_bits(), r.energy.to_bits(), "case {case}");
        assert_eq!(
            (rs.iterations, rs.chord_steps, rs.factorizations),
            (r.iterations, r.chord_steps, r.factorizations),
            "case {case}"
        );
        let evals = |r: &Report| r.energy_evals + r.gradient_evals + r.hessian_evals;
        assert!(evals(&rs) <= evals(&r), "case {case}: {rs} against {r}");
        fewer += usize::from(evals(&rs) < evals(&r));
        chorded += usize::from(rs.gradient_evals < r.gradient_evals);
        rejected += usize::from(rs.energy_evals > 0 && rs.hessian_evals > r.hessian_evals);
    }
    // every kind of landing happened
    assert!(
        fewer >= 10 && chorded > 0 && rejected > 0,
        "{fewer} {chorded} {rejected}"
    );
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The bordered solve of a semiseparable-backed chain agrees with the
/// same chain through [`DenseBordered`] along a path in the controlled
/// tip rotation that starts where `H` is indefinite (the load falls) and
/// passes a limit point in load to where `H` is definite (the load rises).
/// After every solve, `last_inertia` is that of the dense `H` where the
/// solver last factorised it.
#[test]
fn bordered_semiseparable_chain_matches_dense_past_a_limit_point() {
    let mut rng = Lcg::new(12);
    for (n, blocks) in [(3, 8), (2, 10), (4, 4), (1, 16), (5, 3), (6, 3)] {
        let m =
            ChainModel::random(n, blocks, 0.3, 0.5, 0.5, 0.2, &mut rng).tip_controlled(2.0, 1.0);
        let dim = m.size();
        let mut semi = Recording::new(SemiChain::new(m.clone()));
        let mut dense = Recording::new(Dense::bordered(m.clone()));
        let opts = NewtonOptions::default();
        let mut bs = BorderedNewton::new(dim, opts).unwrap();
        let mut bd = BorderedNewton::new(dim, opts).unwrap();
        let (mut xs, mut ls) = (vec![0.0; dim], 0.0);
        let (mut xd, mut ld) = (vec![0.0; dim], 0.0);
        let mut loads = vec![];
        let mut unstable = vec![];
        for step in 1..=20 {
            let t = 0.1 * step as f64;
            semi.p.m.t = t;
            dense.p.problem.t = t;
            let rs = bs.solve(&mut semi, &mut xs, &mut ls);
            let rd = bd.solve(&mut dense, &mut xd, &mut ld);
            assert!(rs.converged(), "{n} x {blocks}, t = {t}: {rs}");
            assert!(rd.converged(), "{n} x {blocks}, t = {t}: {rd}");
            let scale = 1.0 + norm_inf_of(&xs);
            let dx = max_abs_diff(&xs, &xd);
            assert!(
                dx <= 1e-10 * scale,
                "{n} x {blocks}, t = {t}: x differs by {dx}"
            );
            assert!(
                (ls - ld).abs() <= 1e-10 * (1.0 + ls.abs()),
                "{n} x {blocks}, t = {t}: lambda {ls} vs {ld}"
            );
            // the target holds
            let c: f64 = (0..dim).map(|i| m.e[i] * xs[i]).sum::<f64>() - t;
            assert!(c.abs() <= 1e-10);
            // the inertia of the last factorisation, both ways
            for (bn, at, what) in [
                (&bs, &semi.factored_at, "structured"),
                (&bd, &dense.factored_at, "dense"),
            ] {
                let inertia = bn.last_inertia().expect("a factorisation");
                let (xf, lf) = at.clone().unwrap();
                let mut mf = m.clone();
                mf.lambda = lf;
                let neg = mf.negative_eigenvalues_at(&xf);
                assert_eq!(
                    (inertia.negative, inertia.positive),
                    (neg, dim - neg),
                    "{n} x {blocks}, t = {t}, {what}"
                );
            }
            loads.push(ls);
            unstable.push(m.negative_eigenvalues_at(&xs));
        }
        // H indefinite at the first solutions, definite at the last ones
        assert_eq!(unstable[0], 1, "{unstable:?}");
        assert_eq!(*unstable.last().unwrap(), 0, "{unstable:?}");
        // the load falls, then rises: a limit point was passed
        assert!(loads[1] < loads[0] && loads[19] > loads[18], "{loads:?}");
        let (kmin, _) = loads
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))
            .unwrap();
        assert!(kmin > 0 && kmin < 19, "{loads:?}");
    }
}

/// `last_inertia` from cold starts, where the solve takes several steps:
/// the inertia of `H` at the last factorised point (not the returned one),
/// for the structured and the dense algebra alike.
#[test]
fn bordered_last_inertia_matches_dense_eigenvalues() {
    let mut rng = Lcg::new(31);
    let m = ChainModel::random(3, 6, 0.3, 0.5, 0.5, 0.2, &mut rng).tip_controlled(2.0, 1.0);
    let dim = m.size();
    let opts = NewtonOptions::default();
    let mut seen = vec![];
    for &t in &[0.1, 0.4, 1.6] {
        for structured in [true, false] {
            let mut model = m.clone();
            model.t = t;
            let mut x = vec![0.0; dim];
            let mut lambda = 0.0;
            let mut bn = BorderedNewton::new(dim, opts).unwrap();
            let (r, at) = if structured {
                let mut p = Recording::new(SemiChain::new(model));
                (bn.solve(&mut p, &mut x, &mut lambda), p.factored_at)
            } else {
                let mut p = Recording::new(Dense::bordered(model));
                (bn.solve(&mut p, &mut x, &mut lambda), p.factored_at)
            };
            assert!(r.converged(), "t = {t}: {r}");
            assert!(r.iterations > 1, "{r}");
            let inertia = bn.last_inertia().expect("a factorisation");
            let (xf, lf) = at.unwrap();
            assert!(
                max_abs_diff(&xf, &x) > 0.0,
                "factorised before the last step"
            );
            let mut mf = m.clone();
            mf.lambda = lf;
            let neg = mf.negative_eigenvalues_at(&xf);
            assert_eq!(inertia.negative, neg, "t = {t}, structured {structured}");
            assert_eq!(inertia.positive, dim - neg);
            seen.push(neg);
        }
    }
    assert!(seen.iter().any(|&k| k > 0) && seen.contains(&0), "{seen:?}");
}

/// `Newton::minimize` on a release-size chain (4 x 500 unknowns) converges
/// through the semiseparable algebra, and agrees with the dense path (a
/// 2000 x 2000 Cholesky per iteration, about a second each in a debug
/// build: that comparison starts near the minimum, where Newton takes
/// three steps).
#[test]
fn newton_semiseparable_release_size_matches_dense() {
    let mut rng = Lcg::new(500);
    let mut m = ChainModel::random(4, 500, 0.5, 0.1, 0.002, 0.1, &mut rng);
    m.lambda = 0.3;
    let dim = m.size();
    let mut semi = SemiChain::new(m.clone());
    let mut x = vec![0.0; dim];
    let mut newton = Newton::new(dim, NewtonOptions::default());
    let r = newton.minimize(&mut semi, &mut x);
    assert!(r.converged(), "{r}");
    assert!(r.iterations >= 4, "a nonlinear problem: {r}");
    let mut g = vec![0.0; dim];
    semi.gradient(&x, &mut g);
    assert!(norm_inf_of(&g) <= 1e-10);
    assert_eq!(
        semi.h.factor(0.0, PivotKind::Symmetric).unwrap().negative,
        0
    );
    // both algebras from the same start near the minimum
    let start: Vec<f64> = (0..dim)
        .map(|i| x[i] + 0.005 * (0.37 * i as f64).sin())
        .collect();
    let mut xs = start.clone();
    let rs = newton.minimize(&mut semi, &mut xs);
    let mut dense = Dense::new(m);
    let mut xd = start;
    let rd = newton.minimize(&mut dense, &mut xd);
    assert!(rs.converged() && rd.converged(), "{rs}\n{rd}");
    assert_eq!(
        (rs.iterations, rs.factorizations),
        (rd.iterations, rd.factorizations)
    );
    assert!(rd.factorizations <= 3, "{rd}");
    let scale = 1.0 + norm_inf_of(&x);
    for (y, what) in [(&xs, "structured"), (&xd, "dense")] {
        let d = max_abs_diff(&x, y);
        assert!(d <= 1e-10 * scale, "{what} differs by {d}");
    }
}

/// As [`newton_nonfinite_hessian_is_reported`], for a problem whose
/// Hessian is a [`Semiseparable`]: a non-finite entry (in a block, or in a
/// coupling vector) is `FactorError::NonFinite` (the contract of
/// [`LinearSystem::factor`]) and the solve ends `NonFinite` at the first
/// factorisation, instead of escalating the shift.
#[test]
fn newton_nonfinite_structured_hessian_is_reported() {
    struct BadSemi {
        p: SemiChain,
        coupling: bool,
    }
    impl Energy for BadSemi {
        fn dim(&self) -> usize {
            self.p.m.size()
        }
        fn energy(&mut self, x: &[f64]) -> f64 {
            self.p.energy(x)
        }
    }
    impl Gradient for BadSemi {
        fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
            self.p.gradient(x, g)
        }
    }
    impl Hessian for BadSemi {
        fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
            let f = self.p.hessian(x, g);
            if self.coupling {
                let n = self.p.h.block_size();
                let (mut u, mut w) = (vec![0.0; n], vec![0.0; n]);
                self.p.h.coupling(0, &mut u, &mut w);
                w[0] = f64::NAN;
                self.p.h.set_coupling(0, &u, &w);
            } else {
                let n = self.p.h.block_size();
                let mut b = vec![0.0; n * n];
                self.p.h.block(2, &mut b);
                b[4] = f64::INFINITY;
                self.p.h.set_block(2, &b);
            }
            f
        }
    }
    impl LinearSystem for BadSemi {
        fn diagonal_range(&self) -> (f64, f64) {
            self.p.diagonal_range()
        }
        fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
            self.p.factor(tau, kind)
        }
        fn solve(&mut self, b: &mut [f64]) {
            self.p.solve(b)
        }
        fn apply(&self, x: &[f64], out: &mut [f64]) {
            self.p.apply(x, out)
        }
    }
    let mut rng = Lcg::new(3);
    let m = ChainModel::random(3, 4, 0.5, 0.5, 0.1, 0.1, &mut rng);
    for coupling in [false, true] {
        let mut bad = BadSemi {
            p: SemiChain::new(m.clone()),
            coupling,
        };
        let mut x = vec![0.1; 12];
        let r = Newton::new(12, NewtonOptions::default()).minimize(&mut bad, &mut x);
        assert_eq!(r.reason, Termination::NonFinite, "coupling {coupling}: {r}");
        assert_eq!(r.factorizations, 1, "{r}");
        assert!(x.iter().all(|v| v.is_finite()));
        for kind in [PivotKind::Cholesky, PivotKind::Symmetric] {
            assert!(
                matches!(bad.factor(0.0, kind), Err(FactorError::NonFinite { .. })),
                "coupling {coupling}, {kind:?}: {:?}",
                bad.factor(0.0, kind)
            );
        }
    }
}

/// `M` from the solves of the last factorisation: column `j` of `M^-1`
/// is the solve of `e_j`, and faer's LU inverts that.
fn matrix_of_solves(hs: &mut Semiseparable) -> Vec<f64> {
    let dim = hs.dim();
    let mut inv = vec![0.0; dim * dim];
    for j in 0..dim {
        let col = &mut inv[j * dim..(j + 1) * dim];
        col[j] = 1.0;
        hs.solve(col);
    }
    let mut m = vec![0.0; dim * dim];
    for j in 0..dim {
        let mut e = vec![0.0; dim];
        e[j] = 1.0;
        m[j * dim..(j + 1) * dim].copy_from_slice(&lu_solve(dim, &inv, &e));
    }
    m
}

/// The modified factorisation is the exact one of `H + tau I + E`, with
/// `E` block diagonal and positive semidefinite, zero where `H + tau I` is
/// positive definite, and `H + tau I + E` positive definite: checked on
/// the matrix its solves invert, with faer's LU and eigenvalues.
#[test]
fn modified_pivots_add_a_block_diagonal_semidefinite_term() {
    let mut rng = Lcg::new(11);
    for (n, blocks) in [(4, 1), (6, 1), (3, 6), (4, 8), (2, 5), (5, 3)] {
        let mut m = ChainModel::random(n, blocks, -0.5, 1.0, 0.05, 0.5, &mut rng);
        let dim = m.size();
        let x: Vec<f64> = (0..dim).map(|i| 0.05 * (i as f64 * 0.9).sin()).collect();
        m.sweep(&x);
        let mut hs = Semiseparable::new(n, blocks);
        m.structured(&x, &mut hs);
        let mut h = vec![0.0; dim * dim];
        hs.dense(&mut h);
        let negative = negative_eigenvalues(dim, &h).unwrap();
        assert!(negative > 0, "{n} x {blocks}: indefinite");
        let scale = norm_inf_of(&h);
        // a shift that leaves it indefinite, and one that makes it definite
        let definite = 1.1 * -min_eigenvalue(dim, &h);
        for tau in [0.0, 0.1 * definite, definite] {
            let inertia = hs.factor(tau, PivotKind::Modified).unwrap();
            assert_eq!((inertia.positive, inertia.negative), (dim, 0));
            let mm = matrix_of_solves(&mut hs);
            let mut e = mm.clone();
            for (ei, hi) in e.iter_mut().zip(&h) {
                *ei -= hi;
            }
            for i in 0..dim {
                e[i * (dim + 1)] -= tau;
            }
            let tol = 1e-9 * (scale + tau);
            assert_eq!(
                negative_eigenvalues(dim, &mm),
                Some(0),
                "{n} x {blocks}, tau {tau}"
            );
            for j in 0..dim {
                for i in 0..dim {
                    let v = e[i + j * dim];
                    assert!((v - e[j + i * dim]).abs() <= tol, "symmetric");
                    if i / n != j / n || tau == definite {
                        assert!(
                            v.abs() <= tol,
                            "{n} x {blocks}, tau {tau}: E[{i},{j}] = {v}"
                        );
                    }
                }
            }
            if tau == 0.0 {
                assert!(norm_inf_of(&e) > 1e-3 * scale, "something was modified");
            }
            for k in 0..blocks {
                let mut ek = vec![0.0; n * n];
                for j in 0..n {
                    for i in 0..n {
                        ek[i + j * n] = e[k * n + i + (k * n + j) * dim];
                    }
                }
                assert!(
                    min_eigenvalue(n, &ek) >= -tol,
                    "block {k} of E semidefinite"
                );
            }
        }
    }
}

/// One 2 x 2 block in closed form: the modified matrix keeps the
/// eigenvectors and turns the negative eigenvalue's sign.
#[test]
fn modified_pivots_of_one_block_flip_the_negative_eigenvalue() {
    let (a, b, c) = (0.3f64, -1.7, 2.2);
    let mid = 0.5 * (a + c);
    let r = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let (l1, l2) = (mid + r, mid - r);
    assert!(l2 < 0.0);
    let mut hs = Semiseparable::new(2, 1);
    hs.set_block(0, &[a, b, b, c]);
    hs.clear_coupling();
    hs.factor(0.0, PivotKind::Modified).unwrap();
    let mm = matrix_of_solves(&mut hs);
    // trace and determinant of Q diag(l1, -l2) Q^T
    let (tr, det) = (mm[0] + mm[3], mm[0] * mm[3] - mm[1] * mm[2]);
    assert!((tr - (l1 - l2)).abs() <= 1e-13 * l1, "{tr}");
    assert!((det + l1 * l2).abs() <= 1e-13 * l1 * l1, "{det}");
    // the eigenvector of l1 is kept: M v1 = l1 v1
    let v = [b, l1 - a];
    let mv = [mm[0] * v[0] + mm[2] * v[1], mm[1] * v[0] + mm[3] * v[1]];
    assert!((mv[0] - l1 * v[0]).abs() + (mv[1] - l1 * v[1]).abs() <= 1e-12 * l1);
}
