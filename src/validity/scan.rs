//! The validity check's scan of each element's check points, eight
//! elements side by side in vector lanes ([`scan`]).

use super::clearance::{greater, lesser};
use crate::element::walk::approx_atan2;
use crate::element::{self, Element};
use crate::model::Kinematics;

/// Elements scanned side by side by [`scan`] (a vector register's worth of
/// doubles and more: the loop over them vectorises).
pub(super) const SCAN_LANES: usize = 8;

/// One element's extremes over its check points ([`check`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Extremes {
    /// A tangent past the slope limit (the root's excluded).
    pub(super) steep: bool,
    /// Every tangent points forwards in the element's frame.
    pub(super) forward: bool,
    /// The range of `dz/dx` over the forward tangents.
    pub(super) r: (f64, f64),
    /// The largest `|d(X, Z)/dx|`, squared.
    pub(super) stretch: f64,
    /// The largest `|mid-plane strain|`.
    pub(super) mid: f64,
    /// The range of `eps0 +` the strain at the prestressed layer's faces.
    pub(super) pre: (f64, f64),
    /// The element's end frame ([`Element::frame`]) and the approximate
    /// angle of its end tangent ([`approx_atan2`]).
    pub(super) frame: [f64; 4],
    pub(super) turn: f64,
}

/// What [`scan`] checks: `samples + 1` check points per element, the
/// faces of the prestressed layer at heights `z` with prestrain `eps0`,
/// and the slope limit's tangent.
#[derive(Debug, Clone, Copy)]
pub(super) struct ScanRules {
    pub(super) samples: usize,
    pub(super) z: [f64; 2],
    pub(super) eps0: f64,
    pub(super) limit_tan: f64,
}

/// The [`Extremes`] of elements `first..` (at most [`SCAN_LANES`] of
/// them) of state `k` under `rules`. Each element's numbers are its own
/// scalar arithmetic, in the order of its check points, so they do not
/// depend on which elements share the lanes (lanes past the last element
/// repeat the first and are ignored).
pub(super) fn scan<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    first: usize,
    rules: ScanRules,
) -> [Extremes; SCAN_LANES] {
    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: the processor has AVX-512 (checked above)
        return unsafe { scan_avx512(elements, k, first, rules) };
    }
    scan_in(elements, k, first, rules)
}

/// [`scan`] compiled for AVX-512 (no fused multiply-adds: the same
/// roundings as the scalar code).
#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
#[target_feature(enable = "avx512f,avx2")]
fn scan_avx512<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    first: usize,
    rules: ScanRules,
) -> [Extremes; SCAN_LANES] {
    scan_in(elements, k, first, rules)
}

#[inline(always)]
fn scan_in<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
    first: usize,
    rules: ScanRules,
) -> [Extremes; SCAN_LANES] {
    let ScanRules {
        samples,
        z,
        eps0,
        limit_tan,
    } = rules;
    let at = |l: usize| {
        if first + l < elements.len() {
            first + l
        } else {
            first
        }
    };
    let ks: [M::Coeffs; SCAN_LANES] = std::array::from_fn(|l| element::coeffs::<M>(k, at(l)));
    let ls: [f64; SCAN_LANES] = std::array::from_fn(|l| elements[at(l)].length());
    let mut steep = [false; SCAN_LANES];
    let mut forward = [true; SCAN_LANES];
    let (mut rlo, mut rhi) = ([f64::INFINITY; SCAN_LANES], [f64::NEG_INFINITY; SCAN_LANES]);
    let (mut stretch, mut mid) = ([0.0f64; SCAN_LANES], [0.0f64; SCAN_LANES]);
    let (mut slo, mut shi) = ([f64::INFINITY; SCAN_LANES], [f64::NEG_INFINITY; SCAN_LANES]);
    for j in 0..=samples {
        for l in 0..SCAN_LANES {
            let x = ls[l] * j as f64 / samples as f64;
            let [dx, dz] = M::tangent(&ks[l], x);
            steep[l] |= j > 0 && !(dx > 0.0 && dz.abs() <= limit_tan * dx);
            let fw = dx > 0.0;
            forward[l] &= fw;
            let r = dz / dx;
            rlo[l] = if fw { lesser(rlo[l], r) } else { rlo[l] };
            rhi[l] = if fw { greater(rhi[l], r) } else { rhi[l] };
            stretch[l] = greater(stretch[l], dx * dx + dz * dz);
            mid[l] = greater(mid[l], M::strain(&ks[l], x, 0.0).abs());
            for z in z {
                let s = eps0 + M::strain(&ks[l], x, z);
                slo[l] = lesser(slo[l], s);
                shi[l] = greater(shi[l], s);
            }
        }
    }
    // the end frames, then their turns over plain lane arrays (so that
    // the polynomial runs in vector lanes)
    let frame: [[f64; 4]; SCAN_LANES] = std::array::from_fn(|l| elements[at(l)].frame(&ks[l]));
    let (c, s): ([f64; SCAN_LANES], [f64; SCAN_LANES]) = (
        std::array::from_fn(|l| frame[l][2]),
        std::array::from_fn(|l| frame[l][3]),
    );
    let mut turn = [0.0; SCAN_LANES];
    for l in 0..SCAN_LANES {
        turn[l] = approx_atan2(s[l], c[l]);
    }
    std::array::from_fn(|l| Extremes {
        frame: frame[l],
        turn: turn[l],
        steep: steep[l],
        forward: forward[l],
        r: (rlo[l], rhi[l]),
        stretch: stretch[l],
        mid: mid[l],
        pre: (slo[l], shi[l]),
    })
}
