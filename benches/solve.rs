//! Criterion benchmarks of the generated kernels, the assembled chain and
//! the solves built on them.
//!
//! ```sh
//! cargo bench --bench solve                                   # everything
//! cargo bench --bench solve -- solves/                        # one group
//! cargo bench --bench solve -- --warm-up-time 0.5 --measurement-time 2
//! ```
//!
//! Groups:
//!
//! - `kernels`: one element's generated kernels through the `ElementModel`
//!   trait (the element with the channel and ribs, at a strained state):
//!   each integral family alone (`family_hessian`), the end kinematics, and
//!   the element potential that combines them (`hessian`, `gradient`,
//!   `energy`); the element's moments are folded from the library's
//!   blocks (`fpc::actuator::element_blocks`), and
//!   `finger_element_hessian` times the same element through the public
//!   `Finger::element_hessian` (trait object, vectors);
//! - `assembly`: energy, gradient and structured Hessian of a
//!   pressurised, tip-loaded finger for N = 4 ... 64 on the solver's own
//!   Newton problem in scaled unknowns (`Finger::problem`, buffers reused,
//!   what the solver iterates on);
//! - `solves`: whole solves at N = 8 (see the ids), all through a reused
//!   `Solver` workspace; the tip-loaded cold ones start from the unloaded
//!   equilibrium (`Solver::solve_from_rest`), the warm ones from a nearby
//!   load's;
//! - `sweep`: a 50-point force sweep, throughput in solves per second;
//! - `scene_line`: a line of `fpc sweep` through the scene path (21
//!   points of `scenes/tip_load.toml` over `load.fx`, of
//!   `scenes/cuboid_grasp.toml` over `gripper.grasp.d_mm`), each point
//!   warm-started from the one before and reusing its fingers or gripper,
//!   against every point solved afresh;
//! - `lanes`: the N = 8 structured Hessian and the tip-loaded cold and
//!   warm solves with the element pass (potentials, gradients, Hessians)
//!   evaluated at each lane width this processor runs (`Finger::with_lane_width`: `scalar`, `4`,
//!   `4-avx2`, `8-avx512`; the same results bit for bit at every width);
//! - `envelope`: study 5's sphere envelope (the best lifting force per
//!   radius) on 16 radii of the Sec. 5 gripper, followed along the radius
//!   (`SphereEnvelope`) against a fresh search per radius
//!   (`Gripper::max_sphere_lift`); and study 5 whole.
//!
//! Before each solve benchmark its iteration count is printed once, so
//! that time differences can be told apart from work differences.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use fpc::finger::{Solver, Strategy, TargetProblem};
use fpc::lanes::Width;
use fpc::model::ccm::Ccm;
use fpc::model::EnergyScalars;
use fpc::model::{Energy as _, Kinematics as _, ModelCore as _};
use fpc::scene::{Scene, SceneFile, SceneKey, SceneSolution};
use fpc::{Actuator, Coefficients, Finger, Load, Partition, Solution, SolveOptions};
use fpc_newton::{Energy, Gradient, Hessian};

/// The tip load of the paper's loaded validation case (N, finger frame).
const FX: f64 = 0.939782;
const FZ: f64 = 0.521707;

/// A strained state typical of a loaded finger (raw `[a1, a3, b1, c2]`).
const STRAINED: [f64; 4] = [-0.012, 2.0e-6, 0.004, -0.0035];

fn tip_load() -> Load {
    Load::unloaded().with_tip_force(FX, FZ)
}

fn tip_only() -> SolveOptions {
    SolveOptions::default().tip_only()
}

/// Solves once, prints the iteration count under `id`, and returns the solution.
fn probe(id: &str, sol: Result<Solution, fpc::SolveError>) -> Solution {
    let sol = sol.unwrap_or_else(|e| panic!("{id}: solve failed: {e}"));
    eprintln!(
        "  [{id}] iterations {}, evaluations {}, coupled {}, continuation steps {}, residual {:.2e}",
        sol.report.iterations,
        sol.report.evaluations,
        sol.report.coupled,
        sol.report.continuation_steps,
        sol.report.residual_norm
    );
    sol
}

