//! The search for the design with the largest worst-case margin, and the
//! brute-force grid that checks it.
//!
//! The optimiser works on the varied variables scaled to `[0, 1]`. Its
//! starts are the box's centre, its corners (up to 8) and seeded random
//! points; each is evaluated once and scored by a smooth minimum of its
//! margins, `S = -(1/k) ln sum_i exp(-k m_i)` (within `ln(n) / k` below the
//! true minimum, and smooth, so that a start near several binding margins
//! ranks below one clear of them). The best few by S
//! (`DesignOptions::ascents`) are ascended, and the best design by its true
//! worst margin is returned with the margins' sensitivities to each
//! variable.
//!
//! An ascent maximises the worst margin `min_i m_i` itself, by a trust
//! region on the margins' linearisations: the step is the one within the
//! trust radius (a box, cut by the bounds) that maximises `min_i (m_i +
//! grad m_i . d)` ([`super::minimax`]: a linear programme in at most four
//! unknowns, solved exactly). A step whose worst margin rises by at least
//! a hundredth of the predicted rise is taken, and the radius doubled when
//! the prediction held to three quarters at the full radius; any other
//! step halves the radius. The ascent stops where the linearisation
//! predicts no rise, the radius falls below `MIN_RADIUS`, or after
//! `DesignOptions::max_iterations` steps. At an optimum where two margins
//! cross (a cuboid's lift against a sphere's, say), the linear programme
//! steps along their crossing, where gradient ascent on `S` zig-zags
//! across it.
//!
//! Each margin's exact gradient comes from the sensitivities of the
//! gripper's outputs
//! (`Gripper::geometry_sensitivities`, `grasp_sensitivities`,
//! `size_sensitivities`, `max_sphere_lift_sensitivities`: one
//! factorisation and a few solves per grasp, no re-solve; where a sphere's
//! best angle is the turn of closing from rest, the grasp's sensitivities
//! at that angle plus the turn's own rate in the design, by differences of
//! the turn of nearby grippers, which solve no grasp). A variable that
//! some margin's sensitivities do not cover (an actuator parameter of a
//! finger whose innermost rest point is not its tip, a sphere whose best
//! angle lies on another boundary) falls back to central differences of
//! the margins (each a set of full re-solves through the gripper path), for
//! that variable only.

use serde::Serialize;

use crate::error::{positive, require, InputError};
use crate::field::Field;

use super::evaluate::{evaluate, evaluate_seeded, evaluate_with_gradients, Evaluation, Seeds};
use super::progress::{DesignProgress, DesignStage, Tracker};
use super::reproduce::{reproduce, Reproduction};
use super::requirements::Requirements;
use super::variables::MarginGradient;

/// Settings of [`optimize`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesignOptions {
    /// Random starts besides the centre and the corners.
    pub random_starts: usize,
    /// Starts ascended: the best by the smooth minimum of their margins
    /// (every start costs one evaluation; the others stop there).
    pub ascents: usize,
    /// Steps (trials) per ascent.
    pub max_iterations: usize,
    /// Central-difference step, as a fraction of each variable's range (for
    /// the variables the exact gradients do not cover, and the reported
    /// sensitivities).
    pub step: f64,
    /// Sharpness `k` of the smooth minimum that ranks the starts.
    pub sharpness: f64,
    /// Seed of the random starts.
    pub seed: u64,
}

/// The most random starts of [`optimize`]. Each start costs one design
/// evaluation, about 0.15 ms of one core per cuboid and 3 ms per sphere on
/// the paper's 8-element finger, in proportion to `elements` beyond that
/// (the screening runs on every core): 10 000 starts on
/// scenes/design/paper_sec5.toml take about 30 s of one core (15 s on
/// two); on [`MAX_OBJECTS`](super::MAX_OBJECTS) spheres, about 15 minutes
/// of one core, and 32 times that at 256 elements.
pub const MAX_RANDOM_STARTS: usize = 10_000;
/// The most ascents of [`optimize`].
pub const MAX_ASCENTS: usize = 100;
/// The most iterations per ascent.
pub const MAX_ASCENT_ITERATIONS: usize = 1_000;
/// The most grid points of [`grid_search`] in all.
pub const MAX_GRID_POINTS: usize = 1_000_000;

