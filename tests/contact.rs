//! The mid-plane as exact curves (`Finger::midplane_curves`) and the exact
//! object-finger clearances of `fpc::gripper::contact`, against methods
//! independent of them:
//!
//! - the curves against `Finger::shape`'s samples and `Finger::tip`;
//! - the deepest point against dense sampling, 10^5 points per element:
//!   the exact maximum is at least every sample and exceeds the best one
//!   by no more than the depth's Lipschitz bound times half the spacing
//!   (depth is 1-Lipschitz in the point, and |dq/dx| <= sum_j j |c_j|
//!   L^(j-1) on an element);
//! - closed forms for straight fingers (a segment against a line and a
//!   circle) and for curves touching a line or a circle tangentially;
//! - the contact's own arc, left out by `deepest_apart_from`, against the
//!   same exclusion done on dense samples.
//!
//! States: `Finger::paper` and the other models, unloaded, pressurised and
//! with tip loads (solved), and random perturbations of solved states;
//! fastrand with fixed seeds.

use fpc::finger::{Affine2, PolyCurve};
use fpc::gripper::contact::{deepest, deepest_apart_from, Deepest, Obstacle, DEPTH_TOLERANCE_MM};
use fpc::gripper::finger_point_to_gripper;
use fpc::gripper::frames::finger_to_gripper_map;
use fpc::{Actuator, Coefficients, Finger, Load, ModelId, Partition, SolveOptions};

const SAMPLES: usize = 100_000;

struct Rng(fastrand::Rng);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(fastrand::Rng::with_seed(seed))
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.0.f64()
    }
    fn index(&mut self, n: usize) -> usize {
        self.0.usize(..n)
    }
}

fn finger(model: ModelId, eps0: f64, n: usize) -> Finger {
    let act = Actuator::paper(eps0).unwrap();
    let part = Partition::equal(act.geometry().lx, n).unwrap();
    Finger::with_model(model, &act, &part, true)
}

