//! Element energy from the laminate description.

use super::*;

// ---------------------------------------------------------------------------
// 6. Element energy from the laminate description of docs/model.md section 3.

/// The default finger, from docs/model.md's numbers (not from the library).
pub(super) mod paper {
    pub const LX: f64 = 110.0;
    pub const LY: f64 = 31.75;
    pub const H: f64 = 8.2;
    pub const H1: f64 = 3.7;
    pub const H2: f64 = 1.8;
    pub const H3: f64 = 2.2;
    pub const CX: f64 = 105.0;
    pub const CY: f64 = 26.0;
    pub const H3A: f64 = 0.8;
    pub const H3B: f64 = 1.2;
    /// Longitudinal rib: width t over the whole channel.
    pub const T: f64 = 2.0;
    /// Transverse ribs: t long, centred at k w1, total width 2 w2.
    pub const W1: f64 = 8.0;
    pub const W2: f64 = 6.0;
    pub const PSI: [f64; 4] = [1.598, 2.306, 2.29, 0.698];
    pub const PEMC_E2: f64 = 250.0;

    /// (Q11, Q12, Q22) of an isotropic material.
    pub fn iso(e: f64, nu: f64) -> (f64, f64, f64) {
        let d = 1.0 - nu * nu;
        (e / d, nu * e / d, e / d)
    }

    /// (Q11, Q12, Q22) of an orthotropic material.
    pub fn ortho(e1: f64, e2: f64, nu12: f64) -> (f64, f64, f64) {
        let d = 1.0 - nu12 * nu12 * e2 / e1;
        (e1 / d, nu12 * e2 / d, e2 / d)
    }

    /// Total rib width at X_ref (inside the channel).
    pub fn rib_width(x: f64) -> f64 {
        let mut w = if x < CX { T } else { 0.0 };
        let mut k = 1.0;
        while k * W1 + T / 2.0 <= CX {
            if (x - k * W1).abs() < T / 2.0 {
                w += 2.0 * W2;
            }
            k += 1.0;
        }
        w
    }

    /// X_ref where the fluidic cross-section changes.
    pub fn breakpoints() -> Vec<f64> {
        let mut b = vec![0.0, CX];
        let mut k = 1.0;
        while k * W1 + T / 2.0 <= CX {
            b.push(k * W1 - T / 2.0);
            b.push(k * W1 + T / 2.0);
            k += 1.0;
        }
        b
    }
}

/// (Psi, V) of the element [start, start + len] at K, integrating the
/// laminate cross-section by cross-section over pieces of constant section.
pub(super) fn laminate_energy<M: Fields>(
    start: f64,
    len: f64,
    eps0: f64,
    k: &M::Coeffs,
) -> (Quad, Quad) {
    use paper::*;
    let n = self::len::<M>();
    let (cl, emc, fl) = (iso(305.0, 0.43), ortho(1.5, 250.0, 0.0), iso(1.2, 0.48));
    // transverse shear (shear-deformable models): G13 = E / (2 (1 + nu)),
    // E1 and nu12 for the EMC, p1 / 2 for the prestressed layer; ks = 5/6
    let ks = 5.0 / 6.0;
    let (g_cl, g_emc, g_fl) = (305.0 / 2.86, 1.5 / 2.0, 1.2 / 2.96);
    let lin = |q: (f64, f64, f64), g13: f64| Density::Linear {
        q11: q.0,
        q12: q.1,
        q22: q.2,
        g13,
        ks,
    };
    let pemc = Density::Prestressed {
        eps0,
        p: PSI,
        q22: PEMC_E2,
        g13: PSI[0] / 2.0,
        ks,
    };
    let end = start + len;
    let mut cuts = vec![start, end];
    cuts.extend(breakpoints().into_iter().filter(|&b| b > start && b < end));
    cuts.sort_by(f64::total_cmp);

    let (mut psi_total, mut vol) = (Quad::zero(n), Quad::zero(n));
    for w in cuts.windows(2) {
        let (a, b) = (w[0] - start, w[1] - start);
        let mid = 0.5 * (w[0] + w[1]);
        let in_channel = mid < CX;
        let ribs = if in_channel { rib_width(mid) } else { 0.0 };
        let fl_mid_width = if in_channel { LY - CY + ribs } else { LY };
        let gas_width = if in_channel { CY - ribs } else { 0.0 };
        let piece = |z0: f64, z1: f64, width: f64, d: Density| {
            quad::<M>(
                &d,
                &Bx {
                    x0: a,
                    x1: b,
                    z0,
                    z1,
                    width,
                },
                k,
            )
        };
        psi_total.add(&piece(H1, H / 2.0, LY, lin(cl, g_cl)));
        psi_total.add(&piece(H2, H1, LY, lin(emc, g_emc)));
        psi_total.add(&piece(H3A, H2, LY, lin(fl, g_fl)));
        psi_total.add(&piece(-H3B, H3A, fl_mid_width, lin(fl, g_fl)));
        psi_total.add(&piece(-H3, -H3B, LY, lin(fl, g_fl)));
        psi_total.add(&piece(-H / 2.0, -H3, LY, pemc));
        if gas_width > 0.0 {
            vol.add(&piece(-H3B, H3A, gas_width, Density::Gas));
        }
    }
    (psi_total, vol)
}

