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
//!   ([`Gripper::closing_turn_angle`]), else by bisection of the edge.
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

use super::frames::{finger_to_gripper_map, grasping_angle_range};
use super::setup::{Grasp, Gripper, CONTACT_TOL_MM};
use super::sphere::{SphereLift, ENVELOPE_BETA_TOL};
use crate::brent::{brent_max, brent_root};
use crate::solve_error::SolveError;

/// Solves the corrector may spend on one radius before the radius is
/// searched afresh.
const FOLLOW_MAX_EVALUATIONS: usize = 40;

/// Tolerance (rad) on a boundary optimum: the lift changes there at its
/// full slope in the angle, so the boundary is located well within
/// [`ENVELOPE_BETA_TOL`] (a root search converges fast enough for that).
const BOUNDARY_BETA_TOL: f64 = 1e-11;

/// Traces from rest that confirm a probed optimum (the probe's angle, then
/// steps back from a boundary) before its radius is corrected again with
/// every grasp traced.
const CONFIRM_STEPS: usize = 4;

/// The bracket (rad) traced around a predicted turn of the path from rest
/// ([`Gripper::closing_turn_angle`], computed to rounding): the rate that
/// turns changes by about 1e-11 of its scale over it, well above its
/// rounding.
const TURN_BETA_TOL: f64 = 1e-11;

/// How far (rad) from the prediction the turn of closing from rest is
/// still taken for the edge to try first (a trial of a design may move it
/// far from the last trial's; the traces check it).
const TURN_REACH: f64 = 0.5;

/// How close (rad) a searched optimum must lie to the turn of closing from
/// rest to be taken for an edge there first (a search locates an edge to
/// [`ENVELOPE_BETA_TOL`]).
const TURN_NEAR: f64 = 1e-7;

/// Bracket expansions (each step four times the last) before a corrector
/// gives up.
const MAX_EXPANSIONS: usize = 8;

/// The first step (rad) from the prediction when nothing says how good it
/// is, and the bounds of any step.
const DEFAULT_STEP: f64 = 1e-4;
const MIN_STEP: f64 = 1e-8;
const MAX_STEP: f64 = 0.05;

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

/// Where a followed optimum lies.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Regime {
    /// On a validity boundary: the side its invalid grasps lie on (+1
    /// above, -1 below) and the contact function's slope in the angle
    /// there (per rad; a secant over the bracket that located it).
    Boundary { side: f64, slope: f64 },
    /// Inside, where `d f_v / d b = 0`.
    Interior,
    /// At the fingers' reach: the tip at `Xg = r cos b = d_max / 2`, the
    /// contact the flat fingers just reach.
    Reach,
    /// At the edge of the angles whose grasp is reached on the path from
    /// rest, the angles past it (on `side`: +1 above, -1 below) failing:
    /// the path from rest turns back before the object (a fold), as where
    /// the contact force's first push moves the tip away from the object.
    Edge { side: f64 },
}

