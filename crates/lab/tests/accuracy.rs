//! The accuracy-time study on a reduced configuration list with a tiny
//! time budget (a debug build is slow): the references, the orders, the
//! extrapolation and the front.

use std::time::Duration;

use fpc::plan::PartitionKind;
use fpc_lab::{accuracy_study, AccuracyStudy, StudyConfig, TIME_RESOLUTION, TOLERANCES_MM};

fn study() -> AccuracyStudy {
    let config = StudyConfig::quick().with_budget(Duration::ZERO);
    let mut calls = Vec::new();
    let s = accuracy_study(&config, |done, total| calls.push((done, total))).unwrap();
    let total = calls.last().unwrap().1;
    assert_eq!(calls.len(), total, "one progress call per step");
    assert!(calls
        .iter()
        .enumerate()
        .all(|(i, &(d, t))| d == i + 1 && t == total));
    s
}

#[test]
fn the_quick_study_reproduces_the_front() {
    let s = study();
    assert_eq!(s.references.len(), fpc_lab::study_models().len());
    let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    for r in &s.references {
        let m = r.model.name();
        // two partition families agree on the limit
        assert!(r.families_agree, "{m}: {:?}", r.families);
        assert!(
            r.uncertainty_mm < 1e-7,
            "{m}: reference uncertainty {:.3e} mm",
            r.uncertainty_mm
        );
        let [a, b] = [&r.families[0], &r.families[1]];
        assert_eq!(a.elements, [27, 54, 108, 216, 432, 864], "{m}");
        assert_eq!(b.elements, [40, 80, 160, 320, 640], "{m}");
        assert!(dist(a.limit, b.limit) <= a.uncertainty_mm + b.uncertainty_mm);
        assert_eq!(r.material.elements.first(), Some(&27), "{m}");
        assert_eq!(r.material.elements.last(), Some(&864), "{m}");
        // X at second order; for the paper's end slope (D2) Z's orders
        // fall below 2 as the first-order term takes over; the shear
        // element's end angle, the section's, leaves Z a first-order term
        // a fraction of that (docs/performance.md)
        assert_eq!(r.material.orders_x.len(), 4);
        for &o in &r.material.orders_x {
            assert!((1.9..=2.1).contains(&o), "{m}: X order {o}");
        }
        let z = &r.material.orders_z;
        let c1 = a.terms_mm[0];
        if m == "shear" {
            assert!(z.iter().all(|o| (1.9..=2.1).contains(o)), "{m}: Z {z:?}");
            assert!(c1[1].abs() < 3e-6, "{m}: c1 h {c1:?}");
        } else {
            assert!(z.windows(2).all(|w| w[1] < w[0]), "{m}: Z orders {z:?}");
            assert!(z[0] > 1.9 && z[3] < 1.7, "{m}: Z orders {z:?}");
            // the fitted first-order term of Z at 864 elements, about
            // 1e-5 mm
            assert!((5e-6..5e-5).contains(&-c1[1]), "{m}: c1 h {c1:?}");
        }
        assert_eq!(r.equal.partition, PartitionKind::Equal);
        assert!(!r.equal.orders.is_empty());
        // the library's six-level extrapolation and its estimate
        let est = r.refiner_estimate_mm.unwrap();
        assert!(
            r.refiner_offset_mm + r.uncertainty_mm <= est,
            "{m}: {est:e}"
        );
    }
    let ccm = s.ccm_reference();
    assert!(
        dist(ccm.tip, [83.93746494, -47.61183456]) < 1e-7,
        "CCM reference {:?}",
        ccm.tip
    );
    for g in &s.gaps {
        // quad: the end slope's gap; shear: the shear deflection
        let range = if g.model.name() == "shear" {
            4e-2..7e-2
        } else {
            4e-3..6e-3
        };
        assert!(
            range.contains(&g.gap_mm),
            "{} gap {:.3e} mm",
            g.model.name(),
            g.gap_mm
        );
    }

    assert_eq!(s.rows.len(), s.config.plans.len() * s.config.models.len());
    for r in &s.rows {
        assert!(
            r.error_vs_ccm_mm.is_finite() && r.error_vs_own_mm.is_finite(),
            "{}",
            r.label
        );
        assert!(r.time_us > 0.0 && r.time_over_n8.is_finite(), "{}", r.label);
        assert_eq!(r.iterations.len(), r.plan.levels, "{}", r.label);
        assert_eq!(
            r.elements_per_level.last(),
            Some(&r.elements),
            "{}",
            r.label
        );
    }
    for m in &fpc_lab::study_models() {
        let label = format!("{}/material/8x2+richardson", m.name());
        let r = s.rows.iter().find(|r| r.label == label).expect(&label);
        assert_eq!(r.elements_per_level, [27, 54]);
        assert!(
            r.error_vs_own_mm < 1e-3,
            "{label}: {:.3e} mm",
            r.error_vs_own_mm
        );
    }
    let n8 = s.rows.iter().find(|r| r.label == "ccm/equal/8x1").unwrap();
    assert!(
        (0.2..0.3).contains(&n8.error_vs_ccm_mm),
        "{}",
        n8.error_vs_ccm_mm
    );

    assert!(!s.front.is_empty());
    for w in s.front.windows(2) {
        assert!(w[0].time_us <= w[1].time_us, "front sorted by time");
        assert!(w[0].error_vs_ccm_mm >= w[1].error_vs_ccm_mm, "and error");
    }
    assert!(s.front.iter().all(|f| s.rows[f.row].pareto));
    assert_eq!(s.front.len(), s.rows.iter().filter(|r| r.pareto).count());

    assert_eq!(s.fastest.len(), TOLERANCES_MM.len());
    for f in &s.fastest {
        let best = f.fastest.as_ref().expect("a row within every tolerance");
        assert!(best.error_vs_ccm_mm <= f.tolerance_mm);
        assert!(s
            .rows
            .iter()
            .filter(|r| r.error_vs_ccm_mm <= f.tolerance_mm)
            .all(|r| r.time_us * (1.0 + TIME_RESOLUTION) >= best.time_us));
        if let Some(e) = &f.fastest_estimated {
            let r = &s.rows[e.row];
            assert!(r.estimated_error_mm.unwrap() <= f.tolerance_mm);
            assert!(e.time_us * (1.0 + TIME_RESOLUTION) >= best.time_us);
        }
        let lib = f.library.as_ref().expect("the library's choice solves");
        assert!(lib.meets, "{} at {} mm", lib.label, f.tolerance_mm);
    }
    assert!(s.n8.time_us > 0.0 && s.n8.batches_us.len() > s.rows.len());

    // the whole study serialises, non-finite numbers as null
    let v = serde_json::to_value(&s).unwrap();
    assert_eq!(v["references"][0]["model"], "ccm");
    assert!(v["rows"][0]["tip_mm"].is_array());
}
