//! `fpc-lab stress`: the JSON report's keys (the inside and outside of the
//! validity envelope among them), the text summary, and `--case`.

use serde_json::Value;

use super::{lab, ok};

fn count(v: &Value, key: &str) -> u64 {
    v[key]
        .as_u64()
        .unwrap_or_else(|| panic!("{key} is a count: {v}"))
}

#[test]
fn json_reports_the_envelope_and_the_stable_keys() {
    let args = [
        "stress",
        "--seed",
        "3",
        "--cases",
        "40",
        "--max-elements",
        "16",
        "--json",
    ];
    let out = ok("fpc-lab stress --json", &lab(&args));
    let v: Value = serde_json::from_str(out.trim()).expect("one JSON object");
    for key in [
        "seed",
        "cases_requested",
        "cases_run",
        "stopped_early",
        "budget_s",
        "elapsed_s",
        "max_elements",
        "converged",
        "failed",
        "failed_by_reason",
        "rejected",
        "rejected_draws",
        "rejected_draws_by_field",
        "panics",
        "silently_wrong",
        "wrong_stability",
        "unstable_reported_stable",
        "stability_checked",
        "stability_unknown",
        "unstable",
        "beyond_validity",
        "missed_findings",
        "convergence_rate",
        "largest_residual",
        "largest_residual_case",
        "worst_conditioning",
        "worst_conditioning_case",
        "envelope",
        "inside_envelope",
        "outside_envelope",
        "by_elements",
        "by_model",
        "failures",
        "inside_defects",
    ] {
        assert!(v.get(key).is_some(), "missing {key}: {out}");
    }
    assert!(v.get("cases").is_none(), "cases only with --all-cases");
    assert_eq!(count(&v, "seed"), 3);
    assert_eq!(count(&v, "cases_run"), 40);
    assert_eq!(count(&v, "panics"), 0);
    assert_eq!(count(&v, "silently_wrong"), 0);
    assert_eq!(count(&v, "wrong_stability"), 0);
    assert_eq!(count(&v, "unstable_reported_stable"), 0);
    let inside = &v["inside_envelope"];
    let outside = &v["outside_envelope"];
    for key in ["cases", "converged", "warned"] {
        count(inside, key);
        count(outside, key);
    }
    assert_eq!(
        count(inside, "cases") + count(outside, "cases"),
        count(&v, "cases_run") - count(&v, "rejected")
    );
    assert_eq!(
        count(inside, "converged") + count(outside, "converged"),
        count(&v, "converged")
    );
    assert!(count(outside, "warned") <= count(outside, "converged"));
    assert_eq!(
        count(inside, "warned") + count(outside, "warned"),
        count(&v, "beyond_validity")
    );
    assert!(v["envelope"]["max_curl"].is_number());
    assert!(v["envelope"]["max_thickness_over_lx"].is_number());
    // per partition class (fixed N or auto) and per model
    let by_n = v["by_elements"].as_object().unwrap();
    let legal: u64 = by_n.values().map(|t| count(t, "legal")).sum();
    assert_eq!(legal, count(&v, "cases_run") - count(&v, "rejected"));
    for n in by_n.keys() {
        assert!(
            n == "auto" || n.parse::<usize>().is_ok_and(|n| n <= 16),
            "{n}"
        );
    }
    let by_model = v["by_model"].as_object().unwrap();
    for m in by_model.keys() {
        assert!(fpc::ModelId::from_name(m).is_some(), "{m}");
    }
    // --all-cases lists every case with its classification
    let mut all = args.to_vec();
    all.push("--all-cases");
    let out = ok("fpc-lab stress --json --all-cases", &lab(&all));
    let w: Value = serde_json::from_str(out.trim()).unwrap();
    let cases = w["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 40);
    let inside_listed = cases
        .iter()
        .filter(|c| c["inside_envelope"].as_bool().unwrap())
        .filter(|c| c["outcome"] != "rejected")
        .count() as u64;
    assert_eq!(inside_listed, count(&w["inside_envelope"], "cases"));
    for c in cases {
        assert!(c["inputs"]["model"].is_string());
        assert!(c["inputs"]["partition"] == "auto" || c["inputs"]["partition"] == "custom");
        assert!(c["findings"].is_array());
    }
}

#[test]
fn text_shows_inside_and_outside_and_a_case_reproduces() {
    let run = [
        "stress",
        "--seed",
        "2",
        "--cases",
        "12",
        "--max-elements",
        "8",
    ];
    let out = ok("fpc-lab stress", &lab(&run));
    assert!(out.contains("validity envelope"), "{out}");
    assert!(out.contains("  inside: "), "{out}");
    assert!(out.contains("  outside: "), "{out}");
    assert!(out.contains("converged by model"), "{out}");
    // --case runs one case of the seed, as the run drew it
    let all: Value = serde_json::from_str(
        ok(
            "fpc-lab stress --json --all-cases",
            &lab(&[&run[..], &["--json", "--all-cases"]].concat()),
        )
        .trim(),
    )
    .unwrap();
    let one: Value = serde_json::from_str(
        ok(
            "fpc-lab stress --case 5 --json",
            &lab(&[
                "stress",
                "--seed",
                "2",
                "--case",
                "5",
                "--max-elements",
                "8",
                "--json",
            ]),
        )
        .trim(),
    )
    .unwrap();
    let listed = &all["cases"][5];
    assert_eq!(one["index"], 5);
    assert_eq!(one["inputs"], listed["inputs"]);
    assert_eq!(one["outcome"], listed["outcome"]);
    assert_eq!(one["findings"], listed["findings"]);
}
