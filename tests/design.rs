//! Inverse design (`fpc::design`) checked by brute force and by forward
//! solves: no point of a grid over the same variables has a larger
//! worst-case margin than the optimiser's design, beyond what one grid
//! step can change; every claimed grasp is reproduced by the ordinary
//! scene path; infeasible requirements name what fails.

use fpc::design::{evaluate, grid_search, optimize, DesignOptions, Requirements};
use fpc::scene::{Scene, SceneSolution};

const CUBOID: &str = r#"
[[object]]
kind = "cuboid"
size_mm = [70.0, 100.0]
lift_n = 0.6
[vary]
eps0 = [0.1, 0.45]
mounting_angle_deg = [55.0, 90.0]
"#;

#[test]
fn no_grid_point_beats_the_optimiser_beyond_the_grid_resolution() {
    let req = Requirements::parse(CUBOID).unwrap();
    let d = optimize(&req, &DesignOptions::default()).unwrap();
    let grid = grid_search(&req, 11).unwrap();
    assert_eq!(grid.evaluated, 121);
    // how much the worst margin can change over one grid step, from the
    // margins' sensitivities at the grid's best point
    let best = grid.best.design;
    let step = |i: usize, h: f64| {
        let mut a = best;
        let mut b = best;
        a[i] += h;
        b[i] -= h;
        (evaluate(&req, a).worst - evaluate(&req, b).worst).abs() / 2.0
    };
    let slack = step(0, grid.resolution[0]) + step(1, grid.resolution[1]);
    assert!(
        grid.best.worst <= d.best.worst + slack + 1e-9,
        "grid {:?} worst {} > optimiser {:?} worst {} (+ slack {slack})",
        grid.best.design,
        grid.best.worst,
        d.best.design,
        d.best.worst
    );
    assert!(d.feasible, "{:?}", d.best);
    // the claim reproduces from scratch
    assert_eq!(evaluate(&req, d.best.design).worst, d.best.worst);
}

#[test]
fn every_claimed_grasp_is_reproduced_by_the_scene_path() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/design/paper_sec5.toml"
    ))
    .unwrap();
    let req = Requirements::parse(&text).unwrap();
    // a fixed design (the paper's), so the check does not depend on the search
    let e = evaluate(&req, [0.25, 60.0, 20.0]);
    let mut d = fpc::design::Designed {
        feasible: e.feasible(),
        best: e,
        sensitivities: Vec::new(),
        evaluations: 1,
        starts: 0,
        reproductions: Vec::new(),
        failure: None,
    };
    let scenes = d.scenes(&req);
    assert_eq!(scenes.len(), 2);
    for (i, (file, toml)) in scenes.iter().enumerate() {
        let claim = d.best.hardest_lift(i).unwrap();
        let solved = Scene::from_toml(toml).unwrap().solve().unwrap();
        let SceneSolution::Gripper { grasp: Some(g), .. } = solved else {
            panic!("{file}: no grasp")
        };
        assert_eq!(Some(g.is_valid()), claim.valid, "{file}: {:?}", g.invalid());
        for (solved, claimed) in [
            (g.grasp.lift, claim.value.unwrap()),
            (g.grasp.normal, claim.normal_n.unwrap()),
        ] {
            assert!(
                (solved - claimed).abs() <= 1e-6 * claimed,
                "{file}: solved {solved} vs claimed {claimed}"
            );
        }
    }
    // the library's check agrees, scene by scene
    let checks = fpc::design::reproduce(&d.best, &req);
    assert_eq!(checks.len(), 2);
    assert!(checks.iter().all(|c| c.reproduced), "{checks:?}");
    // a claim its scene does not reproduce is caught: a lift 1 % too high
    let i = d
        .best
        .margins
        .iter()
        .position(|m| m.requirement.starts_with("object[1] ") && m.requirement.ends_with("lift"))
        .unwrap();
    let hardest = d.best.hardest_lift(1).unwrap().requirement.clone();
    for m in d
        .best
        .margins
        .iter_mut()
        .filter(|m| m.requirement == hardest)
    {
        m.value = m.value.map(|v| v * 1.01);
    }
    assert!(i < d.best.margins.len());
    let checks = fpc::design::reproduce(&d.best, &req);
    assert!(checks[0].reproduced && !checks[1].reproduced, "{checks:?}");
}

