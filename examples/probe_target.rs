use fpc::*;
fn main() {
    let f = Finger::paper(0.4, 8).unwrap();
    let opts = SolveOptions::default();
    for p in [0.0, 27.6, 55.2, 82.7] {
        let base = Load::unloaded().with_pressure_kpa(p);
        let s0 = f.solve(&base, &opts).unwrap();
        let prob = TargetProblem {
            base,
            direction: [1.0, 0.0],
            weights: [1.0, 0.0],
            target: s0.tip[0] + 10.0,
        };
        let mut solver = Solver::new(&f);
        match solver.solve_target(&prob, &s0.coefficients, 0.0, 1e-9, &opts) {
            Ok((s, lam)) => {
                // feed back
                let fwd = f
                    .solve_from(&prob.load_at(lam), &s0.coefficients, &opts)
                    .unwrap();
                println!(
                    "P={p}: Fx={lam:.5} N tip dx={:.6} fwd dx={:.6} it {}",
                    s.tip[0] - s0.tip[0],
                    fwd.tip[0] - s0.tip[0],
                    s.report.iterations
                );
            }
            Err(e) => println!("P={p}: {e}"),
        }
    }
}
