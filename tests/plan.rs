//! The front door (src/plan/): every plan solved through
//! `PlannedFinger::solve` gives what the low-level `Finger::solve` gives on
//! the partition built here, independently of the plan's implementation;
//! the refined plans keep the values the separate entry points gave
//! before the front door replaced them (recorded from that code).

use fpc::plan::{PartitionKind, MAX_AUTO_ELEMENTS, MAX_AUTO_SPLITS};
use fpc::{
    Actuator, Coefficients, Finger, Load, ModelId, Partition, Plan, PlannedFinger, SolveOptions,
    Solved, Warning,
};

fn loads() -> Vec<Load> {
    vec![
        Load::unloaded(),
        Load::unloaded().with_pressure_kpa(50.0),
        Load::unloaded().with_tip_force(0.939782, 0.521707),
        Load::unloaded()
            .with_pressure_kpa(20.0)
            .with_tip_force(0.4, 0.3),
    ]
}

fn planned(act: &Actuator, model: ModelId, plan: Plan) -> PlannedFinger {
    PlannedFinger::builder(act)
        .model(model)
        .plan(plan)
        .build()
        .expect("the plan builds")
}

/// A single-partition solve: its solution is `expected`, on `finger`'s
/// elements, without a refinement.
fn is_single(s: &Solved, expected: &fpc::Solution, finger: &Finger) {
    assert_eq!(&s.solution, expected);
    assert_eq!(s.elements(), finger.len());
    assert_eq!(s.finger.element_lengths(), finger.element_lengths());
    assert!(s.refinement.is_none());
    assert_eq!(s.splits, 0);
    assert_eq!(s.tip(), expected.tip);
    assert_eq!(s.end_angle(), expected.end_angle);
    assert_eq!(s.estimated_tip_error_mm(), None);
    assert!(!s.is_extrapolated());
    assert_eq!(
        s.is_valid(),
        !expected.warnings.iter().any(Warning::is_validity)
    );
}

#[test]
fn equal_and_fixed_plans_are_the_low_level_solve() {
    let act = Actuator::paper(0.25).unwrap();
    let lx = act.geometry().lx;
    let opts = SolveOptions::default();
    let custom = Partition::custom(vec![30.0, 20.0, 15.0, 15.0, 10.0, 10.0, 10.0], lx).unwrap();
    for name in ModelId::names() {
        let model = ModelId::from_name(name).unwrap();
        for load in loads() {
            for (plan, part) in [
                (Plan::Equal(8), Partition::equal(lx, 8).unwrap()),
                (Plan::Equal(3), Partition::equal(lx, 3).unwrap()),
                (Plan::Fixed(custom.clone()), custom.clone()),
            ] {
                let finger = Finger::with_model(model, &act, &part, true);
                let door = planned(&act, model, plan);
                assert_eq!(door.fixed().unwrap().len(), part.len());
                let expected = finger.solve(&load, &opts).unwrap();
                is_single(&door.solve(&load, &opts).unwrap(), &expected, &finger);
                // from a guess: the low-level solve from the same guess
                let guess = Coefficients::zeros(part.len(), finger.unknowns_per_element());
                let expected = finger.solve_from(&load, &guess, &opts).unwrap();
                is_single(
                    &door.solve_from(&load, &guess, &opts).unwrap(),
                    &expected,
                    &finger,
                );
            }
        }
    }
    // the default plan is 8 equal elements, ribs on, the default model
    let door = PlannedFinger::builder(&act).build().unwrap();
    let finger = Finger::paper(0.25, 8).unwrap();
    let load = Load::unloaded().with_tip_force(0.5, 0.2);
    is_single(
        &door.solve(&load, &opts).unwrap(),
        &finger.solve(&load, &opts).unwrap(),
        &finger,
    );
    // without ribs
    let door = PlannedFinger::builder(&act).ribs(false).build().unwrap();
    let finger = Finger::new(&act, &Partition::equal(lx, 8).unwrap(), false);
    is_single(
        &door.solve(&load, &opts).unwrap(),
        &finger.solve(&load, &opts).unwrap(),
        &finger,
    );
}

