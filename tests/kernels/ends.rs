//! End kinematics.

use super::*;

// ---------------------------------------------------------------------------
// 5. End kinematics.

/// docs/model.md Eqs. 11, 13 with decision D2, from the fields: `[X(L),
/// Z(L), s(L) - s(0)]`, the turn of the section, where a section's angle
/// `s = atan2(Z', X') - atan2(g, |t|)` is its tangent's angle less the
/// shear angle, `g = Z'(0)` the shear strain (the element's frame is its
/// start section's; zero for the CCM, whose tangent starts along the
/// frame) and `|t|` the tangent's length (docs/model.md section 4.8); and
/// the unnormalised end frame, the section's direction at L,
/// `n = (|t| X' + g Z', |t| Z' - g X')`, turned back by its direction at
/// 0: `[X(L), Z(L), n(0) . n(L), n(0) x n(L)]` (`[X(L), Z(L), X'(L),
/// Z'(L)]` for the CCM, whose kernel hands on the tangent itself).
pub(super) fn end_closed_form<M: Fields>(k: &M::Coeffs, l: f64) -> ([f64; 3], [f64; 4]) {
    let [[x, dx, _], [z, dz, _]] = M::shape(k, l);
    let [[_, dx0, _], [_, g, _]] = M::shape(k, 0.0);
    let section = |dx: f64, dz: f64| dz.atan2(dx) - g.atan2(dx.hypot(dz));
    let normal = |dx: f64, dz: f64| {
        let t = dx.hypot(dz);
        [t * dx + g * dz, t * dz - g * dx]
    };
    let frame = if g == 0.0 {
        [x, z, dx, dz]
    } else {
        let ([n0x, n0z], [nx, nz]) = (normal(dx0, g), normal(dx, dz));
        [x, z, n0x * nx + n0z * nz, n0x * nz - n0z * nx]
    };
    ([x, z, section(dx, dz) - section(dx0, g)], frame)
}

/// Gradient of (Xe, Ze, eta) by the chain rule from the fields' gradients:
/// d atan2(Z', X') = (X' dZ' - Z' dX') / (X'^2 + Z'^2), and the shear
/// angle's d atan2(g, |t|) = (|t| dg - g d|t|) / (|t|^2 + g^2).
pub(super) fn end_gradient_closed_form<M: Fields>(k: &M::Coeffs, l: f64) -> [Vec<f64>; 3] {
    let n = len::<M>();
    let [[_, dx, _], [_, dz, _]] = M::shape(k, l);
    let [gx, gz, gdx, gdz] = M::shape_gradients(k, l);
    let [[_, dx0, _], [_, g, _]] = M::shape(k, 0.0);
    let [_, _, gdx0, gdz0] = M::shape_gradients(k, 0.0);
    // d s at one end, tangent (dx, dz) with gradients (gdx, gdz)
    let d_section = |dx: f64, dz: f64, gdx: f64, gdz: f64, gg: f64| {
        let r2 = dx * dx + dz * dz;
        let t = r2.sqrt();
        let gt = (dx * gdx + dz * gdz) / t;
        (dx * gdz - dz * gdx) / r2 - (t * gg - g * gt) / (r2 + g * g)
    };
    [
        (0..n).map(|i| gx[i]).collect(),
        (0..n).map(|i| gz[i]).collect(),
        (0..n)
            .map(|i| {
                d_section(dx, dz, gdx[i], gdz[i], gdz0[i])
                    - d_section(dx0, g, gdx0[i], gdz0[i], gdz0[i])
            })
            .collect(),
    ]
}

pub(super) fn random_end_case<M: Fields>(rng: &mut Rng) -> (M::Coeffs, f64) {
    let l = rng.range(1.0, 110.0);
    let k = rng.within(&M::typical_at(l));
    (k, l)
}

