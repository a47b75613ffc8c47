//! The structured factorisation and its pivots against dense references.

use super::pivot::CERTIFIED_RATIO;
use super::*;

/// A random structured matrix, its dense form, and a right-hand side.
fn random(n: usize, nb: usize, seed: u64, shift: f64) -> (Semiseparable, Vec<f64>) {
    let mut rng = fastrand::Rng::with_seed(seed);
    let mut m = Semiseparable::new(n, nb);
    for k in 0..nb {
        // a symmetric block with a diagonal shift (sign picks the definiteness)
        let mut a = vec![0.0; n * n];
        for c in 0..n {
            for r in 0..=c {
                let v = rng.f64() - 0.5;
                a[r + n * c] = v;
                a[c + n * r] = v;
            }
            a[c + n * c] += shift;
        }
        m.set_block(k, &a);
        let (mut u, mut w) = (vec![0.0; n], vec![0.0; n]);
        for i in 0..n {
            u[i] = 0.3 * (rng.f64() - 0.5);
            w[i] = 0.3 * (rng.f64() - 0.5);
        }
        m.set_coupling(k, &u, &w);
    }
    let dim = n * nb;
    let mut h = vec![0.0; dim * dim];
    m.dense(&mut h);
    (m, h)
}

fn dense_solve(dim: usize, h: &[f64], b: &[f64]) -> Vec<f64> {
    // Gaussian elimination with partial pivoting, written here
    let mut a = h.to_vec();
    let mut x = b.to_vec();
    for c in 0..dim {
        let p = (c..dim)
            .max_by(|&i, &j| a[i + dim * c].abs().total_cmp(&a[j + dim * c].abs()))
            .unwrap();
        for k in 0..dim {
            a.swap(c + dim * k, p + dim * k);
        }
        x.swap(c, p);
        for r in c + 1..dim {
            let f = a[r + dim * c] / a[c + dim * c];
            for k in c..dim {
                a[r + dim * k] -= f * a[c + dim * k];
            }
            x[r] -= f * x[c];
        }
    }
    for r in (0..dim).rev() {
        let mut v = x[r];
        for k in r + 1..dim {
            v -= a[r + dim * k] * x[k];
        }
        x[r] = v / a[r + dim * r];
    }
    x
}

/// The factorised `m` solves `b` as a dense elimination of its dense form
/// `h` does, to 1e-10 of the solution's size.
fn solves_like_dense(m: &mut Semiseparable, h: &[f64], b: &[f64], what: &str) {
    let dim = b.len();
    let mut x = b.to_vec();
    m.solve(&mut x);
    let want = dense_solve(dim, h, b);
    let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for i in 0..dim {
        assert!((x[i] - want[i]).abs() <= 1e-10 * scale, "{what}: {i}");
    }
}

#[test]
fn structured_solves_match_a_dense_elimination() {
    for (n, nb, seed) in [(1, 1, 1), (4, 1, 2), (4, 3, 3), (5, 8, 4), (3, 40, 5)] {
        for (shift, kind) in [(4.0, PivotKind::Cholesky), (0.3, PivotKind::Symmetric)] {
            let (mut m, h) = random(n, nb, seed, shift);
            let dim = n * nb;
            let b: Vec<f64> = (0..dim).map(|i| (i as f64 * 0.7).sin()).collect();
            // apply against the dense product
            let mut hb = vec![0.0; dim];
            m.apply(&b, &mut hb);
            for i in 0..dim {
                let d: f64 = (0..dim).map(|j| h[i + dim * j] * b[j]).sum();
                assert!((d - hb[i]).abs() <= 1e-13 * (1.0 + d.abs()), "apply {i}");
            }
            let inertia = match m.factor(0.0, kind) {
                Ok(i) => i,
                Err(FactorError::NotPositiveDefinite { .. }) if kind == PivotKind::Cholesky => {
                    continue
                }
                Err(e) => panic!("{e:?}"),
            };
            assert_eq!(inertia.positive + inertia.negative, dim);
            solves_like_dense(&mut m, &h, &b, &format!("n {n} N {nb}"));
        }
    }
}

