//! Physical sanity at K = 0.

use super::energy::{element_family, paper_finger, N};
use super::*;

// ---------------------------------------------------------------------------
// 7. Physical sanity at K = 0.

pub(super) fn unstressed<M: ElementModel>() {
    let n = len::<M>();
    let f = paper_finger::<M>(0.0);
    let straight = f.straight();
    // the whole finger: no energy, no force
    assert_eq!(f.energy(&Load::unloaded(), &straight).unwrap(), 0.0);
    let (v, g) = f.gradient(&Load::unloaded(), &straight).unwrap();
    assert_eq!(v, 0.0);
    assert!(g.iter().all(|&gi| gi == 0.0), "{g:?}");
    for i in 0..f.len() {
        let k = straight.element(i);
        let (v, g, hu) = f
            .element_hessian(i, None, &Load::unloaded(), k)
            .expect("element in range");
        let psi = element_family(&f, i, 0, k).0 + element_family(&f, i, 1, k).0;
        assert_eq!(psi, 0.0, "{} element {i}", M::NAME);
        assert_eq!(v, 0.0, "{} element {i}", M::NAME);
        assert!(
            g.iter().all(|&gi| gi == 0.0),
            "{} element {i}: {g:?}",
            M::NAME
        );
        // positive definite Hessian (Cholesky)
        let h = full(n, &hu);
        let mut l = vec![vec![0.0f64; n]; n];
        for i in 0..n {
            for j in 0..=i {
                let s: f64 = h[i][j] - (0..j).map(|m| l[i][m] * l[j][m]).sum::<f64>();
                if i == j {
                    assert!(
                        s > 0.0,
                        "{}: Hessian at rest not positive definite: {h:?}",
                        M::NAME
                    );
                    l[i][i] = s.sqrt();
                } else {
                    l[i][j] = s / l[j][j];
                }
            }
        }
    }
}

#[test]
pub(super) fn unstressed_finger_has_zero_energy_and_gradient_and_is_stable() {
    for_each_model!(unstressed);
}

#[test]
pub(super) fn ccm_prestrain_gradient_at_rest_matches_closed_form() {
    use super::energy::paper::*;
    let len = LX / N as f64;
    let (z0, z1) = (-H / 2.0, -H3);
    let mut worst = 0.0f64;
    for eps0 in [0.15, 0.25, 0.4] {
        let (_, stress, _) = psi(&PSI, eps0);
        assert!(stress > 0.0);
        // d Psi/dK at K = 0: psi'(eps0) times the integral of d eps_x/dK
        // over the prestressed layer: (1, 3 x^2, 0, -2 z)
        let area = LY * (z1 - z0);
        let want = [
            stress * area * len,
            stress * area * len.powi(3),
            0.0,
            stress * LY * len * (z0 * z0 - z1 * z1),
        ];
        let f = paper_finger::<Ccm>(eps0);
        let straight = f.straight();
        // the gradient kernels (through the finger) and the Hessian kernels
        let (_, g_all) = f.gradient(&Load::unloaded(), &straight).unwrap();
        for i in 0..f.len() {
            let (_, gh, _) = f
                .element_hessian(i, None, &Load::unloaded(), straight.element(i))
                .unwrap();
            for (what, g) in [("gradient", &g_all[4 * i..4 * i + 4]), ("Hessian", &gh[..])] {
                // stretched prestressed layer: shortening (a1 < 0) and curling
                // towards -Z (c2 < 0) both lower the energy
                assert!(g[0] > 0.0 && g[3] > 0.0, "element {i}: {g:?}");
                for j in 0..4 {
                    let err = (g[j] - want[j]).abs() / want[0].abs().max(want[j].abs());
                    worst = worst.max(err);
                    assert!(
                        err <= 1e-13,
                        "eps0 {eps0} element {i} ({what} kernel): dPsi/dK[{j}] = {}, closed form {}",
                        g[j],
                        want[j]
                    );
                }
            }
        }
    }
    eprintln!("prestrain gradient at rest: worst relative error {worst:e}");
}

/// Gas volume of each element at rest, channel minus ribs (mm^3), and the
/// channel-minus-ribs area in (x, y) of each element (mm^2).
pub(super) fn gas_at_rest_by_hand() -> Vec<(f64, f64)> {
    use super::energy::paper::*;
    let len = LX / N as f64;
    let height = H3A + H3B;
    (0..N)
        .map(|i| {
            let (s, e) = (i as f64 * len, (i + 1) as f64 * len);
            let overlap = |a: f64, b: f64| (b.min(e) - a.max(s)).max(0.0);
            let mut area = CY * overlap(0.0, CX) - T * overlap(0.0, CX);
            let mut k = 1.0;
            while k * W1 + T / 2.0 <= CX {
                area -= 2.0 * W2 * overlap(k * W1 - T / 2.0, k * W1 + T / 2.0);
                k += 1.0;
            }
            (area * height, area)
        })
        .collect()
}

pub(super) fn gas_volume_at_rest<M: ElementModel>() {
    use super::energy::paper::*;
    let height = H3A + H3B;
    let f = paper_finger::<M>(0.25);
    let zero = M::Coeffs::zero();
    let mut total = 0.0;
    let mut worst = 0.0f64;
    for (i, (want, _)) in gas_at_rest_by_hand().into_iter().enumerate() {
        let got = element_family(&f, i, 2, zero.as_ref()).0;
        let err = (got - want).abs() / want.abs().max(1.0);
        worst = worst.max(err);
        assert!(
            err <= 1e-13,
            "{} element {i}: V = {got}, channel minus ribs {want}",
            M::NAME
        );
        total += got;
    }
    // 2 mm x (26 x 105 - 2 x 105 - 13 x 12 x 2) mm^2
    let all = height * (CY * CX - T * CX - 13.0 * 2.0 * W2 * T);
    assert!(
        (total - all).abs() <= 1e-12 * all,
        "{}: total {total} vs {all}",
        M::NAME
    );
    eprintln!(
        "{} gas volume at rest: worst relative error {worst:e}, total {total} mm^3",
        M::NAME
    );
}

#[test]
pub(super) fn gas_volume_at_rest_is_channel_minus_ribs() {
    for_each_model!(gas_volume_at_rest);
}

#[test]
pub(super) fn ccm_gas_volume_gradient_at_rest_matches_closed_form() {
    use super::energy::paper::*;
    let f = paper_finger::<Ccm>(0.25);
    for (i, (want, area)) in gas_at_rest_by_hand().into_iter().enumerate() {
        // pressure flattens: dV/dc2 = (gas width * length) (z0^2 - z1^2) > 0
        // over z in [-h3b, h3a], and dV/da1 = V at rest
        let (_, g, _) = element_family(&f, i, 2, &[0.0; 4]);
        let want_c2 = area * (H3B * H3B - H3A * H3A);
        assert!(
            (g[0] - want).abs() <= 1e-12 * want.abs().max(1.0),
            "element {i}: {g:?}"
        );
        assert!(
            (g[3] - want_c2).abs() <= 1e-12 * want.abs().max(1.0),
            "element {i}: {g:?}"
        );
        if want > 0.0 {
            assert!(g[3] > 0.0);
        }
    }
}
