//! Brent's one-dimensional maximiser over solves: the maximum of a function
//! that may be undefined (an invalid grasp, a failed solve) at some points.
//! It takes a closure that runs a solve, so each evaluation is expensive
//! and counted.

/// Where a maximum search ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Maximum {
    /// The best point found.
    pub x: f64,
    /// Its value.
    pub value: f64,
    /// Evaluations made (the bracket's middle point included).
    pub evaluations: usize,
}

/// Brent's method for a maximum of `f` on `[a, c]`, started from a point
/// `b` inside with `f(b)` defined and at least `f(a)`, `f(c)` (a bracket,
/// e.g. the best point of a scan and its neighbours). Parabolic steps
/// through the three best points where they stay inside the bracket and
/// shrink it fast enough, golden-section steps otherwise; a point where `f`
/// is undefined (`None`) counts as `-inf`, so the search converges to the
/// best defined point, at a constraint boundary when the maximum lies on
/// one. Stops when the bracket is shorter than `2 (tol + 1e-12 |x|)` or
/// after `max_evaluations`.
pub(crate) fn brent_max<E>(
    mut f: impl FnMut(f64) -> Result<Option<f64>, E>,
    a: f64,
    b: f64,
    c: f64,
    fb: f64,
    tol: f64,
    max_evaluations: usize,
) -> Result<Maximum, E> {
    const GOLDEN: f64 = 0.381_966_011_250_105_1; // (3 - sqrt 5) / 2
    let value = |v: Option<f64>| v.filter(|v| v.is_finite()).unwrap_or(f64::NEG_INFINITY);
    let (mut lo, mut hi) = if a < c { (a, c) } else { (c, a) };
    // x: best; w: second best; v: previous w (minimising -f, as in Brent's text)
    let (mut x, mut w, mut v) = (b, b, b);
    let (mut fx, mut fw, mut fv) = (-fb, -fb, -fb);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    let mut evaluations = 1;
    while evaluations < max_evaluations {
        let mid = 0.5 * (lo + hi);
        let tol1 = tol + 1e-12 * x.abs();
        let tol2 = 2.0 * tol1;
        if (x - mid).abs() <= tol2 - 0.5 * (hi - lo) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 && fx.is_finite() && fw.is_finite() && fv.is_finite() {
            // parabola through x, w, v
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            let e_prev = e;
            if p.abs() < (0.5 * q * e_prev).abs() && p > q * (lo - x) && p < q * (hi - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - lo < tol2 || hi - u < tol2 {
                    d = if x < mid { tol1 } else { -tol1 };
                }
                golden = false;
            }
        }
        if golden {
            e = if x < mid { hi - x } else { lo - x };
            d = GOLDEN * e;
        }
        let u = if d.abs() >= tol1 {
            x + d
        } else {
            x + tol1.copysign(d)
        };
        let fu = -value(f(u)?);
        evaluations += 1;
        if fu <= fx {
            if u < x {
                hi = x;
            } else {
                lo = x;
            }
            (v, fv) = (w, fw);
            (w, fw) = (x, fx);
            (x, fx) = (u, fu);
        } else {
            if u < x {
                lo = u;
            } else {
                hi = u;
            }
            if fu <= fw || w == x {
                (v, fv) = (w, fw);
                (w, fw) = (u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    Ok(Maximum {
        x,
        value: -fx,
        evaluations,
    })
}

/// Where a root search ended: the bracket `[x, other]` around the root's
/// sign change (`x` on the side of `f(x) <= 0`, `other` on `f > 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Root {
    /// The end of the final bracket where `f <= 0`.
    pub x: f64,
    /// The end where `f > 0`.
    pub other: f64,
    /// Evaluations made (the two given ends not counted).
    pub evaluations: usize,
}

/// Brent's method (Dekker's secant and inverse quadratic steps,
/// bisection where they do not shrink the bracket fast enough) for the
/// sign change of `f` between `a` (with `f(a) = fa <= 0`) and `b` (`fb >
/// 0`): stops when the bracket is shorter than `2 (tol + 1e-12 |x|)`, or
/// after `max_evaluations` (`None`: the bracket was not closed). A point
/// where `f` is undefined (`None`) ends the search with `None`.
pub(crate) fn brent_root<E>(
    mut f: impl FnMut(f64) -> Result<Option<f64>, E>,
    a: f64,
    fa: f64,
    b: f64,
    fb: f64,
    tol: f64,
    max_evaluations: usize,
) -> Result<Option<Root>, E> {
    if !(fa <= 0.0 && fb > 0.0) {
        return Ok(None);
    }
    // b: the latest estimate; c: the other end of the bracket; a: the
    // previous b (Brent's 1973 notation)
    let (mut a, mut fa, mut b, mut fb) = (a, fa, b, fb);
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for evaluations in 0..=max_evaluations {
        if (fb > 0.0) == (fc > 0.0) {
            (c, fc) = (a, fa);
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            (a, fa) = (b, fb);
            (b, fb) = (c, fc);
            (c, fc) = (a, fa);
        }
        let tol1 = tol + 1e-12 * b.abs();
        let m = 0.5 * (c - b);
        if m.abs() <= tol1 || fb == 0.0 {
            let (x, other) = if fb > 0.0 { (c, b) } else { (b, c) };
            // a root hit exactly: the other end is the bracket's
            return Ok(Some(Root {
                x,
                other,
                evaluations,
            }));
        }
        if evaluations == max_evaluations {
            break;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q) = if a == c {
                (2.0 * m * s, 1.0 - s)
            } else {
                let (qa, r) = (fa / fc, fb / fc);
                (
                    s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0)),
                    (qa - 1.0) * (r - 1.0) * (s - 1.0),
                )
            };
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        (a, fa) = (b, fb);
        b += if d.abs() > tol1 { d } else { tol1.copysign(m) };
        let Some(v) = f(b)?.filter(|v| v.is_finite()) else {
            return Ok(None);
        };
        fb = v;
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn max_of(f: impl Fn(f64) -> Option<f64>, a: f64, b: f64, c: f64) -> Maximum {
        let fb = f(b).unwrap();
        brent_max(|x| Ok::<_, ()>(f(x)), a, b, c, fb, 1e-12, 200).unwrap()
    }

    #[test]
    fn finds_a_smooth_interior_maximum_quickly() {
        // max of sin on [1, 2.5] at pi/2
        let m = max_of(|x| Some(x.sin()), 1.0, 1.3, 2.5);
        assert!((m.x - std::f64::consts::FRAC_PI_2).abs() < 1e-7, "{m:?}");
        assert!(m.evaluations < 30, "{m:?}");
        // a quartic with an off-centre maximum
        let m = max_of(
            |x| Some(-(x - 0.3).powi(4) - 0.1 * (x - 0.3).powi(2)),
            -1.0,
            0.0,
            2.0,
        );
        assert!((m.x - 0.3).abs() < 1e-6, "{m:?}");
    }

    #[test]
    fn converges_to_a_constraint_boundary() {
        // increasing function, undefined beyond 0.7: the maximum is the boundary
        let m = max_of(|x| (x <= 0.7).then_some(x), 0.0, 0.5, 1.0);
        assert!((m.x - 0.7).abs() < 1e-10 && m.x <= 0.7, "{m:?}");
        assert_eq!(m.value, m.x);
    }

    #[test]
    fn never_returns_an_undefined_point_and_propagates_errors() {
        let m = max_of(|x| (x.abs() < 0.2).then_some(1.0 - x * x), -1.0, 0.1, 1.0);
        assert!(m.value.is_finite() && m.x.abs() < 0.2);
        let e = brent_max(
            |_| Err::<Option<f64>, _>("solve failed"),
            0.0,
            0.5,
            1.0,
            1.0,
            1e-9,
            50,
        );
        assert_eq!(e, Err("solve failed"));
    }

    #[test]
    fn brackets_a_root_to_the_tolerance_in_few_steps() {
        // a smooth root (cube root of 2), the bracket's sides kept apart
        let mut n = 0;
        let f = |x: f64| {
            n += 1;
            Ok::<_, ()>(Some(x * x * x - 2.0))
        };
        let r = brent_root(f, 0.0, -2.0, 3.0, 25.0, 1e-12, 100)
            .unwrap()
            .unwrap();
        let root = 2f64.cbrt();
        assert!(r.x <= root && root < r.other + 1e-15, "{r:?}");
        assert!((r.other - r.x).abs() < 3e-12, "{r:?}");
        assert!(r.evaluations < 15 && r.evaluations == n, "{r:?}");
        // a kink at the root (the max of two lines) is still bracketed
        let g = |x: f64| Ok::<_, ()>(Some((2.0 * (x - 0.3)).max(0.1 * (x - 0.3))));
        let r = brent_root(g, -1.0, -0.13, 1.0, 1.4, 1e-10, 100)
            .unwrap()
            .unwrap();
        assert!(
            r.x <= 0.3 && r.other > 0.3 && r.other - r.x < 3e-10,
            "{r:?}"
        );
    }

    #[test]
    fn a_root_search_needs_a_sign_change_and_stops_on_an_undefined_point() {
        let f = |x: f64| Ok::<_, ()>(Some(x));
        assert_eq!(brent_root(f, 1.0, 1.0, 2.0, 2.0, 1e-9, 50), Ok(None));
        let g = |x: f64| Ok::<_, ()>((x < 0.5).then_some(x - 0.7));
        assert_eq!(brent_root(g, 0.0, -0.7, 1.0, 0.3, 1e-9, 50), Ok(None));
        let h = |x: f64| Ok::<_, ()>(Some(x * x * x - 2.0));
        assert_eq!(brent_root(h, 0.0, -2.0, 3.0, 25.0, 1e-12, 2), Ok(None));
    }
}
