//! Generates the element models from the energy specs (see the README,
//! "Generated kernels").
//!
//! Thin on purpose: read every `energy-spec/*.spec`, hand them to
//! `fpc-modelgen` (a pure function of the spec texts), and write the files
//! it returns to `OUT_DIR`, each only when its text changed.

use std::path::Path;

const SPEC_DIR: &str = "energy-spec";

/// The model `ModelId::default()` picks: the paper's element.
const DEFAULT_MODEL: &str = "ccm";

fn write_if_changed(path: &Path, text: &str) {
    if std::fs::read_to_string(path).ok().as_deref() == Some(text) {
        return;
    }
    if let Err(e) = std::fs::write(path, text) {
        panic!("cannot write {}: {e}", path.display());
    }
}

fn main() {
    println!("cargo:rerun-if-changed={SPEC_DIR}");
    println!("cargo:rerun-if-changed=build.rs");
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    let dir = Path::new(&manifest).join(SPEC_DIR);
    let mut paths: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {SPEC_DIR}: {e}"))
        .filter_map(|entry| {
            let name = entry.ok()?.file_name().into_string().ok()?;
            name.ends_with(".spec")
                .then(|| format!("{SPEC_DIR}/{name}"))
        })
        .collect();
    paths.sort();
    let specs: Vec<fpc_modelgen::SpecFile> = paths
        .iter()
        .map(|path| {
            println!("cargo:rerun-if-changed={path}");
            let text = std::fs::read_to_string(Path::new(&manifest).join(path))
                .unwrap_or_else(|e| panic!("cannot read {path}: {e}"));
            fpc_modelgen::SpecFile {
                path: path.clone(),
                text,
            }
        })
        .collect();
    let files = fpc_modelgen::generate(&specs, DEFAULT_MODEL).unwrap_or_else(|e| panic!("{e}"));
    for f in &files {
        write_if_changed(&Path::new(&out).join(&f.name), &f.text);
    }
}