#[test]
fn designs_keep_to_the_design_space_unless_the_file_widens_it() {
    let base = "[[object]]\nkind = \"cuboid\"\nsize_mm = [60.0, 80.0]\nlift_n = 0.3\n[vary]\n";
    // clamped to [arccot mu, 90] = [59.04, 90] degrees, with a note
    let req = Requirements::parse(&format!("{base}mounting_angle_deg = [50.0, 90.0]\n")).unwrap();
    let lo = (1.0f64 / 0.6).atan().to_degrees();
    assert!(
        (req.bounds()[1][0] - lo).abs() < 1e-12,
        "{:?}",
        req.bounds()
    );
    assert_eq!(req.bounds()[1][1], 90.0);
    assert_eq!(req.notes().len(), 1, "{:?}", req.notes());
    assert!(req.notes()[0].contains("searched within the design space"));
    // inside it: no note
    let req = Requirements::parse(&format!("{base}mounting_angle_deg = [60.0, 90.0]\n")).unwrap();
    assert!(req.notes().is_empty());
    assert_eq!(req.bounds()[1], [60.0, 90.0]);
    // widened explicitly: the bounds as given, and a note that says so
    let req = Requirements::parse(&format!(
        "{base}mounting_angle_deg = [50.0, 90.0]\nallow_outside_design_space = true\n"
    ))
    .unwrap();
    assert_eq!(req.bounds()[1], [50.0, 90.0]);
    assert!(req.notes()[0].contains("reaches outside the design space"));
    // nothing left inside it: an error naming the key
    let e = Requirements::parse(&format!("{base}mounting_angle_deg = [40.0, 55.0]\n")).unwrap_err();
    assert!(e.to_string().contains("vary.mounting_angle_deg"), "{e}");
    // the search never leaves the design space
    let req = Requirements::parse(&format!(
        "mu = 0.6\n{base}mounting_angle_deg = [50.0, 90.0]\neps0 = [0.2, 0.3]\n"
    ))
    .unwrap();
    let d = optimize(
        &req,
        &DesignOptions {
            random_starts: 1,
            max_iterations: 6,
            ..DesignOptions::default()
        },
    )
    .unwrap();
    assert!(d.best.design[1] >= lo - 1e-12, "{:?}", d.best.design);
}

#[test]
fn a_design_far_outside_the_model_is_not_called_feasible_on_invalid_grasps() {
    // the issue's case: one cuboid, a light lift, eps0 free in [0.1, 0.5];
    // at eps0 0.5 the grasps fold the finger through itself, far outside
    // the model: every margin that counts a lift must come from a valid
    // grasp, and the claimed grasps must reproduce through the scene path
    let req = Requirements::parse(
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [90.0, 100.0]\nlift_n = 0.3\n[vary]\neps0 = [0.1, 0.5]\n",
    )
    .unwrap();
    let d = optimize(&req, &DesignOptions::default()).unwrap();
    for m in &d.best.margins {
        if m.requirement.ends_with("lift") && m.margin >= 0.0 {
            assert_eq!(m.valid, Some(true), "{m:?}");
        }
    }
    assert!(
        d.reproductions.iter().all(|r| r.reproduced),
        "{:?}",
        d.reproductions
    );
    if d.feasible {
        assert!(d.reproductions.iter().all(|r| r.valid));
        // a lift of about 28 N (margin +93) came from an invalid grasp
        assert!(d.best.worst < 50.0, "{:?}", d.best);
    }
}

#[test]
fn design_work_is_bounded_before_it_starts() {
    let req = Requirements::parse(
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [90.0, 100.0]\nlift_n = 0.3\n[vary]\neps0 = [0.1, 0.5]\nmounting_angle_deg = [60.0, 90.0]\noverlap_mm = [0.0, 20.0]\n",
    )
    .unwrap();
    // refused at once: an unbounded run would not return
    for (opts, field) in [
        (
            DesignOptions {
                random_starts: 100_000_000,
                ..DesignOptions::default()
            },
            "design.random_starts",
        ),
        (
            DesignOptions {
                ascents: usize::MAX,
                ..DesignOptions::default()
            },
            "design.ascents",
        ),
        (
            DesignOptions {
                step: f64::NAN,
                ..DesignOptions::default()
            },
            "design.step",
        ),
    ] {
        let e = optimize(&req, &opts).unwrap_err();
        assert_eq!(e.field(), field, "{e}");
    }
    // 3 variables: 101^3 points pass the bound, usize::MAX overflows
    for per_axis in [101, usize::MAX] {
        let e = grid_search(&req, per_axis).unwrap_err();
        assert_eq!(e.field(), "grid.per_axis", "{e}");
    }
}

