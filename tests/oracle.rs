//! Every case of `tests/data/oracle_element_cases.json` (reference values
//! from an independent symbolic implementation, see `tests/data/README.md`) against the generated kernels assembled with the
//! docs/model.md defaults: energy, gas volume, gradient, Hessian and end
//! kinematics, each to 1e-10 relative.

use fpc::{element_blocks, kernels::upper_index, Actuator, Element, Partition};
use serde_json::Value;

const TOL: f64 = 1e-10;

fn oracle() -> Value {
    let text = include_str!("data/oracle_element_cases.json");
    serde_json::from_str(text).expect("oracle JSON parses")
}

fn f(v: &Value) -> f64 {
    v.as_f64().expect("a number")
}

fn vec4(v: &Value) -> [f64; 4] {
    let a = v.as_array().expect("an array");
    [f(&a[0]), f(&a[1]), f(&a[2]), f(&a[3])]
}

/// Relative error, with the scale floored at a small fraction of the array's
/// largest entry so exact zeros and cancellations compare sensibly.
fn check(label: &str, got: &[f64], want: &[f64], worst: &mut f64) {
    let scale = want.iter().fold(0.0f64, |m, w| m.max(w.abs()));
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        let denom = w.abs().max(1e-6 * scale).max(f64::MIN_POSITIVE);
        let rel = (g - w).abs() / denom;
        *worst = worst.max(rel);
        assert!(
            rel <= TOL,
            "{label}[{i}]: got {g:e}, oracle {w:e}, relative error {rel:e}"
        );
    }
}

#[test]
fn every_oracle_case_matches() {
    let data = oracle();
    let cases = data["cases"].as_array().expect("cases");
    assert!(
        cases.len() >= 40,
        "expected the full oracle set, got {}",
        cases.len()
    );
    let mut worst = 0.0f64;
    for c in cases {
        let n = c["N"].as_u64().expect("N") as usize;
        let i = c["element"].as_u64().expect("element") as usize;
        let eps0 = f(&c["eps0"]);
        let p_mpa = f(&c["P_kPa"]) * 1e-3;
        let kappa = f(&c["kappa"]);
        let k = vec4(&c["K"]);
        let act = Actuator::paper(eps0).expect("paper actuator");
        let part = Partition::equal(act.geometry().lx, n).expect("partition");
        assert!((part.lengths()[i] - f(&c["L"])).abs() < 1e-12);
        let blocks = element_blocks(&act, &part, true);
        let el = Element::from_blocks(&blocks[i]);
        let label = format!("N={n} element={i} eps0={eps0} P={}kPa", f(&c["P_kPa"]));

        check(
            &format!("{label} Psi"),
            &[el.strain_energy(&k)],
            &[f(&c["Psi"])],
            &mut worst,
        );
        check(
            &format!("{label} V"),
            &[el.gas_volume(&k)],
            &[f(&c["V"])],
            &mut worst,
        );
        let (pi, g, h) = el.hessian(&k, kappa * p_mpa);
        check(&format!("{label} Pi"), &[pi], &[f(&c["Pi"])], &mut worst);
        check(
            &format!("{label} grad_Pi"),
            &g,
            &vec4(&c["grad_Pi"]),
            &mut worst,
        );
        let rows = c["hess_Pi"].as_array().expect("hess");
        let mut full = Vec::new();
        let mut want = Vec::new();
        for r in 0..4 {
            let row = vec4(&rows[r]);
            for s in 0..4 {
                full.push(h[upper_index(r, s)]);
                want.push(row[s]);
            }
        }
        check(&format!("{label} hess_Pi"), &full, &want, &mut worst);
        // the value-and-gradient variant agrees with the Hessian variant
        let (pi2, g2) = el.gradient(&k, kappa * p_mpa);
        check(
            &format!("{label} gradient variant"),
            &[pi2],
            &[pi],
            &mut worst,
        );
        check(&format!("{label} gradient variant"), &g2, &g, &mut worst);

        let (end, end_g, _) = el.end_hessian(&k);
        check(
            &format!("{label} Xe Ze eta"),
            &end,
            &[f(&c["Xe"]), f(&c["Ze"]), f(&c["eta"])],
            &mut worst,
        );
        check(
            &format!("{label} grad_Xe"),
            &end_g[0],
            &vec4(&c["grad_Xe"]),
            &mut worst,
        );
        check(
            &format!("{label} grad_Ze"),
            &end_g[1],
            &vec4(&c["grad_Ze"]),
            &mut worst,
        );
        check(
            &format!("{label} grad_eta"),
            &end_g[2],
            &vec4(&c["grad_eta"]),
            &mut worst,
        );
    }
    eprintln!(
        "worst relative error over {} oracle cases: {worst:e}",
        cases.len()
    );
}
