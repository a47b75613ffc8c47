//! The gradient of a sphere's best grasp over the design variables: at a
//! best angle inside the reachable ones, or at the turn of closing from
//! rest, whose rate in the design is taken once per design ([`Turn`]).

use crate::actuator::Actuator;
use crate::gripper::sphere::{nearest_turn, turn_within};
use crate::gripper::{Gripper, SphereLift};
use crate::sensitivity::{GraspKind, GripperParam};

use super::requirements::Requirements;
use super::variables::{design_gradient, gripper, MarginGradient, DESIGN_PARAMS};

/// Central-difference steps of the design variables (eps0, degrees, mm)
/// for the rate of the turn of closing from rest ([`Turn::rate`]).
const TURN_STEPS: [f64; 3] = [1e-4, 1e-2, 1e-2];

/// d lift / d x and d normal force / d x (design units) of a sphere's best
/// grasp.
#[derive(Debug, Clone, Copy)]
pub(super) struct BestGradient {
    pub(super) lift: MarginGradient,
    pub(super) normal: MarginGradient,
}

impl BestGradient {
    /// The gradients of the best grasp `best` of gripper `g`, built from
    /// `design` with actuator `act`:
    ///
    /// - where the best angle is the turn of closing from rest (the edge of
    ///   the angles the path from rest reaches, [`Gripper::closing_turn`]),
    ///   the grasp's sensitivities at that fixed angle plus its rate in the
    ///   angle times the turn's rate in the design (`turn`, shared by the
    ///   radii of one evaluation);
    /// - elsewhere [`Gripper::max_sphere_lift_sensitivities`] (an interior
    ///   optimum or a contact boundary).
    ///
    /// `None` where neither covers the optimum (the optimiser then falls
    /// back to central differences of whole evaluations).
    pub(super) fn at(
        g: &Gripper,
        act: &Actuator,
        best: &SphereLift,
        turn: &Turn<'_>,
    ) -> Option<BestGradient> {
        // one row per design parameter, in DESIGN_PARAMS order
        let of = |rows: &[(f64, f64)]| {
            let [a, b, c] = [rows.first()?, rows.get(1)?, rows.get(2)?];
            Some(BestGradient {
                lift: design_gradient([a.0, b.0, c.0], 1.0),
                normal: design_gradient([a.1, b.1, c.1], 1.0),
            })
        };
        if turn.within(best.beta).is_none() {
            let s = g
                .max_sphere_lift_sensitivities(act, 0.0, best, &DESIGN_PARAMS)
                .ok()?;
            let rows: Vec<(f64, f64)> = s.rows.iter().map(|w| (w.lift, w.normal)).collect();
            return of(&rows);
        }
        // at fixed angle, with the angle's own row last
        let sg = g
            .sphere_grasp_at_friction_limit(0.0, best.radius, best.beta, None)
            .ok()?;
        let near = |a: f64, b: f64| (a - b).abs() <= 1e-6 * (a.abs().max(b.abs()) + 1e-9);
        if !near(sg.grasp.lift, best.lift) {
            return None;
        }
        let mut params = DESIGN_PARAMS.to_vec();
        params.push(GripperParam::Beta);
        let kind = GraspKind::SphereAtFrictionLimit {
            radius: best.radius,
        };
        let s = g.grasp_sensitivities(act, &sg.grasp, kind, &params).ok()?;
        let rows: Vec<(f64, f64)> = s.rows.iter().map(|w| (w.lift, w.normal)).collect();
        let fixed = of(&rows)?;
        let (lift_b, normal_b) = *rows.get(3)?;
        let db = turn.rate();
        let along = |fixed: MarginGradient, rate: f64| {
            let mut out = [None; 3];
            for i in 0..3 {
                out[i] = match (fixed[i], db[i]) {
                    (Some(f), Some(d)) => Some(f + rate * d).filter(|v| v.is_finite()),
                    _ => None,
                };
            }
            out
        };
        Some(BestGradient {
            lift: along(fixed.lift, lift_b),
            normal: along(fixed.normal, normal_b),
        })
    }
}

/// The turn of closing from rest at zero pressure of the gripper `g` of
/// design `x` ([`Gripper::closing_turn`]), and its rate in the design,
/// each computed once, when first asked.
pub(super) struct Turn<'a> {
    g: &'a Gripper,
    req: &'a Requirements,
    x: [f64; 3],
    zero: std::cell::OnceCell<Option<f64>>,
    rate: std::cell::OnceCell<[Option<f64>; 3]>,
}

impl<'a> Turn<'a> {
    pub(super) fn new(g: &'a Gripper, (req, x): (&'a Requirements, [f64; 3])) -> Turn<'a> {
        Turn {
            g,
            req,
            x,
            zero: std::cell::OnceCell::new(),
            rate: std::cell::OnceCell::new(),
        }
    }

    pub(super) fn zero(&self) -> Option<f64> {
        *self.zero.get_or_init(|| self.g.closing_turn(0.0))
    }

    /// The turn within reach of `beta` ([`turn_within`]), if any.
    pub(super) fn within(&self, beta: f64) -> Option<f64> {
        turn_within(self.zero()?, beta)
    }

    /// d b / d x (rad per design unit) for each varied design variable:
    /// Richardson-extrapolated central differences of the turn of the
    /// grippers built at `x` +- [`TURN_STEPS`] (no grasp is solved, only
    /// their rest states and tangents). `None` for a fixed variable and
    /// where a gripper cannot be built.
    pub(super) fn rate(&self) -> [Option<f64>; 3] {
        *self.rate.get_or_init(|| {
            let (req, x) = (self.req, self.x);
            let bounds = req.bounds();
            let mut out = [None; 3];
            let Some(zero) = self.zero() else {
                return out;
            };
            for (i, &h) in TURN_STEPS.iter().enumerate() {
                if bounds[i][1] <= bounds[i][0] {
                    continue;
                }
                let at = |t: f64| {
                    let mut y = x;
                    y[i] += t;
                    let turn = gripper(req, y).ok()?.closing_turn(0.0)?;
                    Some(nearest_turn(turn, zero))
                };
                let diff = |t: f64| Some((at(t)? - at(-t)?) / (2.0 * t));
                out[i] = (|| {
                    let (d1, d2) = (diff(h)?, diff(0.5 * h)?);
                    Some((4.0 * d2 - d1) / 3.0).filter(|v| v.is_finite())
                })();
            }
            out
        })
    }
}
