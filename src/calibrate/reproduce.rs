//! A calibration's claim checked through the ordinary path: the calibrated
//! scene of every specimen ([`calibrated_scenes`]) is read back as that
//! specimen's scene, the fitted camera frames are put in their tests, and
//! the data are compared with the model by [`crate::measure::compare`]'s
//! path, as `fpc compare` does (its rows; not the curves of its figures).
//! Every row the fit predicted must be predicted again, each residual
//! within [`REPRODUCE_SD`] standard deviations of the fit's, give or
//! take [`REPRODUCE_RELATIVE`] of the predicted value (for a prediction
//! many standard deviations large), before the calibration is reported
//! as reproduced.

use std::collections::HashMap;

use super::params::Unknown;
use super::record::{Calibration, Reproduction, REPRODUCE_RELATIVE, REPRODUCE_SD};
use super::scene::calibrated_scenes;
use crate::measure::{compare_with, Manifest, TestData};
use crate::scene::Scene;

impl Reproduction {
    /// Before the comparison.
    pub(crate) fn not_run() -> Reproduction {
        Reproduction::failed("not compared yet".into())
    }

    fn failed(detail: String) -> Reproduction {
        Reproduction {
            chi_square: None,
            points: 0,
            largest_difference_sd: None,
            reproduced: false,
            detail,
        }
    }
}

/// Compares `fit`'s calibrated scenes (and fitted camera frames, from
/// `unknowns`, the fit's unknowns in its order) with `manifest`'s data.
pub(crate) fn reproduce(
    manifest: &Manifest,
    unknowns: &[Unknown],
    fit: &Calibration,
) -> Reproduction {
    let scenes = match calibrated_scenes(manifest, fit) {
        Ok(s) => s,
        Err(e) => return Reproduction::failed(format!("a calibrated scene is refused: {e}")),
    };
    let mut again = manifest.clone();
    for (s, (_, text)) in again.specimens.iter_mut().zip(&scenes) {
        match Scene::from_toml(text) {
            Ok(scene) => s.scene = scene,
            Err(e) => {
                return Reproduction::failed(format!(
                    "the calibrated scene of specimen {:?} does not read back: {e}",
                    s.name
                ))
            }
        }
    }
    for (u, p) in unknowns.iter().zip(&fit.parameters) {
        let (Some((t, k)), Some(name)) = (u.camera, &u.specimen) else {
            continue;
        };
        let test = again
            .specimens
            .iter_mut()
            .find(|s| &s.name == name)
            .and_then(|s| s.tests.get_mut(t));
        if let Some(TestData::Markers {
            camera: Some(c), ..
        }) = test.map(|t| &mut t.data)
        {
            *[&mut c.angle_deg, &mut c.x_mm, &mut c.z_mm][k] = p.value;
        }
    }
    // the rows only: the figures' curves are no part of the claim
    let comparison = match compare_with(&again, false) {
        Ok(c) => c,
        Err(e) => return Reproduction::failed(format!("the comparison fails: {e}")),
    };
    let mut fitted: HashMap<(&str, &str, usize, &str), (f64, f64)> = fit
        .residuals
        .iter()
        .map(|r| {
            let key = (r.specimen.as_str(), r.file.as_str(), r.line, r.quantity);
            (key, (r.residual_sd, r.predicted / r.sd))
        })
        .collect();
    let mut largest = 0.0f64;
    let mut worst = 0.0f64;
    let mut unmatched = 0;
    for s in &comparison.specimens {
        for t in &s.tests {
            for p in &t.predictions {
                for r in &p.residuals {
                    let key = (s.name.as_str(), t.file.as_str(), p.line, r.quantity);
                    // (a difference that is not a number pairs with nothing)
                    match (fitted.remove(&key), r.residual_sd) {
                        (Some((want, scale)), Some(got)) if (got - want).is_finite() => {
                            let d = (got - want).abs();
                            largest = largest.max(d);
                            // in units of what is allowed: 1 is the limit
                            let allowed = REPRODUCE_SD + REPRODUCE_RELATIVE * scale.abs();
                            worst = worst.max(d / allowed);
                        }
                        _ => unmatched += 1,
                    }
                }
            }
        }
    }
    unmatched += fitted.len();
    let reproduced = unmatched == 0 && worst <= 1.0;
    let detail = if unmatched > 0 {
        format!(
            "{unmatched} residuals of the fit and of the comparison do not pair up (a row predicted by one and not the other)"
        )
    } else if reproduced {
        format!(
            "every residual within {largest:.1e} sd of the fit's; chi2 {:.6}",
            comparison.chi_square
        )
    } else {
        format!(
            "residuals up to {largest:.3e} sd from the fit's; chi2 {:.6} against the fit's {:.6}",
            comparison.chi_square, fit.chi_square
        )
    };
    Reproduction {
        chi_square: Some(comparison.chi_square),
        points: comparison.points,
        largest_difference_sd: Some(largest),
        reproduced,
        detail,
    }
}