/// Solved states of a finger (unloaded, pressurised, tip loads) and random
/// perturbations of them (each unknown by up to 5 % of its scaled unit).
fn states(f: &Finger, rng: &mut Rng, perturbed: usize) -> Vec<(String, Coefficients)> {
    let opts = SolveOptions::default();
    let mut out = Vec::new();
    let loads = [
        Load::unloaded(),
        Load::unloaded().with_pressure_kpa(rng.range(20.0, 150.0)),
        Load::unloaded().with_tip_force(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
        Load::unloaded()
            .with_pressure_kpa(rng.range(0.0, 100.0))
            .with_tip_force(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5)),
    ];
    for load in loads {
        if let Ok(sol) = f.solve(&load, &opts) {
            out.push((format!("solved {load:?}"), sol.coefficients));
        }
    }
    assert!(out.len() >= 3, "too few solves succeeded");
    let scales = f.unknown_scales();
    let solved = out.len();
    for p in 0..perturbed {
        let mut k = out[p % solved].1.clone();
        for (v, s) in k.as_mut_slice().iter_mut().zip(&scales) {
            *v += s * rng.range(-0.05, 0.05);
        }
        out.push((format!("perturbed {p}"), k));
    }
    out
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The size of the curve set: the largest coordinate of any coefficient
/// term over the range (the scale of rounding).
fn size(curves: &[PolyCurve]) -> f64 {
    curves
        .iter()
        .map(|c| {
            c.coefficients()
                .iter()
                .enumerate()
                .map(|(j, cj)| cj[0].abs().max(cj[1].abs()) * c.length().powi(j as i32))
                .sum::<f64>()
        })
        .fold(1.0, f64::max)
}

/// `sum_j j |c_j| L^(j-1)`: a bound of |dq/dx| over the curve.
fn speed_bound(c: &PolyCurve) -> f64 {
    c.coefficients()
        .iter()
        .enumerate()
        .skip(1)
        .map(|(j, cj)| j as f64 * cj[0].hypot(cj[1]) * c.length().powi(j as i32 - 1))
        .sum()
}

/// Dense samples of the depth: per curve, `SAMPLES + 1` points (both ends).
fn sampled_depths(curves: &[PolyCurve], obstacle: &Obstacle) -> Vec<Vec<f64>> {
    curves
        .iter()
        .map(|c| {
            (0..=SAMPLES)
                .map(|i| obstacle.depth(c.point(c.length() * i as f64 / SAMPLES as f64)))
                .collect()
        })
        .collect()
}

/// Checks `found` against dense samples of the kept parts; returns the
/// excess of the exact maximum over the best sample relative to its bound.
fn check_against_samples(
    label: &str,
    curves: &[PolyCurve],
    obstacle: &Obstacle,
    found: &Deepest,
    depths: &[Vec<f64>],
    kept: &dyn Fn(usize, usize) -> bool,
) -> f64 {
    let rounding = 1e-14 * size(curves);
    let mut best = f64::NEG_INFINITY;
    let mut bound: f64 = 0.0;
    for (e, (c, d)) in curves.iter().zip(depths).enumerate() {
        bound = bound.max(speed_bound(c) * c.length() / SAMPLES as f64 / 2.0);
        for (i, &v) in d.iter().enumerate() {
            if kept(e, i) {
                assert!(
                    found.depth >= v - rounding - DEPTH_TOLERANCE_MM,
                    "{label}: sample {i} of element {e} is {v:e} deep, the exact maximum {:e}",
                    found.depth
                );
                best = best.max(v);
            }
        }
    }
    assert!(
        found.depth <= best + bound + rounding,
        "{label}: exact maximum {:e} exceeds the best sample {best:e} by more than {bound:e}",
        found.depth
    );
    // the report is one point of the curve set
    let c = &curves[found.element];
    assert!((0.0..=c.length()).contains(&found.x), "{label}: {found:?}");
    assert_eq!(found.point, c.point(found.x), "{label}");
    assert_eq!(found.depth, obstacle.depth(found.point), "{label}");
    if bound > 0.0 {
        (found.depth - best) / bound
    } else {
        0.0
    }
}

// ---------------------------------------------------------------------------
// The curves.

#[test]
fn midplane_curves_match_the_shape_samples_and_the_tip() {
    let mut rng = Rng::new(1);
    let mut worst: f64 = 0.0;
    for &model in ModelId::ALL {
        for (eps0, n) in [(0.25, 8), (0.15, 3), (0.4, 12)] {
            let f = finger(model, eps0, n);
            let sheared = model.info().unknowns.contains(&"g0");
            for (label, k) in states(&f, &mut rng, 3) {
                let label = format!("{model} eps0 {eps0} N {n} {label}");
                let curves = f.midplane_curves(&k).unwrap();
                assert_eq!(curves.len(), n, "{label}");
                let per = 16;
                let shape = f.shape(&k, per).unwrap();
                let scale = f.length();
                assert_eq!(curves[0].start(), [0.0, 0.0], "{label}: the root");
                for (i, c) in curves.iter().enumerate() {
                    assert_eq!(c.length(), f.element_lengths()[i], "{label}");
                    for j in 1..=per {
                        let x = c.length() * j as f64 / per as f64;
                        let err = dist(c.point(x), shape[1 + i * per + (j - 1)]) / scale;
                        worst = worst.max(err);
                        assert!(err <= 1e-14, "{label}: element {i} sample {j}: {err:e}");
                    }
                    if i + 1 < n {
                        let err = dist(c.end(), curves[i + 1].start()) / scale;
                        assert!(err <= 1e-14, "{label}: joint {i}: {err:e}");
                        // the chain is smooth: tangents are parallel at
                        // joints (a model with a shear strain, `g0`, kinks
                        // where it changes: there the sections, not the
                        // mid-plane's tangents, are continuous)
                        if sheared {
                            continue;
                        }
                        let (a, b) = (c.tangent(c.length()), curves[i + 1].tangent(0.0));
                        let cross =
                            (a[0] * b[1] - a[1] * b[0]) / (a[0].hypot(a[1]) * b[0].hypot(b[1]));
                        assert!(
                            cross.abs() <= 1e-13,
                            "{label}: kink at joint {i}: {cross:e}"
                        );
                    }
                }
                let (tip, angle) = f.tip(&k).unwrap();
                let end = curves[n - 1].end();
                let err = dist(end, tip) / scale;
                worst = worst.max(err);
                assert!(err <= 1e-14, "{label}: tip {tip:?}, curves end at {end:?}");
                // the tip angle is the sections' rotation: the sum of each
                // element's tangent turn less the change of its shear angle
                // atan2(g0, |t|) (docs/model.md (M34); for a model without
                // shear the tangent turns alone, and the tangent's angle at
                // the tip)
                let g0 = model.info().unknowns.iter().position(|u| *u == "g0");
                let turn = |(c, k): (&PolyCurve, &[f64])| {
                    let (a, b) = (c.tangent(0.0), c.tangent(c.length()));
                    let tangent = (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1]);
                    let shear = |t: [f64; 2]| g0.map_or(0.0, |i| k[i].atan2(t[0].hypot(t[1])));
                    tangent - (shear(b) - shear(a))
                };
                let sum: f64 = curves.iter().zip(k.iter()).map(turn).sum();
                let d = (sum - angle).rem_euclid(std::f64::consts::TAU);
                assert!(
                    d.min(std::f64::consts::TAU - d) <= 1e-12,
                    "{label}: tip angle {angle} vs the tangent's turns {sum}"
                );
                if !sheared {
                    let t = curves[n - 1].tangent(curves[n - 1].length());
                    let d = (t[1].atan2(t[0]) - angle).rem_euclid(std::f64::consts::TAU);
                    assert!(
                        d.min(std::f64::consts::TAU - d) <= 1e-12,
                        "{label}: tip angle"
                    );
                }
            }
        }
    }
    eprintln!("midplane curves vs shape samples and tip: worst {worst:e} of the finger length");
}

