fn main() {
    let src = std::fs::read_to_string("energy-spec/ccm.spec").unwrap();
    let g = fpc_symbolic::codegen::generate(&src).unwrap();
    let text = fpc_symbolic::codegen::format_file(&g.tokens).unwrap();
    println!("{text}");
    for r in &g.report {
        eprintln!(
            "{} {:?} {:?}",
            r.function,
            r.ops_before_cse.total(),
            r.ops_after_cse.total()
        );
    }
}
