//! The N -> infinity references: two families of material partitions, each
//! solved to rounding and extrapolated through its five finest levels, and
//! the observed orders of both partition kinds.

use fpc::plan::{Level, PartitionKind, Refinement};
use fpc::{Actuator, Coefficients, Load, ModelId, PlannedFinger, SolveError, SolveOptions};
use serde::Serialize;

use super::{dist, Plan};

/// Relative residual every reference level is solved to: rounding. A
/// relative residual of 3e-14 still leaves 1e-8 mm at the tip on 432
/// elements, which the five-level extrapolation multiplies by up to 7.
pub const REFERENCE_RTOL: f64 = 1e-16;

/// The first family's material partition: pieces at most lx / this (27
/// elements for the default actuator).
pub const REFERENCE_START: usize = 8;

/// Levels of the first family (27 -> 864 elements).
pub const REFERENCE_LEVELS: usize = 6;

/// The second family's material partition: pieces at most lx / this (40
/// elements for the default actuator: other lengths, other error
/// coefficients).
pub const SECOND_FAMILY_START: usize = 20;

/// Levels of the second family (40 -> 640 elements).
pub const SECOND_FAMILY_LEVELS: usize = 5;

/// Levels an extrapolated limit is built from: the terms h to h^4 removed.
pub const LIMIT_LEVELS: usize = 5;

/// Equal elements of the coarsest level of the equal-partition orders.
pub const EQUAL_ORDER_START: usize = 8;

/// Levels of the equal-partition orders in a full study (N = 8 -> 512).
pub const EQUAL_ORDER_LEVELS: usize = 7;

/// A sequence of fully converged levels and its observed orders.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Convergence {
    /// The partition kind.
    pub partition: PartitionKind,
    /// Elements per level.
    pub elements: Vec<usize>,
    /// Tip per level (mm).
    #[serde(rename = "tips_mm")]
    pub tips: Vec<[f64; 2]>,
    /// `|t_l - t_{l-1}|` for l = 1, 2, ... (mm).
    pub changes_mm: Vec<f64>,
    /// `log2` of the ratios of successive changes (one fewer than the
    /// changes; NaN, written `null`, where a change is 0).
    pub orders: Vec<f64>,
    /// The same for the tip's X alone (NaN where successive changes differ
    /// in sign).
    pub orders_x: Vec<f64>,
    /// The same for the tip's Z alone.
    pub orders_z: Vec<f64>,
}

impl Convergence {
    fn new(partition: PartitionKind, levels: &[Level]) -> Convergence {
        let tips: Vec<[f64; 2]> = levels.iter().map(|l| l.tip).collect();
        let changes_mm: Vec<f64> = tips.windows(2).map(|w| dist(w[1], w[0])).collect();
        let orders = changes_mm.windows(2).map(|w| order(w[0], w[1])).collect();
        let component = |c: usize| -> Vec<f64> {
            let d: Vec<f64> = tips.windows(2).map(|w| w[1][c] - w[0][c]).collect();
            d.windows(2)
                .map(|w| {
                    if w[0] * w[1] > 0.0 {
                        order(w[0].abs(), w[1].abs())
                    } else {
                        f64::NAN
                    }
                })
                .collect()
        };
        Convergence {
            partition,
            elements: levels.iter().map(|l| l.elements).collect(),
            orders_x: component(0),
            orders_z: component(1),
            tips,
            changes_mm,
            orders,
        }
    }
}

/// `log2(coarse / fine)`, NaN when either change is not positive.
pub(super) fn order(coarse: f64, fine: f64) -> f64 {
    if coarse > 0.0 && fine > 0.0 {
        (coarse / fine).log2()
    } else {
        f64::NAN
    }
}

/// One family's extrapolated limit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FamilyLimit {
    /// Pieces at most lx / `start`.
    pub start: usize,
    /// Elements per level.
    pub elements: Vec<usize>,
    /// Tip per level (mm).
    #[serde(rename = "tips_mm")]
    pub tips: Vec<[f64; 2]>,
    /// The limit: the terms h, h^2, h^3 and h^4 removed from the
    /// [`LIMIT_LEVELS`] finest levels (mm).
    #[serde(rename = "limit_mm")]
    pub limit: [f64; 2],
    /// Its uncertainty: the distance from the limit with the terms h to h^3
    /// removed from the four finest levels (mm).
    pub uncertainty_mm: f64,
    /// The fitted terms `c1 h`, `c2 h^2`, `c3 h^3` and `c4 h^4` at the
    /// finest level, per component (mm): the expansion through the
    /// [`LIMIT_LEVELS`] finest levels.
    pub terms_mm: Vec<[f64; 2]>,
}