/// Requirements with every size, force and friction at a bound of its
/// range, large or small: every margin, every value behind one, and
/// every sensitivity of the design found is finite, and the design found
/// can be built.
#[test]
fn requirements_at_their_bounds_keep_every_margin_finite() {
    use fpc::design::{Evaluation, FORCE_RANGE_N, LENGTH_RANGE_MM, MU_RANGE};
    let [short, long] = LENGTH_RANGE_MM;
    let [light, heavy] = FORCE_RANGE_N;
    let objects = format!(
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [100.0, {long:e}]\nlift_n = {light:e}\nmax_normal_n = {light:e}\n\
         [[object]]\nkind = \"cuboid\"\nsize_mm = [{short:e}, {short:e}]\nlift_n = {heavy:e}\nmax_normal_n = {heavy:e}\n\
         [[object]]\nkind = \"sphere\"\nradius_mm = [{short:e}, {long:e}]\nlift_n = {light:e}\nmax_normal_n = {light:e}\n\
         [open]\nsize_mm = {short:e}\npressure_kpa = 1000.0\n"
    );
    let finite = |e: &Evaluation| {
        assert!(e.worst.is_finite(), "{e:?}");
        for m in &e.margins {
            let numbers = [Some(m.margin), m.at_mm, m.beta_deg, m.value, m.normal_n];
            assert!(numbers.into_iter().flatten().all(f64::is_finite), "{m:?}");
        }
    };
    let settings = DesignOptions {
        random_starts: 0,
        ascents: 1,
        max_iterations: 3,
        ..DesignOptions::default()
    };
    // the default friction, and either end of its range (the angles
    // within each one's design space, [arccot mu, 90] degrees)
    for (mu, angles) in [
        (0.6, [60.0, 90.0]),
        (MU_RANGE[0], [89.95, 90.0]),
        (MU_RANGE[1], [10.0, 90.0]),
    ] {
        let text = format!(
            "elements = 4\nmu = {mu:e}\n{objects}[vary]\neps0 = [0.1, 0.5]\nmounting_angle_deg = {angles:?}\n"
        );
        let req = Requirements::parse(&text).unwrap();
        for x in [0.1, 0.3, 0.5] {
            finite(&evaluate(&req, [x, angles[1], 20.0]));
        }
        let d = optimize(&req, &settings).unwrap();
        finite(&d.best);
        for s in &d.sensitivities {
            assert!(s.gradient.iter().all(|v| v.is_finite()), "mu {mu}: {s:?}");
        }
        // a normal force of a micronewton is missed by a factor of a
        // million and more, yet the design reported can be built: its
        // margins all rank above an unbuildable gripper's
        assert!(
            d.best.margins.iter().all(
                |m| m.requirement != "buildable" && m.margin > fpc::design::UNBUILDABLE_MARGIN
            ),
            "mu {mu}: {:#?}",
            d.best.margins
        );
        if mu != 0.6 {
            continue;
        }
        // a lift of a micronewton, far exceeded by the paper's design,
        // says so by a finite margin
        let paper = evaluate(&req, [0.25, 60.0, 20.0]);
        let lift = paper
            .margins
            .iter()
            .find(|m| m.requirement == "object[0] cuboid d = 100.0 mm: lift")
            .unwrap_or_else(|| panic!("{:#?}", paper.margins));
        assert!(lift.margin > 1e3, "{lift:?}");
    }
}

/// Requirements built in code, not read from a file, are checked by the
/// search before any work, as a file's are on reading.
#[test]
fn requirements_built_in_code_are_checked_before_the_search() {
    let mut req = Requirements::parse(CUBOID).unwrap();
    if let fpc::design::ObjectRequirement::Cuboid { lift_n, .. } = &mut req.objects[0] {
        *lift_n = 1e-320;
    }
    let e = optimize(&req, &DesignOptions::default()).unwrap_err();
    assert_eq!(e.field(), "object[0].lift_n", "{e}");
    let e = grid_search(&req, 3).unwrap_err();
    assert_eq!(e.field(), "object[0].lift_n", "{e}");
    let mut req = Requirements::parse(CUBOID).unwrap();
    req.objects = vec![req.objects[0].clone(); fpc::design::MAX_OBJECTS + 1];
    let e = optimize(&req, &DesignOptions::default()).unwrap_err();
    assert_eq!(e.field(), "object", "{e}");
}