/// One grasping angle evaluated by a corrector.
#[derive(Debug, Clone)]
struct Point {
    beta: f64,
    lift: f64,
    valid: bool,
    /// The contact function: `<= 0` where the contact rules hold.
    phi: f64,
    grasp: Grasp,
    /// Traced from rest (else a probe, solved from a neighbour).
    traced: bool,
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
            let (tx, rx) = std::sync::mpsc::channel::<(usize, Probed)>();
            let worker = scope.spawn(move || {
                crate::cancel::under(flag, || {
                    rx.into_iter()
                        .map(|(i, p)| (i, confirm(g, pressure, &p)))
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
                        let _ = tx.send((i, (*probed).clone()));
                        pending.push((i, *probed));
                        out.push(None);
                    }
                }
            }
            drop(tx);
            let mut confirmed = worker.join().unwrap_or_default();
            for (i, probed) in pending {
                let r = probed.radius;
                self.known.retain(|k| k.radius != r);
                let (result, traces) = confirmed
                    .iter_mut()
                    .find(|(j, _)| *j == i)
                    .map_or((None, 0), |(_, c)| (c.0.take(), c.1));
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

    /// The optimum at radius `r` corrected from the prediction `beta` in
    /// the nearest radius's regime first; with an `anchor`, by probes
    /// started from it.
    fn correct(
        &self,
        r: f64,
        beta: f64,
        regime: Option<Regime>,
        step: f64,
        anchor: Option<Grasp>,
    ) -> (Option<(Point, Regime)>, Corrector<'g>) {
        let mut c = Corrector {
            gripper: self.gripper,
            pressure_kpa: self.pressure_kpa,
            radius: r,
            points: Vec::new(),
            failed: Vec::new(),
            spent: 0,
            probes: 0,
            anchor,
        };
        // the nearest radius's regime first, the other where it fails
        let interior = |c: &mut Corrector| c.interior(beta, step).map(|p| (p, Regime::Interior));
        let found = match regime {
            Some(Regime::Reach) => c.reach(beta, step),
            Some(Regime::Boundary { side, slope }) => c
                .boundary(beta, step, side, Some(slope))
                .or_else(|| interior(&mut c)),
            Some(Regime::Interior) => interior(&mut c)
                .or_else(|| c.boundary(beta, step, 1.0, None))
                .or_else(|| c.boundary(beta, step, -1.0, None)),
            // an edge followed from a solved radius is often where it
            // was (it need not move with the radius): its first step the
            // tolerance
            Some(Regime::Edge { side }) => {
                let from_radius = !self.known.is_empty();
                c.edge(beta, if from_radius { 0.0 } else { step }, side)
            }
            // a searched optimum: at the turn of closing from rest the
            // edge first, else the usual case first
            None => {
                let turn = self
                    .gripper
                    .closing_turn_angle(self.pressure_kpa, beta)
                    .filter(|t| (t - beta).abs() <= TURN_NEAR);
                let edge_first = turn.and_then(|t| c.edge(beta, 0.0, (t - beta).signum()));
                edge_first
                    .or_else(|| c.boundary(beta, step, 1.0, None))
                    .or_else(|| interior(&mut c))
                    .or_else(|| c.boundary(beta, step, -1.0, None))
                    .or_else(|| c.edge(beta, step, 1.0))
                    .or_else(|| c.edge(beta, step, -1.0))
            }
        }
        .or_else(|| match regime {
            Some(Regime::Reach) => None,
            _ => c.reach(beta, step),
        });
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

impl Point {
    fn new(g: &Gripper, grasp: Grasp, traced: bool) -> Self {
        Point {
            beta: grasp.beta,
            lift: grasp.lift,
            valid: grasp.is_valid(),
            phi: g.contact_function(&grasp).unwrap_or(f64::NAN),
            grasp,
            traced,
        }
    }
}

/// The grasps of one radius a corrector has solved.
struct Corrector<'g> {
    gripper: &'g Gripper,
    pressure_kpa: f64,
    radius: f64,
    points: Vec<Point>,
    /// Angles whose solve failed or that are out of reach (and whether
    /// the solve was a probe).
    failed: Vec<(f64, bool)>,
    /// Solves made.
    spent: usize,
    /// Of those, probes (solved from a neighbour, not traced).
    probes: usize,
    /// Where probes start: with it, every grasp is a probe from the
    /// nearest angle solved (or from it, before any).
    anchor: Option<Grasp>,
}

impl Corrector<'_> {
    /// The grasp at angle `beta` (solved once; `None` when the angle is out
    /// of reach, the solve fails, or the corrector has spent its solves).
    fn eval(&mut self, beta: f64) -> Option<Point> {
        self.solve(beta, false)
    }

    /// The grasp at angle `beta` traced from rest (solved once; `None` as
    /// [`Corrector::eval`]).
    fn trace(&mut self, beta: f64) -> Option<Point> {
        self.solve(beta, true)
    }

    /// The grasp at `beta`, traced from rest when `traced` or when the
    /// corrector has no anchor, else a probe.
    fn solve(&mut self, beta: f64, traced: bool) -> Option<Point> {
        let known = |p: &&Point| p.beta == beta && (p.traced || !traced);
        if let Some(p) = self.points.iter().find(known) {
            return Some(p.clone());
        }
        let probe = !traced && self.anchor.is_some();
        if self.spent >= FOLLOW_MAX_EVALUATIONS || self.failed.contains(&(beta, probe)) {
            return None;
        }
        self.spent += 1;
        let g = self.gripper;
        let r = self.radius;
        let near = self.anchor.as_ref().filter(|_| probe).map(|a| {
            self.points
                .iter()
                .min_by(|p, q| (p.beta - beta).abs().total_cmp(&(q.beta - beta).abs()))
                .map_or(a, |p| &p.grasp)
        });
        self.probes += usize::from(near.is_some());
        let sg = g.check_sphere(r, beta).ok().and_then(|()| match near {
            Some(near) => g.sphere_probe(self.pressure_kpa, r, beta, near).ok(),
            // the verdict and the forces only, as a fresh search
            None => g
                .sphere_at_limit(self.pressure_kpa, r, beta, None, false)
                .ok(),
        });
        let Some(sg) = sg else {
            self.failed.push((beta, probe));
            return None;
        };
        let p = Point::new(g, sg.grasp, near.is_none());
        self.points.push(p.clone());
        Some(p)
    }

    /// Whether the trace from rest reaches a grasp at `beta` (`None`: the
    /// corrector has spent its solves, which `trace` cannot tell from a
    /// failed one).
    fn reaches(&mut self, beta: f64) -> Option<bool> {
        let known = self.points.iter().any(|p| p.beta == beta && p.traced)
            || self.failed.contains(&(beta, false));
        (known || self.spent < FOLLOW_MAX_EVALUATIONS).then(|| self.trace(beta).is_some())
    }

    /// The best valid grasp among those solved.
    fn best(&self) -> Option<&Point> {
        self.points
            .iter()
            .filter(|p| p.valid)
            .max_by(|a, b| a.lift.total_cmp(&b.lift))
    }

    /// The optimum on the boundary whose invalid side lies at `side` (+1:
    /// above), from the prediction `b0`: a bracket of the contact
    /// function's sign change by growing steps, Brent's root search in it,
    /// and a check that the lift falls away from the boundary on the valid
    /// side (else the optimum is not there).
    fn boundary(
        &mut self,
        b0: f64,
        step: f64,
        side: f64,
        slope: Option<f64>,
    ) -> Option<(Point, Regime)> {
        let mut prev = self.eval(b0)?;
        if !prev.phi.is_finite() {
            return None;
        }
        // towards the boundary from the valid side, away from it otherwise;
        // the first step a Newton step on the contact function with the
        // last radius's slope, a little past the zero to bracket it
        let dir = if prev.phi <= 0.0 { side } else { -side };
        let newton = slope
            .map(|k| 1.01 * (prev.phi / k).abs() + 1e-10)
            .filter(|h| h.is_finite() && *h < MAX_STEP);
        let mut h = newton.unwrap_or(step);
        let mut bracket = None;
        for _ in 0..MAX_EXPANSIONS {
            let p = self.eval(prev.beta + dir * h)?;
            if !p.phi.is_finite() {
                return None;
            }
            if (p.phi <= 0.0) != (prev.phi <= 0.0) {
                bracket = Some(if p.phi <= 0.0 { (p, prev) } else { (prev, p) });
                break;
            }
            prev = p;
            h *= 4.0;
        }
        let (inside, outside) = bracket?;
        let slope = (outside.phi - inside.phi) / (outside.beta - inside.beta);
        let Ok(root) = brent_root(
            |b| Ok::<_, std::convert::Infallible>(self.eval(b).map(|p| p.phi)),
            inside.beta,
            inside.phi,
            outside.beta,
            outside.phi,
            BOUNDARY_BETA_TOL,
            FOLLOW_MAX_EVALUATIONS,
        );
        let x = self.eval(root?.x)?;
        // valid by the verdict, and the best of the valid side, with a
        // valid grasp some way off the boundary lifting less
        let below = |p: &Point| p.valid && (x.beta - p.beta) * side > 10.0 * ENVELOPE_BETA_TOL;
        if !self.points.iter().any(below) {
            self.eval(x.beta - side * step.max(1e-6))?;
        }
        let best = self.best()?;
        let falls = self.points.iter().any(|p| below(p) && p.lift < x.lift);
        let regime = Regime::Boundary { side, slope };
        (x.valid && best.beta == x.beta && falls).then_some((x, regime))
    }

    /// The optimum at the fingers' reach (`r cos b = d_max / 2`, the
    /// edge of the angles the flat fingers reach, `|b| >= arccos(d_max / 2
    /// r)`) on the side of the prediction `b0`: valid, the best solved,
    /// and lifting more than a grasp `step` further into the reach.
    fn reach(&mut self, b0: f64, step: f64) -> Option<(Point, Regime)> {
        let reach = 0.5 * self.gripper.d_max();
        if self.radius <= reach || !reach.is_finite() {
            return None;
        }
        let edge = (reach / self.radius).acos().copysign(b0);
        let x = self.eval(edge)?;
        let off = self.eval(edge + step.max(1e-6).copysign(b0))?;
        let best = self.best()?;
        (x.valid && off.valid && off.lift < x.lift && best.beta == x.beta)
            .then_some((x, Regime::Reach))
    }

    /// The optimum at the edge of the angles reached from rest whose
    /// failing side is `side`, from the prediction `b0` (or, within
    /// [`TURN_REACH`] of it, the angle where closing from rest turns round,
    /// [`Gripper::closing_turn_angle`], half of [`TURN_BETA_TOL`] inside):
    /// the trace there and steps from it (the first a quarter of `step`, or
    /// [`TURN_BETA_TOL`] from the turn, then growing) until one side
    /// succeeds and the other fails, the bracket then halved to
    /// [`ENVELOPE_BETA_TOL`] (or [`TURN_BETA_TOL`] from a turn); the answer is its succeeding end, valid, the
    /// best traced, and lifting more than a grasp `step` further from the
    /// edge. Traces only: a probe converges past the edge as well.
    fn edge(&mut self, b0: f64, step: f64, side: f64) -> Option<(Point, Regime)> {
        let mut h = (0.25 * step).max(ENVELOPE_BETA_TOL);
        // where closing from rest turns round, when near: the usual edge
        let [lo, hi] = grasping_angle_range(self.gripper.mu());
        let turn = self
            .gripper
            .closing_turn_angle(self.pressure_kpa, b0)
            .filter(|b| (b - b0).abs() <= TURN_REACH && *b > lo && *b < hi);
        let b0 = match turn {
            Some(b) => {
                h = TURN_BETA_TOL;
                b - 0.5 * side * h
            }
            None => b0,
        };
        // from b0 towards the failing side while it is reached, away from
        // it while not, until the outcome changes
        let first = self.reaches(b0)?;
        let dir = if first { side } else { -side };
        let mut last = b0;
        let (mut ok, mut bad) = loop {
            let b = last + dir * h;
            if self.reaches(b)? != first {
                break if first { (last, b) } else { (b, last) };
            }
            last = b;
            h *= 4.0;
            if h > MAX_STEP {
                return None;
            }
        };
        // a predicted turn is closed in to its own tolerance
        let tol = if turn.is_some() {
            TURN_BETA_TOL
        } else {
            ENVELOPE_BETA_TOL
        };
        while (bad - ok).abs() > tol {
            let mid = 0.5 * (ok + bad);
            if self.reaches(mid)? {
                ok = mid;
            } else {
                bad = mid;
            }
        }
        let x = self.trace(ok)?;
        let off = self.trace(ok - side * step.max(1e-6))?;
        let best = self
            .points
            .iter()
            .filter(|p| p.traced && p.valid)
            .max_by(|a, b| a.lift.total_cmp(&b.lift))?;
        (x.valid && off.valid && off.lift < x.lift && best.beta == x.beta)
            .then_some((x, Regime::Edge { side }))
    }

    /// The interior optimum near the prediction `b0`: a bracket whose ends
    /// lift less than its middle (moved and widened by growing steps),
    /// then Brent's maximiser in it.
    fn interior(&mut self, b0: f64, step: f64) -> Option<Point> {
        let mut mid = self.eval(b0)?;
        let mut h = step;
        let mut bracket = None;
        for _ in 0..MAX_EXPANSIONS {
            if !mid.valid {
                return None;
            }
            let lo = self.eval(mid.beta - h);
            let hi = self.eval(mid.beta + h);
            let lift = |p: &Option<Point>| p.as_ref().filter(|p| p.valid).map(|p| p.lift);
            match (lift(&lo), lift(&hi)) {
                (Some(a), Some(c)) if a < mid.lift && c < mid.lift => {
                    bracket = Some((mid.beta - h, mid.beta + h));
                    break;
                }
                // a boundary next to the middle: not an interior optimum
                (None, _) | (_, None) => return None,
                (Some(a), Some(c)) => mid = if a > c { lo? } else { hi? },
            }
            h *= 4.0;
        }
        let (a, c) = bracket?;
        let Ok(m) = brent_max(
            |b| Ok::<_, std::convert::Infallible>(self.eval(b).filter(|p| p.valid).map(|p| p.lift)),
            a,
            mid.beta,
            c,
            mid.lift,
            ENVELOPE_BETA_TOL,
            FOLLOW_MAX_EVALUATIONS,
        );
        let x = self.eval(m.x)?;
        let inside = x.beta > a && x.beta < c && (x.beta - a).min(c - x.beta) > ENVELOPE_BETA_TOL;
        let best = self.best()?;
        (x.valid && inside && best.beta == x.beta).then_some(x)
    }
}

impl Gripper {
    /// The contact function of a sphere grasp: the larger of the cosine
    /// between the finger's tangent at the tip and the sphere's outward
    /// normal there (positive: the finger reaches its tip from inside the
    /// sphere) and the depth (mm) of the deepest point of the mid-plane in
    /// the sphere apart from the tip's own contact, less
    /// [`CONTACT_TOL_MM`] (positive: a second contact). Non-positive where
    /// both contact rules hold; continuous in the grasping angle while the
    /// same point meets the sphere first. `None` where the sphere or its
    /// contact cannot be computed.
    pub(crate) fn contact_function(&self, grasp: &Grasp) -> Option<f64> {
        let sol = &grasp.solution;
        let a = self.mounting_angle();
        let tangent = (a - sol.end_angle - grasp.beta).cos();
        let (sb, cb) = grasp.beta.sin_cos();
        let tip = self.to_gripper(sol.tip);
        let r = tip[0] / cb;
        if !(r > 0.0 && r.is_finite()) {
            return None;
        }
        let map = finger_to_gripper_map(a, self.palm()).ok()?;
        let curves: Vec<_> = self
            .finger()
            .midplane_curves(&sol.coefficients)
            .ok()?
            .iter()
            .map(|k| k.map(map))
            .collect();
        let last = curves.len().checked_sub(1)?;
        let disc = super::contact::Obstacle::disc([tip[0] - r * cb, tip[1] - r * sb], r).ok()?;
        let deep =
            super::contact::deepest_apart_from(&curves, &disc, last, curves[last].length()).ok()?;
        // nothing apart from the tip: the whole finger falls away from it
        let second = deep.map_or(-r, |d| d.depth - CONTACT_TOL_MM);
        Some(tangent.max(second))
    }
}
