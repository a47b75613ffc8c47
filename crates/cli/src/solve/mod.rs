//! `fpc solve SCENE.toml`: solve the finger, or the gripper grasp, that a
//! scene file describes, and write `solution.json`, `shape.csv` and
//! `shape.svg` (or the `--format`s asked for) into the output directory
//! (default `./<stem>-out/`).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context;
use fpc::scene::{warning_text, SceneFile};

mod figure;
mod report;
#[cfg(test)]
mod tests;

use figure::shape_figure;
pub(crate) use report::{refinement_lines, solver_lines, stability_line, validity_line};
use report::{shape_csv, solution_file, summary, uncertainty_lines};

/// Flags of `fpc solve`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scene file (TOML; see scenes/ and the README for the keys).
    scene: PathBuf,
    /// Output directory, created if missing. Default: `<stem>-out` in the
    /// current directory, where `<stem>` is the scene file's name without
    /// its extension.
    #[arg(long)]
    out: Option<PathBuf>,
    #[command(flatten)]
    format: crate::render::formats::FormatArgs,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    let shown = args.scene.display().to_string();
    let text = read_scene(&args.scene, &shown)?;
    // a syntax error is rejected input, its position as file:line:col
    let file =
        SceneFile::parse(&text).map_err(|e| crate::status::rejected(format!("{shown}:{e}")))?;
    let scene = file.resolve().with_context(|| shown.clone())?;
    // notes on the input first: they hold even when the solve fails
    crate::report::warnings(scene.warnings(), warning_text, "solution.json");
    let solved = scene.solve().with_context(|| shown.clone())?;
    let found = solved.warnings();
    crate::report::warnings(
        found.iter().filter(|w| !scene.warnings().contains(w)),
        warning_text,
        "solution.json",
    );

    // first-order error bars from a [calibration] covariance (none without)
    let uncertainty = scene.uncertainty(&solved).with_context(|| shown.clone())?;

    let (stem, out) = crate::output::stem_and_dir(&args.scene, args.out.as_deref(), "scene", "out");
    // every file is made before any is written
    let json = serde_json::to_string_pretty(&solution_file(
        &stem,
        scene.file(),
        &solved,
        uncertainty.as_ref(),
    ))? + "\n";
    let csv = shape_csv(&solved)?;
    let svg = crate::render::svg::svg(&shape_figure(&stem, &solved))?;
    let figures = args.format.render("shape", &svg)?;
    crate::output::prepare_dir(&out)?;
    write_atomic(&out, "solution.json", json.as_bytes())?;
    write_atomic(&out, "shape.csv", &csv)?;
    let mut written = vec!["solution.json".to_string(), "shape.csv".to_string()];
    for (name, bytes) in figures {
        write_atomic(&out, &name, &bytes)?;
        written.push(name);
    }
    crate::render::formats::remove_figure(&out, "shape", &args.format.list())?;

    let mut stdout = crate::output::stdout();
    summary(&mut stdout, &stem, scene.file(), &solved)?;
    if let Some(u) = &uncertainty {
        uncertainty_lines(&mut stdout, u)?;
    }
    writeln!(
        stdout,
        "wrote          {}",
        written
            .iter()
            .map(|f| out.join(f).display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    )?;
    Ok(())
}

use crate::output::write_atomic;

/// The scene file at `path`, read ([`read_scene`]) and resolved: a
/// syntax or value error is rejected input naming `path:line:col` or the
/// key.
pub(crate) fn load_scene(path: &Path) -> anyhow::Result<fpc::scene::Scene> {
    let shown = path.display().to_string();
    let text = read_scene(path, &shown)?;
    fpc::scene::Scene::from_toml(&text).map_err(|e| crate::status::rejected(format!("{shown}:{e}")))
}

/// The text of the scene (or requirements) file at `path` (`shown` in
/// messages), read through the library's bounded reader
/// ([`fpc::scene::read_scene_text`]). Missing, unreadable, a directory,
/// larger than [`fpc::scene::MAX_SCENE_BYTES`] (4 MiB) or not UTF-8:
/// rejected input, one line naming the path.
pub(crate) fn read_scene(path: &Path, shown: &str) -> anyhow::Result<String> {
    fpc::scene::read_scene_text(path)
        .map_err(|e| crate::status::rejected(format!("cannot read {shown}: {e}")))
}
