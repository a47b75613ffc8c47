//! Exact clearances between the finger's mid-plane and an object, on the
//! continuous curve (docs/model.md section 5.4, "Validity of a grasp").
//!
//! The mid-plane is one polynomial curve per element
//! ([`Finger::midplane_curves`](crate::Finger::midplane_curves), in the
//! finger frame; [`PolyCurve::map`] takes it to any other, such as the
//! gripper frame of M15). The object is, in the finger's plane, either
//!
//! - a **half-plane** (a cuboid's face): the line through a point with an
//!   outward unit normal `n`, the object on the side `n . (q - point) < 0`,
//!   so a point `q` lies `depth(q) = -n . (q - point)` deep in it; or
//! - a **disc** (a sphere's section): centre `c`, radius `r`, `depth(q) =
//!   r - |q - c|`.
//!
//! Positive depth is inside the object, negative depth a clearance.
//! [`deepest`] gives the maximum of the depth over the whole curve set,
//! with the element, the local coordinate and the point where it occurs.
//!
//! **Method.** On element `i`, with `s = x / L_i` in `[0, 1]`, the depth is
//! a monotone function of one polynomial `h(s)`: `h = n . (q - point)` for
//! the half-plane (depth `-h`) and `h = |q - c|^2` for the disc (depth `r -
//! sqrt(h)`), of degree `D` and `2 D` for a mid-plane of degree `D` (both
//! shipped models: `D = 3`). The deepest point is where `h` is smallest,
//! and `h`'s minimum over an interval is found exactly, without sampling,
//! by a branch and bound on its Bernstein coefficients (the private
//! `bernstein` module): the coefficients on an interval bound `h` from
//! below there, and their differences (the derivative's coefficients)
//! count the critical points inside it (Descartes' rule of signs in the
//! Bernstein basis). An interval whose bound cannot beat the best value
//! found so far is dropped; one on which `h` is monotone contributes its
//! ends; one holding a single critical point contributes that point,
//! found by Newton's method on `h'` kept inside the bracket (to the
//! resolution of `f64`); any other interval is halved. Every element's
//! ends are candidates first, so an element whose bound on `[0, 1]`
//! cannot beat them costs one basis change and nothing more. The reported
//! depth is within [`DEPTH_TOLERANCE_MM`] of the true maximum (plus the
//! rounding of `h`, about `1e-16` of the curve's size squared over the
//! radius for the disc), and a strict interior maximum is located to the
//! resolution of `f64` in `x`.
//!
//! **The contact itself.** The tip touches the object by construction, so
//! the maximum over the whole finger is at least the tip's depth (0 to
//! rounding): "no penetration beyond 1e-9 mm" is `deepest(..).depth <=
//! 1e-9`, whatever the finger does near the tip. To look for a *second*
//! contact, [`deepest_apart_from`] leaves out the given point's own
//! contact: the arc through it along which the depth falls monotonically
//! away from it. Where the finger approaches the point from inside the
//! object (the depth rises away from it), nothing is left out on that side,
//! so the penetration there is found, never hidden.

mod bernstein;

use crate::error::{finite, positive, InputError};
use crate::field::Field;
use crate::finger::PolyCurve;

use bernstein::{derivatives, restrict, to_bernstein, Best, Search};

/// How far below the true maximum the reported depth may be (mm): an
/// interval is not searched further once it cannot hold a point deeper
/// than the best one by more than this.
pub const DEPTH_TOLERANCE_MM: f64 = 1e-13;

/// The part of the parameter next to the point [`deepest_apart_from`]
/// starts from (per unit of the element) in which a critical point is not
/// looked for: depth varies there only to second order in it, about
/// `1e-16` of the element's size.
const EXCLUSION_GAP: f64 = 1e-8;

/// Two curves continue one another when the end of one is this close to
/// the start of the next (relative to the size of the point, mm).
const JOIN_TOLERANCE: f64 = 1e-9;

/// The object, as the finger's plane cuts it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Obstacle {
    #[serde(flatten)]
    shape: Shape,
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum Shape {
    HalfPlane {
        #[serde(rename = "point_mm")]
        point: [f64; 2],
        normal: [f64; 2],
    },
    Disc {
        #[serde(rename = "center_mm")]
        center: [f64; 2],
        #[serde(rename = "radius_mm")]
        radius: f64,
    },
}