/// The Cholesky path decides definiteness from the blocks and the
/// chain's scalars (module docs): it must say yes exactly when the
/// whole matrix is positive definite, also when every block is
/// positive definite and the coupling alone makes it indefinite, and
/// then solve like a dense elimination.
#[test]
fn cholesky_succeeds_exactly_when_positive_definite() {
    let (mut checked, mut by_coupling) = (0, 0);
    for seed in 0..60u64 {
        let (n, nb) = [(2, 3), (4, 8), (5, 4), (3, 12)][seed as usize % 4];
        // definite blocks (shift 1.5 > the random part's reach for
        // small n), coupling from weak to dominant
        let (mut m, _) = random(n, nb, 100 + seed, 1.5 + 0.5 * n as f64);
        let grow = [1.0, 4.0, 8.0, 16.0][(seed / 4) as usize % 4];
        for k in 0..nb {
            let (mut u, mut w) = (vec![0.0; n], vec![0.0; n]);
            m.coupling(k, &mut u, &mut w);
            u.iter_mut().for_each(|v| *v *= grow);
            w.iter_mut().for_each(|v| *v *= grow);
            m.set_coupling(k, &u, &w);
        }
        let dim = n * nb;
        let mut h = vec![0.0; dim * dim];
        m.dense(&mut h);
        let mut v = h.clone();
        let mut lam = vec![0.0; dim];
        let mut scratch = vec![0.0; dim * dim + 4 * dim];
        jacobi(dim, &mut v, &mut lam, &mut scratch).unwrap();
        let lo = lam.iter().fold(f64::INFINITY, |a, &l| a.min(l));
        let hi = lam.iter().fold(0.0f64, |a, &l| a.max(l.abs()));
        if lo.abs() <= 1e-9 * hi {
            continue; // too close to call
        }
        checked += 1;
        let blocks_definite = (0..nb).all(|k| {
            let mut b = vec![0.0; n * n];
            m.block(k, &mut b);
            cholesky::<0>(n, &mut b).is_ok()
        });
        assert!(
            blocks_definite,
            "seed {seed}: the blocks are meant to be definite"
        );
        match m.factor(0.0, PivotKind::Cholesky) {
            Ok(inertia) => {
                assert!(lo > 0.0, "seed {seed}: accepted with eigenvalue {lo}");
                assert_eq!(inertia.positive, dim);
                let b: Vec<f64> = (0..dim).map(|i| (i as f64 * 0.3).cos()).collect();
                solves_like_dense(&mut m, &h, &b, &format!("seed {seed}"));
            }
            Err(FactorError::NotPositiveDefinite { index }) => {
                assert!(lo < 0.0, "seed {seed}: refused with eigenvalue {lo}");
                assert!(index < dim);
                by_coupling += 1;
            }
            Err(e) => panic!("seed {seed}: {e:?}"),
        }
    }
    assert!(checked >= 40, "{checked}");
    assert!(
        by_coupling >= 5,
        "only {by_coupling} indefinite by the coupling"
    );
}

/// A symmetric `n x n` matrix with the given eigenvalues: `Q diag(lam)
/// Q^T` with `Q` a product of `n` random Householder reflections.
fn with_eigenvalues(lam: &[f64], rng: &mut fastrand::Rng) -> Vec<f64> {
    let n = lam.len();
    let mut q: Vec<f64> = (0..n * n)
        .map(|k| if k % (n + 1) == 0 { 1.0 } else { 0.0 })
        .collect();
    for _ in 0..n {
        let v: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
        let vv = dot(&v, &v);
        for c in 0..n {
            let col = &mut q[c * n..(c + 1) * n];
            let f = 2.0 * dot(&v, col) / vv;
            col.iter_mut().zip(&v).for_each(|(x, vi)| *x -= f * vi);
        }
    }
    let mut a = vec![0.0; n * n];
    for r in 0..n {
        for c in 0..n {
            a[r + n * c] = (0..n).map(|k| q[r + n * k] * lam[k] * q[c + n * k]).sum();
        }
    }
    a
}

