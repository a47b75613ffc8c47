//! Refinement: the error expansion of material partitions (second order
//! with a first-order term under a tip load), the extrapolations, nested
//! iteration and the tolerance-driven choice (src/plan/refine.rs), checked
//! against independently computed sequences and N -> infinity references
//! from two partition families.

#[path = "common/plans.rs"]
mod plans;
use fpc::plan::{PartitionKind, Refinement, RefinementRecord};
use fpc::{
    Actuator, Coefficients, Finger, Load, ModelId, Partition, SolveError, SolveOptions, Solved,
};
use plans::{refine, solve_to_tip_tolerance};

/// The refinement record of a refined solve.
fn record(s: &Solved) -> &RefinementRecord {
    s.refinement.as_ref().expect("a refinement")
}

fn tip_load() -> Load {
    Load::unloaded().with_tip_force(0.939782, 0.521707)
}

/// The solves' tolerance is tighter than the default: these tests compare
/// tips to 1e-6 mm, and a residual at the default `rtol` (1e-11) leaves
/// about that much tip error on 27 to 216 elements.
const RTOL: f64 = 1e-13;

/// The references' levels are solved to rounding: a relative residual of
/// 3e-14 still leaves 1e-8 mm at the tip on 432 elements, which the
/// extrapolation of five levels multiplies by up to 7.
const REFERENCE_RTOL: f64 = 1e-16;

