//! The model's validity findings (docs/model.md section 8): each kind on a
//! case built to raise it, checked against quantities computed here from
//! the coefficients (the paper's element's closed forms, a segment
//! intersection written here), and their absence where the model holds.

use fpc::gripper::rules;
use fpc::{
    solve_auto, Actuator, Finger, Gripper, GripperParams, InputError, Invalid, Load, ModelId,
    Partition, SolveError, SolveOptions, Warning, MIDPLANE_STRAIN_LIMIT, SLOPE_LIMIT_DEG,
};

fn kinds(w: &[Warning]) -> Vec<&'static str> {
    w.iter()
        .filter(|w| w.is_validity())
        .map(Warning::kind)
        .collect()
}

/// The paper's element at local x: (eps_x at height z, slope angle of the
/// mid-plane), from u = a1 x + a3 x^3, w = c2 x^2.
fn ccm_strain(k: &[f64], x: f64, z: f64) -> f64 {
    let [a1, a3, _, c2] = [k[0], k[1], k[2], k[3]];
    a1 + (3.0 * a3 + 2.0 * c2 * c2) * x * x - 2.0 * z * c2
}

fn ccm_slope_deg(k: &[f64], x: f64) -> f64 {
    let [a1, a3, _, c2] = [k[0], k[1], k[2], k[3]];
    (2.0 * c2 * x)
        .atan2(1.0 + a1 + 3.0 * a3 * x * x)
        .to_degrees()
}

#[test]
fn a_coarse_partition_of_a_curled_finger_breaks_the_slope_limit() {
    // eps0 = 0.4 in two elements: each turns far beyond 45 degrees
    let f = Finger::paper(0.4, 2).unwrap();
    let sol = f
        .solve(&Load::unloaded(), &SolveOptions::default())
        .unwrap();
    let mut flagged = 0;
    for w in &sol.warnings {
        if let Warning::ElementSlope {
            element,
            degrees,
            limit,
        } = *w
        {
            flagged += 1;
            assert_eq!(limit, SLOPE_LIMIT_DEG);
            // the largest slope over the element, by the closed form
            let k = sol.coefficients.element(element);
            let l = f.element_lengths()[element];
            let most = (0..=200)
                .map(|j| ccm_slope_deg(k, l * j as f64 / 200.0).abs())
                .fold(0.0, f64::max);
            assert!(degrees > limit, "{degrees}");
            assert!((most - degrees).abs() < 1e-6 * most, "{most} vs {degrees}");
            assert_eq!(w.value(), Some(degrees));
            assert_eq!(w.element(), Some(element));
        }
    }
    assert_eq!(flagged, 2, "{:?}", sol.warnings);
    assert!(!sol.is_within_model());
}

#[test]
fn a_strong_compression_breaks_the_strain_ranges() {
    // 50 N against the finger's axis: the first element folds at a large
    // axial strain and the prestressed layer goes into compression
    let f = Finger::paper(0.25, 8).unwrap();
    let load = Load::unloaded().with_tip_force(-50.0, 0.0);
    let sol = f.solve(&load, &SolveOptions::default()).unwrap();
    let act = Actuator::paper(0.25).unwrap();
    let (pz0, pz1) = act.pemc_z();
    let mut mid = 0;
    let mut pre = 0;
    for w in &sol.warnings {
        match *w {
            Warning::MidplaneStrain {
                element,
                strain,
                limit,
            } => {
                mid += 1;
                assert_eq!(limit, MIDPLANE_STRAIN_LIMIT);
                assert!(strain.abs() > limit);
                let k = sol.coefficients.element(element);
                let l = f.element_lengths()[element];
                let worst = (0..=64)
                    .map(|j| ccm_strain(k, l * j as f64 / 64.0, 0.0))
                    .fold(0.0f64, |m, s| if s.abs() > m.abs() { s } else { m });
                assert!(
                    (worst - strain).abs() <= 1e-3 * worst.abs(),
                    "{worst} vs {strain}"
                );
                assert_eq!(w.kind(), "strain_range");
            }
            Warning::PrestressedStrain {
                element,
                strain,
                range,
            } => {
                pre += 1;
                assert!(strain < range.0 || strain > range.1);
                // the layer's own strain at one of its faces, by the closed form
                let k = sol.coefficients.element(element);
                let l = f.element_lengths()[element];
                let found = (0..=64).any(|j| {
                    let x = l * j as f64 / 64.0;
                    [pz0, pz1]
                        .iter()
                        .any(|&z| ((0.25 + ccm_strain(k, x, z)) - strain).abs() < 1e-3)
                });
                assert!(found, "element {element}: s = {strain}");
            }
            _ => {}
        }
    }
    assert!(mid >= 1 && pre >= 1, "{:?}", kinds(&sol.warnings));
}