#[test]
fn an_infeasible_request_names_what_fails() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/design/infeasible.toml"
    ))
    .unwrap();
    let req = Requirements::parse(&text).unwrap();
    let d = optimize(
        &req,
        &DesignOptions {
            random_starts: 0,
            max_iterations: 8,
            ..DesignOptions::default()
        },
    )
    .unwrap();
    assert!(!d.feasible);
    let w = d.best.worst_margin().unwrap();
    assert!(w.margin < 0.0);
    assert!(w.requirement.starts_with("object[0] cuboid"), "{w:?}");
    // its scene claims no lift, and says which requirement kept it from one
    let checks = fpc::design::reproduce(&d.best, &req);
    assert_eq!(checks.len(), 1);
    let c = &checks[0];
    assert_eq!(c.claimed_lift_n, None);
    assert!(c.reproduced && !c.valid, "{c:?}");
    assert!(c.requirement.starts_with("object[0] cuboid d = "), "{c:?}");
    assert!(c.requirement.ends_with(": fits"), "{c:?}");
    assert_eq!(
        Some(&c.requirement),
        d.best.hardest(0).map(|m| &m.requirement)
    );
}

#[test]
fn a_claim_bent_backwards_carries_its_note_and_a_strict_design_never_claims_one() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/design/paper_sec5.toml"
    ))
    .unwrap();
    // the design fpc design finds for the paper's objects; its grasps bend
    // the root element backwards a little
    let x = [0.2842, 74.31, 20.0];
    let reversed = |toml: &str| {
        let solved = Scene::from_toml(toml).unwrap().solve().unwrap();
        let SceneSolution::Gripper { grasp: Some(g), .. } = solved else {
            panic!("no grasp")
        };
        (g.grasp.is_reversed(), g.is_valid())
    };
    let loose = Requirements::parse(&text).unwrap();
    assert!(!loose.strict);
    let e = evaluate(&loose, x);
    let checks = fpc::design::reproduce(&e, &loose);
    let mut any = false;
    for c in &checks {
        assert!(c.reproduced, "{c:?}");
        assert!(c.text.contains("strict = false"), "{}", c.text);
        let (rev, _) = reversed(&c.text);
        any |= rev;
        // the note is there exactly when the scene's grasp is bent backwards
        assert_eq!(
            rev,
            c.notes.iter().any(|n| n.contains("bent backwards")),
            "{c:?}"
        );
    }
    assert!(any, "the paper's design should bend an element backwards");

    let strict = Requirements::parse(&format!("strict = true\n{text}")).unwrap();
    assert!(strict.strict);
    let e = evaluate(&strict, x);
    for c in fpc::design::reproduce(&e, &strict) {
        assert!(c.reproduced, "{c:?}");
        assert!(c.text.contains("strict = true"), "{}", c.text);
        // a strict claim is valid only without a reversal
        let (rev, valid) = reversed(&c.text);
        assert!(!(rev && valid), "{c:?}");
        assert!(!c.valid || !rev, "{c:?}");
    }
}

