//! Every Rust example in README.md is a program under examples/ (CI runs
//! each with `cargo run --example NAME`): the README shows the file
//! exactly, so what a reader pastes is what CI ran.

use std::path::Path;

#[test]
fn every_readme_example_is_its_example_file() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let mut named = Vec::new();
    for block in readme.split("```rust\n").skip(1) {
        let code = &block[..block.find("```\n").expect("a closed code block")];
        let first = code.lines().next().unwrap_or_default();
        let name = first
            .strip_prefix("// examples/")
            .and_then(|r| r.split(".rs").next())
            .unwrap_or_else(|| panic!("a README example names no examples/ file: {first:?}"));
        let file = std::fs::read_to_string(root.join(format!("examples/{name}.rs")))
            .unwrap_or_else(|e| panic!("examples/{name}.rs: {e}"));
        assert_eq!(
            code, file,
            "README's example differs from examples/{name}.rs"
        );
        assert!(
            code.contains("fn main() -> Result<"),
            "{name}: main returns a Result"
        );
        named.push(name.to_string());
    }
    // and every example file is shown
    let mut files: Vec<String> = std::fs::read_dir(root.join("examples"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "rs").then(|| p.file_stem().unwrap().to_string_lossy().into_owned())
        })
        .collect();
    files.sort();
    named.sort();
    assert_eq!(named, files);
}
