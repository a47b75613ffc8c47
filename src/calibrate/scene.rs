//! A calibrated scene: a specimen's scene with the fitted values written
//! in, and a `[calibration]` table with the fitted keys and their
//! covariance (which `fpc solve`, `fpc paper --scene` and `fpc design`
//! read like any scene: the table changes nothing they solve).

use toml::{Table, Value};

use super::record::Calibration;
use crate::measure::Manifest;
use crate::scene::{CalibrationSection, Scene, SceneFile};

/// The calibrated scene of every specimen of `manifest`, in its order:
/// `(specimen name, scene file text)`. Each is checked by resolving it
/// again (an error names the key it rejects).
pub fn calibrated_scenes(
    manifest: &Manifest,
    fit: &Calibration,
) -> Result<Vec<(String, String)>, crate::error::InputError> {
    let mut out = Vec::new();
    for s in &manifest.specimens {
        let mine: Vec<usize> = fit
            .parameters
            .iter()
            .enumerate()
            .filter(|(_, p)| p.specimen.as_deref().is_none_or(|n| n == s.name))
            // a camera frame is no part of the finger
            .filter(|(_, p)| !p.key.starts_with("camera."))
            .map(|(k, _)| k)
            .collect();
        let file: SceneFile = s.scene.file().clone();
        let mut table =
            Table::try_from(&file).map_err(|e| crate::error::InputError::Inconsistent {
                field: crate::field::Field::key("scene"),
                rule: e.to_string(),
            })?;
        for &k in &mine {
            let key: crate::scene::SceneKey = fit.parameters[k].key.parse()?;
            SceneFile::set_number(&mut table, key, fit.parameters[k].value)?;
        }
        let cov = fit.covariance.as_ref().map(|c| {
            mine.iter()
                .map(|&a| mine.iter().map(|&b| c[a][b]).collect())
                .collect()
        });
        let se = mine
            .iter()
            .map(|&k| fit.parameters[k].standard_error)
            .collect::<Option<Vec<f64>>>();
        let section = CalibrationSection {
            manifest: Some(fit.manifest.clone()),
            parameters: mine
                .iter()
                .map(|&k| fit.parameters[k].key.clone())
                .collect(),
            standard_errors: se,
            covariance: cov,
            chi_square_per_dof: fit
                .chi_square_per_dof
                .is_finite()
                .then_some(fit.chi_square_per_dof),
        };
        let with =
            Table::try_from(&section).map_err(|e| crate::error::InputError::Inconsistent {
                field: crate::field::Field::key("calibration"),
                rule: e.to_string(),
            })?;
        table.insert("calibration".into(), Value::Table(with));
        let text = format!(
            "# calibrated by fpc calibrate from {} (specimen {:?}); [calibration] holds the fitted keys and their covariance\n{}",
            fit.manifest,
            s.name,
            toml::to_string(&table).map_err(|e| crate::error::InputError::Inconsistent {
                field: crate::field::Field::key("scene"),
                rule: e.to_string(),
            })?
        );
        Scene::from_toml(&text).map_err(|e| match e {
            crate::scene::SceneReadError::Input(i) => i,
            crate::scene::SceneReadError::Syntax(x) => crate::error::InputError::Inconsistent {
                field: crate::field::Field::key("scene"),
                rule: x.to_string(),
            },
        })?;
        out.push((s.name.clone(), text));
    }
    Ok(out)
}