/// The certificate is sound (it never passes a matrix whose known
/// smallest eigenvalue is not above CERTIFIED_RATIO times its largest,
/// nor an indefinite one) and useful (it passes every matrix of
/// condition up to 1e8).
#[test]
fn certified_pivots_are_clearly_positive_definite() {
    let mut rng = fastrand::Rng::with_seed(7);
    let (mut passed, mut refused) = (0, 0);
    for trial in 0..600 {
        let n = [1, 2, 4, 5, 6, 9][trial % 6];
        // condition 10^0 .. 10^16, some indefinite
        let cond = 10f64.powf(16.0 * rng.f64());
        let scale = 10f64.powf(6.0 * rng.f64() - 3.0);
        let mut lam: Vec<f64> = (0..n).map(|_| scale * cond.powf(-rng.f64())).collect();
        lam[0] = scale;
        if n > 1 {
            lam[n - 1] = scale / cond;
        }
        let indefinite = trial % 5 == 0 && n > 1;
        if indefinite {
            lam[n - 1] = -lam[n - 1];
        }
        let p = with_eigenvalues(&lam, &mut rng);
        let mut scratch = vec![0.0; n * n + 4 * n];
        let ok = certified_positive::<0>(n, &p, &mut scratch);
        let ratio = lam.iter().fold(f64::INFINITY, |a, &l| a.min(l)) / scale;
        if ok {
            assert!(!indefinite, "trial {trial}: an indefinite matrix passed");
            // the construction's own rounding is about 1e-15 of the scale
            assert!(
                ratio > CERTIFIED_RATIO - 1e-14,
                "trial {trial}: ratio {ratio:e}"
            );
            passed += 1;
        } else {
            if !indefinite {
                assert!(cond > 1e8, "trial {trial}: refused at condition {cond:e}");
            }
            refused += 1;
        }
    }
    assert!(
        passed > 100 && refused > 100,
        "{passed} passed, {refused} refused"
    );
}

/// `inertia` counts as the symmetric factorisation does, with the same
/// errors, and as a dense eigenvalue count of the whole matrix: on
/// random chains from definite to indefinite (by the blocks or by the
/// coupling) and on a chain with a singular pivot.
#[test]
fn inertia_alone_matches_the_symmetric_factorisation() {
    let mut compared = [0usize; 2]; // [definite, indefinite]
    for seed in 0..80u64 {
        let (n, nb) = [(4, 6), (5, 8), (6, 3), (3, 12)][seed as usize % 4];
        let shift = [-0.5, 0.2, 0.6, 1.5, 4.0][(seed / 4) as usize % 5];
        let (mut m, h) = random(n, nb, 300 + seed, shift);
        let want = m.factor(0.0, PivotKind::Symmetric);
        let got = m.inertia(0.0);
        assert_eq!(got, want, "seed {seed}");
        let Ok(inertia) = got else { continue };
        let dim = n * nb;
        let (mut v, mut lam) = (h.clone(), vec![0.0; dim]);
        let mut scratch = vec![0.0; dim * dim + 4 * dim];
        jacobi(dim, &mut v, &mut lam, &mut scratch).unwrap();
        let hi = lam.iter().fold(0.0f64, |a, &l| a.max(l.abs()));
        if lam.iter().any(|l| l.abs() <= 1e-9 * hi) {
            continue; // too close to call
        }
        let neg = lam.iter().filter(|&&l| l < 0.0).count();
        assert_eq!(
            (inertia.negative, inertia.positive),
            (neg, dim - neg),
            "seed {seed}"
        );
        compared[usize::from(neg > 0)] += 1;
    }
    assert!(compared[0] >= 10 && compared[1] >= 10, "{compared:?}");
    // a rank-one pivot: singular both ways
    let (mut m, _) = random(4, 3, 5, 2.0);
    let mut blk = [0.0; 16];
    for c in 0..4 {
        for r in 0..4 {
            blk[r + 4 * c] = (r + 1) as f64 * (c + 1) as f64;
        }
    }
    m.set_block(1, &blk);
    let want = m.factor(0.0, PivotKind::Symmetric);
    assert!(
        matches!(want, Err(FactorError::Singular { block: 1 })),
        "{want:?}"
    );
    assert_eq!(m.inertia(0.0), want);
}

