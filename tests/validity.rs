//! The model's validity findings (docs/model.md section 8): each kind on a
//! case built to raise it, checked against quantities computed here from
//! the coefficients (the paper's element's closed forms, a segment
//! intersection written here), and their absence where the model holds.

#[path = "common/plans.rs"]
mod plans;
use fpc::actuator::RibLayout;
use fpc::error::StripDimension;
use fpc::gripper::rules;
use fpc::gripper::Invalid;
use fpc::scene::{Scene, SolutionRecord};
use fpc::studies::{
    section5_gripper, tip_force_for_displacement, Axis, PAPER_EPS0, STUDY8_PRESSURES_KPA,
};
use fpc::validity::{MIDPLANE_STRAIN_LIMIT, SLOPE_LIMIT_DEG};
use fpc::validity::{THICKNESS_TO_LENGTH_LIMIT, THICKNESS_TO_WIDTH_LIMIT};
use fpc::ActuatorParams;
use fpc::StudyOptions;
use fpc::{
    Actuator, Finger, Gripper, GripperParams, InputError, Load, ModelId, Partition, SolveError,
    SolveOptions, Warning,
};
use plans::solve_auto;

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

/// The paper's laminate thickness H (mm).
const H: f64 = 8.2;

/// Random states, many of them past one strain limit or both: the
/// mid-plane and prestressed findings are exactly the elements whose check
/// points (x = l j / samples) break a limit, by the closed form, with the
/// strain of the largest magnitude and the one farthest outside the range.
#[test]
fn the_strain_findings_are_the_extremes_at_the_check_points() {
    let f = Finger::paper(0.25, 6).unwrap();
    let (pz0, pz1) = Actuator::paper(0.25).unwrap().pemc_z();
    let (lo, hi) = fpc::validity::PRESTRESSED_STRAIN_RANGE;
    let lengths = f.element_lengths();
    let mut rng = fastrand::Rng::with_seed(29);
    let (mut mids, mut pres, mut clean) = (0, 0, 0);
    for case in 0..400 {
        let samples = [1, 4, 7][case % 3];
        let mut values = Vec::new();
        for &l in lengths {
            // within the limits or past them
            let s = if rng.bool() { 0.2 } else { 1.0 };
            values.extend([
                s * 0.5 * (rng.f64() - 0.5),
                s * 0.3 * (rng.f64() - 0.5) / (l * l),
                0.01 * (rng.f64() - 0.5),
                s * (rng.f64() - 0.5) / l,
            ]);
        }
        let k = fpc::Coefficients::new(4, values).unwrap();
        let warnings = f.validity(&k, samples).unwrap();
        for (i, &l) in lengths.iter().enumerate() {
            let ki = k.element(i);
            let xs = (0..=samples).map(|j| l * j as f64 / samples as f64);
            let mid = xs
                .clone()
                .map(|x| ccm_strain(ki, x, 0.0))
                .fold(0.0f64, |m, s| if s.abs() > m.abs() { s } else { m });
            let (by, pre) = xs
                .flat_map(|x| [pz0, pz1].map(|z| 0.25 + ccm_strain(ki, x, z)))
                .map(|s| ((lo - s).max(s - hi), s))
                .fold(
                    (f64::NEG_INFINITY, 0.0),
                    |m, v| if v.0 > m.0 { v } else { m },
                );
            let near = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
            // (a state within rounding of a limit may go either way)
            if near(mid.abs(), MIDPLANE_STRAIN_LIMIT) || near(by, 0.0) {
                continue;
            }
            let found_mid = warnings.iter().find_map(|w| match *w {
                Warning::MidplaneStrain {
                    element, strain, ..
                } if element == i => Some(strain),
                _ => None,
            });
            let found_pre = warnings.iter().find_map(|w| match *w {
                Warning::PrestressedStrain {
                    element, strain, ..
                } if element == i => Some(strain),
                _ => None,
            });
            match found_mid {
                Some(s) => {
                    assert!(near(s, mid), "case {case} element {i}: {s} vs {mid}");
                    mids += 1;
                }
                None => assert!(
                    mid.abs() <= MIDPLANE_STRAIN_LIMIT,
                    "case {case} element {i}"
                ),
            }
            match found_pre {
                Some(s) => {
                    assert!(near(s, pre), "case {case} element {i}: {s} vs {pre}");
                    pres += 1;
                }
                None => assert!(by <= 0.0, "case {case} element {i}: {by}"),
            }
            clean += usize::from(found_mid.is_none() && found_pre.is_none());
        }
    }
    assert!(
        mids > 100 && pres > 100 && clean > 100,
        "{mids} {pres} {clean}"
    );
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

/// The distance from p to the segment ab, by projection.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (ux, uz) = (b[0] - a[0], b[1] - a[1]);
    let t = (((p[0] - a[0]) * ux + (p[1] - a[1]) * uz) / (ux * ux + uz * uz)).clamp(0.0, 1.0);
    (p[0] - a[0] - t * ux).hypot(p[1] - a[1] - t * uz)
}