impl Obstacle {
    /// A cuboid's face: the line through `point` with the outward normal
    /// `normal` (any non-zero length; it is normalised), the object on the
    /// side `normal . (q - point) < 0`.
    pub fn half_plane(point: [f64; 2], normal: [f64; 2]) -> Result<Obstacle, InputError> {
        finite(Field::key("half_plane.point[0]"), point[0])?;
        finite(Field::key("half_plane.point[1]"), point[1])?;
        finite(Field::key("half_plane.normal[0]"), normal[0])?;
        finite(Field::key("half_plane.normal[1]"), normal[1])?;
        let len = normal[0].hypot(normal[1]);
        if !(len > 0.0 && len.is_finite()) {
            return Err(InputError::OutOfRange {
                field: Field::key("half_plane.normal"),
                value: len,
                rule: "must be a non-zero direction".into(),
            });
        }
        Ok(Obstacle {
            shape: Shape::HalfPlane {
                point,
                normal: [normal[0] / len, normal[1] / len],
            },
        })
    }

    /// A sphere's section: the disc of `radius` (positive) about `center`.
    pub fn disc(center: [f64; 2], radius: f64) -> Result<Obstacle, InputError> {
        finite(Field::key("disc.center[0]"), center[0])?;
        finite(Field::key("disc.center[1]"), center[1])?;
        positive(Field::key("disc.radius"), radius)?;
        Ok(Obstacle {
            shape: Shape::Disc { center, radius },
        })
    }

    /// How deep `q` lies in the object (mm; negative: outside, the
    /// clearance).
    pub fn depth(&self, q: [f64; 2]) -> f64 {
        match self.shape {
            Shape::HalfPlane { point, normal } => {
                -(normal[0] * (q[0] - point[0]) + normal[1] * (q[1] - point[1]))
            }
            Shape::Disc { center, radius } => radius - (q[0] - center[0]).hypot(q[1] - center[1]),
        }
    }

    /// `h(q)`, the quantity whose minimum is the deepest point.
    #[inline]
    fn h(&self, q: [f64; 2]) -> f64 {
        match self.shape {
            Shape::HalfPlane { point, normal } => {
                normal[0] * (q[0] - point[0]) + normal[1] * (q[1] - point[1])
            }
            Shape::Disc { center, .. } => {
                let (dx, dz) = (q[0] - center[0], q[1] - center[1]);
                dx * dx + dz * dz
            }
        }
    }

    /// The tolerance on `h` that stands for [`DEPTH_TOLERANCE_MM`] of depth
    /// near `h`.
    #[inline]
    fn h_tolerance(&self, h: f64) -> f64 {
        match self.shape {
            Shape::HalfPlane { .. } => DEPTH_TOLERANCE_MM,
            // depth = r - sqrt(h): d depth = dh / (2 sqrt(h))
            Shape::Disc { .. } => 2.0 * h.max(0.0).sqrt() * DEPTH_TOLERANCE_MM,
        }
    }

    /// `h(q(s L))` in ascending powers of `s`, into `out` (`f` a buffer).
    fn h_polynomial(&self, curve: &PolyCurve, out: &mut Vec<f64>, f: &mut Vec<[f64; 2]>) {
        let l = curve.length();
        let c = curve.coefficients();
        out.clear();
        match self.shape {
            Shape::HalfPlane { point, normal } => {
                let mut lj = 1.0;
                for (j, cj) in c.iter().enumerate() {
                    let (x, z) = if j == 0 {
                        (cj[0] - point[0], cj[1] - point[1])
                    } else {
                        (cj[0], cj[1])
                    };
                    out.push((normal[0] * x + normal[1] * z) * lj);
                    lj *= l;
                }
            }
            Shape::Disc { center, .. } => {
                // f_j = (c_j - [center if j = 0]) L^j; h = |sum_j f_j s^j|^2
                let d = c.len() - 1;
                out.resize(2 * d + 1, 0.0);
                f.clear();
                let mut lj = 1.0;
                for (j, cj) in c.iter().enumerate() {
                    let v = if j == 0 {
                        [cj[0] - center[0], cj[1] - center[1]]
                    } else {
                        [cj[0], cj[1]]
                    };
                    f.push([v[0] * lj, v[1] * lj]);
                    lj *= l;
                }
                for i in 0..=d {
                    out[2 * i] += f[i][0] * f[i][0] + f[i][1] * f[i][1];
                    for k in i + 1..=d {
                        out[i + k] += 2.0 * (f[i][0] * f[k][0] + f[i][1] * f[k][1]);
                    }
                }
            }
        }
    }
}

