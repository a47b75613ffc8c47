//! Model choice: the same data fitted with every element model, with the
//! manifest's ribs and without ribs, in plane stress and in plane strain
//! across the width, and the candidates compared by their
//! leave-one-pressure-out prediction error (docs/calibration.md). A model
//! that only absorbs the data fits as well as the right one but predicts
//! the pressures it did not see worse.

use serde::Serialize;

use super::fit::calibrate;
use super::identify::Verdict;
use super::options::CalibrateOptions;
use super::progress::{CalibrateProgress, CalibrateStage, Tracker};
use crate::actuator::{Actuator, RibLayout};
use crate::measure::Manifest;
use crate::model::ModelId;
use crate::solve_error::SolveError;

/// One element model, rib choice and state across the width, fitted and
/// cross-validated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Candidate {
    /// The element model.
    pub model: &'static str,
    /// With the manifest's ribs (`true`) or with none.
    pub ribs: bool,
    /// Plane strain across the width (`actuator.laminate.plane_strain =
    /// true` in every specimen) or plane stress (`false`).
    pub plane_strain: bool,
    /// The fit's chi-square per degree of freedom.
    pub chi_square_per_dof: Option<f64>,
    /// Root mean square, in standard deviations, of every pressure's
    /// residuals predicted by the fit without that pressure: the measure
    /// the candidates are ranked by.
    pub held_out_rms_sd: Option<f64>,
    /// The fitted values, in the order of `names`.
    pub values: Vec<f64>,
    /// The identifiability verdict at the fit.
    pub verdict: Option<Verdict>,
    /// Predictions at the fit by a finger outside the model.
    pub outside_model: usize,
    /// Why the candidate has no fit (a failed solve or fit).
    pub failure: Option<String>,
}

/// One line: the model, its ribs and plane state, the fit's chi-square
/// per degree of freedom, the held-out error and why it failed, if it did.
impl std::fmt::Display for Candidate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ribs {} plane strain {}: chi2/dof {:?}, held out rms {:?} sd",
            self.model, self.ribs, self.plane_strain, self.chi_square_per_dof, self.held_out_rms_sd
        )?;
        match &self.failure {
            Some(why) => write!(f, " ({why})"),
            None => Ok(()),
        }
    }
}

/// Every candidate, and the best by held-out error.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelChoice {
    /// The fitted parameters' names (as in a calibration's `parameters`).
    pub names: Vec<String>,
    /// In plane stress: every model with ribs as given, then every model
    /// without ribs (left out when the manifest has no ribs to remove);
    /// then the same in plane strain.
    pub candidates: Vec<Candidate>,
    /// The candidate with the smallest held-out error (`None`: none fitted).
    pub best: Option<usize>,
}

/// Fits `options.fit` to `manifest` with every element model, with its
/// ribs and without, in plane stress and in plane strain, each
/// cross-validated (leave-one-pressure-out), and ranks them by the
/// held-out error. Bad options, or parameters the
/// manifest as given cannot fit, are the calibration's input error; a
/// candidate that fails otherwise is recorded with its reason.
pub fn choose_model(
    manifest: &Manifest,
    options: &CalibrateOptions,
) -> Result<ModelChoice, SolveError> {
    choose_model_with_progress(manifest, options, &|_| {})
}

/// [`choose_model`], handing `observer` a [`CalibrateProgress`] (stage
/// [`CalibrateStage::ChoosingModel`]) as it begins and as each candidate's
/// fit ends, as [`calibrate_with_progress`](super::calibrate_with_progress)
/// does: one call at a time, no count falling.
pub fn choose_model_with_progress(
    manifest: &Manifest,
    options: &CalibrateOptions,
    observer: &(dyn Fn(&CalibrateProgress) + Sync),
) -> Result<ModelChoice, SolveError> {
    let options = CalibrateOptions {
        cross_validate: true,
        ..options.clone()
    };
    let has_ribs = manifest
        .specimens
        .iter()
        .any(|s| !s.scene.actuator.ribs().is_empty());
    let rib_choices: &[bool] = if has_ribs { &[true, false] } else { &[true] };
    // every candidate fitted at once (they are independent), then read
    // in order, as a loop over them would
    let combos: Vec<(bool, bool, ModelId)> = [false, true]
        .into_iter()
        .flat_map(|plane_strain| {
            rib_choices.iter().flat_map(move |&ribs| {
                ModelId::ALL
                    .iter()
                    .map(move |&model| (plane_strain, ribs, model))
            })
        })
        .collect();
    let tracker = Tracker::new(observer, {
        let mut p = CalibrateProgress::new(options.max_iterations, manifest.specimens.len());
        p.stage = CalibrateStage::ChoosingModel;
        p.candidates = combos.len();
        p
    });
    tracker.update(|_| {});
    let fits = crate::cancel::par_map(&combos, |&(plane_strain, ribs, model)| {
        let fit =
            variant(manifest, model, ribs, plane_strain).and_then(|m| calibrate(&m, &options));
        tracker.update(|p| p.candidates_done += 1);
        fit
    });
    let mut names = Vec::new();
    let mut candidates = Vec::new();
    for (&(plane_strain, ribs, model), fitted) in combos.iter().zip(fits) {
        let as_given = ribs
            && manifest
                .specimens
                .iter()
                .all(|s| s.scene.model == model && s.scene.actuator.plane_strain() == plane_strain);
        candidates.push(match fitted {
            Ok(c) => {
                names = c.parameters.iter().map(|p| p.name.clone()).collect();
                Candidate {
                    model: model.name(),
                    ribs,
                    plane_strain,
                    chi_square_per_dof: Some(c.chi_square_per_dof),
                    held_out_rms_sd: c.cross_validation.as_ref().map(|cv| cv.rms_sd),
                    values: c.parameters.iter().map(|p| p.value).collect(),
                    verdict: Some(c.identifiability.verdict),
                    outside_model: c.outside_model,
                    failure: None,
                }
            }
            // bad options are the caller's, whatever the model
            Err(e @ SolveError::Input(_)) if as_given => return Err(e),
            Err(e) => Candidate {
                model: model.name(),
                ribs,
                plane_strain,
                chi_square_per_dof: None,
                held_out_rms_sd: None,
                values: Vec::new(),
                verdict: None,
                outside_model: 0,
                failure: Some(e.to_string()),
            },
        });
    }
    let best = candidates
        .iter()
        .enumerate()
        .filter_map(|(i, c)| c.held_out_rms_sd.filter(|e| e.is_finite()).map(|e| (i, e)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i);
    Ok(ModelChoice {
        names,
        candidates,
        best,
    })
}

/// `manifest` with every specimen's finger built from `model`, without
/// ribs unless `ribs`, and in plane strain across the width or not.
fn variant(
    manifest: &Manifest,
    model: ModelId,
    ribs: bool,
    plane_strain: bool,
) -> Result<Manifest, SolveError> {
    let mut m = manifest.clone();
    for s in &mut m.specimens {
        s.scene.model = model;
        let mut params = s.scene.actuator.params().clone();
        if !ribs {
            params.ribs = RibLayout::None;
        }
        params.plane_strain = plane_strain;
        s.scene.actuator = Actuator::new(params)?;
    }
    Ok(m)
}
