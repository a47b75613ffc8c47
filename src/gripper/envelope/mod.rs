//! The best lifting force of a sphere followed along the radius: the
//! optimum of [`Gripper::max_sphere_lift`] continued from the radii
//! already answered instead of searched afresh (docs/model.md, study 5).
//!
//! The best grasping angle `b*(r)` is either the validity boundary where a
//! contact rule becomes active (the usual case: the lift grows with `b`
//! until the sphere touches the finger a second time, or the finger
//! reaches its tip from inside the sphere), the edge of the angles the
//! flat fingers reach (`r cos b = d_max / 2`, large spheres), the edge of
//! the angles whose grasp the path from rest reaches, or an interior
//! point where `d f_v / d b = 0`. Each moves smoothly with `r`
//! while it holds the optimum, so from the radii
//! already solved `b*` is predicted by interpolating them (a secant, or a
//! parabola through three), then corrected:
//!
//! - on a boundary, by Brent's root search on the contact function `phi`
//!   whose zero the boundary is (the larger of the tip's tangent against
//!   the sphere's normal and the deepest second contact less the
//!   tolerance), bracketed from the prediction by a Newton step with the
//!   slope the last radius's bracket measured, then growing steps;
//! - at the reach, by the edge itself;
//! - inside, by Brent's maximiser on a bracket around the prediction;
//! - at the edge of the angles whose grasp the path from rest reaches
//!   (past it the path folds before the object), by traces around the
//!   angle where closing from rest turns round
//!   ([`Gripper::closing_turn`]), else by bisection of the edge.
//!
//! The regime of the nearest solved radius is tried first, the others when
//! it fails (where the regimes meet), and where all fail (a solve fails, another rule binds, the
//! corrector leaves its bracket) the radius is searched afresh with
//! [`Gripper::max_sphere_lift`].
//!
//! The corrector's grasps are probes: Newton's method from the nearest
//! grasp already solved (at this radius, else the nearest radius's
//! answer) instead of a trace from rest, about a quarter of the cost. The
//! optimum they locate is then traced from rest; it must be the same
//! equilibrium and valid by its own verdict (on a boundary, the trace may
//! land a hair on the invalid side, and is stepped back by a Newton step
//! on its contact function). Where it is not, the radius is corrected
//! again with every grasp traced (`EnvelopeCounts::retraced`); where no
//! regime checks out on probes, it is searched afresh. So every grasp
//! answered is an ordinary sphere grasp traced from rest with its full
//! verdict. [`SphereEnvelope::along`] answers a list of radii with those
//! confirming traces on a second thread while the probes go on (each
//! radius probed from the probed answers before it).

mod corrector;

use std::cell::Cell;

use super::frames::grasping_angle_range;
use super::setup::{Grasp, Gripper};
use super::sphere::SphereLift;
use crate::solve_error::SolveError;
use corrector::{Corrector, Point, Regime, BOUNDARY_BETA_TOL, DEFAULT_STEP, MAX_STEP, MIN_STEP};

/// Traces from rest that confirm a probed optimum (the probe's angle, then
/// steps back from a boundary) before its radius is corrected again with
/// every grasp traced.
const CONFIRM_STEPS: usize = 4;

/// One solved radius.
#[derive(Debug, Clone)]
struct Known {
    radius: f64,
    beta: f64,
    /// The optimum's regime (`None`: searched afresh, not known).
    regime: Option<Regime>,
    /// How far the corrector moved the prediction (rad; `None`: searched).
    correction: Option<f64>,
    /// The optimum's grasp (traced from rest), where the next radius's
    /// probes start (`None`: searched).
    grasp: Option<Grasp>,
}

/// How a radius of a [`SphereEnvelope`] was answered, counted.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct EnvelopeCounts {
    /// Radii answered on a validity boundary by continuation.
    pub boundary: usize,
    /// Radii answered at an interior optimum by continuation.
    pub interior: usize,
    /// Radii answered at the fingers' reach by continuation.
    pub reach: usize,
    /// Radii answered at the edge of the angles reached from rest by
    /// continuation.
    pub edge: usize,
    /// Radii searched afresh ([`Gripper::max_sphere_lift`]): the first, and
    /// those where the continuation failed.
    pub searched: usize,
    /// Grasps the continuation traced from rest (the fresh searches' not
    /// counted).
    pub solves: usize,
    /// Grasps the continuation solved by Newton's method from a neighbour
    /// (probes: the corrector's search steps, each radius's answer traced
    /// from rest again and checked against its probe).
    pub probes: usize,
    /// Radii whose probed answer the trace from rest did not confirm
    /// (another branch, or invalid by the traced verdict), corrected again
    /// with every grasp traced.
    pub retraced: usize,
}

