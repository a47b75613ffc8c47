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
    let d = optimize(&req, &DesignOptions::default());
    let grid = grid_search(&req, 11);
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
    let d = fpc::design::Designed {
        feasible: e.feasible(),
        best: e,
        sensitivities: Vec::new(),
        evaluations: 1,
        starts: 0,
    };
    let scenes = d.scenes(&req);
    assert_eq!(scenes.len(), 2);
    for (i, (file, toml)) in scenes.iter().enumerate() {
        let claimed = d
            .best
            .margins
            .iter()
            .filter(|m| {
                m.requirement.starts_with(&format!("object[{i}] "))
                    && m.requirement.ends_with("lift")
            })
            .min_by(|a, b| a.margin.total_cmp(&b.margin))
            .and_then(|m| m.value)
            .unwrap();
        let solved = Scene::from_toml(toml).unwrap().solve().unwrap();
        let SceneSolution::Gripper { grasp: Some(g), .. } = solved else {
            panic!("{file}: no grasp")
        };
        assert!(g.is_valid(), "{file}: {:?}", g.invalid);
        assert!(
            (g.grasp.lift - claimed).abs() <= 1e-6 * claimed,
            "{file}: solved {} vs claimed {claimed}",
            g.grasp.lift
        );
    }
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
    );
    assert!(!d.feasible);
    let w = d.best.worst_margin().unwrap();
    assert!(w.margin < 0.0);
    assert!(w.requirement.starts_with("object[0] cuboid"), "{w:?}");
}