/// Every sample's margin carries its solution's notes, not only the
/// hardest sample's (which its scene reproduces): each cuboid width's and
/// sphere radius's lift margin says "bent backwards" exactly when the same
/// grasp, written as a scene by hand and solved through the scene path,
/// bends an element backwards; and so does its normal-force margin, from
/// the same grasp.
#[test]
fn every_sample_s_margin_carries_its_grasp_s_notes() {
    let text = r#"
[[object]]
kind = "cuboid"
size_mm = [90.0, 110.0]
lift_n = 0.3
max_normal_n = 50.0
[[object]]
kind = "sphere"
radius_mm = [45.0, 55.0]
lift_n = 0.5
max_normal_n = 50.0
[vary]
eps0 = [0.1, 0.5]
mounting_angle_deg = [60.0, 90.0]
overlap_mm = [0.0, 40.0]
"#;
    let req = Requirements::parse(text).unwrap();
    assert!(!req.strict);
    // the paper's design, whose grasps all bend the root element backwards
    // a little (the test above), and the one fpc design finds for
    // paper_sec5.toml's objects, where only some do
    let (mut lifts, mut reversed, mut straight, mut beside_hardest) = (0, 0, 0, 0);
    let mut last = None;
    for x in [[0.2842, 74.31, 20.0], [0.3276, 60.0, 20.0]] {
        let e = evaluate(&req, x);
        let hardest = [0, 1].map(|i| e.hardest_lift(i).unwrap().requirement.clone());
        for m in e.margins.iter().filter(|m| m.requirement.ends_with("lift")) {
            lifts += 1;
            let d = m.at_mm.unwrap();
            let solved = if m.requirement.contains("sphere") {
                // the grasp at its angle with friction at its limit,
                // lifting what it claims
                sphere_by_hand(x, d, m.beta_deg.unwrap(), m.value.unwrap())
            } else {
                by_hand(x, d)
            };
            let SceneSolution::Gripper { grasp: Some(g), .. } = solved else {
                panic!("no grasp at {d} mm")
            };
            let rev = g.grasp.is_reversed();
            let noted = |notes: &[String]| notes.iter().any(|n| n.contains("bent backwards"));
            assert_eq!(rev, noted(&m.notes), "{x:?} {m:?}");
            reversed += usize::from(rev);
            straight += usize::from(!rev);
            beside_hardest += usize::from(rev && !hardest.contains(&m.requirement));
            // the normal-force margin of the same sample, from the same grasp
            let gentle = m.requirement.replace(": lift", ": gentle");
            let gm = e.margins.iter().find(|g| g.requirement == gentle).unwrap();
            assert_eq!(gm.notes, m.notes, "{gm:?}");
        }
        last = Some(e);
    }
    assert!(lifts >= 12, "{lifts} lift margins");
    assert!(
        beside_hardest >= 1 && straight >= 1,
        "{reversed} reversed grasps ({beside_hardest} not the hardest), {straight} not: \
         the test needs both"
    );
    let e = last.unwrap();
    // design.json lists them; a margin without notes has no key
    let json = serde_json::to_value(&e).unwrap();
    let listed = json["margins"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m.get("notes").is_some())
        .count();
    let with = e.margins.iter().filter(|m| !m.notes.is_empty()).count();
    assert_eq!(listed, with);
}

/// A calibrated finger (a stiffer constraining layer, its own kappa and a
/// covariance over eps0, kappa and cl.e), as `fpc calibrate` writes one.
const CALIBRATED: &str = r#"
[actuator.cl]
e = 400.0
[actuator.pemc]
eps0 = 0.3
[load]
kappa = 2.0
[calibration]
parameters = ["actuator.pemc.eps0", "load.kappa", "actuator.cl.e"]
standard_errors = [0.01, 0.2, 20.0]
covariance = [[1e-4, 1e-4, 0.05], [1e-4, 0.04, 0.5], [0.05, 0.5, 400.0]]
"#;

/// The gripper of design `x` with the grasp section `grasp` (its keys,
/// one per line), written by hand as a scene: the check does not go
/// through the design's scene writer.
fn gripper_by_hand(x: [f64; 3], grasp: &str) -> SceneSolution {
    let text = format!(
        "[actuator.cl]\ne = 400.0\n[actuator.pemc]\neps0 = {}\n[partition]\nelements = 8\n\
         [gripper]\nmounting_angle_deg = {}\noverlap_mm = {}\nfingers = 3\nmu = 0.6\n\
         [gripper.grasp]\n{grasp}",
        x[0], x[1], x[2]
    );
    Scene::from_toml(&text).unwrap().solve().unwrap()
}

/// A size grasp of width `d_mm` at beta = 0, as the design's cuboid margins.
fn by_hand(x: [f64; 3], d_mm: f64) -> SceneSolution {
    gripper_by_hand(
        x,
        &format!("kind = \"size\"\nd_mm = {d_mm}\nbeta_deg = 0.0\n"),
    )
}

/// A sphere grasp: radius `r_mm` at grasping angle `beta_deg`, lifting
/// `lift_n` (friction at its limit), as the design's sphere margins.
fn sphere_by_hand(x: [f64; 3], r_mm: f64, beta_deg: f64, lift_n: f64) -> SceneSolution {
    gripper_by_hand(
        x,
        &format!("kind = \"sphere\"\nr_mm = {r_mm}\nbeta_deg = {beta_deg}\nlift_n = {lift_n}\n"),
    )
}