/// True when the closed segments pq and rs intersect (written here,
/// independently of the library's check).
fn intersect(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    let d = (q[0] - p[0]) * (s[1] - r[1]) - (q[1] - p[1]) * (s[0] - r[0]);
    if d == 0.0 {
        return false;
    }
    let t = ((r[0] - p[0]) * (s[1] - r[1]) - (r[1] - p[1]) * (s[0] - r[0])) / d;
    let u = ((r[0] - p[0]) * (q[1] - p[1]) - (r[1] - p[1]) * (q[0] - p[0])) / d;
    (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)
}

#[test]
fn a_finger_that_coils_past_a_full_turn_meets_itself() {
    // eps0 = 0.8 (beyond the fitted range) curls about 500 degrees
    let f = Finger::paper(0.8, 16).unwrap();
    let sol = f
        .solve(&Load::unloaded(), &SolveOptions::default())
        .unwrap();
    assert!(
        sol.warnings
            .iter()
            .any(|w| matches!(w, Warning::Eps0OutsideFit { .. })),
        "the actuator's warning comes with the solution"
    );
    let contact = sol
        .warnings
        .iter()
        .find(|w| w.kind() == "self_contact")
        .unwrap_or_else(|| panic!("{:?}", kinds(&sol.warnings)));
    let Warning::SelfContact { element, other } = *contact else {
        unreachable!()
    };
    assert!(element > other + 1, "{element} vs {other}");
    // brute force on a fine sampling: some non-adjacent segments cross
    let pts = f.shape(&sol.coefficients, 64).unwrap();
    let n = pts.len() - 1;
    let crossed =
        (2..n).any(|b| (0..b - 1).any(|a| intersect(pts[a], pts[a + 1], pts[b], pts[b + 1])));
    assert!(crossed);
    // and the paper's finger does not
    let f = Finger::paper(0.4, 16).unwrap();
    let sol = f
        .solve(&Load::unloaded(), &SolveOptions::default())
        .unwrap();
    let pts = f.shape(&sol.coefficients, 64).unwrap();
    let n = pts.len() - 1;
    assert!(!(2..n).any(|b| (0..b - 1).any(|a| intersect(pts[a], pts[a + 1], pts[b], pts[b + 1]))));
    assert!(!kinds(&sol.warnings).contains(&"self_contact"));
}

#[test]
fn the_papers_fingers_unloaded_and_lightly_loaded_raise_nothing() {
    for eps0 in [0.15, 0.25] {
        let f = Finger::paper(eps0, 8).unwrap();
        for load in [
            Load::unloaded(),
            Load::unloaded().with_pressure_kpa(100.0),
            Load::unloaded().with_pressure_kpa(400.0),
            Load::unloaded().with_tip_force(0.939782, 0.521707),
            Load::unloaded().with_tip_force(0.0, 0.5),
        ] {
            let sol = f.solve(&load, &SolveOptions::default()).unwrap();
            assert!(
                sol.warnings.is_empty(),
                "eps0 {eps0}, {load:?}: {:?}",
                sol.warnings
            );
            assert!(sol.is_within_model());
            // tip-only output runs the same checks
            let tip = f.solve(&load, &SolveOptions::default().tip_only()).unwrap();
            assert!(tip.warnings.is_empty());
            assert_eq!(sol.element_lengths, vec![110.0 / 8.0; 8]);
        }
    }
}

#[test]
fn a_sphere_pressed_near_flat_bends_the_finger_backwards() {
    // the Sec. 5 gripper; a large sphere below the equator: the first
    // elements turn against the unloaded curl (c2 > 0 where it was < 0)
    let g = Gripper::paper(0.25, 8, GripperParams::default()).unwrap();
    let sg = g
        .sphere_grasp_at_friction_limit(0.0, 80.0, -0.4, None)
        .unwrap();
    let w = sg
        .grasp
        .warnings
        .iter()
        .find(|w| w.kind() == "curvature_reversal")
        .unwrap_or_else(|| panic!("{:?}", sg.grasp.warnings));
    let Warning::CurvatureReversal { element, curvature } = *w else {
        unreachable!()
    };
    assert!(curvature < 0.0);
    let reference = g.reference().coefficients.element(element)[3];
    let loaded = sg.grasp.solution.coefficients.element(element)[3];
    assert!(
        reference < 0.0 && loaded > 0.0,
        "c2 {reference} -> {loaded}"
    );
    assert!(sg.grasp.is_reversed());
    assert!(sg.is_valid(), "flagged, not invalid, outside strict mode");
    // strict mode: the same grasp is invalid
    let strict = Gripper::paper(
        0.25,
        8,
        GripperParams {
            strict: true,
            ..GripperParams::default()
        },
    )
    .unwrap();
    let sg = strict
        .sphere_grasp_at_friction_limit(0.0, 80.0, -0.4, None)
        .unwrap();
    assert!(matches!(
        sg.invalid,
        Some(Invalid::CurvatureReversal { .. })
    ));
    // a gentle grasp is not reversed
    let gentle = g.force_control(0.0, 100.0, 0.3, None).unwrap();
    assert!(
        !gentle.is_reversed() && gentle.is_valid(),
        "{:?}",
        gentle.warnings
    );
}