// ---------------------------------------------------------------- kernels

fn kernels(c: &mut Criterion) {
    let act = Actuator::paper(0.25).unwrap();
    let part = Partition::equal(act.geometry().lx, 8).unwrap();
    let finger = Finger::new(&act, &part, true);
    let k = STRAINED;
    let kp = 2.5 * 0.1; // 100 kPa
    let pressure = Load::unloaded().with_pressure_kpa(100.0);
    let all = fpc::actuator::element_blocks(&act, &part, true);
    // the element with the most blocks (channel and ribs)
    let (idx, b) = all
        .iter()
        .enumerate()
        .max_by_key(|(_, b)| b.linear.len() + b.gas.len())
        .unwrap();
    // its blocks folded into the model's moments
    let mut m = Ccm::zero_moments();
    b.linear.iter().for_each(|p| Ccm::add_linear(&mut m, p));
    b.prestressed
        .iter()
        .for_each(|p| Ccm::add_prestressed(&mut m, p));
    b.gas.iter().for_each(|p| Ccm::add_gas(&mut m, p));
    let len = b.length;
    let family = |name: &str| Ccm::FAMILIES.iter().position(|f| *f == name).unwrap();
    let (lin, pre, gas) = (family("linear"), family("prestressed"), family("gas"));
    let with_p = EnergyScalars { kp };
    let without_p = EnergyScalars { kp: 0.0 };

    let mut g = c.benchmark_group("kernels");
    g.bench_function("linear_hessian", |bch| {
        bch.iter(|| Ccm::family_hessian(black_box(&m), lin, black_box(&k)))
    });
    g.bench_function("prestressed_hessian", |bch| {
        bch.iter(|| Ccm::family_hessian(black_box(&m), pre, black_box(&k)))
    });
    g.bench_function("gas_hessian", |bch| {
        bch.iter(|| Ccm::family_hessian(black_box(&m), gas, black_box(&k)))
    });
    g.bench_function("end_hessian", |bch| {
        bch.iter(|| Ccm::end_hessian(black_box(&k), black_box(len)))
    });
    g.bench_function("element_hessian/pressure", |bch| {
        bch.iter(|| Ccm::hessian(black_box(&m), black_box(&k), black_box(&with_p)))
    });
    g.bench_function("element_hessian/no_pressure", |bch| {
        bch.iter(|| Ccm::hessian(black_box(&m), black_box(&k), black_box(&without_p)))
    });
    g.bench_function("element_gradient/pressure", |bch| {
        bch.iter(|| Ccm::gradient(black_box(&m), black_box(&k), black_box(&with_p)))
    });
    g.bench_function("element_energy/pressure", |bch| {
        bch.iter(|| Ccm::energy(black_box(&m), black_box(&k), black_box(&with_p)))
    });
    g.bench_function("finger_element_hessian/pressure", |bch| {
        bch.iter(|| {
            black_box(&finger).element_hessian(
                black_box(idx),
                None,
                black_box(&pressure),
                black_box(&k),
            )
        })
    });
    g.finish();
}

// ---------------------------------------------------------------- assembly

fn assembly(c: &mut Criterion) {
    let mut g = c.benchmark_group("assembly");
    let load = Load::unloaded()
        .with_pressure_kpa(100.0)
        .with_tip_force(FX, FZ);
    for n in [4usize, 8, 16, 32, 64] {
        let finger = Finger::paper(0.25, n).unwrap();
        // a strained, non-uniform state
        let values = (0..n)
            .flat_map(|i| {
                let t = 1.0 + 0.1 * (i as f64 / n as f64);
                STRAINED.map(|v| v * t)
            })
            .collect();
        let k = Coefficients::new(4, values).unwrap();
        let y: Vec<f64> = k
            .as_slice()
            .iter()
            .zip(finger.unknown_scales())
            .map(|(k, s)| k / s)
            .collect();
        let mut p = finger.problem(&load);
        let dim = y.len();
        let mut gr = vec![0.0; dim];
        g.bench_function(BenchmarkId::new("energy", n), |bch| {
            bch.iter(|| p.energy(black_box(&y)))
        });
        g.bench_function(BenchmarkId::new("gradient", n), |bch| {
            bch.iter(|| p.gradient(black_box(&y), &mut gr))
        });
        g.bench_function(BenchmarkId::new("hessian", n), |bch| {
            bch.iter(|| p.hessian(black_box(&y), &mut gr))
        });
    }
    g.finish();
}