#[test]
fn one_level_plans_are_the_low_level_solve() {
    let act = Actuator::paper(0.25).unwrap();
    let lx = act.geometry().lx;
    let opts = SolveOptions::default();
    for (partition, part) in [
        (PartitionKind::Equal, Partition::equal(lx, 8).unwrap()),
        (
            PartitionKind::Material,
            Partition::material(&act, true, lx / 8.0).unwrap(),
        ),
    ] {
        let plan = Plan::Levels {
            partition,
            start: 8,
            levels: 1,
            extrapolate: false,
        };
        let door = planned(&act, ModelId::default(), plan);
        let finger = Finger::new(&act, &part, true);
        for load in loads() {
            let s = door.solve(&load, &opts).unwrap();
            let expected = finger.solve(&load, &opts).unwrap();
            assert_eq!(s.solution, expected);
            assert_eq!(s.elements(), part.len());
            let r = s.refinement.as_ref().unwrap();
            assert_eq!(r.levels.len(), 1);
            assert_eq!(r.levels[0].elements, part.len());
            assert_eq!(r.levels[0].tip, expected.tip);
            assert_eq!(r.levels[0].iterations, expected.report.iterations);
            assert_eq!(s.tip(), expected.tip);
            assert_eq!(s.estimated_tip_error_mm(), None);
            assert!(!s.is_extrapolated());
        }
    }
}

/// The automatic partition computed here: material boundaries, pieces at
/// most lx / 8, every element beyond the slope limit split and the finger
/// re-solved from its parent's coefficients.
fn auto_here(act: &Actuator, load: &Load, opts: &SolveOptions) -> (fpc::Solution, usize, usize) {
    let mut part = Partition::material(act, true, act.geometry().lx / 8.0).unwrap();
    let mut finger = Finger::new(act, &part, true);
    let mut sol = finger.solve(load, opts).unwrap();
    let mut splits = 0;
    loop {
        let split: Vec<bool> = (0..part.len())
            .map(|i| {
                sol.warnings
                    .iter()
                    .any(|w| matches!(w, Warning::ElementSlope { element, .. } if *element == i))
            })
            .collect();
        let extra = split.iter().filter(|&&s| s).count();
        if extra == 0 || part.len() + extra > MAX_AUTO_ELEMENTS || splits == MAX_AUTO_SPLITS {
            return (sol, part.len(), splits);
        }
        let per = sol.coefficients.per_element();
        let mut guess = Vec::new();
        for (i, k) in sol.coefficients.iter().enumerate() {
            guess.extend_from_slice(k);
            if split[i] {
                guess.extend_from_slice(k);
            }
        }
        part = part.split(&split);
        finger = Finger::new(act, &part, true);
        let guess = Coefficients::new(per, guess).unwrap();
        sol = finger
            .solve_from(load, &guess, opts)
            .or_else(|_| finger.solve(load, opts))
            .unwrap();
        splits += 1;
    }
}

#[test]
fn the_auto_plan_is_the_automatic_partition_computed_here() {
    let opts = SolveOptions::default();
    let mut split_somewhere = false;
    // the paper's finger, and one 300 mm long whose 37.5 mm pieces turn
    // beyond the slope limit
    let long = "[actuator.geometry]\nlx = 300\n[actuator.channel]\ncx = 295\n[actuator.ribs]\nkind = \"none\"\n[actuator.pemc]\neps0 = 0.4\n";
    let long = fpc::Scene::from_toml(long).unwrap().actuator;
    for act in [Actuator::paper(0.25).unwrap(), long] {
        let eps0 = act.eps0();
        let door = planned(&act, ModelId::default(), Plan::Auto);
        let mut loads = loads();
        loads.push(Load::unloaded().with_pressure_kpa(400.0));
        loads.push(Load::unloaded().with_pressure_kpa(-80.0));
        for load in loads {
            let s = door.solve(&load, &opts).unwrap();
            let (expected, elements, splits) = auto_here(&act, &load, &opts);
            assert_eq!(s.solution, expected, "eps0 {eps0}, {load:?}");
            assert_eq!(s.elements(), elements);
            assert_eq!(s.splits, splits);
            assert!(s.refinement.is_none());
            split_somewhere |= splits > 0;
        }
    }
    assert!(split_somewhere, "no case exercised a split");
}

#[test]
fn guesses_start_only_fixed_partitions_and_levels() {
    let act = Actuator::default();
    let opts = SolveOptions::default();
    let load = Load::unloaded();
    let guess = Coefficients::zeros(8, 4);
    for plan in [
        Plan::Auto,
        Plan::TipTolerance {
            tip_tol_mm: 0.1,
            start: None,
        },
    ] {
        match planned(&act, ModelId::default(), plan).solve_from(&load, &guess, &opts) {
            Err(fpc::SolveError::Input(e)) => assert_eq!(e.field(), "guess"),
            other => panic!("expected an input error, got {other:?}"),
        }
    }
}