/// The deepest point of a curve set in an object.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Deepest {
    /// The depth (mm): positive inside the object, negative a clearance.
    #[serde(rename = "depth_mm")]
    pub depth: f64,
    /// The curve (element) it lies on, from 0.
    pub element: usize,
    /// The local coordinate on that curve, in `[0, L]` (mm).
    #[serde(rename = "x_mm")]
    pub x: f64,
    /// The point, in the curves' frame (mm).
    #[serde(rename = "point_mm")]
    pub point: [f64; 2],
}

/// The parts of each curve searched, in the unit parameter `s = x / L`.
type Parts = Vec<Vec<(f64, f64)>>;

/// Buffers reused across the elements of one search.
#[derive(Default)]
struct Work {
    search: Search,
    power: Vec<f64>,
    offsets: Vec<[f64; 2]>,
    bern: Vec<f64>,
    part: Vec<f64>,
    scratch: Vec<f64>,
}

impl Work {
    /// `h` of `curve` in powers of `s` and in the Bernstein basis on [0, 1].
    fn prepare(&mut self, obstacle: &Obstacle, curve: &PolyCurve) -> Result<(), InputError> {
        obstacle.h_polynomial(curve, &mut self.power, &mut self.offsets);
        if !self.power.iter().all(|v| v.is_finite()) {
            return Err(overflow());
        }
        let n1 = self.power.len();
        self.bern.resize(n1, 0.0);
        self.part.resize(n1, 0.0);
        self.scratch.resize(2 * n1, 0.0);
        to_bernstein(&self.power, &mut self.bern);
        Ok(())
    }

    /// `h`'s Bernstein coefficients on `[lo, hi]` into `part`.
    fn restrict(&mut self, lo: f64, hi: f64) {
        restrict(&self.bern, lo, hi, &mut self.part, &mut self.scratch);
    }
}

fn overflow() -> InputError {
    InputError::Inconsistent {
        field: Field::key("curves"),
        rule: "the curves are too large for their distance to the object to be computed".into(),
    }
}

/// The deepest point of `curves` in `obstacle`: the maximum of the depth
/// over every point of every curve (each over its whole `[0, L]`), the
/// curve it lies on, its local coordinate and the point (see the module
/// documentation for the method and its accuracy). Fails on an empty set.
pub fn deepest(curves: &[PolyCurve], obstacle: &Obstacle) -> Result<Deepest, InputError> {
    let parts: Parts = vec![vec![(0.0, 1.0)]; curves.len()];
    search(curves, obstacle, &parts)?.ok_or_else(|| InputError::Inconsistent {
        field: Field::key("curves"),
        rule: "there is no curve to measure".into(),
    })
}