// ---------------------------------------------------------------- solves

fn lanes(c: &mut Criterion) {
    let base = Finger::paper(0.25, 8).unwrap();
    let opts = tip_only();
    let tl = Load::unloaded().with_tip_force(FX, FZ);
    let unloaded = base.solve(&Load::unloaded(), &opts).unwrap();
    let near = base
        .solve_from(
            &Load::unloaded().with_tip_force(0.9, 0.5),
            &unloaded.coefficients,
            &opts,
        )
        .unwrap();
    let mut g = c.benchmark_group("lanes");
    for width in Width::ALL.into_iter().filter(|w| w.is_supported()) {
        let finger = base.with_lane_width(width);
        let name = width.name();
        let mut problem = finger.problem(&tl);
        let y: Vec<f64> = near
            .coefficients
            .as_slice()
            .iter()
            .zip(finger.unknown_scales())
            .map(|(k, s)| k / s)
            .collect();
        let mut grad = vec![0.0; y.len()];
        g.bench_function(format!("hessian/{name}"), |bch| {
            bch.iter(|| problem.hessian(black_box(&y), &mut grad))
        });
        let mut solver = Solver::new(&finger);
        probe(
            &format!("lanes/tip_cold/{name}"),
            solver.solve_from_rest(&tl, &unloaded.coefficients, &opts),
        );
        g.bench_function(format!("tip_cold/{name}"), |bch| {
            bch.iter(|| {
                solver
                    .solve_from_rest(black_box(&tl), &unloaded.coefficients, &opts)
                    .unwrap()
            })
        });
        g.bench_function(format!("tip_warm/{name}"), |bch| {
            bch.iter(|| {
                solver
                    .solve(black_box(&tl), Some(&near.coefficients), &opts)
                    .unwrap()
            })
        });
    }
    g.finish();
}

