//! When a grasp is valid (docs/model.md sections 5.4 and 8): every rule in
//! one place, for every study, scene and design.
//!
//! A grasp is invalid when the fingers are not open, the object would pull
//! on the finger (`F < 0`), the friction it needs lies outside `[0, mu F]`,
//! its size exceeds `d_max` (fingers pressed past flat), or, for a sphere,
//! the sphere crosses the finger somewhere else (a second contact). A
//! finger bent backwards (curvature against the unloaded curl) breaks the
//! paper's assumption too: it is always flagged, and invalid in strict mode.

use crate::error::Warning;

/// Curvatures (1/mm) smaller than this count as straight when checking for
/// a reversal (a radius beyond 10 m).
pub const CURVATURE_TOL: f64 = 1e-4;

/// Why a grasp is not valid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Invalid {
    /// The fingers are not open: the grasping size or the tip gap is not
    /// positive.
    NotOpen { size: f64, tip_gap: f64 },
    /// The object would pull on the finger (`F < 0`).
    NegativeNormal { normal: f64 },
    /// The friction needed lies outside `[0, mu F]`.
    FrictionCone { friction: f64, limit: f64 },
    /// The sphere crosses the finger's mid-plane at sample `point` (root =
    /// 0), `depth` mm inside its surface: a second contact.
    SecondContact { point: usize, depth: f64 },
    /// The grasp size exceeds `d_max`: the fingers are pressed past flat.
    BeyondFlat { size: f64, d_max: f64 },
    /// (Strict mode.) An element is bent backwards.
    CurvatureReversal { element: usize, curvature: f64 },
    /// The equilibrium is unstable with the object holding the tip: the
    /// Hessian restricted to the grasp constraint has `negative` negative
    /// eigenvalues (the finger would snap away from this state).
    Unstable { negative: usize },
}

impl Invalid {
    /// A short, stable name (`not_open`, `negative_normal`,
    /// `friction_cone`, `second_contact`, `beyond_flat`,
    /// `curvature_reversal`, `unstable`).
    pub fn kind(&self) -> &'static str {
        match self {
            Invalid::NotOpen { .. } => "not_open",
            Invalid::NegativeNormal { .. } => "negative_normal",
            Invalid::FrictionCone { .. } => "friction_cone",
            Invalid::SecondContact { .. } => "second_contact",
            Invalid::BeyondFlat { .. } => "beyond_flat",
            Invalid::CurvatureReversal { .. } => "curvature_reversal",
            Invalid::Unstable { .. } => "unstable",
        }
    }
}

impl std::fmt::Display for Invalid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Invalid::NotOpen { size, tip_gap } => write!(
                f,
                "the fingers are not open (grasp size {size:.3} mm, tip gap {tip_gap:.3} mm)"
            ),
            Invalid::NegativeNormal { normal } => {
                write!(f, "the object would pull on the finger (F = {normal:.4} N)")
            }
            Invalid::FrictionCone { friction, limit } => write!(
                f,
                "the friction needed, {friction:.4} N, lies outside [0, mu F] = [0, {limit:.4}] N"
            ),
            Invalid::SecondContact { point, depth } => write!(
                f,
                "the sphere crosses the finger at mid-plane sample {point}, {depth:.3} mm deep (a second contact)"
            ),
            Invalid::BeyondFlat { size, d_max } => write!(
                f,
                "grasp size {size:.2} mm exceeds d_max = {d_max:.2} mm (fingers pressed past flat)"
            ),
            Invalid::CurvatureReversal { element, curvature } => write!(
                f,
                "element {element} is bent backwards (curvature {curvature:.3e} 1/mm; strict mode)"
            ),
            Invalid::Unstable { negative } => write!(
                f,
                "the equilibrium is unstable with the object holding the tip ({negative} negative eigenvalue(s) of the constrained Hessian)"
            ),
        }
    }
}

/// Relative tolerance of the force rules: forces come out of iterative
/// solves (residuals of 1e-11, targets to 1e-9 mm), so a grasp solved to
/// lie on the friction limit may land a few 1e-10 N beyond it.
pub const FORCE_RULE_TOL: f64 = 1e-9;

