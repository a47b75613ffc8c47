//! The corrector of one radius of a [`SphereEnvelope`](super::SphereEnvelope):
//! the grasps it solves (probes from a neighbour, or traces from rest) and
//! the optimum it locates from a prediction, in each regime the optimum
//! can lie in (module `envelope`).

use super::super::frames::grasping_angle_range;
use super::super::setup::{Grasp, Gripper};
use super::super::sphere::{nearest_turn, turn_within, ENVELOPE_BETA_TOL};
use crate::brent::{brent_max, brent_root};

/// Solves the corrector may spend on one radius before the radius is
/// searched afresh.
const FOLLOW_MAX_EVALUATIONS: usize = 40;

/// Tolerance (rad) on a boundary optimum: the lift changes there at its
/// full slope in the angle, so the boundary is located well within
/// [`ENVELOPE_BETA_TOL`] (a root search converges fast enough for that).
pub(super) const BOUNDARY_BETA_TOL: f64 = 1e-11;

/// The bracket (rad) traced around a predicted turn of the path from rest
/// ([`Gripper::closing_turn`], computed to rounding): the rate that
/// turns changes by about 1e-11 of its scale over it, well above its
/// rounding.
const TURN_BETA_TOL: f64 = 1e-11;

/// How far (rad) from the prediction the turn of closing from rest is
/// still taken for the edge to try first (a trial of a design may move it
/// far from the last trial's; the traces check it).
const TURN_REACH: f64 = 0.5;

/// Bracket expansions (each step four times the last) before a corrector
/// gives up.
const MAX_EXPANSIONS: usize = 8;

/// The first step (rad) from the prediction when nothing says how good it
/// is, and the bounds of any step.
pub(super) const DEFAULT_STEP: f64 = 1e-4;
pub(super) const MIN_STEP: f64 = 1e-8;
pub(super) const MAX_STEP: f64 = 0.05;

/// Where a followed optimum lies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Regime {
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
pub(super) struct Point {
    pub(super) beta: f64,
    pub(super) lift: f64,
    pub(super) valid: bool,
    /// The contact function: `<= 0` where the contact rules hold.
    pub(super) phi: f64,
    pub(super) grasp: Grasp,
    /// Traced from rest (else a probe, solved from a neighbour).
    pub(super) traced: bool,
}

impl Point {
    pub(super) fn new(g: &Gripper, grasp: Grasp, traced: bool) -> Self {
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
pub(super) struct Corrector<'g> {
    gripper: &'g Gripper,
    pressure_kpa: f64,
    radius: f64,
    points: Vec<Point>,
    /// Angles whose solve failed or that are out of reach (and whether
    /// the solve was a probe).
    failed: Vec<(f64, bool)>,
    /// Solves made.
    pub(super) spent: usize,
    /// Of those, probes (solved from a neighbour, not traced).
    pub(super) probes: usize,
    /// Where probes start: with it, every grasp is a probe from the
    /// nearest angle solved (or from it, before any).
    anchor: Option<Grasp>,
    /// Where closing from rest turns round (one of the angles `turn + k
    /// pi`; `Some(None)`: nowhere), once asked ([`Corrector::turn_near`]).
    pub(super) turn: Option<Option<f64>>,
}

impl<'g> Corrector<'g> {
    /// A corrector of radius `r`, its grasps probes from `anchor` where
    /// given (else traces), with the turn of closing from rest if known.
    pub(super) fn new(
        gripper: &'g Gripper,
        pressure_kpa: f64,
        radius: f64,
        anchor: Option<Grasp>,
        turn: Option<Option<f64>>,
    ) -> Self {
        Corrector {
            gripper,
            pressure_kpa,
            radius,
            points: Vec::new(),
            failed: Vec::new(),
            spent: 0,
            probes: 0,
            anchor,
            turn,
        }
    }

    /// The optimum corrected from the prediction `beta`, in `regime` (the
    /// nearest radius's) first and in the others where it fails; `step` is
    /// the first step from the prediction, and `from_radius` says the
    /// prediction interpolates solved radii (not a seed).
    pub(super) fn correct(
        &mut self,
        beta: f64,
        regime: Option<Regime>,
        step: f64,
        from_radius: bool,
    ) -> Option<(Point, Regime)> {
        let c = self;
        // the nearest radius's regime first, the other where it fails
        let interior = |c: &mut Corrector| c.interior(beta, step).map(|p| (p, Regime::Interior));
        match regime {
            Some(Regime::Reach) => c.reach(beta, step),
            Some(Regime::Boundary { side, slope }) => c
                .boundary(beta, step, side, Some(slope))
                .or_else(|| interior(c)),
            Some(Regime::Interior) => interior(c)
                .or_else(|| c.boundary(beta, step, 1.0, None))
                .or_else(|| c.boundary(beta, step, -1.0, None)),
            // an edge followed from a solved radius is often where it
            // was (it need not move with the radius): its first step the
            // tolerance
            Some(Regime::Edge { side }) => c.edge(beta, if from_radius { 0.0 } else { step }, side),
            // a searched optimum: at the turn of closing from rest the
            // edge first, else the usual case first
            None => {
                let turn = c.turn_near(beta).and_then(|t| turn_within(t, beta));
                let edge_first = turn.and_then(|t| c.edge(beta, 0.0, (t - beta).signum()));
                edge_first
                    .or_else(|| c.boundary(beta, step, 1.0, None))
                    .or_else(|| interior(c))
                    .or_else(|| c.boundary(beta, step, -1.0, None))
                    .or_else(|| c.edge(beta, step, 1.0))
                    .or_else(|| c.edge(beta, step, -1.0))
            }
        }
        .or_else(|| match regime {
            Some(Regime::Reach) => None,
            _ => c.reach(beta, step),
        })
    }

    /// The angle nearest `near` where closing from rest turns round
    /// ([`Gripper::closing_turn`]), computed once per corrector.
    fn turn_near(&mut self, near: f64) -> Option<f64> {
        let (g, pressure) = (self.gripper, self.pressure_kpa);
        let zero = *self.turn.get_or_insert_with(|| g.closing_turn(pressure));
        zero.map(|z| nearest_turn(z, near))
    }

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
    /// [`Gripper::closing_turn`], half of [`TURN_BETA_TOL`] inside):
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
            .turn_near(b0)
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