fn solves(c: &mut Criterion) {
    let finger = Finger::paper(0.25, 8).unwrap();
    let n = finger.len();
    let zeros = Coefficients::zeros(n, finger.unknowns_per_element());
    let opts = tip_only();
    let coupled = SolveOptions {
        strategy: Strategy::Coupled,
        ..opts
    };
    let mut solver = Solver::new(&finger);
    let unloaded = solver.solve(&Load::unloaded(), None, &opts).unwrap();

    let mut g = c.benchmark_group("solves");

    // unloaded: decoupled 4x4 solves (equal elements once) vs the coupled 4N system
    let un = Load::unloaded();
    probe("unloaded/decoupled", solver.solve(&un, None, &opts));
    g.bench_function("unloaded/decoupled", |bch| {
        bch.iter(|| solver.solve(black_box(&un), None, &opts).unwrap())
    });
    probe(
        "unloaded/coupled",
        solver.solve(&un, Some(&zeros), &coupled),
    );
    g.bench_function("unloaded/coupled", |bch| {
        bch.iter(|| {
            solver
                .solve(black_box(&un), Some(&zeros), &coupled)
                .unwrap()
        })
    });

    // the same at N = 32, where the coupled factorisation costs more
    {
        let f32e = Finger::paper(0.25, 32).unwrap();
        let z32 = f32e.straight();
        let mut s32 = Solver::new(&f32e);
        probe("unloaded_n32/decoupled", s32.solve(&un, None, &opts));
        g.bench_function("unloaded_n32/decoupled", |bch| {
            bch.iter(|| s32.solve(black_box(&un), None, &opts).unwrap())
        });
        probe("unloaded_n32/coupled", s32.solve(&un, Some(&z32), &coupled));
        g.bench_function("unloaded_n32/coupled", |bch| {
            bch.iter(|| s32.solve(black_box(&un), Some(&z32), &coupled).unwrap())
        });
    }

    // pressure only, eps0 = 0.4 at 386 kPa
    let f04 = Finger::paper(0.4, 8).unwrap();
    let mut s04 = Solver::new(&f04);
    let pl = Load::unloaded().with_pressure_kpa(386.0);
    probe("pressure/decoupled", s04.solve(&pl, None, &opts));
    g.bench_function("pressure/decoupled", |bch| {
        bch.iter(|| s04.solve(black_box(&pl), None, &opts).unwrap())
    });
    probe("pressure/coupled", s04.solve(&pl, Some(&zeros), &coupled));
    g.bench_function("pressure/coupled", |bch| {
        bch.iter(|| s04.solve(black_box(&pl), Some(&zeros), &coupled).unwrap())
    });

    // tip load: cold start from the unloaded shape, warm start from a nearby load
    let tl = tip_load();
    probe(
        "tip/cold",
        solver.solve_from_rest(&tl, &unloaded.coefficients, &opts),
    );
    g.bench_function("tip/cold", |bch| {
        bch.iter(|| {
            solver
                .solve_from_rest(black_box(&tl), &unloaded.coefficients, &opts)
                .unwrap()
        })
    });
    let near = solver
        .solve(
            &Load::unloaded().with_tip_force(0.9, 0.5),
            Some(&unloaded.coefficients),
            &opts,
        )
        .unwrap();
    probe(
        "tip/warm",
        solver.solve(&tl, Some(&near.coefficients), &opts),
    );
    g.bench_function("tip/warm", |bch| {
        bch.iter(|| {
            solver
                .solve(black_box(&tl), Some(&near.coefficients), &opts)
                .unwrap()
        })
    });

    // bordered target solve: the +X force that moves the eps0 = 0.4 tip 10 mm along X
    let un04 = s04.solve(&un, None, &opts).unwrap();
    let target = TargetProblem {
        base: Load::unloaded(),
        direction: [1.0, 0.0],
        weights: [1.0, 0.0],
        target: un04.tip[0] + 10.0,
    };
    let (sol, lambda) = s04
        .solve_target(&target, &un04.coefficients, 0.0, 1e-9, &opts)
        .unwrap();
    eprintln!(
        "  [target/bordered] lambda = {lambda:.6} N, tip X {:.4} -> {:.4} mm, iterations {}",
        un04.tip[0], sol.tip[0], sol.report.iterations
    );
    g.bench_function("target/bordered", |bch| {
        bch.iter(|| {
            s04.solve_target(black_box(&target), &un04.coefficients, 0.0, 1e-9, &opts)
                .unwrap()
        })
    });
    // for comparison: the plain solve at the load the target solve found
    let at = target.load_at(lambda);
    probe(
        "target/plain_at_found_load",
        s04.solve(&at, Some(&un04.coefficients), &opts),
    );
    g.bench_function("target/plain_at_found_load", |bch| {
        bch.iter(|| {
            s04.solve(black_box(&at), Some(&un04.coefficients), &opts)
                .unwrap()
        })
    });

    // ribs vs no ribs: building the finger (moments) and the unloaded
    // decoupled solve (ribs make elements distinct), and the tip-loaded solve
    let act = Actuator::paper(0.25).unwrap();
    let part = Partition::equal(act.geometry().lx, 8).unwrap();
    for (name, ribs) in [("ribs", true), ("no_ribs", false)] {
        g.bench_function(format!("{name}/build"), |bch| {
            bch.iter(|| Finger::new(black_box(&act), black_box(&part), ribs))
        });
        let f = Finger::new(&act, &part, ribs);
        let mut s = Solver::new(&f);
        let u = probe(&format!("{name}/unloaded"), s.solve(&un, None, &opts));
        g.bench_function(format!("{name}/unloaded"), |bch| {
            bch.iter(|| s.solve(black_box(&un), None, &opts).unwrap())
        });
        probe(
            &format!("{name}/tip_cold"),
            s.solve_from_rest(&tl, &u.coefficients, &opts),
        );
        g.bench_function(format!("{name}/tip_cold"), |bch| {
            bch.iter(|| {
                s.solve_from_rest(black_box(&tl), &u.coefficients, &opts)
                    .unwrap()
            })
        });
    }

    // zero vs tiny pressure (the gas kernel is skipped at exactly zero)
    for (name, kpa) in [("pressure_zero", 0.0), ("pressure_tiny", 1e-6)] {
        let l = tl.with_pressure_kpa(kpa);
        probe(
            &format!("{name}/tip_cold"),
            solver.solve_from_rest(&l, &unloaded.coefficients, &opts),
        );
        g.bench_function(format!("{name}/tip_cold"), |bch| {
            bch.iter(|| {
                solver
                    .solve_from_rest(black_box(&l), &unloaded.coefficients, &opts)
                    .unwrap()
            })
        });
    }
    for (name, kpa) in [("pressure_zero", 0.0), ("pressure_tiny", 1e-6)] {
        let l = un.with_pressure_kpa(kpa);
        probe(&format!("{name}/unloaded"), solver.solve(&l, None, &opts));
        g.bench_function(format!("{name}/unloaded"), |bch| {
            bch.iter(|| solver.solve(black_box(&l), None, &opts).unwrap())
        });
    }

    // tip-only vs full output (shape samples + circle fit + smallest eigenvalue)
    let full = SolveOptions::default();
    let shape_only = SolveOptions {
        shape: true,
        ..opts
    };
    let stability_only = SolveOptions {
        stability: true,
        ..opts
    };
    for (name, o) in [
        ("output_tip_only", opts),
        ("output_full", full),
        ("output_shape_only", shape_only),
        ("output_stability_only", stability_only),
    ] {
        g.bench_function(format!("{name}/tip_cold"), |bch| {
            bch.iter(|| {
                solver
                    .solve_from_rest(black_box(&tl), &unloaded.coefficients, &o)
                    .unwrap()
            })
        });
        g.bench_function(format!("{name}/unloaded"), |bch| {
            bch.iter(|| solver.solve(black_box(&un), None, &o).unwrap())
        });
    }
    g.finish();
}