/// The best lifting force of a sphere against its radius, each radius
/// continued from those already answered (module documentation).
#[derive(Debug, Clone)]
pub struct SphereEnvelope<'g> {
    gripper: &'g Gripper,
    pressure_kpa: f64,
    samples: usize,
    known: Vec<Known>,
    counts: EnvelopeCounts,
    /// Where another gripper's optimum lay, the prediction for the first
    /// radius ([`SphereEnvelope::seeded`]).
    seed: Option<EnvelopeSeed>,
    /// Where closing from rest turns round, once a corrector asked (the
    /// same for every radius).
    turn: Cell<Option<Option<f64>>>,
}

/// A followed optimum of one gripper at one radius, to start another
/// gripper's envelope from ([`SphereEnvelope::seeded`]): a design's next
/// trial differs a little from the last, and so does its best angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct EnvelopeSeed {
    radius: f64,
    beta: f64,
    /// The regime it was followed in (for a searched optimum, that of the
    /// nearest radius followed).
    regime: Option<Regime>,
    /// It was continued (from radii or a seed before it), not searched.
    followed: bool,
}

impl EnvelopeSeed {
    /// The optimum was continued (from radii or a seed before it), not
    /// searched afresh.
    #[cfg(test)]
    pub(crate) fn followed(&self) -> bool {
        self.followed
    }
}

impl<'g> SphereEnvelope<'g> {
    /// A follower of `gripper`'s best sphere lift at `pressure_kpa`; a fresh
    /// search scans `samples` angles ([`Gripper::max_sphere_lift`]).
    pub fn new(gripper: &'g Gripper, pressure_kpa: f64, samples: usize) -> Self {
        SphereEnvelope {
            gripper,
            pressure_kpa,
            samples,
            known: Vec::new(),
            counts: EnvelopeCounts::default(),
            seed: None,
            turn: Cell::new(None),
        }
    }

    /// The follower, its first radius predicted from `seed` (another
    /// gripper's optimum at that radius) and corrected as any other radius
    /// is, with the full verdict; searched afresh only where the
    /// correction fails. A seed at another radius is ignored.
    pub(crate) fn seeded(mut self, seed: Option<EnvelopeSeed>) -> Self {
        self.seed = seed;
        self
    }

    /// The optimum answered at radius `r`, as a seed for another gripper
    /// (with its regime where it was followed, not searched).
    pub(crate) fn seed_at(&self, r: f64) -> Option<EnvelopeSeed> {
        self.known
            .iter()
            .find(|k| k.radius == r)
            .map(|k| EnvelopeSeed {
                radius: k.radius,
                beta: k.beta,
                // a searched radius: the regime its neighbours were
                // followed in
                regime: k.regime.or_else(|| {
                    self.known
                        .iter()
                        .filter(|o| o.regime.is_some())
                        .min_by(|a, b| (a.radius - r).abs().total_cmp(&(b.radius - r).abs()))
                        .and_then(|o| o.regime)
                }),
                followed: k.regime.is_some(),
            })
    }

    /// How the radii so far were answered.
    pub fn counts(&self) -> EnvelopeCounts {
        self.counts
    }

    /// The largest lifting force per finger that holds a sphere of radius
    /// `r` validly, as [`Gripper::max_sphere_lift`] (`None`: no valid grasp
    /// found), continued from the radii answered before where it can be.
    pub fn at(&mut self, r: f64) -> Result<Option<SphereLift>, SolveError> {
        match self.locate(r) {
            Located::Done(found) => Ok(Some(found)),
            Located::No => self.search(r),
            Located::Probed(probed) => {
                let (confirmed, traces) = confirm(self.gripper, self.pressure_kpa, &probed);
                match self.settle(*probed, confirmed, traces) {
                    Some(found) => Ok(Some(found)),
                    None => self.search(r),
                }
            }
        }
    }

    /// The optima at `radii`, in order, as [`SphereEnvelope::at`] answers
    /// them one after the other; the traces from rest that confirm the
    /// probed optima run on another thread meanwhile (each radius is
    /// predicted and probed from the probed answers before it, confirmed
    /// or not), and a radius whose confirmation fails is then corrected
    /// again with every grasp traced, or searched afresh, as `at` would.
    pub fn along(&mut self, radii: &[f64]) -> Result<Vec<Option<SphereLift>>, SolveError> {
        let (g, pressure) = (self.gripper, self.pressure_kpa);
        let flag = crate::cancel::current();
        std::thread::scope(|scope| {
            // the worker confirms in the order it is sent
            let (tx, rx) = std::sync::mpsc::channel::<Probed>();
            let worker = scope.spawn(move || {
                crate::cancel::under(flag, || {
                    rx.into_iter()
                        .map(|p| confirm(g, pressure, &p))
                        .collect::<Vec<_>>()
                })
            });
            let mut out: Vec<Option<SphereLift>> = Vec::with_capacity(radii.len());
            let mut pending = Vec::new();
            for (i, &r) in radii.iter().enumerate() {
                match self.locate(r) {
                    Located::Done(found) => out.push(Some(found)),
                    Located::No => out.push(self.search(r)?),
                    Located::Probed(probed) => {
                        // the probed optimum stands in for the next radii
                        self.known.push(probed.stand_in());
                        // (a worker gone leaves its result missing: the
                        // radius is then corrected again below)
                        let _ = tx.send((*probed).clone());
                        pending.push((i, *probed));
                        out.push(None);
                    }
                }
            }
            drop(tx);
            let mut confirmed = worker.join().unwrap_or_default().into_iter();
            for (i, probed) in pending {
                let r = probed.radius;
                self.known.retain(|k| k.radius != r);
                let (result, traces) = confirmed.next().unwrap_or((None, 0));
                out[i] = match self.settle(probed, result, traces) {
                    Some(found) => Some(found),
                    None => self.search(r)?,
                };
            }
            Ok(out)
        })
    }

