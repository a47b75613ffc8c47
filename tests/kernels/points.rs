//! Point kernels: mid-plane, tangent, strain, curvature; scaling.

use super::*;

// ---------------------------------------------------------------------------
// 4. Point kernels: mid-plane, tangent, strain, curvature; scaling.

pub(super) fn point_kernels_vs_closed_forms<M: Fields>() {
    let mut rng = Rng::new(10);
    let n = len::<M>();
    let (mut worst_p, mut worst_t, mut worst_s, mut worst_c, mut worst_fd) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for case in 0..400 {
        let l = rng.range(1.0, 110.0);
        let k: M::Coeffs = rng.within(&M::typical_at(l));
        let x = if case % 10 == 0 {
            0.0
        } else {
            rng.range(0.0, l)
        };
        let z = rng.range(-4.1, 4.1);
        let [[xx, dxx, ddxx], [zz, dzz, ddzz]] = M::shape(&k, x);
        let label = format!("{} case {case} L={l} x={x} z={z} K={k:?}", M::NAME);

        // mid-plane [X, Z] = [x + u, w], on the scale of the element
        let got = M::midplane(&k, x);
        for (o, want) in [xx, zz].into_iter().enumerate() {
            let err = (got[o] - want).abs() / want.abs().max(l);
            worst_p = worst_p.max(err);
            assert!(
                err <= 1e-14,
                "{label}: midplane[{o}] {:e}, closed form {want:e}",
                got[o]
            );
        }
        // tangent [X', Z']
        let got = M::tangent(&k, x);
        for (o, want) in [dxx, dzz].into_iter().enumerate() {
            let err = (got[o] - want).abs() / want.abs().max(1.0);
            worst_t = worst_t.max(err);
            assert!(
                err <= 1e-14,
                "{label}: tangent[{o}] {:e}, closed form {want:e}",
                got[o]
            );
        }
        // the tangent is the mid-plane's derivative in x
        let hx = 1e-3 * l;
        for (o, &t_o) in got.iter().enumerate() {
            let d = fd1(|t| M::midplane(&k, t)[o], x, hx);
            let err = (d - t_o).abs() / t_o.abs().max(1.0);
            worst_fd = worst_fd.max(err);
            assert!(
                err <= 1e-9,
                "{label}: tangent[{o}] {t_o:e}, finite difference of the mid-plane {d:e}"
            );
        }
        // axial strain eps_x; scale: its terms by absolute value
        let (want, _) = M::eps_x(&k, x, z);
        let dm = M::eps_x_gradient_magnitude(&k, x, z);
        let scale = (0..n).map(|i| (dm[i] * k[i]).abs()).sum::<f64>();
        let got = M::strain(&k, x, z);
        let err = (got - want).abs() / scale.max(f64::MIN_POSITIVE);
        worst_s = worst_s.max(err);
        assert!(
            err <= 1e-14,
            "{label}: strain {got:e}, closed form {want:e}"
        );
        // curvature (X' Z'' - Z' X'') / (X'^2 + Z'^2)^(3/2)
        let r3 = (dxx * dxx + dzz * dzz).powf(1.5);
        let want = (dxx * ddzz - dzz * ddxx) / r3;
        let scale = ((dxx * ddzz).abs() + (dzz * ddxx).abs()) / r3;
        let got = M::curvature(&k, x);
        if scale == 0.0 {
            assert_eq!(got, 0.0, "{label}: curvature of a straight element");
        } else {
            let err = (got - want).abs() / scale;
            worst_c = worst_c.max(err);
            assert!(
                err <= 1e-13,
                "{label}: curvature {got:e}, closed form {want:e} ({err:e})"
            );
        }
    }
    // the straight element: flat, unit tangent, no strain, no curvature
    let zero = M::Coeffs::zero();
    for x in [0.0, 1.0, 13.75, 110.0] {
        assert_eq!(M::midplane(&zero, x), [x, 0.0], "{}", M::NAME);
        assert_eq!(M::tangent(&zero, x), [1.0, 0.0], "{}", M::NAME);
        assert_eq!(M::strain(&zero, x, 2.0), 0.0, "{}", M::NAME);
        assert_eq!(M::curvature(&zero, x), 0.0, "{}", M::NAME);
    }
    eprintln!(
        "{}: point kernels vs closed forms: worst mid-plane {worst_p:e}, tangent {worst_t:e}, strain {worst_s:e}, curvature {worst_c:e}; tangent vs FD of the mid-plane {worst_fd:e}",
        M::NAME
    );
}

#[test]
pub(super) fn midplane_tangent_strain_and_curvature_match_closed_forms() {
    for_each_model!(point_kernels_vs_closed_forms);
}

