//! Derivatives of the generated kernels.

use super::*;

// ---------------------------------------------------------------------------
// 2. Derivatives.

/// 5-point central difference (Richardson-extrapolated) of `f` along e_i.
pub(super) fn fd_vec<C: Vector>(f: impl Fn(&C) -> Vec<f64>, k: &C, i: usize, h: f64) -> Vec<f64> {
    let at = |t: f64| {
        let mut kk = *k;
        kk[i] += t * h;
        f(&kk)
    };
    let terms = [
        (8.0, at(1.0)),
        (-8.0, at(-1.0)),
        (-1.0, at(2.0)),
        (1.0, at(-2.0)),
    ];
    let mut out = vec![0.0; terms[0].1.len()];
    for (c, v) in &terms {
        for (o, x) in out.iter_mut().zip(v) {
            *o += c * x;
        }
    }
    out.iter().map(|o| o / (12.0 * h)).collect()
}

/// The same for a scalar function.
pub(super) fn fd<C: Vector>(f: impl Fn(&C) -> f64, k: &C, i: usize, h: f64) -> f64 {
    fd_vec(|kk| vec![f(kk)], k, i, h)[0]
}

/// 5-point central difference in a scalar argument.
pub(super) fn fd1(f: impl Fn(f64) -> f64, s: f64, h: f64) -> f64 {
    (8.0 * (f(s + h) - f(s - h)) - (f(s + 2.0 * h) - f(s - 2.0 * h))) / (12.0 * h)
}

/// Step of the finite differences, as a fraction of each unknown's typical
/// size. The 5-point stencil's truncation error grows as step^4 (about 1e-9
/// of the energy scale at 1e-3 for the CCM's degree-10 prestressed kernel)
/// and its rounding error as 1/step; 3e-4 keeps both near 1e-11.
pub(super) const FD_STEP: f64 = 3e-4;

/// A random scene for a family: 1 to 3 blocks of random material.
pub(super) fn random_scene<M: ElementModel>(kind: usize, rng: &mut Rng) -> M::Moments {
    let mut m = M::zero_moments();
    let n = 1 + (rng.next_u64() % 3) as usize;
    for _ in 0..n {
        let d = random_density(kind, rng);
        let b = random_box(rng);
        add_block::<M>(&d, &b, &mut m);
    }
    m
}

pub(super) fn derivatives_vs_fd<M: Fields>() {
    let mut rng = Rng::new(3);
    let n = len::<M>();
    let typical = M::typical();
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        let (mut worst_g, mut worst_h, mut worst_variant) = (0.0f64, 0.0f64, 0.0f64);
        for case in 0..60 {
            let m = random_scene::<M>(kind, &mut rng);
            let k = random_k::<M>(&mut rng);
            let v = k_value::<M>(kind, &k, &m);
            let (vg, g) = k_gradient::<M>(kind, &k, &m);
            let (vh, gh, hu) = M::hessian(&m, &k, &alone(kind));
            let (vf, gf, hf) = k_family::<M>(kind, &k, &m);
            let h = full(n, hf.as_ref());

            // the value, gradient and Hessian variants and the family's own
            // kernel agree
            let gscale = (0..n).fold(0.0f64, |s, i| s.max(g[i].abs() * typical[i]));
            let scale = v.abs().max(gscale);
            let mut variant = (vg - v).abs().max((vh - v).abs()).max((vf - v).abs()) / scale;
            for i in 0..n {
                let d = (gh[i] - g[i]).abs().max((gf[i] - g[i]).abs());
                variant = variant.max(d * typical[i] / scale);
                for j in 0..n {
                    let hij = hu[upper_index(n, i, j)];
                    let d = (hij - h[i][j]).abs() * typical[i] * typical[j] / scale;
                    variant = variant.max(d);
                }
            }
            worst_variant = worst_variant.max(variant);
            assert!(
                variant <= 1e-14,
                "{} {name} case {case}: value/gradient/hessian/family variants differ by {variant:e}",
                M::NAME
            );

            // gradient: finite differences of the value; errors are measured
            // as the change of the value over a typical step, over the
            // energy scale
            for i in 0..n {
                let d = fd(|kk| k_value::<M>(kind, kk, &m), &k, i, FD_STEP * typical[i]);
                let err = (d - g[i]).abs() * typical[i] / scale;
                worst_g = worst_g.max(err);
                assert!(
                    err <= 1e-9,
                    "{} {name} case {case}: dV/dK[{i}] kernel {:e}, finite difference {d:e} (error {err:e})",
                    M::NAME,
                    g[i]
                );
            }
            // Hessian: finite differences of the gradient, full n x n
            for j in 0..n {
                let col = fd_vec(
                    |kk| k_gradient::<M>(kind, kk, &m).1.as_ref().to_vec(),
                    &k,
                    j,
                    FD_STEP * typical[j],
                );
                for i in 0..n {
                    let err = (col[i] - h[i][j]).abs() * typical[i] * typical[j] / scale;
                    worst_h = worst_h.max(err);
                    assert!(
                        err <= 1e-9,
                        "{} {name} case {case}: H[{i}][{j}] kernel {:e}, finite difference {:e} (error {err:e})",
                        M::NAME,
                        h[i][j],
                        col[i]
                    );
                }
            }
        }
        eprintln!(
            "{} {name}: worst FD gradient error {worst_g:e}, FD Hessian {worst_h:e}, variants {worst_variant:e}",
            M::NAME
        );
    }
}

#[test]
pub(super) fn derivatives_match_finite_differences() {
    for_each_model!(derivatives_vs_fd);
}