/// The deepest point of `curves` in `obstacle` apart from the contact at
/// local coordinate `x` of curve `element` (the tip: the last curve at its
/// length): every point except the arc through that point along which the
/// depth falls monotonically away from it, on each side, and continued
/// across the joints of curves that meet end to start. On a side where the
/// depth does not fall away from the point (the curve comes to it from
/// deeper inside the object, or runs along the object's surface), nothing
/// is left out, so such a penetration is reported. `None` when nothing is
/// left (the depth falls monotonically from the point over the whole set).
pub fn deepest_apart_from(
    curves: &[PolyCurve],
    obstacle: &Obstacle,
    element: usize,
    x: f64,
) -> Result<Option<Deepest>, InputError> {
    let Some(curve) = curves.get(element) else {
        return Err(InputError::OutOfRange {
            field: Field::key("element"),
            value: element as f64,
            rule: format!("must be below the number of curves ({})", curves.len()),
        });
    };
    finite(Field::key("x"), x)?;
    let l = curve.length();
    if !(0.0..=l).contains(&x) {
        return Err(InputError::OutOfRange {
            field: Field::key("x"),
            value: x,
            rule: format!("must lie in the curve's range [0, {l}]"),
        });
    }
    let s0 = (x / l).min(1.0);
    let mut work = Work::default();
    // what is kept of each curve the arc reaches: replaced, not added to
    let mut touched: Vec<(usize, Vec<(f64, f64)>)> = Vec::with_capacity(4);
    let mut keep =
        |e: usize, part: Option<(f64, f64)>| match touched.iter_mut().find(|(t, _)| *t == e) {
            Some((_, parts)) => parts.extend(part),
            None => touched.push((e, part.into_iter().collect())),
        };
    for forward in [false, true] {
        let (mut e, mut from) = (element, s0);
        loop {
            work.prepare(obstacle, &curves[e])?;
            let end = arc_end(&mut work, from, forward);
            keep(
                e,
                match end {
                    ArcEnd::NoSide | ArcEnd::Through => None,
                    ArcEnd::Stays if forward => Some((from, 1.0)),
                    ArcEnd::Stays => Some((0.0, from)),
                    ArcEnd::At(sc) if forward => Some((sc, 1.0)),
                    ArcEnd::At(sc) => Some((0.0, sc)),
                },
            );
            if !matches!(end, ArcEnd::Through | ArcEnd::NoSide) {
                break;
            }
            // the arc reaches this curve's end on this side (or the point
            // is that end): on to the next curve if it continues this one
            let next = if forward {
                (e + 1 < curves.len()).then_some(e + 1)
            } else {
                e.checked_sub(1)
            };
            let Some(n) = next else { break };
            let (a, b) = if forward {
                (curves[e].end(), curves[n].start())
            } else {
                (curves[n].end(), curves[e].start())
            };
            let gap = (a[0] - b[0]).hypot(a[1] - b[1]);
            if gap > JOIN_TOLERANCE * (1.0 + a[0].abs().max(a[1].abs())) {
                break;
            }
            e = n;
            from = if forward { 0.0 } else { 1.0 };
        }
    }
    let mut parts: Parts = vec![vec![(0.0, 1.0)]; curves.len()];
    for (e, p) in touched {
        parts[e] = p;
    }
    search(curves, obstacle, &parts)
}

/// The deepest point of `curves` in a cuboid held at its edge: the
/// half-plane of outward normal `normal` through `point` (the face, the
/// contact on it), cut to the side `along . (q - point) >= 0` (the face
/// runs from the contact in direction `along`; above the contact there is
/// no object). Its depth is the one into the face. `None` when no part of
/// the curves lies on that side. Exact like [`deepest`]: the parts of each
/// curve on that side are bounded by the roots of `along . (q - point)`,
/// a polynomial in the curve's parameter.
pub fn deepest_below(
    curves: &[PolyCurve],
    point: [f64; 2],
    normal: [f64; 2],
    along: [f64; 2],
) -> Result<Option<Deepest>, InputError> {
    let face = Obstacle::half_plane(point, normal)?;
    finite(Field::key("along[0]"), along[0])?;
    finite(Field::key("along[1]"), along[1])?;
    let mut parts: Parts = Vec::with_capacity(curves.len());
    for curve in curves {
        let l = curve.length();
        let mut g = Vec::with_capacity(curve.coefficients().len());
        let mut lj = 1.0;
        for (j, c) in curve.coefficients().iter().enumerate() {
            let v = if j == 0 {
                [c[0] - point[0], c[1] - point[1]]
            } else {
                *c
            };
            g.push((along[0] * v[0] + along[1] * v[1]) * lj);
            lj *= l;
        }
        if !g.iter().all(|v| v.is_finite()) {
            return Err(overflow());
        }
        let mut cuts = vec![0.0];
        cuts.extend(bernstein::roots(&g));
        cuts.push(1.0);
        let below: Vec<(f64, f64)> = cuts
            .windows(2)
            .filter(|w| bernstein::value(&g, 0.5 * (w[0] + w[1])) >= 0.0)
            .map(|w| (w[0], w[1]))
            .collect();
        parts.push(below);
    }
    search(curves, &face, &parts)
}

/// Where the arc on which `h` rises away from `s = from` ends, on one side.
#[derive(Debug, Clone, Copy, PartialEq)]
enum ArcEnd {
    /// The curve has no part on this side of the point.
    NoSide,
    /// `h` does not rise away from the point on this side: nothing is left out.
    Stays,
    /// `h` rises up to a critical point at this `s`.
    At(f64),
    /// `h` rises to the curve's end on this side.
    Through,
}

