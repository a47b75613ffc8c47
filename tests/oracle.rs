//! Every case of `tests/data/oracle_element_cases.json` (reference values
//! from an independent symbolic implementation, see `tests/data/README.md`)
//! against the generated CCM model assembled with the docs/model.md
//! defaults: energy, gas volume, gradient, Hessian and end kinematics, each
//! to 1e-10 relative.
//!
//! The element energies go through the public finger API
//! (`Finger::element_hessian`: the whole potential, or one integral family
//! alone), the end kinematics through the model's trait
//! (`Kinematics::end_hessian`) at the finger's element length.

use fpc::model::ccm::Ccm;
use fpc::model::upper_index;
use fpc::model::{Kinematics, ModelCore};
use fpc::{Actuator, Coefficients, Finger, Load, ModelId, Partition};
use serde_json::Value;

const TOL: f64 = 1e-10;

/// The number of cases in the data file.
const CASES: usize = 42;

fn oracle() -> Value {
    let text = include_str!("data/oracle_element_cases.json");
    serde_json::from_str(text).expect("oracle JSON parses")
}

fn f(v: &Value) -> f64 {
    v.as_f64().expect("a number")
}

fn vec4(v: &Value) -> [f64; 4] {
    let a = v.as_array().expect("an array");
    assert_eq!(a.len(), 4);
    [f(&a[0]), f(&a[1]), f(&a[2]), f(&a[3])]
}

/// Relative error, with the scale floored at a small fraction of the array's
/// largest entry so exact zeros and cancellations compare sensibly.
fn check(label: &str, got: &[f64], want: &[f64], worst: &mut f64) {
    assert_eq!(got.len(), want.len(), "{label}: length");
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

/// Family positions of the CCM, by name.
fn family(name: &str) -> usize {
    Ccm::FAMILIES
        .iter()
        .position(|f| *f == name)
        .unwrap_or_else(|| panic!("the CCM has no family {name}"))
}

#[test]
fn every_oracle_case_matches() {
    let data = oracle();
    let cases = data["cases"].as_array().expect("cases");
    assert_eq!(cases.len(), CASES, "expected the full oracle set");
    let (linear, prestressed, gas) = (family("linear"), family("prestressed"), family("gas"));
    let mut worst = 0.0f64;
    let mut checked = 0;
    for c in cases {
        let n = c["N"].as_u64().expect("N") as usize;
        let i = c["element"].as_u64().expect("element") as usize;
        let eps0 = f(&c["eps0"]);
        let p_mpa = f(&c["P_kPa"]) * 1e-3;
        let kappa = f(&c["kappa"]);
        let k = vec4(&c["K"]);
        let act = Actuator::paper(eps0).expect("paper actuator");
        let part = Partition::equal(act.geometry().lx, n).expect("partition");
        let finger = Finger::with_model(ModelId::Ccm, &act, &part, true);
        assert_eq!(finger.model(), ModelId::Ccm);
        assert_eq!(finger.unknowns_per_element(), 4);
        let l = finger.element_lengths()[i];
        assert!((l - f(&c["L"])).abs() < 1e-12);
        let load = Load {
            pressure: p_mpa,
            kappa,
            fx: 0.0,
            fz: 0.0,
        };
        let label = format!("N={n} element={i} eps0={eps0} P={}kPa", f(&c["P_kPa"]));
        let fam = |fi: usize| {
            finger
                .element_hessian(i, Some(fi), &load, &k)
                .expect("element and family in range")
        };

        // Psi: the two strain-energy families; V: the gas family alone
        let psi = fam(linear).0 + fam(prestressed).0;
        check(&format!("{label} Psi"), &[psi], &[f(&c["Psi"])], &mut worst);
        check(
            &format!("{label} V"),
            &[fam(gas).0],
            &[f(&c["V"])],
            &mut worst,
        );

        // the element potential at the case's load
        let (pi, g, h) = finger
            .element_hessian(i, None, &load, &k)
            .expect("element in range");
        check(&format!("{label} Pi"), &[pi], &[f(&c["Pi"])], &mut worst);
        check(
            &format!("{label} grad_Pi"),
            &g,
            &vec4(&c["grad_Pi"]),
            &mut worst,
        );
        let rows = c["hess_Pi"].as_array().expect("hess");
        assert_eq!(rows.len(), 4);
        let mut full = Vec::new();
        let mut want = Vec::new();
        for (r, row) in rows.iter().enumerate() {
            let row = vec4(row);
            for (s, w) in row.iter().enumerate() {
                full.push(h[upper_index(4, r, s)]);
                want.push(*w);
            }
        }
        check(&format!("{label} hess_Pi"), &full, &want, &mut worst);

        // The value and gradient variants agree with the Hessian variant:
        // the finger's energy (value kernels) and gradient (gradient
        // kernels) at element i's K, the other elements straight.
        let mut values = vec![0.0; 4 * n];
        values[4 * i..4 * i + 4].copy_from_slice(&k);
        let ks = Coefficients::new(4, values).expect("coefficients");
        let others: f64 = (0..n)
            .map(|j| {
                let kj = ks.element(j);
                finger
                    .element_hessian(j, None, &load, kj)
                    .expect("element")
                    .0
            })
            .sum();
        let total = finger.energy(&load, &ks).expect("valid coefficients");
        check(
            &format!("{label} value variant (finger energy)"),
            &[total],
            &[others],
            &mut worst,
        );
        let (total2, g2) = finger.gradient(&load, &ks).expect("valid coefficients");
        check(
            &format!("{label} gradient variant (finger energy)"),
            &[total2],
            &[others],
            &mut worst,
        );
        check(
            &format!("{label} gradient variant"),
            &g2[4 * i..4 * i + 4],
            &g,
            &mut worst,
        );

        // end kinematics: the model's kernel at the finger's element length
        let end = vec![f(&c["Xe"]), f(&c["Ze"]), f(&c["eta"])];
        let (e, end_g, _) = Ccm::end_hessian(&k, l);
        check(&format!("{label} Xe Ze eta"), &e, &end, &mut worst);
        let e2 = finger.element_end(i, &k).expect("element in range");
        check(&format!("{label} finger Xe Ze eta"), &e2, &end, &mut worst);
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
        checked += 1;
    }
    assert_eq!(checked, CASES);
    eprintln!("worst relative error over {checked} oracle cases: {worst:e}");
}