#[test]
fn midplane_curves_check_their_input() {
    let f = Finger::paper(0.25, 4).unwrap();
    let wrong = Coefficients::zeros(3, 4);
    assert_eq!(f.midplane_curves(&wrong).unwrap_err().field(), "guess");
    let mut k = f.straight();
    k.as_mut_slice()[0] = f64::NAN;
    assert_eq!(f.midplane_curves(&k).unwrap_err().field(), "guess");
    // the straight finger: X = x along the chain
    let curves = f.midplane_curves(&f.straight()).unwrap();
    let mut x0 = 0.0;
    for c in &curves {
        assert_eq!(c.start(), [x0, 0.0]);
        x0 += c.length();
        assert!((c.end()[0] - x0).abs() < 1e-12 && c.end()[1] == 0.0);
    }
}

#[test]
fn the_gripper_map_is_m15() {
    let mut rng = Rng::new(2);
    for _ in 0..50 {
        let (a, palm) = (rng.range(0.0, 1.6), rng.range(10.0, 80.0));
        let m = finger_to_gripper_map(a, palm).unwrap();
        let p = [rng.range(-50.0, 120.0), rng.range(-60.0, 60.0)];
        let (q, want) = (m.apply(p), finger_point_to_gripper(p, a, palm));
        assert!(dist(q, want) <= 1e-13, "{q:?} vs {want:?}");
    }
    assert_eq!(
        finger_to_gripper_map(f64::NAN, 1.0).unwrap_err().field(),
        "mounting_angle"
    );
    assert_eq!(
        finger_to_gripper_map(1.0, f64::INFINITY)
            .unwrap_err()
            .field(),
        "palm"
    );
}

// ---------------------------------------------------------------------------
// Dense sampling.

/// A random half-plane or disc near the finger: through or near a random
/// point of the curves, so that it cuts some element, grazes it or clears
/// it by a little.
fn random_obstacle(rng: &mut Rng, curves: &[PolyCurve], disc: bool) -> Obstacle {
    let c = &curves[rng.index(curves.len())];
    let p = c.point(rng.range(0.0, c.length()));
    let offset = [rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)];
    let q = [p[0] + offset[0], p[1] + offset[1]];
    if disc {
        let r = rng.range(1.0, 40.0);
        let dir = rng.range(0.0, std::f64::consts::TAU);
        Obstacle::disc([q[0] + r * dir.cos(), q[1] + r * dir.sin()], r).unwrap()
    } else {
        let dir = rng.range(0.0, std::f64::consts::TAU);
        Obstacle::half_plane(q, [dir.cos(), dir.sin()]).unwrap()
    }
}

#[test]
fn deepest_point_against_dense_sampling() {
    let mut rng = Rng::new(3);
    let mut cases = 0;
    let mut worst: f64 = 0.0;
    let mut inside = 0;
    for &model in ModelId::ALL {
        for (eps0, n) in [(0.25, 8), (0.4, 5)] {
            let f = finger(model, eps0, n);
            for (label, k) in states(&f, &mut rng, 2) {
                let curves = f.midplane_curves(&k).unwrap();
                // in the finger frame and in a gripper frame
                let m = finger_to_gripper_map(rng.range(0.5, 1.5), rng.range(20.0, 60.0)).unwrap();
                let mapped: Vec<PolyCurve> = curves.iter().map(|c| c.map(m)).collect();
                for (frame, set) in [("finger", &curves), ("gripper", &mapped)] {
                    for disc in [false, true] {
                        let obstacle = random_obstacle(&mut rng, set, disc);
                        let found = deepest(set, &obstacle).unwrap();
                        let depths = sampled_depths(set, &obstacle);
                        let label =
                            format!("{model} eps0 {eps0} {label}, {frame} frame, {obstacle:?}");
                        let r = check_against_samples(
                            &label,
                            set,
                            &obstacle,
                            &found,
                            &depths,
                            &|_, _| true,
                        );
                        worst = worst.max(r);
                        inside += usize::from(found.depth > 0.0);
                        cases += 1;
                    }
                }
            }
        }
    }
    assert!(
        inside > cases / 4,
        "too few penetrating cases: {inside} of {cases}"
    );
    eprintln!(
        "deepest point vs 1e5 samples per element: {cases} cases ({inside} penetrating); exact - best sample <= {worst:e} of the sampling bound"
    );
}