/// The mid-plane's polynomial coefficients against the mid-plane point
/// kernel: `sum_j c_j x^j` evaluated here (Horner) equals `midplane(k, x)`
/// to rounding at random states and points, inside and beyond the element.
pub(super) fn midplane_polynomial_vs_point_kernel<M: Fields>() {
    let mut rng = Rng::new(12);
    let d = M::MIDPLANE_DEGREE;
    let mut c = vec![[f64::NAN; 2]; d + 2];
    let mut worst = 0.0f64;
    for case in 0..2000 {
        let l = rng.range(1.0, 110.0);
        // typical states, and large ones (every coefficient matters)
        let k: M::Coeffs = if case % 4 == 3 {
            M::Coeffs::from_fn(|_| rng.range(-2.0, 2.0))
        } else {
            rng.within(&M::typical_at(l))
        };
        c.iter_mut().for_each(|e| *e = [f64::NAN; 2]);
        M::midplane_coefficients(&k, &mut c);
        assert!(
            c[d + 1][0].is_nan(),
            "{}: wrote beyond MIDPLANE_DEGREE + 1 entries",
            M::NAME
        );
        let x = rng.range(-0.5 * l, 1.5 * l);
        let want = M::midplane(&k, x);
        for o in 0..2 {
            let got = c[..=d].iter().rev().fold(0.0, |acc, cj| acc * x + cj[o]);
            // rounding scale: the terms by absolute value
            let scale = c[..=d]
                .iter()
                .enumerate()
                .map(|(j, cj)| (cj[o] * x.powi(j as i32)).abs())
                .sum::<f64>()
                .max(l);
            let err = (got - want[o]).abs() / scale;
            worst = worst.max(err);
            assert!(
                err <= 4.0 * f64::EPSILON,
                "{} case {case}: polynomial[{o}]({x}) = {got:e}, point kernel {:e} (K = {k:?})",
                M::NAME,
                want[o]
            );
        }
    }
    // the straight, unstrained element is X = x, Z = 0
    M::midplane_coefficients(&M::Coeffs::zero(), &mut c);
    for (j, cj) in c[..=d].iter().enumerate() {
        assert_eq!(
            *cj,
            if j == 1 { [1.0, 0.0] } else { [0.0, 0.0] },
            "{}",
            M::NAME
        );
    }
    // a shorter slice gets the lowest powers only
    let mut short = [[f64::NAN; 2]; 1];
    M::midplane_coefficients(&M::Coeffs::zero(), &mut short);
    assert_eq!(short, [[0.0, 0.0]]);
    eprintln!(
        "{}: mid-plane polynomial (degree {d}) vs point kernel: worst {worst:e} of the term magnitude",
        M::NAME
    );
}

#[test]
pub(super) fn midplane_polynomial_matches_the_point_kernel() {
    for_each_model!(midplane_polynomial_vs_point_kernel);
}

#[test]
pub(super) fn ccm_constant_curvature_is_twice_c2() {
    // an element with a1 = a3 = 0 bends as w = c2 x^2: curvature at the
    // root 2 c2, and 2 c2 / (1 + 4 c2^2 x^2)^(3/2) along it
    for c2 in [-0.03f64, -1e-4, 1e-4, 0.03] {
        let k = [0.0, 0.0, 0.01, c2];
        for x in [0.0f64, 3.0, 13.75] {
            let want = 2.0 * c2 / (1.0 + 4.0 * c2 * c2 * x * x).powf(1.5);
            let got = Ccm::curvature(&k, x);
            assert!(
                (got - want).abs() <= 2e-15 * want.abs(),
                "c2 {c2}, x {x}: {got} vs {want}"
            );
        }
    }
}

#[test]
pub(super) fn ccm_unscale_is_the_natural_scaling() {
    let mut rng = Rng::new(11);
    let mut lengths = vec![1e-3, 0.11, 1.0, 5.0, 13.75, 110.0, 1e3];
    lengths.extend((0..50).map(|_| rng.range(0.1, 200.0)));
    for l in lengths {
        let got = Ccm::unscale(l);
        let want = [1.0, 1.0 / (l * l), 1.0, 1.0 / l];
        for i in 0..4 {
            assert!(
                (got[i] - want[i]).abs() <= 1e-15 * want[i],
                "L = {l}: unscale[{i}] = {:e}, want {:e}",
                got[i],
                want[i]
            );
        }
    }
    assert_eq!(Ccm::UNKNOWNS, ["a1", "a3", "b1", "c2"]);
    assert_eq!(Ccm::LOCAL, [2], "b1 couples only within its element");
}
