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
use crate::num::Num;

/// Curvatures (1/mm) smaller than this count as straight when checking for
/// a reversal (a radius beyond 10 m).
pub const CURVATURE_TOL: f64 = 1e-4;

/// Why a grasp is not valid: the first reason its [`Verdict`] finds.
#[derive(Debug, Clone, PartialEq)]
pub enum Invalid {
    /// The fingers are not open: the grasping size or the tip gap is not
    /// positive.
    NotOpen { size: f64, tip_gap: f64 },
    /// The object would pull on the finger (`F < 0`).
    NegativeNormal { normal: f64 },
    /// The friction needed lies outside `[0, mu F]`.
    FrictionCone { friction: f64, limit: f64 },
    /// The object reaches into the finger away from the tip (a second
    /// contact): the deepest point of the mid-plane inside the object is
    /// `depth` mm deep, in element `element` at `x` mm along it, at `point`
    /// (gripper frame, mm).
    SecondContact {
        element: usize,
        x: f64,
        depth: f64,
        point: [f64; 2],
    },
    /// The finger reaches its tip from inside the object: its tangent at
    /// the tip points `angle` (rad) into it, so the object rests on the
    /// finger's face just before the tip, not on the tip.
    TipEntry { angle: f64 },
    /// The object's contact with the finger could not be computed (the
    /// mid-plane's polynomial coefficients overflow).
    ContactUnknown,
    /// The grasp size exceeds `d_max`: the fingers are pressed past flat.
    BeyondFlat { size: f64, d_max: f64 },
    /// (Strict mode.) An element is bent backwards.
    CurvatureReversal { element: usize, curvature: f64 },
    /// The finger's equilibrium leaves the model's assumptions (a validity
    /// finding of docs/model.md section 8).
    OutsideModel { finding: Warning },
    /// The equilibrium is unstable with the object holding the tip: the
    /// Hessian restricted to the grasp constraint has `negative` negative
    /// eigenvalues (the finger would snap away from this state).
    Unstable { negative: usize },
    /// The stability with the object holding the tip could not be
    /// determined (the restricted Hessian is singular there: the grasp sits
    /// on a limit of stability).
    StabilityUnknown,
}

impl Invalid {
    /// A short, stable name (`not_open`, `negative_normal`,
    /// `friction_cone`, `tip_entry`, `second_contact`, `contact_unknown`,
    /// `beyond_flat`,
    /// `curvature_reversal`, `outside_model`, `unstable`,
    /// `stability_unknown`).
    pub fn kind(&self) -> &'static str {
        match self {
            Invalid::NotOpen { .. } => "not_open",
            Invalid::NegativeNormal { .. } => "negative_normal",
            Invalid::FrictionCone { .. } => "friction_cone",
            Invalid::SecondContact { .. } => "second_contact",
            Invalid::ContactUnknown => "contact_unknown",
            Invalid::TipEntry { .. } => "tip_entry",
            Invalid::BeyondFlat { .. } => "beyond_flat",
            Invalid::CurvatureReversal { .. } => "curvature_reversal",
            Invalid::OutsideModel { .. } => "outside_model",
            Invalid::Unstable { .. } => "unstable",
            Invalid::StabilityUnknown => "stability_unknown",
        }
    }
}

impl std::fmt::Display for Invalid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            &Invalid::NotOpen { size, tip_gap } => {
                // a size or gap below zero is an overlap, said as one (no
                // negative sizes in the words; the numbers keep their sign
                // in the data)
                let size = if size < 0.0 {
                    format!("the grasp points overlap by {:.3} mm", Num(-size))
                } else {
                    format!("grasp size {:.3} mm", Num(size))
                };
                let gap = if tip_gap < 0.0 {
                    format!("the tips overlap by {:.3} mm", Num(-tip_gap))
                } else {
                    format!("tip gap {:.3} mm", Num(tip_gap))
                };
                write!(f, "the fingers are not open ({size}, {gap})")
            }
            &Invalid::NegativeNormal { normal } => {
                write!(
                    f,
                    "the object would pull on the finger (F = {:.4} N)",
                    Num(normal)
                )
            }
            // a value near zero keeps a digit: `1e-300`, not `0.0000`
            &Invalid::FrictionCone { friction, limit } => write!(
                f,
                "the friction needed, {:.4} N, lies outside [0, mu F] = [0, {:.4}] N",
                Num(friction),
                Num(limit)
            ),
            &Invalid::SecondContact {
                element,
                x,
                depth,
                point,
            } => write!(
                f,
                "the object reaches {} mm into the finger at element {element}, {x:.3} mm along it (Xg {:.3} mm, Zg {:.3} mm): a second contact",
                fmt_depth(depth),
                point[0],
                point[1]
            ),
            &Invalid::TipEntry { angle } => write!(
                f,
                "the finger reaches its tip from inside the object (its tangent there points {:.4} degrees into it): the object rests on the finger's face, not on its tip",
                Num(angle.to_degrees())
            ),
            Invalid::ContactUnknown => write!(
                f,
                "the object's contact with the finger cannot be computed (the mid-plane is too large)"
            ),
            &Invalid::BeyondFlat { size, d_max } => write!(
                f,
                "grasp size {size:.2} mm exceeds d_max = {d_max:.2} mm (fingers pressed past flat)"
            ),
            &Invalid::CurvatureReversal { element, curvature } => write!(
                f,
                "element {element} is bent backwards (curvature {curvature:.3e} 1/mm; strict mode)"
            ),
            Invalid::OutsideModel { finding } => {
                write!(f, "the finger leaves the model: {finding}")
            }
            &Invalid::Unstable { negative } => write!(
                f,
                "the equilibrium is unstable with the object holding the tip ({negative} negative eigenvalue(s) of the constrained Hessian)"
            ),
            Invalid::StabilityUnknown => write!(
                f,
                "the stability with the object holding the tip cannot be determined (the constrained Hessian is singular)"
            ),
        }
    }
}

