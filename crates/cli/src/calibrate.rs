//! `fpc calibrate MANIFEST --fit eps0,kappa,...`: the named parameters
//! fitted to measurements by weighted least squares (`fpc::calibrate`;
//! docs/calibration.md). Prints the fitted values with standard errors,
//! the chi-square per degree of freedom and the identifiability verdict;
//! writes `calibration.json` (everything: covariance, correlations,
//! singular values, residuals, counts) and one calibrated scene per
//! specimen (`<specimen>.toml`, with a `[calibration]` table of the
//! fitted keys and their covariance) that `fpc solve` reads. With
//! `--cross-validate`, leave-one-pressure-out prediction errors.

use std::io::Write as _;
use std::path::PathBuf;

use fpc::calibrate::{
    calibrate_with_progress, calibrated_scenes, choose_model_with_progress, CalibrateOptions,
    CalibrateProgress, CalibrateStage, Calibration, ModelChoice,
};
use fpc::measure::Manifest;
use fpc::num::Num;
use fpc::SolveError;
use serde::Serialize;

/// Flags of `fpc calibrate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The measurement manifest (TOML; docs/measurements.md).
    manifest: PathBuf,
    /// The parameters to fit, comma-separated: eps0, kappa, p1..p4, or
    /// scene keys (pemc.e2, emc.e1, cl.e, actuator.fluidic.e, ...), or
    /// camera (every markers test's camera frame). A parameter in a
    /// specimen's own tables is fitted per specimen.
    #[arg(long, value_delimiter = ',', required = true)]
    fit: Vec<String>,
    /// Most Levenberg-Marquardt iterations.
    #[arg(
        long,
        default_value_t = fpc::calibrate::DEFAULT_ITERATIONS,
        allow_hyphen_values = true
    )]
    max_iterations: usize,
    /// Also fit again without each pressure in turn and predict it
    /// (leave-one-pressure-out prediction errors; one refit per pressure).
    #[arg(long)]
    cross_validate: bool,
    /// Also fit with every element model, with the manifest's ribs and
    /// without, in plane stress and in plane strain across the width, each
    /// cross-validated, and rank them by held-out error.
    #[arg(long)]
    choose_model: bool,
    /// Output directory (default `<stem>-calibrate`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print calibration.json's object instead of the summary.
    #[arg(long)]
    json: bool,
}

/// A calibration's error in the terms of the command line: the options
/// the library names `fit` and `max_iterations` are the flags `--fit` and
/// `--max-iterations` here.
fn in_flag_terms(e: SolveError) -> SolveError {
    let SolveError::Input(i) = e else {
        return e;
    };
    let flag = if i.field() == "fit" {
        "--fit"
    } else if i.field() == "max_iterations" {
        "--max-iterations"
    } else {
        return SolveError::Input(i);
    };
    SolveError::Input(i.renamed(fpc::Field::key(flag), |v| v))
}

#[derive(Serialize)]
struct Report<'a> {
    #[serde(flatten)]
    calibration: &'a Calibration,
    /// The calibrated scene files written, one per specimen.
    scenes: Vec<String>,
    /// Every element model, rib choice and plane state ranked
    /// (`--choose-model`).
    #[serde(skip_serializing_if = "Option::is_none")]
    model_choice: Option<ModelChoice>,
    provenance: crate::provenance::Provenance,
}