impl DesignOptions {
    /// Checks every field against its bound, before any work.
    pub fn validate(&self) -> Result<(), InputError> {
        let at_most = |field: &'static str, v: usize, max: usize| {
            require(v <= max, Field::key(field), v as f64, || {
                format!("must be at most {max}")
            })
        };
        at_most(
            "design.random_starts",
            self.random_starts,
            MAX_RANDOM_STARTS,
        )?;
        at_most("design.ascents", self.ascents, MAX_ASCENTS)?;
        at_most(
            "design.max_iterations",
            self.max_iterations,
            MAX_ASCENT_ITERATIONS,
        )?;
        positive(Field::key("design.step"), self.step)?;
        require(
            self.step <= 0.5,
            Field::key("design.step"),
            self.step,
            || "must be at most 0.5 (a fraction of each variable's range)".into(),
        )?;
        positive(Field::key("design.sharpness"), self.sharpness)?;
        Ok(())
    }
}

impl Default for DesignOptions {
    fn default() -> DesignOptions {
        DesignOptions {
            random_starts: 2,
            ascents: 3,
            max_iterations: 25,
            step: 2e-3,
            sharpness: 40.0,
            seed: 1,
        }
    }
}

/// The design found, with everything that backs the claim.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Designed {
    /// True when the best design meets every requirement.
    pub feasible: bool,
    /// The best design's evaluation (every margin).
    pub best: Evaluation,
    /// d margin / d variable at the best design, per margin, for each
    /// varied variable (`VARIABLES` order; fixed ones are 0): exact, from
    /// the gripper-output sensitivities, where they cover the margin;
    /// otherwise by central differences of full re-solves.
    pub sensitivities: Vec<MarginSensitivity>,
    /// Design evaluations spent.
    pub evaluations: usize,
    /// Starts run.
    pub starts: usize,
    /// Every object's scene file solved again through the ordinary scene
    /// path ([`super::reproduce`]): the design meets its requirements only
    /// if each confirms its claim.
    pub reproductions: Vec<Reproduction>,
    /// Why the best design does not meet its requirements, when it does
    /// not: the requirement that fails and by how much, or the claim its
    /// scene does not reproduce.
    pub failure: Option<String>,
}

/// A margin's sensitivity to the design variables.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MarginSensitivity {
    /// The requirement.
    pub requirement: String,
    /// d margin / d (eps0, mounting angle deg, overlap mm); serialised
    /// with the variables' names (`eps0`, `mounting_angle_deg`,
    /// `overlap_mm`), as design.json names the design.
    #[serde(serialize_with = "by_variable")]
    pub gradient: [f64; 3],
}

/// `[eps0, angle, overlap]` as a map keyed by the variables' names.
fn by_variable<S: serde::Serializer>(g: &[f64; 3], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let mut m = s.serialize_map(Some(3))?;
    m.serialize_entry("eps0", &g[0])?;
    m.serialize_entry("mounting_angle_deg", &g[1])?;
    m.serialize_entry("overlap_mm", &g[2])?;
    m.end()
}

/// A brute-force grid over the varied variables.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridResult {
    /// The best grid point by worst margin.
    pub best: Evaluation,
    /// Points evaluated.
    pub evaluated: usize,
    /// The grid spacing of each variable (0 for a fixed one).
    pub resolution: [f64; 3],
}

/// The varied variables: index, low, high.
fn active(req: &Requirements) -> Vec<(usize, f64, f64)> {
    req.bounds()
        .iter()
        .enumerate()
        .filter(|(_, b)| b[1] > b[0])
        .map(|(i, b)| (i, b[0], b[1]))
        .collect()
}