// ---------------------------------------------------------------------------
// Closed forms.

/// A state whose every element is straight: no bending (c2 = 0), any
/// stretch with X increasing (a1, and a2/a3 small enough).
fn straight_state(f: &Finger, rng: &mut Rng) -> Coefficients {
    let names = f.model().info().unknowns;
    let lengths = f.element_lengths();
    let mut values = Vec::new();
    for &l in lengths {
        for &name in names {
            values.push(match name {
                // no curvature, no shear strain (which would turn each
                // element's mid-plane from its section)
                "c2" | "g0" => 0.0,
                "a1" => rng.range(-0.1, 0.1),
                "a2" => rng.range(-0.1, 0.1) / l,
                "a3" => rng.range(-0.1, 0.1) / (l * l),
                _ => rng.range(-0.1, 0.1),
            });
        }
    }
    Coefficients::new(names.len(), values).unwrap()
}

#[test]
fn straight_fingers_against_closed_forms() {
    let mut rng = Rng::new(4);
    let (mut worst_depth, mut worst_point): (f64, f64) = (0.0, 0.0);
    for &model in ModelId::ALL {
        for n in [1, 4, 9] {
            let f = finger(model, 0.25, n);
            for case in 0..25 {
                let k = if case == 0 {
                    f.straight()
                } else {
                    straight_state(&f, &mut rng)
                };
                // a rigid motion of the segment
                let m = Affine2::rotation(
                    rng.range(-3.2, 3.2),
                    [rng.range(-50.0, 50.0), rng.range(-50.0, 50.0)],
                )
                .unwrap();
                let curves: Vec<PolyCurve> = f
                    .midplane_curves(&k)
                    .unwrap()
                    .iter()
                    .map(|c| c.map(m))
                    .collect();
                let (p0, p1) = (m.apply([0.0, 0.0]), m.apply(f.tip(&k).unwrap().0));
                let label = format!("{model} N {n} case {case}");
                // the curves lie on the segment
                for c in &curves {
                    let q = c.point(0.37 * c.length());
                    let (u, v) = ([p1[0] - p0[0], p1[1] - p0[1]], [q[0] - p0[0], q[1] - p0[1]]);
                    let cross = (u[0] * v[1] - u[1] * v[0]) / u[0].hypot(u[1]);
                    assert!(cross.abs() < 1e-12, "{label}: not straight");
                }

                // a line: depth is affine along the segment, deepest at an end
                let dir = rng.range(0.0, std::f64::consts::TAU);
                let through = [rng.range(-60.0, 60.0), rng.range(-60.0, 60.0)];
                let plane = Obstacle::half_plane(through, [dir.cos(), dir.sin()]).unwrap();
                let want = plane.depth(p0).max(plane.depth(p1));
                let found = deepest(&curves, &plane).unwrap();
                let err = (found.depth - want).abs();
                worst_depth = worst_depth.max(err);
                assert!(
                    err <= 1e-12,
                    "{label}: line depth {:e}, closed form {want:e}",
                    found.depth
                );

                // a circle: the nearest point of the segment to the centre
                let center = [rng.range(-80.0, 80.0), rng.range(-80.0, 80.0)];
                let r = rng.range(1.0, 60.0);
                let disc = Obstacle::disc(center, r).unwrap();
                let u = [p1[0] - p0[0], p1[1] - p0[1]];
                let t = (((center[0] - p0[0]) * u[0] + (center[1] - p0[1]) * u[1])
                    / (u[0] * u[0] + u[1] * u[1]))
                    .clamp(0.0, 1.0);
                let nearest = [p0[0] + t * u[0], p0[1] + t * u[1]];
                let want = r - dist(nearest, center);
                let found = deepest(&curves, &disc).unwrap();
                let err = (found.depth - want).abs();
                worst_depth = worst_depth.max(err);
                assert!(
                    err <= 1e-12,
                    "{label}: circle depth {:e}, closed form {want:e}",
                    found.depth
                );
                let err = dist(found.point, nearest);
                worst_point = worst_point.max(err);
                assert!(
                    err <= 1e-10,
                    "{label}: nearest point {:?}, closed form {nearest:?}",
                    found.point
                );
            }
        }
    }
    eprintln!("straight fingers: depth within {worst_depth:e} mm of the closed forms, nearest point within {worst_point:e} mm");
}

