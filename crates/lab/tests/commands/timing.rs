//! `fpc-lab timing --json`: the keys the issue tracker and
//! docs/performance.md rely on, and their consistency with each other
//! (times are not checked: they are measured by benches, not by tests).

use serde_json::Value;

use super::{lab, ok};

#[test]
fn the_json_report_has_the_scaling_and_the_0p01mm_entries() {
    let out = ok(
        "fpc-lab timing --json",
        &lab(&["timing", "--json", "--budget-ms", "1"]),
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    // scaling: one row per N, per-iteration time = time / iterations
    let rows = v["scaling"].as_array().unwrap();
    let ns: Vec<u64> = rows
        .iter()
        .map(|r| r["elements"].as_u64().unwrap())
        .collect();
    assert_eq!(ns, [8, 32, 128, 256]);
    for r in rows {
        let (t, it, per) = (
            r["loaded_cold_us"].as_f64().unwrap(),
            r["iterations"].as_f64().unwrap(),
            r["per_iteration_us"].as_f64().unwrap(),
        );
        assert!(t > 0.0 && it >= 1.0);
        assert!((per - t / it).abs() <= 1e-9 * t, "{r}");
    }
    let ratio = &v["scaling_ratio"];
    assert_eq!(ratio["from_elements"], 32);
    assert_eq!(ratio["to_elements"], 256);
    assert!(ratio["per_iteration_ratio"].as_f64().unwrap() > 0.0);
    // 0.01 mm: the tip is where the error says, and within the tolerance
    let to = &v["to_0p01mm"];
    let tip: Vec<f64> = serde_json::from_value(to["tip_mm"].clone()).unwrap();
    let reference: Vec<f64> = serde_json::from_value(to["reference_tip_mm"].clone()).unwrap();
    let error = to["error_mm"].as_f64().unwrap();
    assert!((error - (tip[0] - reference[0]).hypot(tip[1] - reference[1])).abs() < 1e-12);
    assert!(error < 0.01, "{to}");
    assert!(to["us"].as_f64().unwrap() > 0.0 && to["ratio_to_n8_cold"].as_f64().unwrap() > 0.0);
    assert_eq!(to["model"], "ccm");
    // the N = 8 tip of the standard case (docs/performance.md)
    let t8: Vec<f64> = serde_json::from_value(v["loaded_cold_tip_mm"].clone()).unwrap();
    assert!((t8[0] - 84.182361).abs() < 1e-6 && (t8[1] + 47.566866).abs() < 1e-6);
    assert_eq!(v["provenance"]["command"][0], "fpc-lab");
    assert_eq!(v["provenance"]["command"][1], "timing");
}