/// The closest approach of a sampled mid-plane to itself, by brute force
/// over every pair of its segments at least pi H / 2 apart along it (arc
/// length by chords): `(distance, a, b)` with segment indices `a < b`.
fn closest_approach(pts: &[[f64; 2]], h: f64) -> (f64, usize, usize) {
    let sep = std::f64::consts::PI * h / 2.0;
    let mut arc = vec![0.0];
    for w in pts.windows(2) {
        arc.push(arc.last().unwrap() + (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]));
    }
    let mut best = (f64::INFINITY, 0, 0);
    for b in 1..pts.len() - 1 {
        for a in 0..b - 1 {
            if arc[b] - arc[a + 1] < sep {
                break;
            }
            let (p, q, r, s) = (pts[a], pts[a + 1], pts[b], pts[b + 1]);
            let d = if intersect(p, q, r, s) {
                0.0
            } else {
                to_segment(p, r, s)
                    .min(to_segment(q, r, s))
                    .min(to_segment(r, p, q))
                    .min(to_segment(s, p, q))
            };
            if d < best.0 {
                best = (d, a, b);
            }
        }
    }
    best
}

/// The finger's mid-plane sampled at most `h / 40` apart (for the
/// stretches met here), and the samples per element.
fn dense_shape(f: &Finger, sol: &fpc::Solution, h: f64) -> (Vec<[f64; 2]>, usize) {
    let longest = f.element_lengths().iter().cloned().fold(0.0, f64::max);
    let per = ((40.0 * 1.3 * longest / h).ceil() as usize).max(4);
    (f.shape(&sol.coefficients, per).unwrap(), per)
}

/// The self-contact finding of a solution, as (element, other, distance, H).
fn contact(sol: &fpc::Solution) -> Option<(usize, usize, f64, f64)> {
    sol.warnings.iter().find_map(|w| match *w {
        Warning::SelfContact {
            element,
            other,
            distance,
            thickness,
        } => Some((element, other, distance, thickness)),
        _ => None,
    })
}

#[test]
fn a_finger_that_coils_past_a_full_turn_crosses_itself() {
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
    let (element, other, distance, _) =
        contact(&sol).unwrap_or_else(|| panic!("{:?}", kinds(&sol.warnings)));
    assert!(element > other + 1, "{element} vs {other}");
    // brute force on a fine sampling: some segments pi H / 2 apart cross
    let pts = f.shape(&sol.coefficients, 64).unwrap();
    let (d, a, b) = closest_approach(&pts, H);
    assert_eq!(d, 0.0);
    assert!(intersect(pts[a], pts[a + 1], pts[b], pts[b + 1]));
    assert_eq!(distance, 0.0);
    let w = sol
        .warnings
        .iter()
        .find(|w| w.kind() == "self_contact")
        .unwrap();
    assert!(w.to_string().contains("crosses itself"), "{w}");
}

#[test]
fn the_issues_coiled_finger_touches_its_root() {
    // eps0 = 0.6 on the automatic partition: 371 degrees of curl, the tip
    // 3.6 mm from the root on a finger 8.2 mm thick
    let act = Actuator::paper(0.6).unwrap();
    let auto = solve_auto(
        ModelId::default(),
        &act,
        true,
        &Load::unloaded(),
        &SolveOptions::default(),
    )
    .unwrap();
    let sol = &auto.solution;
    assert!(sol.end_angle.to_degrees() < -360.0, "{}", sol.end_angle);
    let (element, other, distance, thickness) =
        contact(sol).unwrap_or_else(|| panic!("{:?}", sol.warnings));
    assert_eq!(thickness, H);
    assert!(!sol.is_within_model());
    // brute force on a dense sampling
    let (pts, per) = dense_shape(&auto.finger, sol, H);
    let (d, a, b) = closest_approach(&pts, H);
    let element_of = |j: usize| j / per;
    assert!(d < H);
    assert!((distance - d).abs() < 0.005, "{distance} vs {d}");
    // the pair found is the brute force's (up to a neighbouring element)
    assert!(element.abs_diff(element_of(b)) <= 1 && other.abs_diff(element_of(a)) <= 1);
    // the tip has curled onto the root
    assert_eq!(other, 0);
    assert_eq!(element, auto.finger.len() - 1);
    let w = sol
        .warnings
        .iter()
        .find(|w| w.kind() == "self_contact")
        .unwrap();
    assert_eq!(w.value(), Some(distance));
    assert_eq!(w.limit(), Some(H));
    assert_eq!(w.element(), Some(element));
    assert!(w.to_string().contains("8.2 mm"), "{w}");
}