/// A depth in mm with as many digits as it needs (a micrometre shows).
fn fmt_depth(depth: f64) -> String {
    if depth >= 0.01 {
        format!("{depth:.3}")
    } else {
        format!("{depth:.2e}")
    }
}

/// Stability of a grasp with the object holding the tip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Stability {
    /// The Hessian restricted to the grasp constraint is positive definite.
    Stable,
    /// It has `negative` negative eigenvalues.
    Unstable { negative: usize },
    /// It is singular: not determined.
    Unknown,
    /// Not judged (stability switched off for this gripper).
    NotJudged,
}

/// How a grasp's equilibrium was reached: by closing the gripper on the
/// object from rest, traced in the target ([`crate::finger::Solver::trace_target`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct PathRecord {
    /// `rest` (traced from the rest state at the grasp's pressure) or
    /// `previous` (continued along the same path from a previous grasp of
    /// the same load family, itself reached from rest).
    pub from: &'static str,
    /// Accepted steps of the trace.
    pub steps: usize,
}

/// A grasp's verdict, its reasons kept apart: the paper's rules, the
/// finger's validity findings, the stability with the object holding the
/// tip, and the path. A grasp is valid only when all four hold
/// ([`Verdict::is_valid`]); `valid` means that everywhere (text, JSON, CSV,
/// figures, Python). A grasp the library returns is always on the loading
/// path (a target beyond a fold of that path is refused, not answered), so
/// `path` records how it was reached.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    /// The first of the paper's rules the grasp breaks (not open, `F < 0`,
    /// the friction cone, past flat, a second contact, in strict mode a
    /// reversed element).
    pub rules: Option<Invalid>,
    /// The finger's validity findings at the grasp (`Warning::is_validity`).
    pub findings: Vec<Warning>,
    /// Stability with the object holding the tip.
    pub stability: Stability,
    /// How the equilibrium was reached.
    pub path: PathRecord,
}

impl Verdict {
    /// The first reason the grasp is not valid, in the order rules,
    /// findings, stability (`None`: valid).
    pub fn first(&self) -> Option<Invalid> {
        self.rules
            .clone()
            .or_else(|| {
                self.findings
                    .first()
                    .map(|w| Invalid::OutsideModel { finding: w.clone() })
            })
            .or(match self.stability {
                Stability::Unstable { negative } => Some(Invalid::Unstable { negative }),
                Stability::Unknown => Some(Invalid::StabilityUnknown),
                Stability::Stable | Stability::NotJudged => None,
            })
    }

    /// True when the rules hold, the finger is inside the model, the grasp
    /// is stable (or stability is not judged) and on the loading path.
    pub fn is_valid(&self) -> bool {
        self.first().is_none()
    }
}

impl serde::Serialize for Verdict {
    /// `{"valid", "invalid", "rules", "findings", "stability", "path"}`:
    /// the verdict, its first reason (`{kind, message}` or null), then the
    /// reasons apart.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(6))?;
        m.serialize_entry("valid", &self.is_valid())?;
        m.serialize_entry("invalid", &self.first())?;
        m.serialize_entry("rules", &self.rules)?;
        m.serialize_entry("findings", &self.findings)?;
        m.serialize_entry("stability", &self.stability)?;
        m.serialize_entry("path", &self.path)?;
        m.end()
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

impl serde::Serialize for Invalid {
    /// `{"kind", "message"}`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(2))?;
        m.serialize_entry("kind", self.kind())?;
        m.serialize_entry("message", &self.to_string())?;
        m.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_overlap_is_said_as_one_never_as_a_negative_size() {
        let text = open_rule(-2.741, -1.5).unwrap().to_string();
        assert_eq!(
            text,
            "the fingers are not open (the grasp points overlap by 2.741 mm, the tips overlap by 1.500 mm)"
        );
        assert!(!text.contains('-'), "{text}");
        let text = open_rule(0.0, 3.0).unwrap().to_string();
        assert_eq!(
            text,
            "the fingers are not open (grasp size 0.000 mm, tip gap 3.000 mm)"
        );
        // a value near zero keeps its digit (not `0.000`, `-0.0000`)
        let text = open_rule(-2e-7, 3.0).unwrap().to_string();
        assert!(text.contains("overlap by 2e-7 mm"), "{text}");
        let text = Invalid::NegativeNormal { normal: -3e-9 }.to_string();
        assert!(text.contains("(F = -3e-9 N)"), "{text}");
        let text = Invalid::TipEntry { angle: 1e-8 }.to_string();
        assert!(text.contains("points 5.7296e-7 degrees"), "{text}");
    }

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