/// The progress line of a calibration whose last event is `p`.
fn status(p: Option<&CalibrateProgress>) -> String {
    let Some(p) = p else {
        return "fpc calibrate: starting".into();
    };
    match p.stage {
        CalibrateStage::Fitting => format!(
            "fpc calibrate: fitting: iteration {}/{}, {} evaluations done (the next: {}/{} specimens solved), chi2 {}",
            p.iterations,
            p.max_iterations,
            p.evaluations,
            p.specimens_of_this_evaluation(),
            p.specimens,
            p.chi_square
                .map_or("not known yet".into(), |c| format!("{c:.6e}"))
        ),
        CalibrateStage::CrossValidating => format!(
            "fpc calibrate: fitted in {} iterations; leaving out each pressure in turn: {}/{} refits done",
            p.iterations, p.refits_done, p.refits
        ),
        CalibrateStage::Checking => {
            "fpc calibrate: comparing the calibrated scenes with the data again".into()
        }
        CalibrateStage::ChoosingModel => format!(
            "fpc calibrate: fitting every element model, with and without ribs, in both plane states: {}/{} done",
            p.candidates_done, p.candidates
        ),
    }
}

/// A file name from a specimen's name: letters, digits, `.`, `-`, `_`
/// kept, anything else `_`.
fn file_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_') {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{}.toml", s.trim_start_matches('.'))
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let options = CalibrateOptions {
        fit: args.fit.clone(),
        max_iterations: args.max_iterations,
        cross_validate: args.cross_validate,
    };
    // every file is read and checked before anything is computed
    let manifest =
        Manifest::load(&args.manifest).map_err(|e| crate::status::rejected(e.to_string()))?;
    let (_, out) =
        crate::output::stem_and_dir(&args.manifest, args.out.as_deref(), "manifest", "calibrate");
    // the last event of the fit (then of the model choice), shown once
    // the work has taken a while
    let latest = crate::report::Latest::<CalibrateProgress>::default();
    let observe = |p: &CalibrateProgress| latest.set(p);
    let compute = || -> Result<_, SolveError> {
        let fit = calibrate_with_progress(&manifest, &options, &observe).map_err(in_flag_terms)?;
        if !args.choose_model {
            return Ok((fit, None));
        }
        let choice =
            choose_model_with_progress(&manifest, &options, &observe).map_err(in_flag_terms)?;
        Ok((fit, Some(choice)))
    };
    let (fit, model_choice) =
        crate::report::with_progress(|| status(latest.get().as_ref()), compute)?;
    crate::output::prepare_dir(&out)?;
    let mut scenes = Vec::new();
    for (i, (_, text)) in calibrated_scenes(&manifest, &fit)?.into_iter().enumerate() {
        let mut name = file_name(&manifest.specimens[i].name);
        if scenes.contains(&name) || name == ".toml" {
            name = format!("specimen-{}.toml", i + 1);
        }
        crate::output::write_atomic(&out, &name, text.as_bytes())?;
        scenes.push(name);
    }
    let report = Report {
        calibration: &fit,
        scenes,
        model_choice,
        provenance: crate::provenance::Provenance::now(),
    };
    let json = serde_json::to_string_pretty(&report)? + "\n";
    crate::output::write_atomic(&out, "calibration.json", json.as_bytes())?;
    let mut w = crate::output::stdout();
    if args.json {
        writeln!(w, "{}", serde_json::to_string(&report)?)?;
        return checked(&fit.reproduction);
    }
    let sd = |v: Option<f64>| v.map_or("undetermined".to_string(), |s| format!("{s:.6e}"));
    writeln!(
        w,
        "{:<40} {:>14} {:>14} {:>14} {:>14}",
        "parameter", "value", "sd", "sd (scaled)", "start"
    )?;
    for p in &fit.parameters {
        writeln!(
            w,
            "{:<40} {:>14.8} {:>14} {:>14} {:>14.8}{}",
            p.name,
            Num(p.value),
            sd(p.standard_error),
            sd(p.scaled_standard_error),
            Num(p.start),
            if p.at_bound { "  (at a bound)" } else { "" }
        )?;
    }
    writeln!(
        w,
        "chi2         {:.4} over {} residuals, {} degrees of freedom (per dof {:.4}; at the start {:.4})",
        Num(fit.chi_square),
        fit.points,
        fit.dof,
        Num(fit.chi_square_per_dof),
        Num(fit.start_chi_square)
    )?;
    writeln!(w, "identify     {}", fit.identifiability.message)?;
    writeln!(
        w,
        "cost         {} iterations, {} evaluations, {} equilibrium solves, {} target solves (stopped: {})",
        fit.iterations,
        fit.evaluations,
        fit.solves,
        fit.target_solves,
        serde_json::to_value(fit.termination)?
            .as_str()
            .unwrap_or("?")
    )?;
    writeln!(
        w,
        "check        calibrated scenes compared again as fpc compare does: {} ({})",
        if fit.reproduction.reproduced {
            "the fit is reproduced"
        } else {
            "NOT reproduced"
        },
        fit.reproduction.detail
    )?;
    if let Some(cv) = &fit.cross_validation {
        let failed = cv.held_out.iter().filter(|h| h.failure.is_some()).count();
        writeln!(
            w,
            "held out     each of {} pressures left out and predicted: rms {:.4} sd over {} residuals (chi2 {:.4}){}",
            cv.held_out.len(),
            Num(cv.rms_sd),
            cv.points,
            Num(cv.chi_square),
            if failed > 0 {
                format!("; {failed} refits failed")
            } else {
                String::new()
            }
        )?;
    }
    if fit.outside_model > 0 {
        writeln!(
            w,
            "validity     {} predictions at the fit come from a finger outside the model (docs/model.md section 8)",
            fit.outside_model
        )?;
    }
    if let Some(choice) = &report.model_choice {
        writeln!(
            w,
            "models       each element model with the ribs and without, in plane stress and plane strain, ranked by held-out error:"
        )?;
        let num = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.4}", Num(v)));
        for (i, c) in choice.candidates.iter().enumerate() {
            writeln!(
                w,
                "  {:<6} {:<12} {:<12} chi2/dof {:>10}  held out rms {:>10} sd{}{}",
                c.model,
                if c.ribs { "ribs" } else { "without ribs" },
                if c.plane_strain {
                    "plane strain"
                } else {
                    "plane stress"
                },
                num(c.chi_square_per_dof),
                num(c.held_out_rms_sd),
                if choice.best == Some(i) {
                    "  <- best"
                } else {
                    ""
                },
                c.failure
                    .as_deref()
                    .map(|f| format!("  (no fit: {f})"))
                    .unwrap_or_default()
            )?;
        }
    }
    let mut files = vec!["calibration.json".to_string()];
    files.extend(report.scenes.iter().cloned());
    writeln!(w, "wrote        {}: {}", out.display(), files.join(", "))?;
    checked(&fit.reproduction)
}