#[test]
fn self_contact_is_exactly_the_mid_plane_within_h_of_itself() {
    // coiled fingers under suction down to vacuum: each is flagged exactly
    // when a dense brute force finds two parts pi H / 2 apart along the
    // finger closer than H
    let base = Actuator::paper(0.25).unwrap();
    let (mut flagged, mut total) = (0, 0);
    let mut margin = f64::INFINITY;
    for eps0 in [0.45, 0.5, 0.55, 0.6] {
        let act = base.with_eps0(eps0).unwrap();
        for i in 0..10 {
            let p = -101.325 + 151.325 * i as f64 / 9.0;
            let load = Load::unloaded().with_pressure_kpa(p);
            let auto = solve_auto(
                ModelId::default(),
                &act,
                true,
                &load,
                &SolveOptions::default(),
            )
            .unwrap_or_else(|e| panic!("eps0 {eps0}, {p} kPa: {e}"));
            let sol = &auto.solution;
            let (pts, _) = dense_shape(&auto.finger, sol, H);
            let (d, _, _) = closest_approach(&pts, H);
            let found = contact(sol);
            total += 1;
            margin = margin.min((d - H).abs());
            assert_eq!(
                found.is_some(),
                d < H,
                "eps0 {eps0}, {p} kPa: {d} vs {found:?}"
            );
            if let Some((_, _, distance, _)) = found {
                flagged += 1;
                assert!(
                    (distance - d).abs() < 0.005,
                    "eps0 {eps0}, {p} kPa: {distance} vs {d}"
                );
            }
        }
    }
    println!("{flagged} of {total} flagged; closest to the limit {margin} mm");
    assert!(flagged > 0 && flagged < total, "{flagged} of {total}");
    // no finger so near the limit that sampling could decide it
    assert!(margin > 0.01, "{margin}");
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
        sg.invalid(),
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
                assert_eq!(field, fpc::Field::GraspSize);
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
                let what = format!("eps0 {eps0}, {load:?}, N = {}", auto.elements());
                // independently: every element's slope by the closed form
                for (i, k) in auto.solution.coefficients.iter().enumerate() {
                    let l = auto.finger.element_lengths()[i];
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
                assert_eq!(auto.solution.element_lengths, auto.finger.element_lengths());
                // element ends on the channel's end and the rib edges
                let ends: Vec<f64> = auto
                    .finger
                    .element_lengths()
                    .iter()
                    .scan(0.0, |end, l| {
                        *end += l;
                        Some(*end)
                    })
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

/// The paper's actuator scaled to thickness `h` (every z dimension in
/// proportion) and length `lx` (the channel ending 5/110 of it early).
fn scaled_actuator(h: f64, lx: f64) -> ActuatorParams {
    let mut p = ActuatorParams::default();
    let s = h / p.geometry.h;
    let g = &mut p.geometry;
    (g.h, g.h1, g.h2, g.h3) = (h, g.h1 * s, g.h2 * s, g.h3 * s);
    p.channel.h3a *= s;
    p.channel.h3b *= s;
    g.lx = lx;
    p.channel.cx = lx * 105.0 / 110.0;
    p
}

fn thickness_findings(w: &[Warning]) -> Vec<(StripDimension, f64, f64)> {
    w.iter()
        .filter_map(|w| match *w {
            Warning::ThicknessRatio {
                dimension,
                thickness,
                extent,
                limit,
            } => Some((dimension, thickness / extent, limit)),
            _ => None,
        })
        .collect()
}

#[test]
fn a_laminate_too_thick_for_its_length_or_width_is_outside_the_model() {
    // the default strip: H / Lx = 8.2 / 110 and H / Ly = 8.2 / 31.75
    let act = Actuator::default();
    assert!(thickness_findings(act.warnings()).is_empty());
    let g = act.geometry();
    assert!(g.h / g.lx < THICKNESS_TO_LENGTH_LIMIT && g.h / g.ly < THICKNESS_TO_WIDTH_LIMIT);
    for (what, params, dims) in [
        // 200 mm thick, 110 mm long (and 31.75 mm wide)
        (
            "200 mm thick",
            scaled_actuator(200.0, 110.0),
            vec![StripDimension::Length, StripDimension::Width],
        ),
        // one micrometre long
        (
            "1 um long",
            scaled_actuator(8.2, 0.001),
            vec![StripDimension::Length],
        ),
        // as wide as it is thick
        (
            "8.2 mm wide",
            {
                let mut p = ActuatorParams::default();
                p.geometry.ly = 8.2;
                p.channel.cy = 6.0;
                p.ribs = RibLayout::None;
                p
            },
            vec![StripDimension::Width],
        ),
    ] {
        let act = Actuator::new(params.clone()).unwrap();
        let found = thickness_findings(act.warnings());
        assert_eq!(
            found.iter().map(|f| f.0).collect::<Vec<_>>(),
            dims,
            "{what}: {:?}",
            act.warnings()
        );
        let g = &params.geometry;
        for &(dimension, ratio, limit) in &found {
            let extent = match dimension {
                StripDimension::Length => g.lx,
                StripDimension::Width => g.ly,
            };
            assert_eq!(ratio, g.h / extent);
            assert!(ratio > limit, "{what}");
        }
        let w = act
            .warnings()
            .iter()
            .find(|w| w.kind() == "thickness_ratio")
            .unwrap();
        assert!(w.is_validity() && w.element().is_none());
        assert!(w.to_string().contains("actuator.geometry.h"), "{w}");
        // every solution built from it carries the finding
        let finger = Finger::new(&act, &Partition::equal(g.lx, 8).unwrap(), true);
        assert_eq!(thickness_findings(finger.warnings()).len(), dims.len());
        let sol = finger
            .solve(&Load::unloaded(), &SolveOptions::default())
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        println!("{what}: {:?}", sol.warnings);
        assert_eq!(
            thickness_findings(&sol.warnings).len(),
            dims.len(),
            "{what}"
        );
        assert!(!sol.is_within_model(), "{what}");
    }
}

#[test]
fn a_scene_of_a_thick_strip_records_validity_false() {
    for (what, geometry) in [
        (
            "200 mm thick",
            "[actuator.geometry]\nh = 200\nh1 = 90\nh2 = 44\nh3 = 54\n[actuator.channel]\nh3a = 19\nh3b = 29\n",
        ),
        (
            "1 um long",
            "[actuator.geometry]\nlx = 0.001\n[actuator.channel]\ncx = 0.00095\n",
        ),
        ("the paper's", ""),
    ] {
        let text = format!("{geometry}[partition]\nelements = 8\n");
        let scene = Scene::from_toml(&text).unwrap_or_else(|e| panic!("{what}: {e}"));
        let flagged = what != "the paper's";
        assert_eq!(
            scene.warnings().iter().any(|w| w.kind() == "thickness_ratio"),
            flagged,
            "{what}"
        );
        let solved = scene.solve().unwrap_or_else(|e| panic!("{what}: {e}"));
        let record =
            serde_json::to_value(SolutionRecord::new("thick", scene.file(), &solved)).unwrap();
        assert_eq!(record["validity"], !flagged, "{what}: {record}");
        let kinds: Vec<&str> = record["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|w| w["kind"].as_str().unwrap())
            .collect();
        assert_eq!(kinds.contains(&"thickness_ratio"), flagged, "{what}: {kinds:?}");
    }
}

#[test]
fn the_papers_fingers_at_the_studies_loads_do_not_touch_themselves() {
    let mut closest = f64::INFINITY;
    let mut checked = 0;
    let mut check = |what: &str, f: &Finger, sol: &fpc::Solution| {
        assert!(contact(sol).is_none(), "{what}: {:?}", sol.warnings);
        let (pts, _) = dense_shape(f, sol, H);
        let (d, _, _) = closest_approach(&pts, H);
        assert!(d >= H, "{what}: {d}");
        closest = closest.min(d);
        checked += 1;
    };
    for eps0 in PAPER_EPS0 {
        let f = Finger::paper(eps0, 8).unwrap();
        // study 7: unloaded, 0 to 400 kPa
        for i in 0..=8 {
            let load = Load::unloaded().with_pressure_kpa(50.0 * i as f64);
            let sol = f.solve(&load, &SolveOptions::default()).unwrap();
            check(&format!("eps0 {eps0}, {load:?}"), &f, &sol);
        }
        // study 8: the force that moves the tip 10 mm, along X and along Z
        for p in STUDY8_PRESSURES_KPA {
            for axis in [Axis::X, Axis::Z] {
                let r = tip_force_for_displacement(&f, p, axis, 10.0).unwrap();
                check(&format!("eps0 {eps0}, {p} kPa, {axis:?}"), &f, &r.solution);
            }
        }
    }
    // study 4: the Sec. 5 gripper holding the 100 mm cuboid by pressure
    let g = section5_gripper(&Actuator::default(), &StudyOptions::default()).unwrap();
    let f = g.finger().clone();
    for i in 0..=10 {
        let grasp = g.force_control(10.0 * i as f64, 100.0, 0.3, None).unwrap();
        check(&format!("grasp at {} kPa", 10 * i), &f, &grasp.solution);
    }
    println!("{checked} states; closest approach {closest} mm");
}