// ---------------------------------------------------------------- sweep

const SWEEP_POINTS: usize = 50;

fn sweep(c: &mut Criterion) {
    let finger = Finger::paper(0.25, 8).unwrap();
    let opts = tip_only();
    let mut solver = Solver::new(&finger);
    let unloaded = solver.solve(&Load::unloaded(), None, &opts).unwrap();
    let loads: Vec<Load> = (1..=SWEEP_POINTS)
        .map(|i| {
            let t = i as f64 / SWEEP_POINTS as f64;
            tip_load().with_tip_force(t * FX, t * FZ)
        })
        .collect();
    {
        // work per sweep, for the record
        let mut guess = unloaded.coefficients.clone();
        let mut it = 0;
        for l in &loads {
            let s = solver.solve(l, Some(&guess), &opts).unwrap();
            it += s.report.iterations;
            guess = s.coefficients;
        }
        eprintln!("  [sweep/warm] {it} Newton iterations over {SWEEP_POINTS} points");
        let it: usize = loads
            .iter()
            .map(|l| {
                solver
                    .solve_from_rest(l, &unloaded.coefficients, &opts)
                    .unwrap()
                    .report
                    .iterations
            })
            .sum();
        eprintln!("  [sweep/cold] {it} Newton iterations over {SWEEP_POINTS} points");
    }

    let mut g = c.benchmark_group("sweep");
    g.throughput(Throughput::Elements(SWEEP_POINTS as u64));
    // each point warm-started from the previous one
    g.bench_function("force_50/warm", |bch| {
        bch.iter(|| {
            let mut guess = unloaded.coefficients.clone();
            for l in &loads {
                let s = solver.solve(black_box(l), Some(&guess), &opts).unwrap();
                guess = s.coefficients;
            }
            guess
        })
    });
    // each point from the unloaded shape
    g.bench_function("force_50/cold", |bch| {
        bch.iter(|| {
            for l in &loads {
                black_box(
                    solver
                        .solve_from_rest(black_box(l), &unloaded.coefficients, &opts)
                        .unwrap(),
                );
            }
        })
    });
    g.finish();

    // a sweep's line through the scene path (what `fpc sweep` runs per
    // line): each point warm-started from the one before, reusing what it
    // built, against each point solved afresh
    let line = |file: &str, key: &str, from: f64, to: f64| -> Vec<Scene> {
        let base: toml::Table = toml::from_str(file).unwrap();
        let key: SceneKey = key.parse().unwrap();
        (0..SCENE_LINE_POINTS)
            .map(|i| {
                let v = from + (to - from) * i as f64 / (SCENE_LINE_POINTS - 1) as f64;
                let mut doc = base.clone();
                SceneFile::set_number(&mut doc, key, v).unwrap();
                SceneFile::from_table(&doc).unwrap().resolve().unwrap()
            })
            .collect()
    };
    let lines = [
        (
            "tip_load",
            line(
                include_str!("../scenes/tip_load.toml"),
                "load.fx",
                -1.0,
                1.0,
            ),
        ),
        (
            "cuboid_grasp",
            line(
                include_str!("../scenes/cuboid_grasp.toml"),
                "gripper.grasp.d_mm",
                60.0,
                110.0,
            ),
        ),
    ];
    let mut g = c.benchmark_group("scene_line");
    g.sample_size(10);
    g.throughput(Throughput::Elements(SCENE_LINE_POINTS as u64));
    for (name, scenes) in &lines {
        g.bench_function(format!("{name}/warm"), |bch| {
            bch.iter(|| {
                let mut warm: Option<SceneSolution> = None;
                for s in scenes {
                    warm = s.solve_warm(warm.as_ref()).ok();
                }
                warm
            })
        });
        g.bench_function(format!("{name}/fresh"), |bch| {
            bch.iter(|| {
                for s in scenes {
                    black_box(s.solve().unwrap());
                }
            })
        });
    }
    g.finish();
}

