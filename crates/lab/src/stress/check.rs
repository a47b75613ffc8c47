//! The checks of a returned solution, independent of the solver: residual,
//! consistency and the dense stability and conditioning counts.

use fpc_newton::{min_eigenvalue, negative_eigenvalues};

use fpc::{Coefficients, Finger, Load, Solution, Warning};

use super::report::finding_name;
use super::{
    CONDITIONING_MAX_ELEMENTS, DENSE_CHECK_MAX_ELEMENTS, FINE_VALIDITY_SAMPLES, RESIDUAL_LIMIT,
    STABILITY_TOLERANCE,
};

/// What [`check`] found and measured.
pub(super) struct Checked {
    pub(super) residual: f64,
    pub(super) max_rotation: f64,
    pub(super) dense_negative: Option<(usize, usize)>,
    pub(super) min_eig: Option<f64>,
    pub(super) conditioning: Option<f64>,
    pub(super) findings: Vec<&'static str>,
    pub(super) notes: Vec<&'static str>,
    pub(super) missed: Vec<&'static str>,
    pub(super) wrong: Option<String>,
}

impl Checked {
    fn wrong(what: String) -> Checked {
        Checked {
            residual: f64::INFINITY,
            max_rotation: f64::NAN,
            dense_negative: None,
            min_eig: None,
            conditioning: None,
            findings: Vec::new(),
            notes: Vec::new(),
            missed: Vec::new(),
            wrong: Some(what),
        }
    }
}

/// The distinct names of a list of warnings, in order: of its validity
/// findings, or (`validity` false) of its notes.
fn names(ws: &[Warning], validity: bool) -> Vec<&'static str> {
    let mut out: Vec<&'static str> = Vec::new();
    for w in ws.iter().filter(|w| w.is_validity() == validity) {
        let n = finding_name(w);
        if !out.contains(&n) {
            out.push(n);
        }
    }
    out
}

/// The independent checks of a returned solution (the [`stress`](super)
/// module docs).
pub(super) fn check(finger: &Finger, load: &Load, sol: &Solution) -> Checked {
    let stiffness = finger.stiffness_scale();
    let k = &sol.coefficients;
    let mut wrong = Vec::new();
    if k.elements() != finger.len() || k.per_element() != finger.unknowns_per_element() {
        return Checked::wrong(format!(
            "{} coefficient sets of {} for {} elements of {}",
            k.elements(),
            k.per_element(),
            finger.len(),
            finger.unknowns_per_element()
        ));
    }
    if sol.element_lengths != finger.element_lengths() {
        wrong.push("element lengths differ from the finger's".to_string());
    }
    if sol.stable != sol.negative_eigenvalues.map(|n| n == 0) {
        wrong.push(format!(
            "stable {:?} but {:?} negative eigenvalues",
            sol.stable, sol.negative_eigenvalues
        ));
    }
    if !k.as_slice().iter().all(|v| v.is_finite()) {
        wrong.push("non-finite coefficient".into());
    }
    if !(sol.tip.iter().all(|v| v.is_finite()) && sol.end_angle.is_finite()) {
        wrong.push(format!(
            "non-finite tip {:?} or end angle {}",
            sol.tip, sol.end_angle
        ));
    }
    if !sol.energy.is_finite() {
        wrong.push(format!("non-finite energy {}", sol.energy));
    }
    let Ok((energy, g)) = finger.gradient(load, k) else {
        return Checked::wrong("coefficients the finger rejects".into());
    };
    let s = finger.unknown_scales();
    if s.len() != g.len() {
        return Checked::wrong(format!(
            "{} unknown scales for {} unknowns",
            s.len(),
            g.len()
        ));
    }
    let mut residual: f64 = 0.0;
    for (gi, si) in g.iter().zip(&s) {
        let v = (gi * si).abs();
        // NaN poisons the maximum
        residual = if v.is_nan() {
            f64::NAN
        } else {
            residual.max(v)
        };
    }
    residual /= stiffness;
    if residual.is_nan() || residual > RESIDUAL_LIMIT {
        wrong.push(format!(
            "recomputed residual {residual:.3e} > {RESIDUAL_LIMIT:.0e} (solver reported {:.3e})",
            sol.report.residual_norm
        ));
    }
    let energy_tol = 1e-9 * (energy.abs() + stiffness);
    if (energy - sol.energy).abs().is_nan() || (energy - sol.energy).abs() > energy_tol {
        wrong.push(format!(
            "energy {} differs from the recomputed {}",
            sol.energy, energy
        ));
    }
    let (tip, _) = finger.tip(k).unwrap_or(([f64::NAN; 2], f64::NAN));
    let lx = finger.length();
    let tip_err = (tip[0] - sol.tip[0]).abs().max((tip[1] - sol.tip[1]).abs());
    if tip_err.is_nan() || tip_err > 1e-9 * lx {
        wrong.push(format!(
            "tip {:?} differs from the recomputed {:?}",
            sol.tip, tip
        ));
    }
    let findings = names(&sol.warnings, true);
    let missed = finger
        .validity(k, FINE_VALIDITY_SAMPLES)
        .map(|w| {
            names(&w, true)
                .into_iter()
                .filter(|n| !findings.contains(n))
                .collect()
        })
        .unwrap_or_default();
    let (dense_negative, min_eig, conditioning) =
        if wrong.is_empty() && finger.len() <= DENSE_CHECK_MAX_ELEMENTS {
            dense_stability(finger, load, k, &s, stiffness)
        } else {
            (None, None, None)
        };
    let max_rotation = k
        .iter()
        .enumerate()
        .filter_map(|(i, ki)| finger.element_end(i, ki))
        .map(|e| e[2].abs())
        .fold(0.0, f64::max);
    Checked {
        residual,
        max_rotation,
        dense_negative,
        min_eig,
        conditioning,
        findings,
        notes: names(&sol.warnings, false),
        missed,
        wrong: (!wrong.is_empty()).then(|| wrong.join("; ")),
    }
}