#[test]
fn inertia_counts_negative_eigenvalues() {
    // a block diagonal with known signs, then a coupled one against the
    // count from a dense symmetric eigen solve by Jacobi on the whole
    let (mut m, h) = random(3, 5, 9, 0.1);
    let dim = 15;
    let mut v = h.clone();
    let mut lam = vec![0.0; dim];
    let mut scratch = vec![0.0; dim * dim + 4 * dim];
    jacobi(dim, &mut v, &mut lam, &mut scratch).unwrap();
    let neg = lam.iter().filter(|&&l| l < 0.0).count();
    let inertia = m.factor(0.0, PivotKind::Symmetric).unwrap();
    assert_eq!(inertia.negative, neg, "{lam:?}");
    // positive definite exactly when Cholesky succeeds
    let ok = m.factor(0.0, PivotKind::Cholesky).is_ok();
    assert_eq!(ok, neg == 0);
    let shift = 1.0 - lam.iter().fold(f64::INFINITY, |a, &l| a.min(l));
    assert!(m.factor(shift, PivotKind::Cholesky).is_ok());
}

/// A matrix of no blocks (a chain's buffers taken out) holds no storage
/// at all, and still factorises and solves its empty system.
#[test]
fn no_blocks_allocate_nothing() {
    let mut m = Semiseparable::new(4, 0);
    for v in [&m.b, &m.u, &m.w, &m.f, &m.bw, &m.sm, &m.lambda, &m.q] {
        assert_eq!(v.capacity(), 0);
    }
    assert_eq!(m.scratch.capacity() + m.lane_work.capacity(), 0);
    assert_eq!(m.dim(), 0);
    m.factor(0.0, PivotKind::Cholesky).unwrap();
    m.solve(&mut []);
    assert_eq!(m.inertia(0.0).unwrap().negative, 0);
}

/// Every lane of the stores starts a cache line (a 64-byte vector load of
/// it never straddles two), for any number of blocks.
#[test]
fn lanes_sit_on_cache_lines() {
    for blocks in [1, 7, 8, 9, 27, 54] {
        let mut m = Semiseparable::new(4, blocks);
        let groups = blocks.div_ceil(lanes::LANES);
        for v in [&m.b, &m.u, &m.w, &m.f, &m.bw, &m.sm, &m.lambda, &m.q] {
            for g in 0..groups {
                for lane in v.group(g) {
                    assert_eq!(lane.as_ptr() as usize % 64, 0, "{blocks} blocks");
                }
            }
        }
        for lane in m.lane_work.all_mut() {
            assert_eq!(lane.as_ptr() as usize % 64, 0, "{blocks} blocks");
        }
    }
}