/// Points of a `scene_line` benchmark.
const SCENE_LINE_POINTS: usize = 21;

fn envelope(c: &mut Criterion) {
    use fpc::gripper::SphereEnvelope;
    use fpc::studies::{section5_gripper, study5_sphere_region};
    use fpc::StudyOptions;
    let act = Actuator::paper(0.25).unwrap();
    let opts = StudyOptions::default();
    let gripper = section5_gripper(&act, &opts).unwrap();
    let radii: Vec<f64> = (0..16).map(|i| 20.0 + 3.0 * i as f64).collect();
    let mut g = c.benchmark_group("envelope");
    g.sample_size(10);
    g.bench_function("followed_16", |bch| {
        bch.iter(|| {
            let mut env = SphereEnvelope::new(&gripper, 0.0, opts.angle_samples);
            for &r in &radii {
                black_box(env.at(black_box(r)).unwrap());
            }
        })
    });
    g.bench_function("searched_16", |bch| {
        bch.iter(|| {
            for &r in &radii {
                black_box(
                    gripper
                        .max_sphere_lift(0.0, black_box(r), opts.angle_samples)
                        .unwrap(),
                );
            }
        })
    });
    g.bench_function("study5", |bch| {
        bch.iter(|| black_box(study5_sphere_region(&act, &opts).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, kernels, assembly, solves, lanes, sweep, envelope);
criterion_main!(benches);