fn design_of(req: &Requirements, u: &[f64]) -> [f64; 3] {
    let b = req.bounds();
    let mut x = [b[0][0], b[1][0], b[2][0]];
    for (k, &(i, lo, hi)) in active(req).iter().enumerate() {
        x[i] = lo + u[k].clamp(0.0, 1.0) * (hi - lo);
    }
    x
}

/// The smooth minimum of margins (see the module docs).
fn smooth_min(e: &Evaluation, k: f64) -> f64 {
    let m = e.worst;
    if !m.is_finite() {
        return -1e3;
    }
    let s: f64 = e.margins.iter().map(|g| (-k * (g.margin - m)).exp()).sum();
    m - s.ln() / k
}

struct Counter<'a> {
    req: &'a Requirements,
    evaluations: usize,
    /// Where each evaluation is reported, if anywhere.
    progress: Option<&'a Tracker<'a>>,
    /// The spheres' optima of the last evaluation along the current
    /// ascent, where the next trial's start
    /// ([`super::evaluate::evaluate_seeded`]).
    seeds: Seeds,
}

impl<'a> Counter<'a> {
    fn new(req: &'a Requirements, progress: Option<&'a Tracker<'a>>) -> Counter<'a> {
        Counter {
            req,
            evaluations: 0,
            progress,
            seeds: Seeds::default(),
        }
    }

    /// Counts one evaluation (and reports it).
    fn count(&mut self) {
        self.evaluations += 1;
        if let Some(t) = self.progress {
            t.evaluated();
        }
    }

    /// The evaluation at `u`, searched afresh.
    fn eval(&mut self, u: &[f64]) -> Evaluation {
        self.count();
        evaluate(self.req, design_of(self.req, u))
    }

    /// The evaluation at `u` along an ascent: each sphere's envelope
    /// started from the last evaluation's optimum.
    fn eval_near(&mut self, u: &[f64]) -> Evaluation {
        self.count();
        evaluate_seeded(self.req, design_of(self.req, u), false, &mut self.seeds).0
    }

    /// The evaluation at `u` along an ascent with every margin's exact
    /// gradient.
    fn eval_with_gradients(&mut self, u: &[f64]) -> (Evaluation, Vec<MarginGradient>) {
        self.count();
        evaluate_seeded(self.req, design_of(self.req, u), true, &mut self.seeds)
    }
}

/// Every margin's gradient at `u` (whose evaluation `e` and exact margin
/// gradients `grads` are given) over the design variables (per unit of
/// each, `VARIABLES` order; 0 for a fixed one): exact where
/// `grads` covers the margin, otherwise central differences of whole
/// evaluations at `u +- h` (scaled units, clamped to the box; `near`: the
/// evaluations started from the ascent's seeds, else searched afresh),
/// spent once per variable that some margin needs them for.
fn margin_gradients(
    c: &mut Counter<'_>,
    u: &[f64],
    (e, grads): (&Evaluation, &[MarginGradient]),
    h: f64,
    near: bool,
) -> Vec<[f64; 3]> {
    let mut out = vec![[0.0; 3]; e.margins.len()];
    for (j, &(i, lo, hi)) in active(c.req).iter().enumerate() {
        let covered = grads.len() == e.margins.len() && grads.iter().all(|g| g[i].is_some());
        let (ea, eb, dx) = if covered {
            (None, None, 0.0)
        } else {
            let (mut a, mut b) = (u.to_vec(), u.to_vec());
            a[j] = (u[j] + h).min(1.0);
            b[j] = (u[j] - h).max(0.0);
            let dx = (a[j] - b[j]) * (hi - lo);
            let mut eval = |x: &[f64]| if near { c.eval_near(x) } else { c.eval(x) };
            (Some(eval(&a)), Some(eval(&b)), dx)
        };
        for (k, m) in e.margins.iter().enumerate() {
            if let Some(v) = grads.get(k).and_then(|g| g[i]) {
                out[k][i] = v;
                continue;
            }
            let find = |ev: &Option<Evaluation>| {
                ev.as_ref()?
                    .margins
                    .iter()
                    .find(|x| x.requirement == m.requirement)
                    .map(|x| x.margin)
            };
            if let (Some(ma), Some(mb)) = (find(&ea), find(&eb)) {
                if dx > 0.0 {
                    out[k][i] = (ma - mb) / dx;
                }
            }
        }
    }
    out
}

/// The first trust radius of an ascent (scaled units).
const FIRST_RADIUS: f64 = 0.25;
/// The largest trust radius (scaled units).
const MAX_RADIUS: f64 = 0.5;
/// The smallest trust radius (scaled units): an ascent stops below it.
/// Each rejected step halves the radius.
const MIN_RADIUS: f64 = 1e-4;

/// Trust-region ascent of the worst margin from `u0` (module docs): each
/// step maximises the smallest linearised margin within the trust radius
/// and the bounds ([`super::minimax::linear_minimax`]); a step whose
/// worst margin rises by at least a hundredth of the predicted rise is
/// taken (the radius doubled when the prediction held to three quarters
/// and the step reached the radius), any other halves the radius. Every
/// trial is evaluated with its margins' gradients, so a step taken brings
/// the next linearisation along.
fn ascend(c: &mut Counter<'_>, u0: &[f64], opts: &DesignOptions) -> (Vec<f64>, Evaluation) {
    // the ascent's first point searched afresh, its trials started from
    // the points before them
    c.seeds = Seeds::default();
    let act = active(c.req);
    let mut u = u0.to_vec();
    let (mut e, mut grads) = c.eval_with_gradients(&u);
    let mut radius = FIRST_RADIUS;
    // the linearisation at u in the scaled variables (kept while steps
    // from u are rejected: its differences, where any, cost evaluations)
    let mut lin: Option<(Vec<f64>, Vec<Vec<f64>>)> = None;
    for _ in 0..opts.max_iterations {
        if !e.worst.is_finite() || radius < MIN_RADIUS {
            break;
        }
        let (m, g) = lin.get_or_insert_with(|| {
            let g = margin_gradients(c, &u, (&e, &grads), opts.step, true)
                .iter()
                .map(|row| act.iter().map(|&(i, lo, hi)| row[i] * (hi - lo)).collect())
                .collect();
            (e.margins.iter().map(|x| x.margin).collect(), g)
        });
        let lo: Vec<f64> = u.iter().map(|ui| (-radius).max(-ui)).collect();
        let hi: Vec<f64> = u.iter().map(|ui| radius.min(1.0 - ui)).collect();
        let (d, t) = super::minimax::linear_minimax(m, g, &lo, &hi);
        let predicted = t - e.worst;
        // stationary to the linearisation
        if predicted.is_nan() || predicted <= 1e-9 * (1.0 + e.worst.abs()) {
            break;
        }
        let trial: Vec<f64> = u
            .iter()
            .zip(&d)
            .map(|(ui, di)| (ui + di).clamp(0.0, 1.0))
            .collect();
        let (et, gt) = c.eval_with_gradients(&trial);
        let rho = (et.worst - e.worst) / predicted;
        let reach = d.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if rho >= 0.01 {
            if let Some(t) = c.progress {
                t.update(|p| p.offer(et.worst));
            }
            (u, e, grads, lin) = (trial, et, gt, None);
            if rho >= 0.75 && reach >= 0.99 * radius {
                radius = (2.0 * radius).min(MAX_RADIUS);
            }
        } else {
            radius = 0.5 * reach.min(radius);
        }
    }
    (u, e)
}

/// The starting points: the centre, the corners (at most 8), and
/// `random_starts` seeded points.
fn starts(dim: usize, opts: &DesignOptions) -> Vec<Vec<f64>> {
    let mut s = vec![vec![0.5; dim]];
    for corner in 0..(1usize << dim).min(8) {
        s.push(
            (0..dim)
                .map(|j| if corner >> j & 1 == 1 { 0.85 } else { 0.15 })
                .collect(),
        );
    }
    let mut rng = fastrand::Rng::with_seed(opts.seed);
    for _ in 0..opts.random_starts {
        s.push((0..dim).map(|_| rng.f64()).collect());
    }
    s
}

/// The design with the largest worst-case margin (module docs). The
/// settings and the requirements (which a caller may have built without
/// [`Requirements::parse`]) are checked before any work.
pub fn optimize(req: &Requirements, opts: &DesignOptions) -> Result<Designed, InputError> {
    optimize_with_progress(req, opts, &|_| {})
}

/// [`optimize`], handing `observer` a [`DesignProgress`] at every start
/// screened, design evaluated, step an ascent takes, ascent finished and
/// change of stage (none before the settings and the requirements are
/// checked). The observer is called from the search's threads, one call
/// at a time, and its counts never fall from one call to the next; it
/// should return quickly (store the event, say), as the search waits for
/// it.
pub fn optimize_with_progress(
    req: &Requirements,
    opts: &DesignOptions,
    observer: &(dyn Fn(&DesignProgress) + Sync),
) -> Result<Designed, InputError> {
    opts.validate()?;
    req.validate()?;
    let act = active(req);
    let dim = act.len();
    let mut best: Option<(Vec<f64>, Evaluation)> = None;
    let list = starts(dim, opts);
    let ascended = opts.ascents.max(1).min(list.len());
    let tracker = Tracker::new(observer, DesignProgress::new(list.len(), ascended));
    let mut c = Counter::new(req, Some(&tracker));
    tracker.stage(DesignStage::Screening);
    // screen every start by one evaluation; ascend from the best few. The
    // evaluations of the screening are independent, and so are the
    // ascents (each starts its seeds afresh): on every core, in order
    let scores = crate::cancel::par_map(&list, |u0| {
        let e = evaluate(req, design_of(req, u0));
        tracker.update(|p| {
            p.starts_done += 1;
            p.evaluations += 1;
            p.offer(e.worst);
        });
        smooth_min(&e, opts.sharpness)
    });
    c.evaluations += list.len();
    let mut screened: Vec<(&Vec<f64>, f64)> = list.iter().zip(scores).collect();
    screened.sort_by(|a, b| b.1.total_cmp(&a.1));
    let chosen: Vec<&Vec<f64>> = screened
        .into_iter()
        .take(ascended)
        .map(|(u0, _)| u0)
        .collect();
    tracker.stage(DesignStage::Ascending);
    let ascents = crate::cancel::par_map(&chosen, |u0| {
        let mut own = Counter::new(req, Some(&tracker));
        let (u, e) = ascend(&mut own, u0, opts);
        tracker.update(|p| {
            p.ascents_done += 1;
            p.offer(e.worst);
        });
        (u, e, own.evaluations)
    });
    for (u, e, evaluations) in ascents {
        c.evaluations += evaluations;
        if best.as_ref().is_none_or(|(_, b)| e.worst > b.worst) {
            best = Some((u, e));
        }
    }
    let (u, e) = best.unwrap_or_else(|| (Vec::new(), c.eval(&[])));
    // the best design evaluated again, searched afresh (the ascents'
    // trials followed their spheres' optima from the trial before), with
    // the sensitivities of every margin: exact where the gripper-output
    // sensitivities cover them, central differences for the rest
    tracker.stage(DesignStage::Checking);
    c.count();
    let (e, exact) = evaluate_with_gradients(req, e.design);
    let gradients = margin_gradients(&mut c, &u, (&e, &exact), opts.step, false);
    let sens: Vec<MarginSensitivity> = e
        .margins
        .iter()
        .zip(gradients)
        .map(|(m, gradient)| MarginSensitivity {
            requirement: m.requirement.clone(),
            gradient,
        })
        .collect();
    let mut d = Designed {
        feasible: false,
        best: e,
        sensitivities: sens,
        evaluations: c.evaluations,
        starts: list.len(),
        reproductions: Vec::new(),
        failure: None,
    };
    d.reproductions = reproduce(&d.best, req);
    d.failure = match (
        d.best.worst_margin(),
        d.reproductions.iter().find(|r| !r.reproduced),
    ) {
        (Some(m), _) if m.margin < 0.0 => Some(format!(
            "{} fails by {:.4} ({})",
            m.requirement, -m.margin, m.detail
        )),
        (_, Some(r)) => Some(format!(
            "the scene {} does not reproduce the claimed grasp of {} ({})",
            r.file, r.requirement, r.detail
        )),
        _ => None,
    };
    d.feasible = d.failure.is_none() && d.best.feasible();
    Ok(d)
}

/// Every point of a grid of `per_axis` values per varied variable (both
/// bounds included); the best by worst margin. The requirements are
/// checked before any work, as by [`optimize`].
pub fn grid_search(req: &Requirements, per_axis: usize) -> Result<GridResult, InputError> {
    req.validate()?;
    let act = active(req);
    let n = per_axis.max(2);
    let total = u32::try_from(act.len())
        .ok()
        .and_then(|k| n.checked_pow(k))
        .filter(|&t| t <= MAX_GRID_POINTS);
    let Some(total) = total else {
        return Err(InputError::OutOfRange {
            field: Field::key("grid.per_axis"),
            value: per_axis as f64,
            rule: format!(
                "gives more than {MAX_GRID_POINTS} points over {} variables",
                act.len()
            ),
        });
    };
    let mut c = Counter::new(req, None);
    let mut best: Option<Evaluation> = None;
    for idx in 0..total {
        let mut r = idx;
        let u: Vec<f64> = (0..act.len())
            .map(|_| {
                let v = r % n;
                r /= n;
                v as f64 / (n - 1) as f64
            })
            .collect();
        let e = c.eval(&u);
        if best.as_ref().is_none_or(|b| e.worst > b.worst) {
            best = Some(e);
        }
    }
    let mut resolution = [0.0; 3];
    for &(i, lo, hi) in &act {
        resolution[i] = (hi - lo) / (n - 1) as f64;
    }
    Ok(GridResult {
        best: best.unwrap_or_else(|| c.eval(&[])),
        evaluated: c.evaluations,
        resolution,
    })
}

impl Designed {
    /// One scene file per object that `fpc solve` runs to reproduce the
    /// best design's grasp of it ([`Evaluation::scenes`]).
    pub fn scenes(&self, req: &Requirements) -> Vec<(String, String)> {
        self.best.scenes(req)
    }
}

#[cfg(test)]
mod tests {
    use super::super::evaluate::{evaluate, evaluate_seeded, evaluate_with_gradients, Seeds};
    use super::super::Requirements;