/// A curved state's interior point `(element, x0)`, the point, its unit
/// tangent and the unit normal towards the side the curve bends to.
fn touching_point(rng: &mut Rng, curves: &[PolyCurve]) -> (usize, f64, [f64; 2], [f64; 2]) {
    let e = rng.index(curves.len());
    let c = &curves[e];
    // on the sampling grid, so that sampled checks start from the same
    // point; one in five at a joint (or an end of the finger)
    let i0 = match rng.index(10) {
        0 => 0.0,
        1 => SAMPLES as f64,
        _ => (rng.range(0.05, 0.95) * SAMPLES as f64).round(),
    };
    let x0 = c.length() * i0 / SAMPLES as f64;
    let p = c.point(x0);
    let t = c.tangent(x0);
    let tn = t[0].hypot(t[1]);
    let t = [t[0] / tn, t[1] / tn];
    // the second derivative by differences of the tangent decides the side
    let h = 1e-4 * c.length();
    let (ta, tb) = (c.tangent(x0 - h), c.tangent(x0 + h));
    let bend = [tb[0] - ta[0], tb[1] - ta[1]];
    let nu = [-t[1], t[0]];
    let side = if nu[0] * bend[0] + nu[1] * bend[1] >= 0.0 {
        1.0
    } else {
        -1.0
    };
    (e, x0, p, [side * nu[0], side * nu[1]])
}

#[test]
fn tangential_touching_is_found_at_depth_zero() {
    let mut rng = Rng::new(5);
    let (mut worst_depth, mut worst_x): (f64, f64) = (0.0, 0.0);
    let mut cases = 0;
    for &model in ModelId::ALL {
        let f = finger(model, 0.25, 6);
        for (label, k) in states(&f, &mut rng, 4) {
            let curves = f.midplane_curves(&k).unwrap();
            for _ in 0..3 {
                let (e, x0, p, n) = touching_point(&mut rng, &curves);
                // the line tangent at p, the object beyond it away from the
                // curve's bend (outward normal n: the curve on the n side);
                // and a circle inside that half-plane touching the curve at p
                let r = rng.range(2.0, 40.0);
                for obstacle in [
                    Obstacle::half_plane(p, n).unwrap(),
                    Obstacle::disc([p[0] - r * n[0], p[1] - r * n[1]], r).unwrap(),
                ] {
                    // only where the rest of the finger clears the object
                    let depths = sampled_depths(&curves, &obstacle);
                    let clear = depths.iter().enumerate().all(|(i, d)| {
                        d.iter().enumerate().all(|(j, &v)| {
                            let x = curves[i].length() * j as f64 / SAMPLES as f64;
                            v <= 1e-12 || (i == e && (x - x0).abs() < 1e-3)
                        })
                    });
                    if !clear {
                        continue;
                    }
                    let found = deepest(&curves, &obstacle).unwrap();
                    let label =
                        format!("{model} {label}: touching element {e} at {x0}, {obstacle:?}");
                    worst_depth = worst_depth.max(found.depth.abs());
                    assert!(
                        found.depth.abs() <= 1e-12,
                        "{label}: depth {:e}",
                        found.depth
                    );
                    // located: at the touching point (on the neighbouring
                    // curve when the point is a joint)
                    let err = if found.element == e {
                        (found.x - x0).abs() / curves[e].length()
                    } else {
                        assert!(x0 == 0.0 || x0 == curves[e].length(), "{label}: {found:?}");
                        dist(found.point, p) / curves[e].length()
                    };
                    worst_x = worst_x.max(err);
                    assert!(err <= 1e-12, "{label}: found {found:?} ({err:e})");
                    cases += 1;
                }
            }
        }
    }
    assert!(cases >= 20, "only {cases} tangential cases");
    eprintln!("tangential touching: {cases} cases, |depth| <= {worst_depth:e} mm, located within {worst_x:e} of the element length");
}

// ---------------------------------------------------------------------------
// The contact's own arc.