fn arc_end(work: &mut Work, from: f64, forward: bool) -> ArcEnd {
    if (forward && from >= 1.0) || (!forward && from <= 0.0) {
        return ArcEnd::NoSide;
    }
    let (lo, hi) = if forward {
        ((from + EXCLUSION_GAP).min(1.0), 1.0)
    } else {
        (0.0, (from - EXCLUSION_GAP).max(0.0))
    };
    let critical = if hi > lo {
        work.restrict(lo, hi);
        let n1 = work.power.len();
        work.search
            .nearest_critical(&work.power, &work.part[..n1], lo, hi, forward)
    } else {
        None
    };
    // h' keeps its sign between the point and the critical point
    let far = critical.unwrap_or(if forward { 1.0 } else { 0.0 });
    let probe = if hi > lo {
        if forward {
            0.5 * (lo + far)
        } else {
            0.5 * (far + hi)
        }
    } else {
        0.5 * (from + far)
    };
    let (slope, _) = derivatives(&work.power, probe);
    let rises = if forward { slope > 0.0 } else { slope < 0.0 };
    match (rises, critical) {
        (false, _) => ArcEnd::Stays,
        (true, Some(sc)) => ArcEnd::At(sc),
        (true, None) => ArcEnd::Through,
    }
}

/// The deepest point over the given parts of the curves; `None` when no
/// part is given.
fn search(
    curves: &[PolyCurve],
    obstacle: &Obstacle,
    parts: &Parts,
) -> Result<Option<Deepest>, InputError> {
    let mut best = Best::none();
    // every part's ends first: exact values that prune whole elements
    for (e, (curve, ps)) in curves.iter().zip(parts).enumerate() {
        for &(lo, hi) in ps {
            for s in [lo, hi] {
                let h = obstacle.h(curve.point(s * curve.length()));
                if !h.is_finite() {
                    return Err(overflow());
                }
                best.consider(h, s, e);
            }
        }
    }
    if best.tag == usize::MAX {
        return Ok(None);
    }
    let mut work = Work::default();
    let tol = |h: f64| obstacle.h_tolerance(h);
    for (e, (curve, ps)) in curves.iter().zip(parts).enumerate() {
        if ps.is_empty() {
            continue;
        }
        work.prepare(obstacle, curve)?;
        let n1 = work.power.len();
        for &(lo, hi) in ps {
            work.restrict(lo, hi);
            let part = &work.part[..n1];
            let bound = part.iter().copied().fold(f64::INFINITY, f64::min);
            if bound >= best.value {
                continue;
            }
            work.search
                .minimise(&work.power, part, (lo, hi), e, &mut best, &tol);
        }
    }
    let curve = &curves[best.tag];
    let x = (best.s * curve.length()).clamp(0.0, curve.length());
    let point = curve.point(x);
    Ok(Some(Deepest {
        depth: obstacle.depth(point),
        element: best.tag,
        x,
        point,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obstacles_serialize_with_their_kind_and_units() {
        let d = Obstacle::disc([1.0, 2.0], 3.0).unwrap();
        assert_eq!(
            serde_json::to_string(&d).unwrap(),
            r#"{"kind":"disc","center_mm":[1.0,2.0],"radius_mm":3.0}"#
        );
        let h = Obstacle::half_plane([0.0, 1.0], [0.0, -2.0]).unwrap();
        assert_eq!(
            serde_json::to_string(&h).unwrap(),
            r#"{"kind":"half_plane","point_mm":[0.0,1.0],"normal":[0.0,-1.0]}"#
        );
    }

    #[test]
    fn a_single_point_curve_and_a_constant_depth() {
        // degree 0: the curve is one point
        let p = PolyCurve::new(vec![[3.0, 4.0]], 2.0).unwrap();
        let d = deepest(&[p], &Obstacle::disc([0.0, 0.0], 6.0).unwrap()).unwrap();
        assert_eq!((d.depth, d.point), (1.0, [3.0, 4.0]));
        // a segment along a face: depth 0 everywhere, nothing falls away
        let s = PolyCurve::new(vec![[0.0, 0.0], [1.0, 0.0]], 5.0).unwrap();
        let face = Obstacle::half_plane([0.0, 0.0], [0.0, 1.0]).unwrap();
        let d = deepest(std::slice::from_ref(&s), &face).unwrap();
        assert_eq!(d.depth, 0.0);
        let apart = deepest_apart_from(&[s], &face, 0, 5.0).unwrap().unwrap();
        assert_eq!(apart.depth, 0.0);
    }
}