/// The element potential of moments holding every family is the
/// families' sum with the potential's coefficients (1, 1, -kp), in all
/// three variants.
pub(super) fn potential_combines_families<M: Fields>() {
    let mut rng = Rng::new(7);
    let n = len::<M>();
    let mut worst = 0.0f64;
    for case in 0..100 {
        let mut m = M::zero_moments();
        for kind in 0..3 {
            for _ in 0..1 + (rng.next_u64() % 3) {
                let d = random_density(kind, &mut rng);
                let b = random_box(&mut rng);
                add_block::<M>(&d, &b, &mut m);
            }
        }
        let k = random_k::<M>(&mut rng);
        // kappa P from 0 to 2.5 * 400 kPa, exactly zero in a quarter of the cases
        let kp = if case % 4 == 0 {
            0.0
        } else {
            rng.range(0.0, 1.0)
        };
        let s = EnergyScalars { kp };
        let mut want = Quad::zero(n);
        for kind in 0..3 {
            let (v, g, h) = k_family::<M>(kind, &k, &m);
            let c = coefficient(kind, kp);
            want.v += c * v;
            want.mag += (c * v).abs();
            for i in 0..n {
                want.g[i] += c * g[i];
                want.gmag[i] += (c * g[i]).abs();
                for j in 0..n {
                    let hij = h.as_ref()[upper_index(n, i, j)];
                    want.h[i][j] += c * hij;
                    want.hmag[i][j] += (c * hij).abs();
                }
            }
        }
        let v = M::energy(&m, &k, &s);
        let (vg, g) = M::gradient(&m, &k, &s);
        let (vh, gh, hu) = M::hessian(&m, &k, &s);
        for (what, got) in [
            ("value", v),
            ("gradient variant", vg),
            ("Hessian variant", vh),
        ] {
            let err = (got - want.v).abs() / want.mag;
            worst = worst.max(err);
            assert!(
                err <= 1e-14,
                "{} case {case} kp {kp}: {what} {got:e} vs the families' {:e} ({err:e})",
                M::NAME,
                want.v
            );
        }
        for i in 0..n {
            for (what, got) in [("gradient", g[i]), ("Hessian variant's gradient", gh[i])] {
                if want.gmag[i] == 0.0 {
                    assert_eq!(got, 0.0, "{} case {case}: {what}[{i}]", M::NAME);
                    continue;
                }
                let err = (got - want.g[i]).abs() / want.gmag[i].max(1e-300);
                worst = worst.max(err);
                assert!(
                    err <= 1e-14,
                    "{} case {case} kp {kp}: {what}[{i}] {got:e} vs {:e}",
                    M::NAME,
                    want.g[i]
                );
            }
            for j in 0..n {
                let got = hu[upper_index(n, i, j)];
                if want.hmag[i][j] == 0.0 {
                    assert_eq!(got, 0.0, "{} case {case}: H[{i}][{j}]", M::NAME);
                    continue;
                }
                let err = (got - want.h[i][j]).abs() / want.hmag[i][j];
                worst = worst.max(err);
                assert!(
                    err <= 1e-14,
                    "{} case {case} kp {kp}: H[{i}][{j}] {got:e} vs {:e}",
                    M::NAME,
                    want.h[i][j]
                );
            }
        }
    }
    eprintln!(
        "{}: element potential vs the sum of its families: worst {worst:e} of the term magnitude",
        M::NAME
    );
}

#[test]
pub(super) fn element_potential_is_the_sum_of_its_families() {
    for_each_model!(potential_combines_families);
}

pub(super) fn derivatives_vs_density_quadrature<M: Fields>() {
    let mut rng = Rng::new(4);
    let n = len::<M>();
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        let (mut worst_g, mut worst_h) = ((0.0f64, 0.0f64), (0.0f64, 0.0f64));
        for case in 0..150 {
            let d = random_density(kind, &mut rng);
            let b = random_box(&mut rng);
            let k = random_k::<M>(&mut rng);
            let m = moments_of::<M>(&d, &[b]);
            let (_, g, hu) = k_family::<M>(kind, &k, &m);
            let h = full(n, hu.as_ref());
            let q = quad::<M>(&d, &b, &k);
            // Errors over the integral of the absolute terms of each
            // entry's density (exact zeros must be exact); the relative
            // error per entry is reported too.
            let mut entries: Vec<(String, f64, f64, f64, bool)> = Vec::new();
            for i in 0..n {
                entries.push((format!("gradient[{i}]"), g[i], q.g[i], q.gmag[i], true));
                for (j, (hij, (qh, qm))) in
                    h[i].iter().zip(q.h[i].iter().zip(&q.hmag[i])).enumerate()
                {
                    entries.push((format!("H[{i}][{j}]"), *hij, *qh, *qm, false));
                }
            }
            for (entry, got, want, mag, is_grad) in entries {
                if mag == 0.0 {
                    assert_eq!(got, 0.0, "{} {name} case {case}: {entry}", M::NAME);
                    continue;
                }
                let err = (got - want).abs() / mag;
                let worst = if is_grad { &mut worst_g } else { &mut worst_h };
                worst.0 = worst.0.max(err);
                worst.1 = worst.1.max((got - want).abs() / want.abs().max(1e-6 * mag));
                assert!(
                    err <= 1e-12,
                    "{} {name} case {case}: {entry} kernel {got:e}, quadrature {want:e} ({err:e} of the term magnitude {mag:e})",
                    M::NAME
                );
            }
        }
        eprintln!(
            "{} {name}: worst error vs quadrature of density derivatives (of term magnitude / relative): gradient {:e} / {:e}, Hessian {:e} / {:e}",
            M::NAME, worst_g.0, worst_g.1, worst_h.0, worst_h.1
        );
    }
}

#[test]
pub(super) fn derivatives_match_quadrature_of_density_derivatives() {
    for_each_model!(derivatives_vs_density_quadrature);
}
