//! The prestressed law.

use super::*;

// ---------------------------------------------------------------------------
// 3. The prestressed law.

pub(super) fn psi_vs_fd<M: ElementModel>() {
    let mut rng = Rng::new(8);
    let mut worst = 0.0f64;
    for case in 0..200 {
        let p = random_law(&mut rng);
        let law = PsiParams {
            p1: p[0],
            p2: p[1],
            p3: p[2],
            p4: p[3],
        };
        let s = rng.range(-0.3, 0.9);
        let got = M::psi(s, &law);
        // psi' and psi'' against finite differences of psi and psi'; errors
        // over the magnitude of the derivative's terms
        let (_, m1, m2) = psi_magnitude(&p, s);
        let h = 1e-4;
        for (o, fd_value, mag) in [
            (1, fd1(|t| M::psi(t, &law)[0], s, h), m1),
            (2, fd1(|t| M::psi(t, &law)[1], s, h), m2),
        ] {
            let err = (got[o] - fd_value).abs() / mag.max(1e-300);
            worst = worst.max(err);
            assert!(
                err <= 1e-10,
                "{} case {case}: psi derivative {o} at s = {s}: {:e} vs finite difference {fd_value:e} ({err:e})",
                M::NAME,
                got[o]
            );
        }
    }
    eprintln!(
        "{}: psi', psi'' vs finite differences: worst {worst:e} of the term magnitude",
        M::NAME
    );
}

#[test]
pub(super) fn psi_derivatives_match_finite_differences() {
    for_each_model!(psi_vs_fd);
}

#[test]
pub(super) fn ccm_psi_is_the_papers_law() {
    // the default constants are the paper's fit
    assert_eq!(PsiParams::default().to_array(), PAPER_PSI);
    let mut rng = Rng::new(9);
    let mut worst = 0.0f64;
    for case in 0..300 {
        let p = if case == 0 {
            PAPER_PSI
        } else {
            random_law(&mut rng)
        };
        let law = PsiParams {
            p1: p[0],
            p2: p[1],
            p3: p[2],
            p4: p[3],
        };
        let s = if case < 2 { 0.0 } else { rng.range(-0.3, 0.9) };
        let got = Ccm::psi(s, &law);
        let (w0, w1, w2) = psi(&p, s);
        let (m0, m1, m2) = psi_magnitude(&p, s);
        for (o, want, mag) in [(0, w0, m0), (1, w1, m1), (2, w2, m2)] {
            if mag == 0.0 {
                assert_eq!(got[o], 0.0, "case {case}: psi[{o}] at s = 0");
                continue;
            }
            let err = (got[o] - want).abs() / mag;
            worst = worst.max(err);
            assert!(
                err <= 1e-14,
                "case {case}: psi[{o}]({s}) = {:e}, closed form {want:e} ({err:e})",
                got[o]
            );
        }
    }
    // at rest the tangent modulus is p1, exactly
    assert_eq!(Ccm::psi(0.0, &PsiParams::default()), [0.0, 0.0, 1.598]);
    eprintln!("ccm psi vs the paper's law in closed form: worst {worst:e} of the term magnitude");
}