pub(super) fn check_end<M: Fields>(k: &M::Coeffs, l: f64, label: &str, worst: &mut [f64; 4]) {
    let n = len::<M>();
    let v = M::end(k, l);
    let (vg, gg) = M::end_gradient(k, l);
    let (vh, g, hu) = M::end_hessian(k, l);
    // the values-free kernel the chain's Hessian uses: the same derivatives
    // (hu is checked against finite differences below)
    let (dg, dh) = M::end_derivatives(k, l);
    for o in 0..3 {
        let gs = g[o].as_ref().iter().fold(1e-300f64, |s, x| s.max(x.abs()));
        let hs = hu[o].as_ref().iter().fold(1e-300f64, |s, x| s.max(x.abs()));
        for (a, b) in dg[o].as_ref().iter().zip(g[o].as_ref()) {
            assert!(
                (a - b).abs() <= 1e-14 * gs,
                "{label}: end_derivatives gradient {a:e} vs {b:e}"
            );
        }
        for (a, b) in dh[o].as_ref().iter().zip(hu[o].as_ref()) {
            assert!(
                (a - b).abs() <= 1e-14 * hs,
                "{label}: end_derivatives Hessian {a:e} vs {b:e}"
            );
        }
    }
    let (want, want_frame) = end_closed_form::<M>(k, l);
    let want_g = end_gradient_closed_form::<M>(k, l);
    // typical sizes: a step that moves the end as much as the others
    let typ = M::typical_at(l);

    // the unnormalised end frame [Xe, Ze, X'(L), Z'(L)]
    let frame = M::frame(k, l);
    for o in 0..4 {
        let scale = want_frame[o].abs().max(if o < 2 { l } else { 1.0 });
        let err = (frame[o] - want_frame[o]).abs() / scale;
        worst[0] = worst[0].max(err);
        assert!(
            err <= 1e-14,
            "{label}: frame[{o}] kernel {:e}, closed form {:e}",
            frame[o],
            want_frame[o]
        );
    }
    for o in 0..3 {
        let scale = want[o].abs().max(if o == 2 { 1.0 } else { l });
        let err = (v[o] - want[o])
            .abs()
            .max((vh[o] - want[o]).abs())
            .max((vg[o] - want[o]).abs())
            / scale;
        worst[0] = worst[0].max(err);
        assert!(
            err <= 1e-14,
            "{label}: end[{o}] kernel {:e}, closed form {:e}",
            v[o],
            want[o]
        );
        // gradient scale: the output's change over typical steps
        let gscale = (0..n).fold(0.0f64, |s, i| s.max(want_g[o][i].abs() * typ[i]));
        for i in 0..n {
            let err = (g[o][i] - want_g[o][i]).abs() * typ[i] / gscale.max(1e-300);
            worst[1] = worst[1].max(err);
            assert!(
                err <= 1e-13,
                "{label}: d end[{o}]/dK[{i}] kernel {:e}, closed form {:e}",
                g[o][i],
                want_g[o][i]
            );
            // the gradient-only kernel agrees with the Hessian kernel
            let err = (gg[o][i] - g[o][i]).abs() * typ[i] / gscale.max(1e-300);
            worst[1] = worst[1].max(err);
            assert!(
                err <= 1e-14,
                "{label}: d end[{o}]/dK[{i}] end_gradient {:e}, end_hessian {:e}",
                gg[o][i],
                g[o][i]
            );
            let d = fd(|kk| M::end(kk, l)[o], k, i, FD_STEP * typ[i]);
            let err = (d - g[o][i]).abs() * typ[i] / gscale.max(1e-300);
            worst[2] = worst[2].max(err);
            assert!(
                err <= 1e-9,
                "{label}: d end[{o}]/dK[{i}] kernel {:e}, finite difference {d:e}",
                g[o][i]
            );
        }
        let h = full(n, hu[o].as_ref());
        for j in 0..n {
            let col = fd_vec(
                |kk| M::end_hessian(kk, l).1[o].as_ref().to_vec(),
                k,
                j,
                FD_STEP * typ[j],
            );
            for i in 0..n {
                let err = (col[i] - h[i][j]).abs() * typ[i] * typ[j] / scale;
                worst[3] = worst[3].max(err);
                assert!(
                    err <= 1e-9,
                    "{label}: d2 end[{o}]/dK[{i}]dK[{j}] kernel {:e}, finite difference {:e}",
                    h[i][j],
                    col[i]
                );
            }
        }
    }
}