#[test]
fn a_design_from_a_calibrated_scene_uses_its_finger_and_carries_its_error_bars() {
    let base = Scene::from_toml(CALIBRATED).unwrap();
    let text = r#"
[[object]]
kind = "cuboid"
size_mm = [80.0, 100.0]
lift_n = 0.3
[open]
size_mm = 120.0
pressure_kpa = 20.0
[vary]
mounting_angle_deg = [60.0, 90.0]
"#;
    let paper = Requirements::parse(text).unwrap();
    let req = paper.clone().with_base(fpc::design::DesignBase::from_scene(
        &base,
        "the test's scene",
    ));
    // eps0 does not vary: the scene's is the design's
    assert_eq!(req.bounds()[0], [0.3, 0.3]);
    assert_eq!(paper.bounds()[0], [0.25, 0.25]);
    assert!(
        req.notes()[0].contains("the test's scene"),
        "{:?}",
        req.notes()
    );
    let d = optimize(&req, &DesignOptions::default()).unwrap();
    let x = d.best.design;
    assert_eq!(x[0], 0.3);
    // every claimed cuboid lift is the hand-written scene's
    for m in d
        .best
        .margins
        .iter()
        .filter(|m| m.requirement.ends_with("lift"))
    {
        let SceneSolution::Gripper { grasp: Some(g), .. } = by_hand(x, m.at_mm.unwrap()) else {
            panic!("no grasp")
        };
        let claimed = m.value.unwrap();
        assert!(
            (g.grasp.lift - claimed).abs() <= 1e-8 * claimed,
            "{}: {} by hand vs {claimed} claimed",
            m.requirement,
            g.grasp.lift
        );
    }
    // and not the paper's actuator's: the base made a difference
    let on_paper = evaluate(&paper, [0.3, x[1], x[2]]);
    assert!(
        (on_paper.margins[0].value.unwrap() / d.best.margins[0].value.unwrap() - 1.0).abs() > 1e-3
    );
    // the open requirement pressurises with the scene's kappa: the size of
    // a finger scene at 20 kPa with kappa 2 through the design's gripper
    let finger =
        "[actuator.cl]\ne = 400.0\n[actuator.pemc]\neps0 = 0.3\n[partition]\nelements = 8\n\
         [load]\npressure_kpa = 20.0\nkappa = 2.0\n";
    let tip = Scene::from_toml(finger)
        .unwrap()
        .solve()
        .unwrap()
        .solution()
        .tip;
    let size = fpc::design::gripper(&req, x).unwrap().size_of(tip);
    let open = d
        .best
        .margins
        .iter()
        .find(|m| m.requirement == "open")
        .unwrap();
    assert!(
        (open.value.unwrap() - size).abs() <= 1e-6 * size.abs().max(1.0),
        "open: {} claimed vs {size}",
        open.value.unwrap()
    );
    // the reproduced scene keeps the finger and the calibration, without
    // kappa (a gripper scene's grasps use kappa's default): the marginal
    // covariance of the other two keys
    assert!(
        d.reproductions.iter().all(|r| r.reproduced),
        "{:?}",
        d.reproductions
    );
    let scenes = d.scenes(&req);
    let scene = Scene::from_toml(&scenes[0].1).unwrap();
    assert_eq!(scene.actuator, base.actuator.with_eps0(0.3).unwrap());
    let cal = scene.file().calibration.clone().unwrap();
    assert_eq!(cal.parameters, ["actuator.pemc.eps0", "actuator.cl.e"]);
    assert_eq!(cal.covariance.unwrap(), [[1e-4, 0.05], [0.05, 400.0]]);
    assert_eq!(cal.standard_errors.unwrap(), [0.01, 20.0]);
    let solved = scene.solve().unwrap();
    let u = scene.uncertainty(&solved).unwrap().unwrap();
    assert!(u.grasp.unwrap().lift_n > 0.0);
}

#[test]
fn a_least_violating_design_can_be_built() {
    // in strict mode every grasp of the paper's objects bends an element
    // backwards: no design holds them, and the least-violating one the
    // search reports is a gripper that can be built (an unbuildable one
    // ranks below any that holds nothing), whose scenes solve
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/design/paper_sec5.toml"
    ))
    .unwrap();
    let req = Requirements::parse(&format!("strict = true\n{text}")).unwrap();
    let d = optimize(&req, &DesignOptions::default()).unwrap();
    assert!(!d.feasible);
    assert!(
        fpc::design::gripper(&req, d.best.design).is_ok(),
        "{:?}",
        d.best.design
    );
    assert!(
        d.best.margins.iter().all(|m| m.requirement != "buildable"),
        "{:?}",
        d.best.margins
    );
    assert!(d.best.worst > fpc::design::UNBUILDABLE_MARGIN);
    for r in &d.reproductions {
        assert!(r.reproduced, "{r:?}");
        assert!(!r.valid, "{r:?}");
        assert!(
            Scene::from_toml(&r.text).unwrap().solve().is_ok(),
            "{}",
            r.text
        );
    }
}
