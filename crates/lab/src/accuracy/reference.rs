//! The N -> infinity references: fully converged material levels,
//! Richardson-extrapolated, and the observed orders of both partition kinds.

use fpc::{
    Actuator, Coefficients, Level, Load, ModelId, PartitionKind, Refinement, Refiner, SolveError,
    SolveOptions,
};
use serde::Serialize;

use super::{dist, Plan};

/// Relative residual every reference level is solved to.
pub const REFERENCE_RTOL: f64 = 1e-13;

/// The references' material partition: pieces at most lx / this.
pub const REFERENCE_START: usize = 8;

/// Levels of the references (27 -> 864 elements).
pub const REFERENCE_LEVELS: usize = 6;

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
}

impl Convergence {
    fn new(partition: PartitionKind, levels: &[Level]) -> Convergence {
        let tips: Vec<[f64; 2]> = levels.iter().map(|l| l.tip).collect();
        let changes_mm: Vec<f64> = tips.windows(2).map(|w| dist(w[1], w[0])).collect();
        let orders = changes_mm.windows(2).map(|w| order(w[0], w[1])).collect();
        Convergence {
            partition,
            elements: levels.iter().map(|l| l.elements).collect(),
            tips,
            changes_mm,
            orders,
        }
    }

    /// The order from the three finest levels (NaN with fewer).
    pub fn finest_order(&self) -> f64 {
        self.orders.last().copied().unwrap_or(f64::NAN)
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

/// One model's converged reference.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelReference {
    /// The model.
    pub model: ModelId,
    /// The refinement (every level solved to [`REFERENCE_RTOL`]).
    pub plan: Refinement,
    /// The reference tip: `R(5,6)` (mm).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// `|R(5,6) - R(4,5)|` (mm): the uncertainty reported.
    pub uncertainty_mm: f64,
    /// `|R(4,5) - R(3,4)|` (mm).
    pub previous_change_mm: f64,
    /// The extrapolations `R(l-1,l)` for l = 2..=6 (mm).
    pub extrapolations_mm: Vec<[f64; 2]>,
    /// The material levels and their orders.
    pub material: Convergence,
    /// Equal elements from N = 8 and their orders.
    pub equal: Convergence,
    /// The same plan run by [`Refiner::solve`] (intermediate levels to
    /// `INTERMEDIATE_RTOL`): its tip (mm).
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

pub(super) fn richardson(coarse: [f64; 2], fine: [f64; 2]) -> [f64; 2] {
    [
        fine[0] + (fine[0] - coarse[0]) / 3.0,
        fine[1] + (fine[1] - coarse[1]) / 3.0,
    ]
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
    let mut refiner = Refiner::new(act, true, plan)?;
    let mut levels = Vec::with_capacity(plan.levels);
    let mut prev: Option<Coefficients> = None;
    for level in 0..plan.levels {
        let finger = refiner.finger(level)?;
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
    let material = Convergence::new(PartitionKind::Material, &levels);
    let extrapolations: Vec<[f64; 2]> = material
        .tips
        .windows(2)
        .map(|w| richardson(w[0], w[1]))
        .collect();
    let n = extrapolations.len();
    let tip = extrapolations[n - 1];
    let back = |k: usize| {
        if n > k {
            dist(extrapolations[n - k], extrapolations[n - k - 1])
        } else {
            f64::NAN
        }
    };
    let equal_plan = Refinement {
        start: EQUAL_ORDER_START,
        levels: equal_levels.max(1),
        ..Plan::equal(EQUAL_ORDER_START).for_model(model)
    };
    let equal = Convergence::new(
        PartitionKind::Equal,
        &converged_levels(act, load, &equal_plan, &opts)?,
    );
    let refined = Refiner::new(act, true, &plan)?.solve(load, None, &opts)?;
    Ok(ModelReference {
        model,
        plan,
        tip,
        uncertainty_mm: back(1),
        previous_change_mm: back(2),
        extrapolations_mm: extrapolations,
        material,
        equal,
        refiner_tip_mm: refined.tip,
        refiner_estimate_mm: refined.estimated_tip_error_mm,
        refiner_offset_mm: dist(refined.tip, tip),
    })
}