impl FamilyLimit {
    fn new(start: usize, levels: &[Level]) -> FamilyLimit {
        let tips: Vec<[f64; 2]> = levels.iter().map(|l| l.tip).collect();
        let n = tips.len();
        let limit = richardson_table(&tips[n - LIMIT_LEVELS..], &[1, 2, 3, 4]);
        let fewer = richardson_table(&tips[n - LIMIT_LEVELS + 1..], &[1, 2, 3]);
        FamilyLimit {
            start,
            elements: levels.iter().map(|l| l.elements).collect(),
            terms_mm: terms(&tips[n - LIMIT_LEVELS..], limit),
            uncertainty_mm: dist(limit, fewer),
            limit,
            tips,
        }
    }
}

/// One model's converged reference.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelReference {
    /// The model.
    pub model: ModelId,
    /// The refinement of the first family (every level solved to
    /// [`REFERENCE_RTOL`]).
    pub plan: Refinement,
    /// The reference tip: the midpoint of the two families' limits (mm).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// The larger of the two families' uncertainties and their distance
    /// (mm).
    pub uncertainty_mm: f64,
    /// The distance between the two families' limits (mm).
    pub family_gap_mm: f64,
    /// The families agree: their distance is within the sum of their
    /// uncertainties.
    pub families_agree: bool,
    /// The two families: pieces at most lx / [`REFERENCE_START`] and lx /
    /// [`SECOND_FAMILY_START`].
    pub families: Vec<FamilyLimit>,
    /// The first family's levels and their orders.
    pub material: Convergence,
    /// Equal elements from N = 8 and their orders.
    pub equal: Convergence,
    /// The first family's plan run by [`fpc::PlannedFinger::solve`] with
    /// extrapolation (intermediate levels to `INTERMEDIATE_RTOL`): its tip
    /// (mm).
    pub refiner_tip_mm: [f64; 2],
    /// Its `estimated_tip_error_mm`.
    pub refiner_estimate_mm: Option<f64>,
    /// The distance of its tip from the reference tip (mm).
    pub refiner_offset_mm: f64,
}

/// The distance between two models' references.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelGap {
    /// The model compared with the CCM.
    pub model: ModelId,
    /// The CCM (the default model).
    pub against: ModelId,
    /// Distance between the two references' tips (mm).
    pub gap_mm: f64,
    /// The sum of the two references' uncertainties (mm).
    pub uncertainty_mm: f64,
}

/// Repeated Richardson extrapolation of levels halving the element length:
/// removes the terms h^p for each p of `orders` in turn and returns the
/// finest entry (exact when the levels are a polynomial of those orders
/// plus a constant; `tips` needs more entries than `orders`).
pub(super) fn richardson_table(tips: &[[f64; 2]], orders: &[i32]) -> [f64; 2] {
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
    col.last().copied().unwrap_or([f64::NAN; 2])
}

/// The terms `c_p h^p`, p = 1 .. n - 1, at the finest of `n` levels halving
/// h, of the expansion `limit + sum c_p h^p` through them: the
/// differences of the levels from the limit are a Vandermonde system in
/// the terms (h = 2^k at level n - 1 - k, the finest h being 1).
pub(super) fn terms(tips: &[[f64; 2]], limit: [f64; 2]) -> Vec<[f64; 2]> {
    let n = tips.len();
    let m = n - 1;
    let mut out = vec![[0.0; 2]; m];
    for c in 0..2 {
        // rows: level k (h = 2^(n-1-k)), columns p = 1..=m, right-hand side
        let mut a: Vec<Vec<f64>> = (0..n)
            .map(|k| {
                let h = 2f64.powi((n - 1 - k) as i32);
                let mut row: Vec<f64> = (1..=m).map(|p| h.powi(p as i32)).collect();
                row.push(tips[k][c] - limit[c]);
                row
            })
            .collect();
        // the finest level is the limit plus every term: use the m coarsest
        // rows, which fix the terms, and eliminate
        a.truncate(m);
        for i in 0..m {
            let p = (i..m)
                .max_by(|&x, &y| a[x][i].abs().total_cmp(&a[y][i].abs()))
                .unwrap_or(i);
            a.swap(i, p);
            let pivot = a[i].clone();
            for row in a.iter_mut().skip(i + 1) {
                let f = row[i] / pivot[i];
                for (x, q) in row[i..].iter_mut().zip(&pivot[i..]) {
                    *x -= f * q;
                }
            }
        }
        for i in (0..m).rev() {
            let s: f64 = (i + 1..m).map(|j| a[i][j] * out[j][c]).sum();
            out[i][c] = (a[i][m] - s) / a[i][i];
        }
    }
    out
}