/// True when `F >= 0` and `0 <= f <= mu F` (to [`FORCE_RULE_TOL`]).
pub fn friction_ok(normal: f64, friction: f64, mu: f64) -> bool {
    let tol = FORCE_RULE_TOL * (1.0 + normal.abs());
    normal >= -tol && friction >= -tol && friction <= mu * normal + tol
}

/// The force rules: `F >= 0`, then `0 <= f <= mu F`.
pub fn force_rule(normal: f64, friction: f64, mu: f64) -> Option<Invalid> {
    let tol = FORCE_RULE_TOL * (1.0 + normal.abs());
    if normal < -tol {
        return Some(Invalid::NegativeNormal { normal });
    }
    (!friction_ok(normal, friction, mu)).then_some(Invalid::FrictionCone {
        friction,
        limit: mu * normal,
    })
}

/// The fingers open: a positive grasp size and tip gap.
pub fn open_rule(size: f64, tip_gap: f64) -> Option<Invalid> {
    (!(size > 0.0 && tip_gap > 0.0)).then_some(Invalid::NotOpen { size, tip_gap })
}

/// Not pressed past flat: `size <= d_max` (to a relative 1e-9).
pub fn flat_rule(size: f64, d_max: f64) -> Option<Invalid> {
    (size > d_max + 1e-9 * d_max.abs().max(1.0)).then_some(Invalid::BeyondFlat { size, d_max })
}

/// The most reversed element: over matching samples of a state and the
/// reference state (`per_element` samples per element, element-major), the
/// most negative `kappa * sign(kappa_ref)` below `-CURVATURE_TOL`, reported
/// as that signed curvature (negative: bent against the unloaded curl).
pub fn curvature_reversal(
    curvature: &[f64],
    reference: &[f64],
    per_element: usize,
) -> Option<Warning> {
    let mut worst: Option<(usize, f64)> = None;
    for (i, (&k, &r)) in curvature.iter().zip(reference).enumerate() {
        if r.abs() <= CURVATURE_TOL {
            continue;
        }
        let against = k * r.signum();
        if against < -CURVATURE_TOL && worst.is_none_or(|(_, w)| against < w) {
            worst = Some((i / per_element.max(1), against));
        }
    }
    worst.map(|(element, against)| Warning::CurvatureReversal {
        element,
        curvature: against,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_on_constructed_cases() {
        assert_eq!(force_rule(1.0, 0.6, 0.6), None);
        assert!(matches!(
            force_rule(-0.1, 0.0, 0.6),
            Some(Invalid::NegativeNormal { .. })
        ));
        assert!(matches!(
            force_rule(1.0, 0.7, 0.6),
            Some(Invalid::FrictionCone { .. })
        ));
        assert!(matches!(
            force_rule(1.0, -0.1, 0.6),
            Some(Invalid::FrictionCone { .. })
        ));
        assert_eq!(open_rule(10.0, 5.0), None);
        assert!(open_rule(0.0, 5.0).is_some() && open_rule(1.0, -1.0).is_some());
        assert_eq!(flat_rule(143.9, 143.9), None);
        assert!(matches!(
            flat_rule(150.0, 143.9),
            Some(Invalid::BeyondFlat { .. })
        ));
        // reference curls one way everywhere; element 1 (samples 2, 3) turns
        // the other way, element 0 keeps its sign
        let reference = [-0.01, -0.01, -0.01, -0.01];
        let state = [-0.005, -0.001, 0.002, 0.004];
        match curvature_reversal(&state, &reference, 2) {
            Some(Warning::CurvatureReversal { element, curvature }) => {
                assert_eq!(element, 1);
                assert!((curvature + 0.004).abs() < 1e-15, "{curvature}");
            }
            other => panic!("{other:?}"),
        }
        // below the tolerance is straight, not reversed
        assert_eq!(curvature_reversal(&[5e-5], &[-0.01], 1), None);
        assert_eq!(curvature_reversal(&[-0.02], &[-0.01], 1), None);
    }
}