#[test]
fn grasps_beyond_flat_are_never_valid() {
    let g = Gripper::paper(0.25, 8, GripperParams::default()).unwrap();
    let d_max = g.d_max();
    // the rule itself
    assert!(rules::flat_rule(d_max * 1.001, d_max).is_some());
    assert!(rules::flat_rule(d_max, d_max).is_none());
    // targets past flat are typed input errors naming the target
    for e in [
        g.force_control(0.0, d_max + 1.0, 0.3, None).unwrap_err(),
        g.grasp_load_for_size(0.0, d_max + 1.0, 0.0, None)
            .unwrap_err(),
    ] {
        match e {
            SolveError::Input(InputError::OutOfRange { field, rule, .. }) => {
                assert_eq!(field, "grasp.size");
                assert!(rule.contains("d_max"), "{rule}");
            }
            e => panic!("{e:?}"),
        }
    }
    // a sphere whose contact needs the tip beyond the flat fingers
    match g
        .sphere_grasp(0.0, 2.0 * d_max, 0.5, 0.0, None)
        .unwrap_err()
    {
        SolveError::Input(e) => assert_eq!(e.field(), "sphere.radius"),
        e => panic!("{e:?}"),
    }
}

#[test]
fn the_automatic_partition_keeps_every_element_within_the_slope_limit() {
    let base = Actuator::paper(0.25).unwrap();
    let mut coarse_broke = 0;
    for eps0 in [0.05, 0.15, 0.25, 0.4, 0.6] {
        let act = base.with_eps0(eps0).unwrap();
        for p in [0.0, 200.0, 400.0] {
            for (fx, fz) in [(0.0, 0.0), (0.939782, 0.521707), (0.0, 1.0)] {
                let load = Load::unloaded().with_pressure_kpa(p).with_tip_force(fx, fz);
                let auto = solve_auto(
                    ModelId::default(),
                    &act,
                    true,
                    &load,
                    &SolveOptions::default(),
                )
                .unwrap_or_else(|e| panic!("eps0 {eps0}, {load:?}: {e}"));
                let what = format!("eps0 {eps0}, {load:?}, N = {}", auto.partition.len());
                // independently: every element's slope by the closed form
                for (i, k) in auto.solution.coefficients.iter().enumerate() {
                    let l = auto.partition.lengths()[i];
                    for j in 0..=32 {
                        let s = ccm_slope_deg(k, l * j as f64 / 32.0).abs();
                        assert!(
                            s <= SLOPE_LIMIT_DEG,
                            "{what}: element {i} turns {s} degrees"
                        );
                    }
                }
                assert!(
                    !kinds(&auto.solution.warnings).contains(&"element_slope"),
                    "{what}"
                );
                assert_eq!(auto.solution.element_lengths, auto.partition.lengths());
                // element ends on the channel's end and the rib edges
                let ends: Vec<f64> = auto
                    .partition
                    .starts()
                    .iter()
                    .zip(auto.partition.lengths())
                    .map(|(s, l)| s + l)
                    .collect();
                for x in [act.channel().cx, act.ribs()[1].x0, act.ribs()[1].x1] {
                    assert!(
                        ends.iter().any(|e| (e - x).abs() < 1e-9),
                        "{what}: no boundary at {x}"
                    );
                }
                // the paper's N = 8 does break it for the curled fingers
                let eq = Finger::new(&act, &Partition::equal(110.0, 8).unwrap(), true);
                if let Ok(s) = eq.solve(&load, &SolveOptions::default()) {
                    coarse_broke += kinds(&s.warnings).contains(&"element_slope") as usize;
                }
            }
        }
    }
    assert!(
        coarse_broke > 0,
        "the grid should include fingers N = 8 cannot follow"
    );
}
