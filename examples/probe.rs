use fpc::*;
fn main() {
    for eps0 in [0.15, 0.25, 0.4] {
        let f = Finger::paper(eps0, 8).unwrap();
        let s = f
            .solve(&Load::unloaded(), &SolveOptions::default())
            .unwrap();
        println!(
            "eps0 {eps0}: tip {:?} angle {:.4} radius {:?} eig {:.3e} it {} res {:.2e}",
            s.tip,
            s.end_angle,
            s.radius,
            s.min_hessian_eig,
            s.report.iterations,
            s.report.residual_norm
        );
        let c = f
            .solve(
                &Load::unloaded(),
                &SolveOptions {
                    strategy: Strategy::Coupled,
                    ..Default::default()
                },
            )
            .unwrap();
        println!(
            "   coupled tip {:?} it {} res {:.2e} eig {:.3e}",
            c.tip, c.report.iterations, c.report.residual_norm, c.min_hessian_eig
        );
        let l = Load::unloaded().with_tip_force(0.939782, 0.521707);
        let t = std::time::Instant::now();
        let s = f.solve(&l, &SolveOptions::default()).unwrap();
        println!(
            "   loaded tip {:?} it {} res {:.2e} eig {:.3e} cont {} {:?}",
            s.tip,
            s.report.iterations,
            s.report.residual_norm,
            s.min_hessian_eig,
            s.report.continuation_steps,
            t.elapsed()
        );
        for p in [100.0, 386.0] {
            let s = f
                .solve(
                    &Load::unloaded().with_pressure_kpa(p),
                    &SolveOptions::default(),
                )
                .unwrap();
            println!("   P={p} tip {:?} radius {:?}", s.tip, s.radius);
        }
    }
}
