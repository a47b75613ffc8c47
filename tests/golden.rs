//! The checked-in copy of the generated kernels must equal the fresh build
//! output, so every change to the spec or the generator is a reviewable diff.
//! After reviewing a deliberate change, refresh the copy with
//! `FPC_BLESS=1 cargo test --test golden`.

fn compare(name: &str, fresh: &str) {
    let path = format!("{}/energy-spec/golden/{name}", env!("CARGO_MANIFEST_DIR"));
    if std::env::var_os("FPC_BLESS").is_some() {
        std::fs::write(&path, fresh).unwrap_or_else(|e| panic!("cannot write {path}: {e}"));
        return;
    }
    let golden = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "missing golden file {path} ({e}); create it with FPC_BLESS=1 cargo test --test golden"
        )
    });
    if golden == fresh {
        return;
    }
    let (g, f): (Vec<&str>, Vec<&str>) = (golden.lines().collect(), fresh.lines().collect());
    let line = g
        .iter()
        .zip(&f)
        .position(|(a, b)| a != b)
        .unwrap_or(g.len().min(f.len()));
    panic!(
        "energy-spec/golden/{name} differs from the freshly generated code at line {}:\n  golden: {}\n  fresh:  {}\n\
         ({} vs {} lines). Review the generator/spec change, then run `FPC_BLESS=1 cargo test --test golden`.",
        line + 1,
        g.get(line).unwrap_or(&"<end of file>"),
        f.get(line).unwrap_or(&"<end of file>"),
        g.len(),
        f.len()
    );
}

#[test]
fn generated_kernels_match_the_golden_copy() {
    compare("kernels.rs", fpc::kernels::SOURCE);
}

#[test]
fn operation_counts_match_the_golden_copy() {
    compare("kernels_report.txt", fpc::kernels::REPORT);
}