/// The dense count of negative eigenvalues of `finger`'s Hessian at raw
/// coefficients `k` under `load`: the eigenvalues of the scaled Hessian
/// over the stiffness below `-tau` and below `+tau`
/// ([`STABILITY_TOLERANCE`]), from `fpc_newton`'s dense eigensolver
/// (`O(n^3)`; the stress test calls it for at most
/// [`DENSE_CHECK_MAX_ELEMENTS`] elements). `None` when the Hessian is not
/// finite or the eigensolver fails.
pub fn dense_negative_eigenvalues(
    finger: &Finger,
    load: &Load,
    k: &Coefficients,
) -> Option<(usize, usize)> {
    let s = finger.unknown_scales();
    dense_stability(finger, load, k, &s, finger.stiffness_scale()).0
}

/// The dense eigenvalue counts below `-tau` and `+tau` of the scaled
/// Hessian over the stiffness, and (for at most
/// [`CONDITIONING_MAX_ELEMENTS`] elements) `lambda_min / stiffness` and
/// `lambda_min / G`.
#[allow(clippy::type_complexity)]
fn dense_stability(
    finger: &Finger,
    load: &Load,
    k: &Coefficients,
    s: &[f64],
    stiffness: f64,
) -> (Option<(usize, usize)>, Option<f64>, Option<f64>) {
    let Ok((_, _, mut h)) = finger.hessian(load, k) else {
        return (None, None, None);
    };
    let n = s.len();
    if h.len() != n * n {
        return (None, None, None);
    }
    for j in 0..n {
        for i in 0..n {
            h[i + n * j] *= s[i] * s[j] / stiffness;
        }
    }
    let lmin = min_eigenvalue(n, &h);
    if !lmin.is_finite() {
        return (None, None, None);
    }
    let tau = STABILITY_TOLERANCE;
    let counts = if lmin > tau {
        Some((0, 0))
    } else {
        let shifted = |shift: f64| {
            let mut m = h.clone();
            for i in 0..n {
                m[i + n * i] += shift;
            }
            negative_eigenvalues(n, &m)
        };
        shifted(tau).zip(shifted(-tau))
    };
    let (min_eig, conditioning) = if finger.len() <= CONDITIONING_MAX_ELEMENTS {
        let gersh = (0..n)
            .map(|i| (0..n).map(|j| h[i + n * j].abs()).sum::<f64>())
            .fold(0.0, f64::max);
        (Some(lmin), Some(lmin / gersh).filter(|v| v.is_finite()))
    } else {
        (None, None)
    };
    (counts, min_eig, conditioning)
}
