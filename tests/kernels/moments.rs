//! Quadrature and linearity of the moments.

use super::*;

// ---------------------------------------------------------------------------
// 1. Quadrature and linearity of the moments.

pub(super) fn values_vs_quadrature<M: Fields>() {
    let mut rng = Rng::new(1);
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        let (mut worst_value, mut worst_mag) = (0.0f64, 0.0f64);
        for case in 0..300 {
            let d = random_density(kind, &mut rng);
            let b = random_box(&mut rng);
            let k = random_k::<M>(&mut rng);
            let m = moments_of::<M>(&d, &[b]);
            let got = k_value::<M>(kind, &k, &m);
            let q = quad::<M>(&d, &b, &k);
            let rel = (got - q.v).abs() / q.v.abs();
            worst_value = worst_value.max(rel);
            worst_mag = worst_mag.max((got - q.v).abs() / q.mag);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: kernel {got:e}, quadrature {:e}, relative {rel:e}\n{d:?}\n{b:?}\nK = {k:?}",
                M::NAME,
                q.v
            );
            // the family's own kernel gives the same value
            let fam = k_family::<M>(kind, &k, &m).0;
            let rel = (fam - q.v).abs() / q.v.abs();
            worst_value = worst_value.max(rel);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: family kernel {fam:e}, quadrature {:e}",
                M::NAME,
                q.v
            );
        }
        eprintln!(
            "{} {name}: worst relative error vs quadrature {worst_value:e} ({worst_mag:e} of the term magnitude)",
            M::NAME
        );
    }
}

#[test]
pub(super) fn values_match_gauss_legendre_quadrature() {
    for_each_model!(values_vs_quadrature);
}

pub(super) fn linearity<M: Fields>() {
    let mut rng = Rng::new(2);
    let (mut worst_sum, mut worst_cancel, mut worst_split) = (0.0f64, 0.0f64, 0.0f64);
    for (kind, name) in KIND_NAMES.iter().enumerate() {
        for case in 0..200 {
            let k = random_k::<M>(&mut rng);
            // two blocks of different material accumulate into one set of moments
            let (d1, d2) = (
                random_density(kind, &mut rng),
                random_density(kind, &mut rng),
            );
            let (b1, b2) = (random_box(&mut rng), random_box(&mut rng));
            let mut m = M::zero_moments();
            add_block::<M>(&d1, &b1, &mut m);
            add_block::<M>(&d2, &b2, &mut m);
            let v1 = k_value::<M>(kind, &k, &moments_of::<M>(&d1, &[b1]));
            let v2 = k_value::<M>(kind, &k, &moments_of::<M>(&d2, &[b2]));
            let both = k_value::<M>(kind, &k, &m);
            let rel = (both - (v1 + v2)).abs() / (v1.abs() + v2.abs());
            worst_sum = worst_sum.max(rel);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: two blocks {both:e}, sum {:e}",
                M::NAME,
                v1 + v2
            );

            // the same block with the opposite width cancels it
            let neg = Bx {
                width: -b1.width,
                ..b1
            };
            let cancel = k_value::<M>(kind, &k, &moments_of::<M>(&d1, &[b1, neg]));
            let rel = cancel.abs() / v1.abs();
            worst_cancel = worst_cancel.max(rel);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: +w and -w leave {cancel:e} (block {v1:e})",
                M::NAME
            );

            // splitting a box in x and in z does not change the total
            let xm = rng.range(b1.x0, b1.x1);
            let zm = rng.range(b1.z0, b1.z1);
            let parts = [
                Bx {
                    x1: xm,
                    z1: zm,
                    ..b1
                },
                Bx {
                    x0: xm,
                    z1: zm,
                    ..b1
                },
                Bx {
                    x1: xm,
                    z0: zm,
                    ..b1
                },
                Bx {
                    x0: xm,
                    z0: zm,
                    ..b1
                },
            ];
            let split = k_value::<M>(kind, &k, &moments_of::<M>(&d1, &parts));
            let scale = quad::<M>(&d1, &b1, &k).mag;
            let rel = (split - v1).abs() / scale;
            worst_split = worst_split.max(rel);
            assert!(
                rel <= 1e-12,
                "{} {name} case {case}: split {split:e}, whole {v1:e}",
                M::NAME
            );
        }
    }
    eprintln!(
        "{} linearity: worst two-block {worst_sum:e}, cancellation {worst_cancel:e}, split {worst_split:e}",
        M::NAME
    );
}

#[test]
pub(super) fn moments_are_linear_in_blocks() {
    for_each_model!(linearity);
}