    /// The observer of a search sees it begin at zero, every count rise
    /// by steps and never fall, each stage come after the one before,
    /// and the search end where the result says: every start screened,
    /// every ascent finished, the evaluations the result reports, and the
    /// best worst margin it saw at least the result's (the best ascent's
    /// end, seen there). Observing changes nothing in the result.
    #[test]
    fn progress_counts_rise_to_the_results_own() {
        use super::super::{DesignProgress, DesignStage};
        use super::{optimize, optimize_with_progress, DesignOptions};
        let req = Requirements::parse(
            r#"
elements = 4
[[object]]
kind = "cuboid"
size_mm = [60.0, 80.0]
lift_n = 0.5
max_normal_n = 5.0
[vary]
eps0 = [0.1, 0.4]
mounting_angle_deg = [60.0, 90.0]
"#,
        )
        .unwrap();
        let opts = DesignOptions {
            random_starts: 5,
            ascents: 2,
            ..DesignOptions::default()
        };
        let seen = std::sync::Mutex::new(Vec::<DesignProgress>::new());
        let d = optimize_with_progress(&req, &opts, &|p| seen.lock().unwrap().push(*p)).unwrap();
        let seen = seen.into_inner().unwrap();
        // the centre, 4 corners and the 5 random starts
        let starts = 10;
        assert_eq!(d.starts, starts);
        let stage = |p: &DesignProgress| match p.stage {
            DesignStage::Screening => 0,
            DesignStage::Ascending => 1,
            DesignStage::Checking => 2,
        };
        let first = seen.first().expect("no progress event");
        assert_eq!(
            (
                first.stage,
                first.starts_done,
                first.ascents_done,
                first.evaluations
            ),
            (DesignStage::Screening, 0, 0, 0)
        );
        assert!(first.best_worst_margin.is_none());
        for w in seen.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            assert_eq!((a.starts, a.ascents), (starts, 2));
            assert_eq!((b.starts, b.ascents), (starts, 2));
            assert!(stage(b) >= stage(a), "{a:?} then {b:?}");
            assert!(b.starts_done >= a.starts_done && b.starts_done <= a.starts_done + 1);
            assert!(b.ascents_done >= a.ascents_done && b.ascents_done <= a.ascents_done + 1);
            assert!(b.evaluations >= a.evaluations && b.evaluations <= a.evaluations + 1);
            match (a.best_worst_margin, b.best_worst_margin) {
                (Some(x), Some(y)) => assert!(y >= x, "{a:?} then {b:?}"),
                (Some(_), None) => panic!("the best margin went away: {a:?} then {b:?}"),
                _ => {}
            }
        }
        // the screening finished before any ascent began
        for p in &seen {
            if p.stage != DesignStage::Screening {
                assert_eq!(p.starts_done, starts, "{p:?}");
            }
        }
        let last = seen.last().unwrap();
        assert_eq!(last.stage, DesignStage::Checking);
        assert_eq!((last.starts_done, last.ascents_done), (starts, 2));
        assert_eq!(last.evaluations, d.evaluations);
        // more events than evaluations: the stages and the ascents' ends too
        assert!(seen.len() > d.evaluations, "{} events", seen.len());
        let best = last.best_worst_margin.expect("no finite margin seen");
        assert!(best >= d.best.worst - 1e-9, "{best} vs {}", d.best.worst);
        assert_eq!(optimize(&req, &opts).unwrap(), d);
    }