    /// Radius `r` searched afresh ([`Gripper::max_sphere_lift`]).
    fn search(&mut self, r: f64) -> Result<Option<SphereLift>, SolveError> {
        self.counts.searched += 1;
        let best = self
            .gripper
            .max_sphere_lift(self.pressure_kpa, r, self.samples)?;
        Ok(best.inspect(|lift| {
            self.known.push(Known {
                radius: r,
                beta: lift.beta,
                regime: None,
                correction: None,
                grasp: None,
            });
        }))
    }

    /// The prediction of `b*(r)` from the (up to three) nearest solved
    /// radii (or, before any, from the seed at `r`), the regime of the
    /// nearest, and the first step to take.
    fn predict(&self, r: f64) -> Option<(f64, Option<Regime>, f64)> {
        if self.known.is_empty() {
            let seed = self.seed.filter(|s| s.radius == r)?;
            return Some((seed.beta, seed.regime, DEFAULT_STEP));
        }
        let mut near: Vec<usize> = (0..self.known.len()).collect();
        near.sort_by(|&i, &j| {
            let (di, dj) = (self.known[i].radius - r, self.known[j].radius - r);
            di.abs().total_cmp(&dj.abs())
        });
        let nearest = *near.first()?;
        // distinct radii only (a repeated radius adds nothing)
        let mut nodes: Vec<(f64, f64)> = Vec::with_capacity(3);
        for &i in &near {
            let k = &self.known[i];
            if nodes
                .iter()
                .all(|(x, _)| (x - k.radius).abs() > 1e-9 * r.abs().max(1.0))
            {
                nodes.push((k.radius, k.beta));
            }
            if nodes.len() == 3 {
                break;
            }
        }
        // Lagrange's interpolation through the nodes
        let mut beta = 0.0;
        for (i, &(xi, yi)) in nodes.iter().enumerate() {
            let mut w = 1.0;
            for (j, &(xj, _)) in nodes.iter().enumerate() {
                if i != j {
                    w *= (r - xj) / (xi - xj);
                }
            }
            beta += w * yi;
        }
        let step = self.known[nearest]
            .correction
            .map_or(DEFAULT_STEP, |c| 4.0 * c)
            .clamp(MIN_STEP, MAX_STEP);
        beta.is_finite()
            .then_some((beta, self.known[nearest].regime, step))
    }

    /// Radius `r` continued from the radii answered: answered (by traces),
    /// located by probes (to be confirmed by a trace from rest), or not
    /// followed (to be searched afresh).
    fn locate(&mut self, r: f64) -> Located {
        let Some((beta, regime, step)) = self.predict(r) else {
            return Located::No;
        };
        let [lo, hi] = grasping_angle_range(self.gripper.mu());
        if !(beta > lo && beta < hi) {
            return Located::No;
        }
        // probes from the nearest radius's answer
        let anchor = self.nearest(r).and_then(|k| k.grasp.clone());
        let probing = anchor.is_some();
        let (found, c) = self.correct(r, beta, regime, step, anchor);
        self.counts.solves += c.spent - c.probes;
        self.counts.probes += c.probes;
        match found {
            // no regime checked out even on probes: searched afresh (the
            // traced chain would spend its budget the same way)
            None => Located::No,
            Some((p, found)) if p.traced || !probing => {
                Located::Done(self.accept(r, beta, (p, found)))
            }
            Some((p, found)) => Located::Probed(Box::new(Probed {
                radius: r,
                point: p,
                regime: found,
                predicted: (beta, regime, step),
            })),
        }
    }

