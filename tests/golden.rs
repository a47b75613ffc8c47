//! The checked-in copy of every generated file must equal the build output
//! as compiled (`fpc::model::GENERATED_FILES`: `models.rs`, and per spec
//! the model's source and its operation counts), so every change to a spec
//! or to the generator is a reviewable diff. After reviewing a deliberate
//! change, refresh the copies with `FPC_BLESS=1 cargo test --test golden`
//! (which also removes golden files that nothing generates any more).

use std::collections::BTreeSet;
use std::path::PathBuf;

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("energy-spec/golden")
}

fn blessing() -> bool {
    std::env::var_os("FPC_BLESS").is_some()
}

/// The file names in the golden directory (none when it does not exist).
fn golden_names() -> BTreeSet<String> {
    let dir = golden_dir();
    if !dir.exists() {
        return BTreeSet::new();
    }
    std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|entry| {
            let entry = entry.unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()));
            entry
                .file_name()
                .into_string()
                .unwrap_or_else(|n| panic!("non-UTF-8 golden file name {n:?}"))
        })
        .collect()
}

fn generated_names() -> BTreeSet<String> {
    fpc::model::GENERATED_FILES
        .iter()
        .map(|(name, _)| name.to_string())
        .collect()
}

/// `None` when `golden` equals `fresh`, else where and how they differ.
fn difference(name: &str, golden: &str, fresh: &str) -> Option<String> {
    if golden == fresh {
        return None;
    }
    let (g, f): (Vec<&str>, Vec<&str>) = (golden.lines().collect(), fresh.lines().collect());
    let line = g
        .iter()
        .zip(&f)
        .position(|(a, b)| a != b)
        .unwrap_or(g.len().min(f.len()));
    Some(format!(
        "energy-spec/golden/{name} differs from the generated file at line {}:\n  golden:    {}\n  generated: {}\n\
         ({} vs {} lines{})",
        line + 1,
        g.get(line).unwrap_or(&"<end of file>"),
        f.get(line).unwrap_or(&"<end of file>"),
        g.len(),
        f.len(),
        if g == f {
            "; only the line endings or the final newline differ"
        } else {
            ""
        }
    ))
}

const HOW: &str =
    "Review the generator/spec change, then run `FPC_BLESS=1 cargo test --test golden`.";

#[test]
fn generated_file_names_are_distinct_and_plain() {
    let files = fpc::model::GENERATED_FILES;
    assert!(!files.is_empty(), "nothing is generated");
    assert_eq!(
        generated_names().len(),
        files.len(),
        "a file name is generated twice"
    );
    for (name, _) in files {
        assert!(
            !name.is_empty() && !name.contains(['/', '\\']) && !name.starts_with('.'),
            "generated file name {name:?} is not a plain file name"
        );
    }
    // every model's source and report is among them
    for id in fpc::ModelId::ALL {
        let (source, report) = id.generated();
        for (what, text) in [("source", source), ("report", report)] {
            assert!(
                files.iter().any(|(_, t)| *t == text),
                "model {id}: its generated {what} is not in GENERATED_FILES"
            );
        }
    }
}

#[test]
fn every_generated_file_matches_its_golden_copy() {
    let dir = golden_dir();
    if blessing() {
        std::fs::create_dir_all(&dir)
            .unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
        for (name, text) in fpc::model::GENERATED_FILES {
            let path = dir.join(name);
            std::fs::write(&path, text)
                .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        }
        for stale in golden_names().difference(&generated_names()) {
            let path = dir.join(stale);
            std::fs::remove_file(&path)
                .unwrap_or_else(|e| panic!("cannot remove {}: {e}", path.display()));
        }
        return;
    }
    let mut failures = Vec::new();
    for (name, text) in fpc::model::GENERATED_FILES {
        let path = dir.join(name);
        match std::fs::read_to_string(&path) {
            Ok(golden) => failures.extend(difference(name, &golden, text)),
            Err(e) => failures.push(format!(
                "energy-spec/golden/{name} is missing ({e}) but {name} is generated"
            )),
        }
    }
    assert!(failures.is_empty(), "{}\n{HOW}", failures.join("\n"));
}

#[test]
fn every_golden_file_has_a_generated_counterpart() {
    if blessing() {
        // the blessing run removes stale files (in the test above)
        return;
    }
    let stale: Vec<String> = golden_names()
        .difference(&generated_names())
        .cloned()
        .collect();
    assert!(
        stale.is_empty(),
        "energy-spec/golden holds {stale:?}, which nothing generates any more (generated: {:?}).\n{HOW}",
        generated_names()
    );
}