    /// Along a line of nearby designs, as an ascent's trials go, each
    /// sphere envelope started from the last design's optimum
    /// (`evaluate_seeded`) gives the margins of a fresh search at every
    /// design, to the fresh search's tolerance: it locates a boundary
    /// optimum to 1e-9 rad, the followed one to 1e-11 (a few 1e-9 of the
    /// lift apart).
    #[test]
    fn seeded_evaluations_give_the_fresh_margins() {
        let req = Requirements::parse(
            r#"
elements = 6
fingers = 3
mu = 0.6
[[object]]
kind = "sphere"
radius_mm = [35.0, 45.0]
lift_n = 0.35
max_normal_n = 0.9
[vary]
eps0 = [0.1, 0.5]
mounting_angle_deg = [60.0, 90.0]
overlap_mm = [0.0, 30.0]
"#,
        )
        .unwrap();
        let mut seeds = Seeds::default();
        let mut compared = 0;
        for k in 0..5 {
            let t = f64::from(k);
            let x = [0.124 + 0.004 * t, 65.3 + 0.3 * t, 0.5 + 0.5 * t];
            let (seeded, _) = evaluate_seeded(&req, x, false, &mut seeds);
            // the first design searched afresh, each later one followed
            assert_eq!(seeds.followed(), usize::from(k > 0), "design {x:?}");
            let fresh = evaluate(&req, x);
            assert_eq!(seeded.margins.len(), fresh.margins.len());
            for (a, b) in seeded.margins.iter().zip(&fresh.margins) {
                assert_eq!(a.requirement, b.requirement);
                let err = (a.margin - b.margin).abs();
                assert!(
                    err <= 1e-8 * b.margin.abs().max(1.0),
                    "design {x:?}, {}: seeded {} vs fresh {}",
                    a.requirement,
                    a.margin,
                    b.margin
                );
                compared += 1;
            }
        }
        assert!(compared >= 20, "{compared}");
    }