/// A fit that its check through `fpc compare`'s path does not reproduce
/// fails the run (status 1), after everything is written for inspection.
fn checked(r: &fpc::calibrate::Reproduction) -> anyhow::Result<()> {
    if r.reproduced {
        return Ok(());
    }
    anyhow::bail!(
        "the fit is not reproduced by fpc compare's path ({}); calibration.json and the scenes are written for inspection",
        r.detail
    )
}

#[cfg(test)]
mod tests {
    use super::checked;
    use fpc::calibrate::Reproduction;

    /// A fit its check does not reproduce fails the run with status 1,
    /// saying why; a reproduced one passes.
    #[test]
    fn a_fit_not_reproduced_fails_the_run() {
        let mut r = Reproduction {
            chi_square: Some(3.0),
            points: 3,
            largest_difference_sd: Some(0.5),
            reproduced: false,
            detail: "residuals up to 5.000e-1 sd from the fit's".into(),
        };
        let e = checked(&r);
        assert_eq!(crate::status::exit_code(&e), 1);
        let text = e.unwrap_err().to_string();
        assert!(
            text.contains("not reproduced") && text.contains("5.000e-1 sd"),
            "{text}"
        );
        r.reproduced = true;
        let ok = checked(&r);
        assert!(ok.is_ok());
        assert_eq!(crate::status::exit_code(&ok), 0);
    }
}