fn opts() -> SolveOptions {
    SolveOptions {
        rtol: RTOL,
        ..SolveOptions::default().tip_only()
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn material(levels: usize, extrapolate: bool) -> Refinement {
    Refinement {
        model: ModelId::default(),
        partition: PartitionKind::Material,
        start: 8,
        levels,
        extrapolate,
    }
}

/// Each half of every element starts from its parent's coefficients.
fn halved(k: &Coefficients) -> Coefficients {
    let mut values = Vec::new();
    for e in k.iter() {
        values.extend_from_slice(e);
        values.extend_from_slice(e);
    }
    Coefficients::new(k.per_element(), values).unwrap()
}

/// Tips of `levels` partitions, the first `first` and each halving the one
/// before, every level solved to `rtol` from the previous level's
/// solution (independent of the refinement's loosened intermediate levels).
fn tips_of(
    act: &Actuator,
    load: &Load,
    first: Partition,
    levels: usize,
    rtol: f64,
) -> Vec<[f64; 2]> {
    let o = SolveOptions { rtol, ..opts() };
    let mut p = first;
    let mut prev: Option<Coefficients> = None;
    let mut tips = Vec::with_capacity(levels);
    for _ in 0..levels {
        let f = Finger::with_model(ModelId::default(), act, &p, true);
        let sol = match &prev {
            Some(k) => f
                .solve_from(load, &halved(k), &o)
                .or_else(|_| f.solve(load, &o)),
            None => f.solve(load, &o),
        }
        .expect("the level solves");
        tips.push(sol.tip);
        prev = Some(sol.coefficients);
        p = p.halved();
    }
    tips
}

/// Tips of every level of `plan`, solved to [`RTOL`].
fn cold_tips(plan: &Refinement, load: &Load, levels: usize) -> Vec<[f64; 2]> {
    let act = Actuator::default();
    let first = plan.partition(&act, true, 0).expect("a partition");
    tips_of(&act, load, first, levels, RTOL)
}

/// Repeated Richardson extrapolation of a sequence halving the element
/// length: removes the terms h^p for every p of `orders`, in turn, and
/// returns the finest entry (exact for a polynomial of those orders).
fn richardson_table(tips: &[[f64; 2]], orders: &[i32]) -> [f64; 2] {
    let mut col = tips.to_vec();
    for &p in orders {
        let f = 2f64.powi(p) - 1.0;
        col = col
            .windows(2)
            .map(|w| {
                [
                    w[1][0] + (w[1][0] - w[0][0]) / f,
                    w[1][1] + (w[1][1] - w[0][1]) / f,
                ]
            })
            .collect();
    }
    *col.last().expect("enough levels")
}

/// One family's limit: the terms h to h^4 removed from its five finest
/// levels, and as its uncertainty the change from the terms h to h^3
/// removed from its four finest.
fn family_limit(tips: &[[f64; 2]]) -> ([f64; 2], f64) {
    let n = tips.len();
    let t5 = richardson_table(&tips[n - 5..], &[1, 2, 3, 4]);
    let t4 = richardson_table(&tips[n - 4..], &[1, 2, 3]);
    (t5, dist(t5, t4))
}

/// The N -> infinity tip of a finger and its uncertainty, from two
/// partition families that must agree within their uncertainties: the
/// material partitions from pieces at most lx / 8 (27 -> 864 elements for
/// the default actuator) and from pieces at most lx / 20 (40 -> 640).
fn reference(act: &Actuator, load: &Load) -> ([f64; 2], f64) {
    let lx = act.geometry().lx;
    let family = |pieces: f64, levels: usize| {
        let first = Partition::material(act, true, lx / pieces).unwrap();
        family_limit(&tips_of(act, load, first, levels, REFERENCE_RTOL))
    };
    let (a, ua) = family(8.0, 6);
    let (b, ub) = family(20.0, 5);
    let gap = dist(a, b);
    assert!(
        gap <= ua + ub,
        "the families disagree: {a:?} +- {ua:e} vs {b:?} +- {ub:e}"
    );
    let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    (mid, ua.max(ub).max(gap))
}

/// `T + c1 h + c2 h^2 + ...` (one coefficient per level) fitted exactly
/// through levels halving h, with h = 1 at the finest: the coefficients
/// `[T, c1, c2, ...]` per component, by Gaussian elimination of the
/// Vandermonde system.
fn expansion(tips: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = tips.len();
    let mut coeffs = vec![[0.0; 2]; n];
    for c in 0..2 {
        let mut a: Vec<Vec<f64>> = (0..n)
            .map(|k| {
                let h = 2f64.powi((n - 1 - k) as i32);
                let mut row: Vec<f64> = (0..n).map(|p| h.powi(p as i32)).collect();
                row.push(tips[k][c]);
                row
            })
            .collect();
        for i in 0..n {
            let p = (i..n)
                .max_by(|&x, &y| a[x][i].abs().total_cmp(&a[y][i].abs()))
                .unwrap();
            a.swap(i, p);
            let pivot = a[i].clone();
            for row in a.iter_mut().skip(i + 1) {
                let f = row[i] / pivot[i];
                for (x, p) in row[i..].iter_mut().zip(&pivot[i..]) {
                    *x -= f * p;
                }
            }
        }
        for i in (0..n).rev() {
            let s: f64 = (i + 1..n).map(|j| a[i][j] * coeffs[j][c]).sum();
            coeffs[i][c] = (a[i][n] - s) / a[i][i];
        }
    }
    coeffs
}

/// The first-order term `c1 h` at the finest of five levels, fitted with
/// the terms up to h^4.
fn first_order_term(tips: &[[f64; 2]]) -> [f64; 2] {
    assert_eq!(tips.len(), 5);
    expansion(tips)[1]
}

fn ratios(tips: &[[f64; 2]], c: usize) -> Vec<f64> {
    let d: Vec<f64> = tips.windows(2).map(|w| w[1][c] - w[0][c]).collect();
    d.windows(2).map(|w| w[0] / w[1]).collect()
}

#[test]
fn material_partitions_carry_a_first_order_term_under_a_tip_load_only() {
    // no tip load: second order in both components
    let tips = cold_tips(
        &material(1, false),
        &Load::unloaded().with_pressure_kpa(40.0),
        6,
    );
    for c in 0..2 {
        let r = ratios(&tips, c);
        for x in &r {
            assert!((3.6..=4.4).contains(x), "component {c}: ratios {r:?}");
        }
    }
    assert!(first_order_term(&tips[1..]).iter().all(|t| t.abs() < 1e-7));

    // the standard tip load: X at second order, Z's successive ratios
    // falling from 4 as the first-order term takes over (3.93, 3.69, 3.43,
    // 3.11 from 27 to 864 elements)
    let tips = cold_tips(&material(1, false), &tip_load(), 6);
    let x = ratios(&tips, 0);
    let z = ratios(&tips, 1);
    assert!(x.iter().all(|r| (3.85..=4.15).contains(r)), "X {x:?}");
    assert!(z.windows(2).all(|w| w[1] < w[0]), "Z {z:?}");
    assert!(z[0] > 3.8 && z[3] < 3.2, "Z {z:?}");
    // c1 h at 864 elements: -1.27e-5 mm in Z, nothing in X
    let c1 = first_order_term(&tips[1..]);
    assert!((-1.5e-5..-1.0e-5).contains(&c1[1]), "{c1:?}");
    assert!(c1[0].abs() < 1e-6, "{c1:?}");

    // equal elements: first order once they are shorter than the rib pitch
    // (coarser, and without a tip load, the rib edges falling in or out of
    // elements make the changes irregular)
    let equal = Refinement {
        partition: PartitionKind::Equal,
        start: 64,
        ..material(1, false)
    };
    let e = cold_tips(&equal, &tip_load(), 4);
    let orders: Vec<f64> = e
        .windows(3)
        .map(|w| (dist(w[1], w[0]) / dist(w[2], w[1])).log2())
        .collect();
    for p in &orders {
        assert!((0.8..=1.2).contains(p), "equal orders {orders:?}");
    }
}

#[test]
fn the_reference_families_agree() {
    // the standard case: both families give the same limit to 1e-9 mm
    let (tip, unc) = reference(&Actuator::default(), &tip_load());
    assert!(unc < 5e-8, "uncertainty {unc:e}");
    assert!(
        dist(tip, [83.93746494, -47.61183456]) < 1e-7,
        "reference {tip:?}"
    );
}

#[test]
fn the_extrapolations_remove_their_terms() {
    let load = tip_load();
    let (reference, unc) = reference(&Actuator::default(), &load);
    let act = Actuator::default();
    // two levels: R2 removes the h^2 term
    let out = refine(&act, true, &load, &material(2, true), &opts()).unwrap();
    assert!(out.is_extrapolated());
    let fine = dist(out.solution.tip, reference);
    let r2 = dist(out.tip(), reference);
    assert!(r2 * 10.0 <= fine, "R2 {r2:e} mm vs fine {fine:e} mm");
    let est = out.estimated_tip_error_mm().unwrap();
    assert!(r2 + unc <= est, "{r2:e} > estimate {est:e}");

    // four levels: T3 removes the h term too, which R2 of the same levels
    // keeps
    let tips = cold_tips(&material(1, false), &load, 4);
    let r2_4 = richardson_table(&tips[2..], &[2]);
    let out = refine(&act, true, &load, &material(4, true), &opts()).unwrap();
    let t3 = dist(out.tip(), reference);
    assert!(
        2.0 * t3 <= dist(r2_4, reference),
        "T3 {t3:e} mm vs R2 {:e} mm",
        dist(r2_4, reference)
    );
    let est = out.estimated_tip_error_mm().unwrap();
    assert!(t3 + unc <= est, "{t3:e} > estimate {est:e}");
    // and agrees with the cold sequence's own T3, although the refiner
    // solves its intermediate levels to a looser tolerance
    // (INTERMEDIATE_RTOL)
    let cold = richardson_table(&tips[1..], &[1, 2]);
    let offset = dist(out.tip(), cold);
    assert!(offset <= 1e-5, "{offset:e}");
}

#[test]
fn nested_iteration_reaches_the_cold_equilibrium_in_fewer_iterations() {
    let act = Actuator::default();
    let load = tip_load();
    let plan = material(2, false);
    let coarse = Finger::with_model(
        plan.model,
        &act,
        &plan.partition(&act, true, 0).unwrap(),
        true,
    );
    let fine = Finger::with_model(
        plan.model,
        &act,
        &plan.partition(&act, true, 1).unwrap(),
        true,
    );
    let k = coarse.solve(&load, &opts()).unwrap().coefficients;
    let guess = halved(&k);
    let warm = fine.solve_from(&load, &guess, &opts()).unwrap();
    let cold = fine.solve(&load, &opts()).unwrap();
    // both stop at a relative residual of 1e-13, which leaves ~1e-9 mm
    assert!(
        dist(warm.tip, cold.tip) <= 1e-6,
        "{:e}",
        dist(warm.tip, cold.tip)
    );
    assert!(
        warm.report.iterations < cold.report.iterations,
        "nested {} vs cold {} iterations",
        warm.report.iterations,
        cold.report.iterations
    );
    // the refinement does the same
    let out = refine(&act, true, &load, &plan, &opts()).unwrap();
    assert!(dist(out.solution.tip, cold.tip) <= 1e-6);
    assert_eq!(record(&out).levels[1].iterations, warm.report.iterations);
}

/// The fingers the tolerance-driven choice is checked on: eps0 0.15, 0.25
/// and 0.4 under the standard tip load, a pressure alone, a pressure with a
/// tip load, and two tip loads whose first-order term leads early (Fx
/// alone, and a load pushing the tip down and back): on these the former
/// estimates, `|R2 - R2_prev|` from three levels and `|t_n - t_n-1| / 3`
/// from two, fell below the true error.
fn fingers() -> Vec<(&'static str, Actuator, Load)> {
    let act = |eps0| Actuator::paper(eps0).unwrap();
    vec![
        ("eps0 0.15, tip load", act(0.15), tip_load()),
        ("eps0 0.25, tip load", act(0.25), tip_load()),
        ("eps0 0.4, tip load", act(0.4), tip_load()),
        (
            "eps0 0.4, 386 kPa",
            act(0.4),
            Load::unloaded().with_pressure_kpa(386.0),
        ),
        (
            "eps0 0.25, 100 kPa, tip load",
            act(0.25),
            Load::unloaded()
                .with_pressure_kpa(100.0)
                .with_tip_force(0.5, -0.3),
        ),
        (
            "eps0 0.25, Fx alone",
            act(0.25),
            Load::unloaded().with_tip_force(0.939782, 0.0),
        ),
        (
            "eps0 0.15, tip load down and back",
            act(0.15),
            Load::unloaded().with_tip_force(-0.5, -0.5),
        ),
    ]
}

#[test]
fn the_tolerance_choice_estimates_at_or_above_the_true_error() {
    for (name, act, load) in fingers() {
        let (reference, unc) = reference(&act, &load);
        for tol in [0.5, 0.1, 0.01, 0.001] {
            let r =
                solve_to_tip_tolerance(ModelId::default(), &act, true, &load, tol, None, &opts())
                    .unwrap();
            assert_eq!(
                record(&r).plan.partition,
                PartitionKind::Material,
                "{name}, {tol}"
            );
            assert!(r.is_extrapolated());
            let est = r.estimated_tip_error_mm().unwrap();
            assert!(est <= tol, "{name}, tol {tol}: estimate {est:e}");
            // the worst the error can be, given the reference's uncertainty
            let err = dist(r.tip(), reference) + unc;
            assert!(
                err <= est,
                "{name}, tol {tol}: {err:e} mm from the reference, estimate {est:e} ({} levels)",
                record(&r).levels.len()
            );
            // the finest level is solved with the caller's options
            assert!(r.solution.report.residual_norm <= RTOL);
        }
        // equal elements from a given start: three levels before an
        // estimate, which bounds the error too
        for (start, tol) in [(4, 0.5), (8, 0.1)] {
            let r = solve_to_tip_tolerance(
                ModelId::default(),
                &act,
                true,
                &load,
                tol,
                Some(start),
                &opts(),
            );
            let Ok(r) = r else {
                // the pressurised finger converges too slowly on equal
                // elements to reach 0.1 mm within 1000 of them
                continue;
            };
            assert!(record(&r).levels.len() >= 3);
            let est = r.estimated_tip_error_mm().unwrap();
            let err = dist(r.tip(), reference) + unc;
            assert!(
                err <= est && est <= tol,
                "{name}, equal from {start}, tol {tol}: {err:e} mm, estimate {est:e}"
            );
        }
    }
}

#[test]
fn bad_plans_name_their_field() {
    let act = Actuator::default();
    let field = |plan: Refinement| match refine(&act, true, &tip_load(), &plan, &opts()) {
        Err(SolveError::Input(e)) => e.field().to_string(),
        other => panic!("expected an input error, got {other:?}"),
    };
    let base = material(2, false);
    assert_eq!(field(Refinement { levels: 0, ..base }), "refinement.levels");
    assert_eq!(field(Refinement { start: 0, ..base }), "refinement.start");
    assert_eq!(
        field(Refinement {
            levels: 1,
            extrapolate: true,
            ..base
        }),
        "refinement.extrapolate"
    );
    assert_eq!(
        field(Refinement {
            partition: PartitionKind::Equal,
            extrapolate: true,
            ..base
        }),
        "refinement.extrapolate"
    );
    // 27 * 2^6 > MAX_REFINED_ELEMENTS
    assert_eq!(field(Refinement { levels: 7, ..base }), "refinement.levels");
    assert!(PartitionKind::parse(fpc::Field::key("partition"), "bisected").is_err());
    // equal elements from 300: two levels fit, an estimate needs three
    let r = solve_to_tip_tolerance(
        ModelId::default(),
        &act,
        true,
        &tip_load(),
        1.0,
        Some(300),
        &opts(),
    );
    match r {
        Err(SolveError::Input(e)) => assert_eq!(e.field(), "tip_tol_mm", "{e}"),
        other => panic!("expected an input error, got {other:?}"),
    }
}