/// Each half of every element starts from its parent's coefficients.
fn halved(k: &Coefficients) -> Result<Coefficients, SolveError> {
    let mut values = Vec::with_capacity(2 * k.as_slice().len());
    for e in k.iter() {
        values.extend_from_slice(e);
        values.extend_from_slice(e);
    }
    Ok(Coefficients::new(k.per_element(), values)?)
}

/// Every level of `plan` solved to `opts` by nested iteration.
fn converged_levels(
    act: &Actuator,
    load: &Load,
    plan: &Refinement,
    opts: &SolveOptions,
) -> Result<Vec<Level>, SolveError> {
    let refiner = PlannedFinger::builder(act).refinement(plan).build()?;
    let mut levels = Vec::with_capacity(plan.levels);
    let mut prev: Option<Coefficients> = None;
    for finger in refiner.fingers() {
        let sol = match &prev {
            Some(k) if 2 * k.elements() == finger.len() => finger
                .solve_from(load, &halved(k)?, opts)
                .or_else(|_| finger.solve(load, opts))?,
            _ => finger.solve(load, opts)?,
        };
        levels.push(Level {
            elements: finger.len(),
            tip: sol.tip,
            end_angle: sol.end_angle,
            iterations: sol.report.iterations,
            steps: sol.report.steps,
        });
        prev = Some(sol.coefficients);
    }
    Ok(levels)
}

/// The reference of `model` and its orders.
pub(super) fn reference(
    act: &Actuator,
    load: &Load,
    model: ModelId,
    equal_levels: usize,
) -> Result<ModelReference, SolveError> {
    let opts = SolveOptions {
        rtol: REFERENCE_RTOL,
        ..SolveOptions::default().tip_only()
    };
    let plan = Plan::material(REFERENCE_LEVELS, true).for_model(model);
    let levels = converged_levels(act, load, &plan, &opts)?;
    let second_plan = Refinement {
        start: SECOND_FAMILY_START,
        levels: SECOND_FAMILY_LEVELS,
        ..plan
    };
    let second = converged_levels(act, load, &second_plan, &opts)?;
    let families = vec![
        FamilyLimit::new(REFERENCE_START, &levels),
        FamilyLimit::new(SECOND_FAMILY_START, &second),
    ];
    let (a, b) = (&families[0], &families[1]);
    let family_gap_mm = dist(a.limit, b.limit);
    let tip = [
        (a.limit[0] + b.limit[0]) / 2.0,
        (a.limit[1] + b.limit[1]) / 2.0,
    ];
    let uncertainty_mm = a.uncertainty_mm.max(b.uncertainty_mm).max(family_gap_mm);
    let families_agree = family_gap_mm <= a.uncertainty_mm + b.uncertainty_mm;
    let material = Convergence::new(PartitionKind::Material, &levels);
    let equal_plan = Refinement {
        start: EQUAL_ORDER_START,
        levels: equal_levels.max(1),
        ..Plan::equal(EQUAL_ORDER_START).for_model(model)
    };
    let equal = Convergence::new(
        PartitionKind::Equal,
        &converged_levels(act, load, &equal_plan, &opts)?,
    );
    let refined = PlannedFinger::builder(act)
        .refinement(&plan)
        .build()?
        .solve(load, &opts)?;
    Ok(ModelReference {
        model,
        plan,
        tip,
        uncertainty_mm,
        family_gap_mm,
        families_agree,
        families,
        material,
        equal,
        refiner_tip_mm: refined.tip(),
        refiner_estimate_mm: refined.estimated_tip_error_mm(),
        refiner_offset_mm: dist(refined.tip(), tip),
    })
}