/// The lane factorisation of 4 x 4 blocks against the block-by-block one
/// (the scalar kernels, one block at a time from contiguous copies): the
/// same factor, chain scalars and solves bit for bit, and the same error
/// where it fails, at every position in a group of eight and across
/// groups, coupled or not.
#[test]
fn lanes_match_the_block_by_block_factorisation() {
    let mut failures = 0;
    for seed in 0..240u64 {
        let nb = 1 + (seed as usize % 19);
        // mostly definite; some blocks or couplings that are not
        let shift = [2.5, 2.5, 1.0, 0.2][(seed / 19) as usize % 4];
        let (mut lanes, _) = random(4, nb, 500 + seed, shift);
        if seed % 5 == 0 {
            lanes.clear_coupling();
        }
        if seed % 7 == 0 {
            // a NaN in one block
            let mut b = [0.0; 16];
            let k = seed as usize % nb;
            lanes.block(k, &mut b);
            b[5] = f64::NAN;
            lanes.set_block(k, &b);
        }
        let mut blockwise = lanes.clone();
        let tau = 0.05 * (seed % 3) as f64;
        let got = lanes.factor(tau, PivotKind::Cholesky);
        blockwise.kind = PivotKind::Cholesky;
        let want = blockwise.factor_cholesky::<0>(tau);
        assert_eq!(got.is_ok(), want.is_ok(), "seed {seed}: {got:?} {want:?}");
        let Ok(_) = got else {
            // `factor` names non-finite input as such; otherwise the index
            if !matches!(got, Err(FactorError::NonFinite { .. })) {
                assert_eq!(got.err(), want.err(), "seed {seed}");
            }
            failures += 1;
            continue;
        };
        let bits = |s: &Store, per: usize| -> Vec<u64> {
            (0..nb)
                .flat_map(|k| (0..per).map(move |e| (k, e)))
                .map(|(k, e)| s.at(k, e).to_bits())
                .collect()
        };
        assert_eq!(bits(&lanes.f, 16), bits(&blockwise.f, 16), "seed {seed}");
        if lanes.coupled {
            for (a, b) in [(&lanes.q, &blockwise.q), (&lanes.bw, &blockwise.bw)] {
                assert_eq!(bits(a, 4), bits(b, 4), "seed {seed}");
            }
            assert_eq!(bits(&lanes.sm, 3), bits(&blockwise.sm, 3), "seed {seed}");
        }
        let rhs: Vec<f64> = (0..4 * nb)
            .map(|i| (i as f64 * 0.7 + seed as f64).sin())
            .collect();
        let (mut x, mut y) = (rhs.clone(), rhs);
        lanes.solve(&mut x);
        blockwise.factored = true;
        if blockwise.coupled {
            blockwise.solve_cholesky::<0>(&mut y);
        } else {
            for k in 0..nb {
                blockwise.solve_pivot::<0>(k, &mut y[4 * k..4 * k + 4]);
            }
        }
        let xb: Vec<u64> = x.iter().map(|v| v.to_bits()).collect();
        let yb: Vec<u64> = y.iter().map(|v| v.to_bits()).collect();
        assert_eq!(xb, yb, "seed {seed}");
    }
    assert!((20..200).contains(&failures), "{failures} failures");
}

#[test]
fn filling_a_block_sets_exactly_what_was_written() {
    // the workspace holds leftovers of a factorisation; `fill_block` hands
    // it over and stores what the caller wrote, and nothing else changes
    for (n, nb) in [(4, 1), (4, 3), (4, 9), (3, 2), (5, 1)] {
        let (mut m, _) = random(n, nb, 11, 2.0);
        let _ = m.factor(0.0, PivotKind::Symmetric);
        let before: Vec<Vec<f64>> = (0..nb)
            .map(|k| {
                let mut b = vec![0.0; n * n];
                m.block(k, &mut b);
                b
            })
            .collect();
        let k = nb / 2;
        let want: Vec<f64> = (0..n * n).map(|i| i as f64 * 0.25 - 1.0).collect();
        m.fill_block(k, |b| {
            assert_eq!(b.len(), n * n);
            b.copy_from_slice(&want);
        });
        for (j, old) in before.iter().enumerate() {
            let mut got = vec![0.0; n * n];
            m.block(j, &mut got);
            assert_eq!(
                &got,
                if j == k { &want } else { old },
                "n = {n}, block {j} of {nb}"
            );
        }
    }
}
