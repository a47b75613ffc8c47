//! Study option errors and failed studies.

use super::*;

// ------------------------------------------------------------------ studies

/// A sweep that fails part-way keeps every point computed before the
/// failure and records where and why it stopped. A prestressed law with a
/// strong quintic term (p4 = 20 MPa instead of 0.698) makes the energy
/// unbounded below at moderate stretch, so the pressure sweep of study 7
/// fails at a pressure that depends on eps0.
#[test]
fn a_failed_sweep_keeps_the_points_already_computed() {
    let law = PsiLaw {
        p4: 20.0,
        ..PsiLaw::default()
    };
    let act = Actuator::new(ActuatorParams {
        pemc: Prestressed {
            law,
            ..Prestressed::default()
        },
        ..ActuatorParams::default()
    })
    .unwrap();
    let opts = StudyOptions {
        pressure_points: 9, // 0, 50, ..., 400 kPa
        ..StudyOptions::coarse()
    };
    let curves = no_panic("study 7", || study7_curvature(&act, &opts)).unwrap();
    assert_eq!(curves.len(), 3);
    let mut partial = 0;
    for c in &curves {
        let stop = c
            .stopped
            .as_ref()
            .unwrap_or_else(|| panic!("eps0 {}: the sweep did not stop", c.eps0));
        let msg = one_line(&stop.reason);
        assert!(msg.starts_with("solve failed"), "{msg}");
        // the points before the failure, in order, and nothing after it
        for (i, r) in c.rows.iter().enumerate() {
            assert_eq!(r.pressure_kpa, 50.0 * i as f64, "eps0 {}", c.eps0);
            assert!(r.pressure_kpa < stop.at);
            assert!(r.tip.iter().all(|v| v.is_finite()) && r.end_angle.is_finite());
        }
        assert_eq!(stop.at, 50.0 * c.rows.len() as f64, "eps0 {}", c.eps0);
        partial += usize::from(!c.rows.is_empty());
    }
    assert!(partial >= 1, "no sweep stopped part-way: {curves:?}");
}