    /// The exact margin gradients the optimiser ascends against central
    /// differences of `evaluate` (full re-solves through the gripper path;
    /// plain differences, so agreement to 1e-3: the gripper's solve
    /// tolerances and, for spheres, the best angle's 1e-9 rad limit what
    /// the differences resolve; a wrong unit, factor or sign would be off by
    /// far more). tests/gripper_sensitivity.rs checks the underlying
    /// sensitivities to 1e-6.
    #[test]
    fn exact_margin_gradients_match_central_differences() {
        let req = Requirements::parse(
            r#"
elements = 6
[[object]]
kind = "cuboid"
size_mm = [60.0, 90.0]
lift_n = 0.6
max_normal_n = 5.0
[[object]]
kind = "sphere"
radius_mm = [45.0, 50.0]
lift_n = 1.0
max_normal_n = 5.0
[open]
size_mm = 100.0
pressure_kpa = 60.0
[vary]
eps0 = [0.1, 0.3]
mounting_angle_deg = [55.0, 90.0]
overlap_mm = [10.0, 30.0]
"#,
        )
        .unwrap();
        let x = [0.2, 62.0, 18.0];
        // every margin is covered here
        let (covered, margins) = gradients_against_differences(&req, x, [1e-4, 1e-3, 1e-3]);
        assert_eq!(covered, 3 * margins);
    }