/// `deepest_apart_from` against the same exclusion on dense samples: from
/// the sample at the point, walk each way while the depth falls; the
/// samples passed are left out, the one where the fall stops is kept
/// (unless the walk ran off the set's end still falling), and the point
/// itself is kept when a side exists on which the depth does not fall.
/// `deepest_apart_from` the contact at element `e`, `x0` (sample `i0`),
/// checked against the samples left once the contact's own arc is cut
/// away: `None` only where no sample is left, else the answer and its
/// distance from the best kept sample as a fraction of the sampling bound.
fn checked_apart(
    label: &str,
    curves: &[PolyCurve],
    obstacle: &Obstacle,
    (e, x0, i0): (usize, f64, usize),
) -> Option<(Deepest, f64)> {
    let depths = sampled_depths(curves, obstacle);
    let kept = apart_from_samples(&depths, e, i0);
    match deepest_apart_from(curves, obstacle, e, x0).unwrap() {
        None => {
            assert!(
                !kept.iter().flatten().any(|&b| b),
                "{label}: nothing left, but samples say otherwise"
            );
            None
        }
        Some(found) => {
            let r =
                check_against_samples(label, curves, obstacle, &found, &depths, &|e, i| kept[e][i]);
            Some((found, r))
        }
    }
}

fn apart_from_samples(depths: &[Vec<f64>], element: usize, index: usize) -> Vec<Vec<bool>> {
    // one walk over the whole set; a joint is the previous element's last
    // sample and the next one's first, the same point
    let mut order: Vec<(usize, usize)> = Vec::new();
    for (e, d) in depths.iter().enumerate() {
        let from = usize::from(e > 0);
        order.extend((from..d.len()).map(|i| (e, i)));
    }
    let (element, index) = if index == 0 && element > 0 {
        (element - 1, depths[element - 1].len() - 1)
    } else {
        (element, index)
    };
    let at = order.iter().position(|&p| p == (element, index)).unwrap();
    let depth = |k: usize| depths[order[k].0][order[k].1];
    let mut excluded = vec![false; order.len()];
    // backwards
    let mut k = at;
    while k > 0 && depth(k - 1) < depth(k) {
        k -= 1;
        excluded[k] = true;
    }
    if k > 0 {
        excluded[k] = false;
    }
    // forwards
    let mut k = at;
    while k + 1 < order.len() && depth(k + 1) < depth(k) {
        k += 1;
        excluded[k] = true;
    }
    if k + 1 < order.len() {
        excluded[k] = false;
    }
    let stays_back = at > 0 && depth(at - 1) >= depth(at);
    let stays_fwd = at + 1 < order.len() && depth(at + 1) >= depth(at);
    excluded[at] = !(stays_back || stays_fwd);
    let mut kept: Vec<Vec<bool>> = depths.iter().map(|d| vec![true; d.len()]).collect();
    for (k, &(e, i)) in order.iter().enumerate() {
        kept[e][i] = !excluded[k];
        if i == depths[e].len() - 1 && e + 1 < depths.len() {
            kept[e + 1][0] = !excluded[k];
        }
    }
    kept
}