pub(super) const N: usize = 8;

/// `got` against `want = (value, magnitude)`: the error over the integral of
/// the absolute terms of the density (a zero magnitude needs an exact zero).
pub(super) fn against_magnitude(name: &str, got: f64, want: (f64, f64), tol: f64, worst: &mut f64) {
    let (value, mag) = want;
    if mag == 0.0 {
        assert_eq!(got, 0.0, "{name}: expected an exact zero");
        return;
    }
    let err = (got - value).abs() / mag;
    *worst = worst.max(err);
    assert!(
        err <= tol,
        "{name}: {got:e} vs {value:e} ({err:e} of {mag:e})"
    );
}

/// The paper's finger at prestrain `eps0`, N equal elements, ribs on, with model `M`.
pub(super) fn paper_finger<M: ElementModel>(eps0: f64) -> Finger {
    let act = Actuator::paper(eps0).expect("paper actuator");
    let part = Partition::equal(act.geometry().lx, N).expect("partition");
    let f = Finger::with_model(model_id::<M>(), &act, &part, true);
    assert_eq!(f.model(), model_id::<M>());
    assert_eq!(f.unknowns_per_element(), len::<M>());
    f
}

/// A load whose runtime scalar is `kp` exactly (kappa = 1).
pub(super) fn load_kp(kp: f64) -> Load {
    Load {
        pressure: kp,
        kappa: 1.0,
        fx: 0.0,
        fz: 0.0,
    }
}

/// One element's family alone (value, gradient, upper Hessian) through the finger.
pub(super) fn element_family(
    f: &Finger,
    i: usize,
    kind: usize,
    k: &[f64],
) -> (f64, Vec<f64>, Vec<f64>) {
    let pos = f.model().visit(FamilyPosition(KIND_NAMES[kind]));
    f.element_hessian(i, Some(pos), &Load::unloaded(), k)
        .expect("element and family in range")
}