    /// Checks every covered margin gradient at `x` against central
    /// differences of `evaluate` with `steps` (0: not checked), to 1e-3;
    /// returns how many (margin, variable) pairs were covered, and the
    /// number of margins.
    fn gradients_against_differences(
        req: &Requirements,
        x: [f64; 3],
        steps: [f64; 3],
    ) -> (usize, usize) {
        let (e, grads) = evaluate_with_gradients(req, x);
        assert_eq!(grads.len(), e.margins.len());
        let mut covered = 0;
        for (i, &h) in steps.iter().enumerate() {
            if h == 0.0 {
                continue;
            }
            let (mut a, mut b) = (x, x);
            a[i] += h;
            b[i] -= h;
            let (ea, eb) = (evaluate(req, a), evaluate(req, b));
            for (k, m) in e.margins.iter().enumerate() {
                let Some(exact) = grads[k][i] else { continue };
                covered += 1;
                let fd = (ea.margins[k].margin - eb.margins[k].margin) / (2.0 * h);
                let scale = exact.abs().max(fd.abs()).max(1e-2);
                assert!(
                    (exact - fd).abs() <= 1e-3 * scale,
                    "{} / variable {i}: exact {exact:.9e}, central differences {fd:.9e}",
                    m.requirement
                );
            }
        }
        (covered, e.margins.len())
    }