#[test]
fn the_tips_own_contact_is_left_out_and_nothing_else() {
    let mut rng = Rng::new(6);
    let (mut outside, mut inside, mut none) = (0, 0, 0);
    let mut worst: f64 = 0.0;
    for &model in ModelId::ALL {
        for (eps0, n) in [(0.25, 8), (0.4, 6)] {
            let f = finger(model, eps0, n);
            for (label, k) in states(&f, &mut rng, 2) {
                let curves = f.midplane_curves(&k).unwrap();
                let last = &curves[n - 1];
                let (tip, l) = (last.end(), last.length());
                let t = last.tangent(l);
                let tn = t[0].hypot(t[1]);
                let t = [t[0] / tn, t[1] / tn];
                for trial in 0..6 {
                    // a disc through the tip, its centre ahead of the tip
                    // (the finger comes from outside) or behind it (from inside)
                    let r = rng.range(3.0, 40.0);
                    let ahead = trial % 2 == 0;
                    let turn =
                        rng.range(-1.4, 1.4) + if ahead { 0.0 } else { std::f64::consts::PI };
                    let (s, c) = turn.sin_cos();
                    let u = [c * t[0] - s * t[1], s * t[0] + c * t[1]];
                    let obstacle = if trial < 4 {
                        Obstacle::disc([tip[0] + r * u[0], tip[1] + r * u[1]], r).unwrap()
                    } else {
                        // a face through the tip, facing back along the finger
                        Obstacle::half_plane(tip, [-u[0], -u[1]]).unwrap()
                    };
                    let label = format!("{model} eps0 {eps0} {label}, trial {trial}, {obstacle:?}");
                    let all = deepest(&curves, &obstacle).unwrap();
                    assert!(all.depth >= -1e-12, "{label}: the tip touches: {all:?}");
                    match checked_apart(&label, &curves, &obstacle, (n - 1, l, SAMPLES)) {
                        // every sample falls away from the tip
                        None => none += 1,
                        Some((found, r)) => {
                            worst = worst.max(r);
                            if !ahead && trial < 4 {
                                // from inside: the penetration is the deepest point
                                assert_eq!(found.depth, all.depth, "{label}");
                                if all.depth > 1e-9 {
                                    inside += 1;
                                }
                            } else {
                                outside += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(
        inside >= 10 && outside >= 10,
        "inside {inside}, outside {outside}, none {none}"
    );
    eprintln!(
        "apart from the tip: {inside} penetrations from inside found, {outside} second-contact searches, {none} with nothing left; exact - best kept sample <= {worst:e} of the sampling bound"
    );
}

#[test]
fn an_interior_contacts_own_arc_is_left_out() {
    let mut rng = Rng::new(7);
    let (mut some, mut none) = (0, 0);
    let mut worst: f64 = 0.0;
    for &model in ModelId::ALL {
        for eps0 in [0.25, 0.4] {
            let f = finger(model, eps0, 6);
            for (label, k) in states(&f, &mut rng, 2) {
                let curves = f.midplane_curves(&k).unwrap();
                for _ in 0..2 {
                    let (e, x0, p, n) = touching_point(&mut rng, &curves);
                    let i0 = (x0 / curves[e].length() * SAMPLES as f64).round() as usize;
                    // the tangent face, and a small disc inside the bend
                    // touching there (the finger may curl round it)
                    let r = rng.range(1.0, 8.0);
                    for obstacle in [
                        Obstacle::half_plane(p, n).unwrap(),
                        Obstacle::disc([p[0] + r * n[0], p[1] + r * n[1]], r).unwrap(),
                    ] {
                        let label = format!(
                            "{model} eps0 {eps0} {label}: element {e} at {x0}, {obstacle:?}"
                        );
                        match checked_apart(&label, &curves, &obstacle, (e, x0, i0)) {
                            None => none += 1,
                            Some((found, r)) => {
                                worst = worst.max(r);
                                // the contact itself is not the answer
                                assert!(
                                    dist(found.point, p) > 1e-6 * curves[e].length(),
                                    "{label}: {found:?}"
                                );
                                some += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(
        some >= 10 && none >= 10,
        "{some} with a remainder, {none} without"
    );
    eprintln!(
        "apart from an interior contact: {some} searches, {none} with nothing left; exact - best kept sample <= {worst:e} of the sampling bound"
    );
}

#[test]
fn a_finger_falling_away_from_its_tip_leaves_nothing() {
    // a straight finger and a face through the tip facing back along it:
    // the depth falls monotonically from the tip over the whole finger
    let f = Finger::paper(0.25, 5).unwrap();
    let curves = f.midplane_curves(&f.straight()).unwrap();
    let tip = curves[4].end();
    let face = Obstacle::half_plane(tip, [-1.0, 0.0]).unwrap();
    let all = deepest(&curves, &face).unwrap();
    assert_eq!((all.element, all.depth), (4, 0.0));
    assert_eq!(
        deepest_apart_from(&curves, &face, 4, curves[4].length()).unwrap(),
        None
    );
    // the face the other way round: the finger comes from inside, the root
    // is deepest (the whole finger length), and nothing is left out
    let face = Obstacle::half_plane(tip, [1.0, 0.0]).unwrap();
    let apart = deepest_apart_from(&curves, &face, 4, curves[4].length())
        .unwrap()
        .unwrap();
    assert_eq!((apart.element, apart.x), (0, 0.0));
    assert!((apart.depth - f.length()).abs() < 1e-12);
}

#[test]
fn invalid_input_is_a_typed_error() {
    let f = Finger::paper(0.25, 3).unwrap();
    let curves = f.midplane_curves(&f.straight()).unwrap();
    let disc = Obstacle::disc([10.0, 5.0], 3.0).unwrap();
    assert_eq!(deepest(&[], &disc).unwrap_err().field(), "curves");
    for (r, field) in [
        (Obstacle::disc([f64::NAN, 0.0], 1.0), "disc.center[0]"),
        (Obstacle::disc([0.0, 0.0], 0.0), "disc.radius"),
        (Obstacle::disc([0.0, 0.0], f64::INFINITY), "disc.radius"),
        (
            Obstacle::half_plane([0.0, 0.0], [0.0, 0.0]),
            "half_plane.normal",
        ),
        (
            Obstacle::half_plane([0.0, f64::NAN], [1.0, 0.0]),
            "half_plane.point[1]",
        ),
        (
            Obstacle::half_plane([0.0, 0.0], [f64::INFINITY, 0.0]),
            "half_plane.normal[0]",
        ),
    ] {
        assert_eq!(r.unwrap_err().field(), field);
    }
    // a non-unit normal is normalised
    let a = Obstacle::half_plane([1.0, 2.0], [0.0, 5.0]).unwrap();
    assert_eq!(a.depth([7.0, 0.5]), 1.5);
    assert_eq!(
        deepest_apart_from(&curves, &disc, 3, 0.0)
            .unwrap_err()
            .field(),
        "element"
    );
    for x in [-1e-9, curves[1].length() * 1.001, f64::NAN] {
        assert_eq!(
            deepest_apart_from(&curves, &disc, 1, x)
                .unwrap_err()
                .field(),
            "x"
        );
    }
    // curves too large for h: a typed error, not NaN
    let huge = PolyCurve::new(vec![[0.0, 0.0], [1e200, 1e200]], 1e100).unwrap();
    assert_eq!(deepest(&[huge], &disc).unwrap_err().field(), "curves");
}

#[test]
fn sphere_grasps_of_the_section5_gripper() {
    // real grasps: the Sec. 5 gripper holding spheres at the friction limit;
    // the mid-plane in the gripper frame against the sphere of the grasp
    use fpc::{Gripper, GripperParams};
    let gripper = Gripper::paper(0.25, 8, GripperParams::default()).unwrap();
    let to_gripper = finger_to_gripper_map(gripper.mounting_angle(), gripper.palm()).unwrap();
    let finger = gripper.finger();
    let mut checked = 0;
    for (r, beta) in [
        (20.0, 0.2),
        (30.0, 0.5),
        (40.0, 0.9),
        (25.0, -0.3),
        (50.0, 1.2),
    ] {
        let Ok(sg) = gripper.sphere_grasp_at_friction_limit(0.0, r, beta, None) else {
            continue;
        };
        if sg.radius <= 0.0 {
            continue;
        }
        let label = format!("r {r} beta {beta}: {:?}", sg.invalid());
        let curves: Vec<PolyCurve> = finger
            .midplane_curves(&sg.grasp.solution.coefficients)
            .unwrap()
            .iter()
            .map(|c| c.map(to_gripper))
            .collect();
        let sphere = Obstacle::disc(sg.center, sg.radius).unwrap();
        let n = curves.len();
        // the tip touches by construction
        let tip = curves[n - 1].end();
        assert!(
            sphere.depth(tip).abs() <= 1e-9,
            "{label}: tip depth {:e}",
            sphere.depth(tip)
        );
        let all = deepest(&curves, &sphere).unwrap();
        assert!(all.depth >= sphere.depth(tip) - 1e-12, "{label}");
        let depths = sampled_depths(&curves, &sphere);
        check_against_samples(&label, &curves, &sphere, &all, &depths, &|_, _| true);
        let kept = apart_from_samples(&depths, n - 1, SAMPLES);
        match deepest_apart_from(&curves, &sphere, n - 1, curves[n - 1].length()).unwrap() {
            Some(second) => {
                check_against_samples(&label, &curves, &sphere, &second, &depths, &|e, i| {
                    kept[e][i]
                });
                eprintln!(
                    "sphere r {r} beta {beta}: deepest {:e} mm (element {}), apart from the tip {:e} mm (element {} x {:.4})",
                    all.depth, all.element, second.depth, second.element, second.x
                );
            }
            None => {
                assert!(!kept.iter().flatten().any(|&b| b), "{label}");
                eprintln!(
                    "sphere r {r} beta {beta}: deepest {:e} mm at the tip, nothing apart from it",
                    all.depth
                );
            }
        }
        // the grasp's verdict: a second contact only where the sphere
        // reaches deeper than the contact tolerance (checked above against
        // 10^5 samples per element), and any such reach is a contact rule
        // (a second contact, or the finger entering the sphere at its tip)
        let rules = &sg.grasp.verdict.rules;
        let deep = all.depth > fpc::gripper::CONTACT_TOL_MM;
        if matches!(rules, Some(fpc::gripper::Invalid::SecondContact { .. })) {
            assert!(deep, "{label}: deepest {:e}", all.depth);
        }
        if deep {
            assert!(
                matches!(
                    rules,
                    Some(
                        fpc::gripper::Invalid::SecondContact { .. }
                            | fpc::gripper::Invalid::TipEntry { .. }
                    )
                ),
                "{label}: deepest {:e}",
                all.depth
            );
        }
        checked += 1;
    }
    assert!(checked >= 3, "only {checked} grasps");
}