/// The position of a family in a model's `FAMILIES`, for a run-time model.
pub(super) struct FamilyPosition(&'static str);

impl fpc::model::ModelVisitor for FamilyPosition {
    type Output = usize;
    fn visit<M: ElementModel>(self) -> usize {
        M::FAMILIES
            .iter()
            .position(|f| *f == self.0)
            .unwrap_or_else(|| panic!("{} has no family {}", M::NAME, self.0))
    }
}

pub(super) fn laminate_check<M: Fields>() {
    let mut rng = Rng::new(6);
    let n = len::<M>();
    let len = paper::LX / N as f64;
    #[derive(Default)]
    struct Worst {
        psi: f64,
        v: f64,
        pi: f64,
        g: f64,
        h: f64,
        variants: f64,
    }
    let mut worst = Worst::default();
    // Actuator::paper(0.25) is the default actuator; the other two are the
    // paper's other samples
    for eps0 in [0.25, 0.15, 0.4] {
        let finger = paper_finger::<M>(eps0);
        for (i, &l) in finger.element_lengths().iter().enumerate() {
            assert_eq!(l, len, "element {i}");
        }
        for case in 0..8 {
            // every element its own state (the straight finger first)
            let ks: Vec<M::Coeffs> = (0..N)
                .map(|_| {
                    if case == 0 {
                        M::Coeffs::zero()
                    } else {
                        rng.within(&M::typical_at(len))
                    }
                })
                .collect();
            // kappa P from 0 to 2.5 * 400 kPa
            let kp = if case % 2 == 0 {
                0.0
            } else {
                rng.range(0.0, 1.0)
            };
            let load = load_kp(kp);
            let flat: Vec<f64> = ks.iter().flat_map(|k| k.as_ref().to_vec()).collect();
            let coefficients = Coefficients::new(n, flat).expect("coefficients");
            let (mut sum_pi, mut sum_mag) = (0.0, 0.0);
            let mut grads = Vec::new();
            for (i, k) in ks.iter().enumerate() {
                let (psi, gas) = laminate_energy::<M>(i as f64 * len, len, eps0, k);
                let (psi_want, v_want) = (psi.v, gas.v);
                let mut pi_want = Quad::zero(n);
                pi_want.add(&psi);
                pi_want.add_scaled(-kp, &gas);
                let label = format!("{} eps0 {eps0} element {i} K={k:?} kp={kp}", M::NAME);
                let kr = k.as_ref();

                let psi_got =
                    element_family(&finger, i, 0, kr).0 + element_family(&finger, i, 1, kr).0;
                let rel = (psi_got - psi_want).abs() / psi_want.abs();
                worst.psi = worst.psi.max(rel);
                assert!(
                    rel <= 1e-11,
                    "{label}: Psi {psi_got} vs {psi_want} ({rel:e})"
                );

                let v_got = element_family(&finger, i, 2, kr).0;
                if v_want == 0.0 {
                    assert_eq!(v_got, 0.0, "{label}: element without channel");
                } else {
                    let rel = (v_got - v_want).abs() / v_want.abs();
                    worst.v = worst.v.max(rel);
                    assert!(rel <= 1e-11, "{label}: V {v_got} vs {v_want} ({rel:e})");
                }

                let (pi, g, hu) = finger
                    .element_hessian(i, None, &load, kr)
                    .expect("element in range");
                let rel = (pi - pi_want.v).abs() / pi_want.mag;
                worst.pi = worst.pi.max(rel);
                assert!(rel <= 1e-11, "{label}: Pi {pi} vs {} ({rel:e})", pi_want.v);
                sum_pi += pi;
                sum_mag += pi_want.mag;

                // gradient and Hessian, each entry against the integral of
                // its density's absolute terms
                let h = full(n, &hu);
                for r in 0..n {
                    let name = format!("{label}: gradient[{r}]");
                    let want = (pi_want.g[r], pi_want.gmag[r]);
                    against_magnitude(&name, g[r], want, 1e-11, &mut worst.g);
                    for (c, &hrc) in h[r].iter().enumerate() {
                        let name = format!("{label}: H[{r}][{c}]");
                        let want = (pi_want.h[r][c], pi_want.hmag[r][c]);
                        against_magnitude(&name, hrc, want, 1e-11, &mut worst.h);
                    }
                }
                grads.push((g, pi_want.gmag.clone(), label));
            }
            // the finger's value kernels (energy) and gradient kernels
            // (gradient) agree with the elements' Hessian kernels
            let label = format!("{} eps0 {eps0} case {case} kp={kp}", M::NAME);
            let total = finger.energy(&load, &coefficients).expect("valid");
            let err = (total - sum_pi).abs() / sum_mag;
            worst.variants = worst.variants.max(err);
            assert!(err <= 1e-14, "{label}: finger energy {total} vs {sum_pi}");
            let (total_g, g_all) = finger.gradient(&load, &coefficients).expect("valid");
            let err = (total_g - sum_pi).abs() / sum_mag;
            worst.variants = worst.variants.max(err);
            assert!(
                err <= 1e-14,
                "{label}: finger gradient's value {total_g} vs {sum_pi}"
            );
            for (i, (g, gmag, label)) in grads.iter().enumerate() {
                for r in 0..n {
                    let got = g_all[n * i + r];
                    let err = (got - g[r]).abs() / gmag[r].max(f64::MIN_POSITIVE);
                    worst.variants = worst.variants.max(err);
                    assert!(
                        (got - g[r]).abs() <= 1e-14 * gmag[r],
                        "{label}: finger gradient[{r}] {got:e} vs element {:e}",
                        g[r]
                    );
                }
            }
        }
    }
    eprintln!(
        "{} element vs laminate quadrature: worst relative Psi {:e}, V {:e}; of the term magnitude: Pi {:e}, gradient {:e}, Hessian {:e}; finger energy/gradient vs element kernels {:e}",
        M::NAME, worst.psi, worst.v, worst.pi, worst.g, worst.h, worst.variants
    );
}

#[test]
pub(super) fn element_energy_matches_laminate_quadrature() {
    for_each_model!(laminate_check);
}