    /// Where the best grasping angle of a sphere is the edge of the angles
    /// the path from rest reaches, at the turn of closing from rest (the
    /// paper's Sec. 5 sphere near its best design), the lift's and the
    /// normal force's gradients follow the turn as it moves with the
    /// design, and agree with central differences of whole evaluations.
    #[test]
    fn sphere_gradients_at_the_turn_of_closing_from_rest() {
        let req = Requirements::parse(
            r#"
mu = 0.6
[[object]]
kind = "sphere"
radius_mm = [45.0, 55.0]
lift_n = 0.5
max_normal_n = 5.0
[vary]
eps0 = [0.1, 0.5]
mounting_angle_deg = [60.0, 90.0]
"#,
        )
        .unwrap();
        let x = [0.284, 74.3, 20.0];
        // the optimum lies at the turn, at every radius
        let g = super::super::variables::gripper(&req, x).unwrap();
        for r in [45.0, 50.0, 55.0] {
            let best = g.max_sphere_lift(0.0, r, 8).unwrap().unwrap();
            let zero = g.closing_turn(0.0).unwrap();
            assert!(
                crate::gripper::sphere::turn_within(zero, best.beta).is_some(),
                "r = {r}: {best:?}"
            );
        }
        // 3 radii, lift and gentle margins, eps0 and the angle
        assert_eq!(
            gradients_against_differences(&req, x, [1e-4, 1e-3, 0.0]),
            (12, 6)
        );
    }
}