pub(super) fn end_kinematics<M: Fields>() {
    let mut rng = Rng::new(5);
    let mut worst = [0.0f64; 4];
    for case in 0..200 {
        let (k, l) = random_end_case::<M>(&mut rng);
        check_end::<M>(
            &k,
            l,
            &format!("{} case {case} L={l} K={k:?}", M::NAME),
            &mut worst,
        );

        // eta is the turn of the section: the mid-plane's tangent less
        // the shear angle (the tangent's component across the section,
        // its value at x = 0 in the section's frame, over its length), at
        // x = L and at x = 0, tangents by central differences of the
        // mid-plane
        let hh = 1e-4 * l;
        let tangent = |x: f64| {
            let (p, q) = (M::shape(&k, x + hh), M::shape(&k, x - hh));
            [p[0][0] - q[0][0], p[1][0] - q[1][0]].map(|d| d / (2.0 * hh))
        };
        let ([x1, z1], [x0, g]) = (tangent(l), tangent(0.0));
        let section = |x: f64, z: f64| z.atan2(x) - g.atan2(x.hypot(z));
        let eta_fd = section(x1, z1) - section(x0, g);
        let err = (M::end(&k, l)[2] - eta_fd).abs();
        assert!(
            err <= 1e-9,
            "{} case {case}: eta vs mid-plane tangent {err:e}",
            M::NAME
        );
    }
    eprintln!(
        "{} end: worst value {:e}, gradient vs closed form {:e}, vs FD {:e}, Hessian vs FD {:e}",
        M::NAME,
        worst[0],
        worst[1],
        worst[2],
        worst[3]
    );
}

#[test]
pub(super) fn end_kinematics_match_closed_forms_and_finite_differences() {
    for_each_model!(end_kinematics);
}

#[test]
pub(super) fn end_slope_is_right_past_ninety_degrees() {
    let mut worst = [0.0f64; 4];
    let l = 13.75;
    // 1 + a1 + 3 a3 L^2 < 0: the end points backwards
    for (c2, lo, hi) in [(0.02, FRAC_PI_2, PI), (-0.02, -PI, -FRAC_PI_2)] {
        let k = [-0.5, -0.3 / (l * l), 0.01, c2];
        let x = 1.0 + k[0] + 3.0 * k[1] * l * l;
        assert!(x < 0.0);
        let eta = Ccm::end(&k, l)[2];
        assert!(
            eta > lo && eta < hi,
            "eta = {eta} for c2 = {c2}, should lie in ({lo}, {hi})"
        );
        let want = PI.copysign(c2) - (2.0 * c2 * l / -x).atan();
        assert!((eta - want).abs() <= 1e-14, "eta {eta} vs {want}");
        check_end::<Ccm>(&k, l, &format!("past 90 degrees, c2 = {c2}"), &mut worst);
    }
    // exactly 90 degrees: dX/dx = 0 at the end
    let k = [-0.4, -0.6 / (3.0 * l * l), 0.0, 0.01];
    let eta = Ccm::end(&k, l)[2];
    assert!((eta - FRAC_PI_2).abs() <= 1e-12, "eta = {eta}");
    check_end::<Ccm>(&k, l, "at 90 degrees", &mut worst);
    eprintln!(
        "end past 90 degrees: worst value {:e}, gradient {:e}, FD gradient {:e}, FD Hessian {:e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}