    /// A probed optimum after its trace from rest: answered when the trace
    /// `confirmed` it (`traces` spent on that), else corrected again with
    /// every grasp traced (`None`: to be searched afresh).
    fn settle(
        &mut self,
        probed: Probed,
        confirmed: Option<Point>,
        traces: usize,
    ) -> Option<SphereLift> {
        let Probed {
            radius: r,
            regime,
            predicted: (beta, prior, step),
            ..
        } = probed;
        self.counts.solves += traces;
        if let Some(p) = confirmed {
            return Some(self.accept(r, beta, (p, regime)));
        }
        self.counts.retraced += 1;
        let (found, c) = self.correct(r, beta, prior, step, None);
        self.counts.solves += c.spent;
        Some(self.accept(r, beta, found?))
    }

    /// The solved radius nearest `r`.
    fn nearest(&self, r: f64) -> Option<&Known> {
        self.known
            .iter()
            .min_by(|a, b| (a.radius - r).abs().total_cmp(&(b.radius - r).abs()))
    }

    /// The optimum at radius `r` corrected from the prediction `beta`
    /// ([`Corrector::correct`]); with an `anchor`, by probes started from
    /// it.
    fn correct(
        &self,
        r: f64,
        beta: f64,
        regime: Option<Regime>,
        step: f64,
        anchor: Option<Grasp>,
    ) -> (Option<(Point, Regime)>, Corrector<'g>) {
        let mut c = Corrector::new(self.gripper, self.pressure_kpa, r, anchor, self.turn.get());
        let found = c.correct(beta, regime, step, !self.known.is_empty());
        self.turn.set(c.turn);
        (found, c)
    }

    /// Records the optimum `p` found at radius `r` from the prediction
    /// `beta`.
    fn accept(&mut self, r: f64, beta: f64, (p, regime): (Point, Regime)) -> SphereLift {
        match regime {
            Regime::Boundary { .. } => self.counts.boundary += 1,
            Regime::Interior => self.counts.interior += 1,
            Regime::Reach => self.counts.reach += 1,
            Regime::Edge { .. } => self.counts.edge += 1,
        }
        let lift = SphereLift {
            radius: r,
            beta: p.beta,
            lift: p.lift,
            normal: p.grasp.normal,
            reversed: p.grasp.is_reversed(),
            warnings: p.grasp.warnings.clone(),
        };
        self.known.push(Known {
            radius: r,
            beta: p.beta,
            regime: Some(regime),
            correction: Some((p.beta - beta).abs()),
            grasp: Some(p.grasp),
        });
        lift
    }
}

/// The probed optimum traced from rest: the traced grasp, when it is the
/// same equilibrium as the probe and valid by its own verdict (`None`
/// otherwise), and the traces spent. On a boundary the probe and the trace
/// differ in their last digits (the contact function by up to about
/// 1e-9), so a trace on the boundary's invalid side by that much is
/// stepped back into the valid side (a Newton step on the traced contact
/// function with the boundary's slope, a tenth and [`BOUNDARY_BETA_TOL`]
/// past its zero, doubling while the trace is still invalid,
/// [`CONFIRM_STEPS`] traces in all).
fn confirm(g: &Gripper, pressure_kpa: f64, probed: &Probed) -> (Option<Point>, usize) {
    let p = &probed.point;
    let mut beta = p.beta;
    let mut back = BOUNDARY_BETA_TOL;
    for traces in 1..=CONFIRM_STEPS {
        let Ok(sg) = g.sphere_at_limit(pressure_kpa, probed.radius, beta, None, false) else {
            return (None, traces);
        };
        let traced = Point::new(g, sg.grasp, true);
        if !Gripper::same_equilibrium(&traced.grasp, &p.grasp) {
            return (None, traces);
        }
        if traced.valid {
            return (Some(traced), traces);
        }
        let Regime::Boundary { side, slope } = probed.regime else {
            return (None, traces);
        };
        // a Newton step on the traced contact function, past its zero
        back = back.max(1.1 * (traced.phi / slope).abs() + BOUNDARY_BETA_TOL);
        beta -= side * back;
        back *= 2.0;
    }
    (None, CONFIRM_STEPS)
}

/// What continuing one radius gave.
enum Located {
    /// Answered by traces from rest.
    Done(SphereLift),
    /// Located by probes, to be confirmed by a trace from rest.
    Probed(Box<Probed>),
    /// Not followed: to be searched afresh.
    No,
}

/// An optimum located by probes.
#[derive(Clone)]
struct Probed {
    radius: f64,
    point: Point,
    regime: Regime,
    /// The prediction it was corrected from: angle, regime, first step.
    predicted: (f64, Option<Regime>, f64),
}

impl Probed {
    /// The radius as the next ones see it until it is confirmed.
    fn stand_in(&self) -> Known {
        Known {
            radius: self.radius,
            beta: self.point.beta,
            regime: Some(self.regime),
            correction: Some((self.point.beta - self.predicted.0).abs()),
            grasp: Some(self.point.grasp.clone()),
        }
    }
}