/// What the entry points before the front door (`solve_auto`,
/// `solve_to_tip_tolerance`, `refine`) gave on the paper's finger at 20 kPa
/// under a tip force of (0.4, 0.3) N, recorded from that code: the finest
/// solution's tip, the best tip, the best end angle, the estimate, the
/// elements and each level's elements and Newton iterations. Since Newton
/// solves in its straightened unknowns (docs/model.md section 4.6) the
/// numbers agree to the solver's tolerance, not bit for bit: the finest
/// level's tip and the angle to 1e-6, the extrapolated tip and the
/// estimate (both made of differences of levels, which amplify each
/// level's tolerance) to 1e-5 mm, elements exactly, and no level takes
/// more than three iterations beyond the recorded ones.
#[test]
fn refined_plans_give_what_the_former_entry_points_gave() {
    let act = Actuator::paper(0.25).unwrap();
    let load = Load::unloaded()
        .with_pressure_kpa(20.0)
        .with_tip_force(0.4, 0.3);
    let opts = SolveOptions::default();
    let solve = |plan: Plan| {
        planned(&act, ModelId::default(), plan)
            .solve(&load, &opts)
            .unwrap()
    };
    type Record = (
        [f64; 2],
        [f64; 2],
        f64,
        Option<f64>,
        usize,
        Vec<(usize, usize)>,
    );
    let record = |s: &Solved| -> Record {
        let r = s.refinement.as_ref().unwrap();
        (
            s.solution.tip,
            s.tip(),
            s.end_angle(),
            s.estimated_tip_error_mm(),
            s.elements(),
            r.levels
                .iter()
                .map(|l| (l.elements, l.iterations))
                .collect(),
        )
    };

    let same = |got: Record, want: Record| {
        let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
        let ok = (0..2)
            .all(|i| close(got.0[i], want.0[i], 1e-6) && close(got.1[i], want.1[i], 1e-5))
            && close(got.2, want.2, 1e-6)
            && match (got.3, want.3) {
                (Some(a), Some(b)) => close(a, b, 1e-5),
                (a, b) => a == b,
            }
            && got.4 == want.4
            && got.5.len() == want.5.len()
            && got
                .5
                .iter()
                .zip(&want.5)
                .all(|(g, w)| g.0 == w.0 && g.1 <= w.1 + 3);
        assert!(ok, "got {got:?}\nrecorded {want:?}");
    };

    let auto = solve(Plan::Auto);
    for i in 0..2 {
        let want = [59.46226076354199, -65.57264978966606][i];
        assert!(
            (auto.solution.tip[i] - want).abs() <= 1e-6,
            "{:?}",
            auto.solution.tip
        );
    }
    assert!((auto.solution.end_angle - -1.8795195192997696).abs() <= 1e-6);
    assert_eq!((auto.elements(), auto.splits), (27, 0));

    let tol = |start| Plan::TipTolerance {
        tip_tol_mm: 0.05,
        start,
    };
    same(
        record(&solve(tol(None))),
        (
            [59.47203316587682, -65.56323918838721],
            [59.475285959704415, -65.56010425174806],
            -1.878633428751768,
            Some(0.004517576276758651),
            54,
            vec![(27, 15), (54, 3)],
        ),
    );
    same(
        record(&solve(tol(Some(8)))),
        (
            [59.491307002598354, -65.55579025243762],
            [59.491307002598354, -65.55579025243762],
            -1.8782518442538638,
            Some(0.042924450799599),
            128,
            vec![(8, 22), (16, 3), (32, 3), (64, 3), (128, 3)],
        ),
    );

    let levels = |partition, extrapolate| Plan::Levels {
        partition,
        start: 8,
        levels: 3,
        extrapolate,
    };
    same(
        record(&solve(levels(PartitionKind::Material, true))),
        (
            [59.47469144774879, -65.56070347977516],
            [59.47586740258202, -65.55961293381253],
            -1.878634615716295,
            Some(0.001224288242920775),
            108,
            vec![(27, 15), (54, 2), (108, 2)],
        ),
    );
    same(
        record(&solve(levels(PartitionKind::Material, false))),
        (
            [59.47469144774879, -65.56070347977516],
            [59.47469144774879, -65.56070347977516],
            -1.8786892251936398,
            Some(0.0028280838241576114),
            108,
            vec![(27, 15), (54, 2), (108, 2)],
        ),
    );
    same(
        record(&solve(levels(PartitionKind::Equal, false))),
        (
            [59.529402178093875, -65.55103563660496],
            [59.529402178093875, -65.55103563660496],
            -1.877509578200763,
            Some(0.10715786619376647),
            32,
            vec![(8, 22), (16, 3), (32, 3)],
        ),
    );
    // the extrapolated tip is T3 of the levels' tips, computed here:
    // (8 t2 - 6 t1 + t0) / 3
    let s = solve(levels(PartitionKind::Material, true));
    let t = &s.refinement.as_ref().unwrap().levels;
    for i in 0..2 {
        let t3 = (8.0 * t[2].tip[i] - 6.0 * t[1].tip[i] + t[0].tip[i]) / 3.0;
        assert!((s.tip()[i] - t3).abs() < 1e-10, "{:?} vs {t3}", s.tip());
    }
    assert!(s.is_extrapolated());
}
