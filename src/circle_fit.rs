//! Least-squares circle fit of planar points (the radius of curvature the
//! paper reports, Sec. 6.2).
//!
//! An algebraic (Kasa) fit on centred data gives the start; a few Newton
//! steps on the geometric distances `|p - c| - r` refine it (Gauss-Newton
//! where the exact Hessian is not positive definite).
//! Nearly collinear points have no meaningful circle: the fit returns `None`.
//!
//! The fit's radius has a derivative with respect to the points
//! (`radius_tangents`, by implicit differentiation of the fit's optimum):
//! the calibration's Jacobian and a scene's radius error bar share it.

/// A fitted circle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle {
    /// Centre (X, Z).
    pub center: [f64; 2],
    /// Radius.
    pub radius: f64,
    /// Root-mean-square geometric residual.
    pub rms: f64,
}

fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let m = nalgebra::Matrix3::from_fn(|i, j| a[i][j]);
    let v = nalgebra::Vector3::from_column_slice(&b);
    let x = m.lu().solve(&v)?;
    x.iter().all(|t| t.is_finite()).then(|| [x[0], x[1], x[2]])
}

/// The solution of `a x = b` for a positive definite `a` (Cholesky);
/// `None` when `a` is not.
fn solve3_definite(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let m = nalgebra::Matrix3::from_fn(|i, j| a[i][j]);
    let x = m
        .cholesky()?
        .solve(&nalgebra::Vector3::from_column_slice(&b));
    x.iter().all(|t| t.is_finite()).then(|| [x[0], x[1], x[2]])
}

/// Most refinement steps of the geometric fit.
const MAX_REFINEMENTS: usize = 20;

/// Fits a circle to at least three points. Returns `None` when the points
/// are (numerically) collinear: the radius would exceed `1e6` times their extent.
pub fn fit_circle(points: &[[f64; 2]]) -> Option<Circle> {
    if points.len() < 3
        || points
            .iter()
            .any(|p| !p[0].is_finite() || !p[1].is_finite())
    {
        return None;
    }
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p[0]).sum::<f64>() / n;
    let mz = points.iter().map(|p| p[1]).sum::<f64>() / n;
    // (the square root of the largest square is the largest root)
    let extent = points
        .iter()
        .map(|p| (p[0] - mx).powi(2) + (p[1] - mz).powi(2))
        .fold(0.0f64, f64::max)
        .sqrt();
    if extent == 0.0 {
        return None;
    }
    // centred, scaled coordinates (at most unit size: plain square roots
    // do not overflow)
    let s = 1.0 / extent;
    let q: Vec<[f64; 2]> = points
        .iter()
        .map(|p| [(p[0] - mx) * s, (p[1] - mz) * s])
        .collect();
    // Kasa: minimise sum (u^2 + v^2 + D u + E v + F)^2
    let (mut uu, mut uv, mut vv, mut su, mut sv) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let mut b = [0.0; 3];
    for &[u, v] in &q {
        let rhs = -(u * u + v * v);
        uu += u * u;
        uv += u * v;
        vv += v * v;
        su += u;
        sv += v;
        b[0] += u * rhs;
        b[1] += v * rhs;
        b[2] += rhs;
    }
    let a = [[uu, uv, su], [uv, vv, sv], [su, sv, n]];
    let [d, e, f] = solve3(a, b)?;
    let (mut cu, mut cv) = (-d / 2.0, -e / 2.0);
    let r2 = cu * cu + cv * cv - f;
    if r2.is_nan() || r2 <= 0.0 {
        return None;
    }
    let mut r = r2.sqrt();
    if r > 1e6 {
        return None;
    }
    // geometric refinement: Newton on F = 1/2 sum (|q - c| - r)^2 with its
    // exact Hessian (the derivative section below), quadratic near the
    // fit, and a Gauss-Newton step wherever that Hessian is not positive
    // definite. With `w = (q - c) / d` the Gauss-Newton part is `sum [[w
    // w^T, w], [w^T, 1]]`, the curvature `sum e (I - w w^T) / d`.
    let mut last = f64::INFINITY;
    for _ in 0..MAX_REFINEMENTS {
        let (mut ww, mut wz, mut zz, mut sw, mut sz, mut count) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let (mut cww, mut cwz, mut czz) = (0.0, 0.0, 0.0);
        let mut rhs = [0.0; 3];
        for &[u, v] in &q {
            let (du, dv) = (u - cu, v - cv);
            let d2 = du * du + dv * dv;
            if d2 == 0.0 {
                continue;
            }
            let dist = d2.sqrt();
            let inv = 1.0 / dist;
            let res = dist - r;
            let (w, z) = (du * inv, dv * inv);
            ww += w * w;
            wz += w * z;
            zz += z * z;
            sw += w;
            sz += z;
            count += 1.0;
            rhs[0] += w * res;
            rhs[1] += z * res;
            rhs[2] += res;
            let f = res * inv;
            cww += f * (1.0 - w * w);
            cwz -= f * w * z;
            czz += f * (1.0 - z * z);
        }
        let gauss = [[ww, wz, sw], [wz, zz, sz], [sw, sz, count]];
        let hessian = [
            [ww + cww, wz + cwz, sw],
            [wz + cwz, zz + czz, sz],
            [sw, sz, count],
        ];
        let newton = solve3_definite(hessian, rhs);
        let Some(step) = newton.or_else(|| solve3(gauss, rhs)) else {
            break;
        };
        cu += step[0];
        cv += step[1];
        r += step[2];
        // converged: a Newton step this small leaves a next one of about
        // its square (a few times 1e-18 here), so none is taken; or the
        // steps are rounding noise (no longer shrinking at a size Newton
        // reaches in its last step)
        let size = step.iter().map(|x| x.abs()).fold(0.0, f64::max);
        if size < 1e-14 * (1.0 + r)
            || (newton.is_some() && size < 1e-9 * (1.0 + r))
            || (size < 1e-11 * (1.0 + r) && size > 0.5 * last)
        {
            break;
        }
        last = size;
    }
    if !(r.is_finite() && r > 0.0 && r <= 1e6) {
        return None;
    }
    let rms = (q
        .iter()
        .map(|&[u, v]| (((u - cu).powi(2) + (v - cv).powi(2)).sqrt() - r).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    Some(Circle {
        center: [cu / s + mx, cv / s + mz],
        radius: r / s,
        rms: rms / s,
    })
}

// ------------------------------------------------------------ derivative

// The derivative of the least-squares circle fit (paper Sec. 4.7) with
// respect to the points, by implicit differentiation.
//
// The fit minimises `F(c, r) = 1/2 sum_k (|q_k - c| - r)^2` over the
// centre `c` and radius `r`. At its minimum the gradient `g(theta; q)`
// vanishes (`theta = (c, r)`), so a change `dq` of the points moves the
// fit by `dtheta = -H^-1 (dg/dq) dq` with `H` the full Hessian of `F` in
// `theta` (not the Gauss-Newton one: the model's mid-plane is no exact
// circle, its residuals `e_k = d_k - r` are not zero). With
// `d_k = |q_k - c|`, `u_k = (q_k - c) / d_k` and `P_k = I - u_k u_k^T`:
//
// ```text
// g     = sum_k e_k (-u_k, -1)
// H     = sum_k [[u_k u_k^T + e_k P_k / d_k, u_k], [u_k^T, 1]]
// dg    = sum_k [(-u_k, -1) (u_k . dq_k) - e_k (P_k dq_k / d_k, 0)]
// ```

/// The fitted circle and the derivative of its radius along each
/// direction of `dqs` (one derivative per point each); `None` when no
/// circle fits or the Hessian is singular.
pub(crate) fn radius_tangents(
    points: &[[f64; 2]],
    dqs: &[Vec<[f64; 2]>],
) -> Option<(Circle, Vec<f64>)> {
    let circle = fit_circle(points)?;
    let [cx, cz] = circle.center;
    let r = circle.radius;
    let mut h = nalgebra::Matrix3::<f64>::zeros();
    let mut terms = Vec::with_capacity(points.len());
    for q in points {
        let (dx, dz) = (q[0] - cx, q[1] - cz);
        let d = dx.hypot(dz);
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        let u = [dx / d, dz / d];
        let e = d - r;
        let p = [
            [1.0 - u[0] * u[0], -u[0] * u[1]],
            [-u[1] * u[0], 1.0 - u[1] * u[1]],
        ];
        for i in 0..2 {
            for j in 0..2 {
                h[(i, j)] += u[i] * u[j] + e * p[i][j] / d;
            }
            h[(i, 2)] += u[i];
            h[(2, i)] += u[i];
        }
        h[(2, 2)] += 1.0;
        terms.push((u, e, d, p));
    }
    let lu = h.lu();
    let out = dqs
        .iter()
        .map(|dq| {
            let mut dg = nalgebra::Vector3::<f64>::zeros();
            for ((u, e, d, p), dqk) in terms.iter().zip(dq) {
                let ud = u[0] * dqk[0] + u[1] * dqk[1];
                dg[0] += -u[0] * ud - e * (p[0][0] * dqk[0] + p[0][1] * dqk[1]) / d;
                dg[1] += -u[1] * ud - e * (p[1][0] * dqk[0] + p[1][1] * dqk[1]) / d;
                dg[2] += -ud;
            }
            lu.solve(&(-dg)).map(|t| t[2])
        })
        .collect::<Option<Vec<f64>>>()?;
    out.iter().all(|v| v.is_finite()).then_some((circle, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_known_arc() {
        let (cx, cz, r) = (3.0, -40.0, 40.0);
        let pts: Vec<[f64; 2]> = (0..=30)
            .map(|i| {
                let t = -1.2 + 1.5 * i as f64 / 30.0;
                [cx + r * t.cos(), cz + r * t.sin()]
            })
            .collect();
        let c = fit_circle(&pts).unwrap();
        assert!((c.radius - r).abs() < 1e-9 * r, "{c:?}");
        assert!((c.center[0] - cx).abs() < 1e-8 && (c.center[1] - cz).abs() < 1e-8);
        assert!(c.rms < 1e-9);
    }

    /// The fit is the least-squares circle: at the returned centre and
    /// radius the gradient of `F = 1/2 sum (|q - c| - r)^2` vanishes
    /// (`sum e = 0`, `sum e u = 0`) and no nearby circle has a smaller `F`,
    /// on curves far from circles: spirals of growing curvature like a
    /// pressurised finger's, with noise, from a few points to a thousand.
    #[test]
    fn the_fit_is_the_least_squares_circle() {
        let mut rng = fastrand::Rng::with_seed(31);
        for trial in 0..300 {
            let n = [3, 4, 7, 40, 257, 1000][trial % 6];
            // a curve turning by 0.2 to 6.2 rad in all, its curvature
            // growing from k0 to (1 + grow) k0 along its length
            let (turn, grow) = (0.2 + 6.0 * rng.f64(), 3.0 * rng.f64());
            let (noise, step) = (1e-3 * rng.f64(), 0.5 + 3.0 * rng.f64());
            let k0 = turn / ((1.0 + 0.5 * grow) * n as f64 * step);
            let (mut p, mut angle) = ([10.0 * rng.f64(), -5.0 * rng.f64()], rng.f64());
            let pts: Vec<[f64; 2]> = (0..n)
                .map(|i| {
                    angle += k0 * (1.0 + grow * i as f64 / n as f64) * step;
                    p = [p[0] + step * angle.cos(), p[1] + step * angle.sin()];
                    [
                        p[0] + noise * (rng.f64() - 0.5),
                        p[1] + noise * (rng.f64() - 0.5),
                    ]
                })
                .collect();
            let Some(c) = fit_circle(&pts) else { continue };
            let cost = |cx: f64, cz: f64, r: f64| -> f64 {
                pts.iter()
                    .map(|q| 0.5 * ((q[0] - cx).hypot(q[1] - cz) - r).powi(2))
                    .sum()
            };
            let (mut se, mut su) = (0.0, [0.0; 2]);
            for q in &pts {
                let (dx, dz) = (q[0] - c.center[0], q[1] - c.center[1]);
                let d = dx.hypot(dz);
                let e = d - c.radius;
                se += e;
                su[0] += e * dx / d;
                su[1] += e * dz / d;
            }
            let tol = 1e-9 * n as f64 * (c.rms + 1e-6 * c.radius);
            assert!(
                se.abs().max(su[0].abs()).max(su[1].abs()) <= tol,
                "trial {trial}: {se:e} {su:?}"
            );
            let f0 = cost(c.center[0], c.center[1], c.radius);
            for (dx, dz, dr) in [
                (1.0, 0.0, 0.0),
                (0.0, 1.0, 0.0),
                (0.0, 0.0, 1.0),
                (0.6, -0.8, 0.3),
            ] {
                for h in [1e-3, -1e-3] {
                    let hh = h * c.radius;
                    let f = cost(
                        c.center[0] + dx * hh,
                        c.center[1] + dz * hh,
                        c.radius + dr * hh,
                    );
                    assert!(f >= f0 * (1.0 - 1e-12), "trial {trial}: {f} < {f0}");
                }
            }
        }
    }

    #[test]
    fn noisy_arc_is_close_and_collinear_points_have_no_circle() {
        let mut seed = 12345u64;
        let mut noise = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 1e-3
        };
        let pts: Vec<[f64; 2]> = (0..50)
            .map(|i| {
                let t = i as f64 / 49.0 * 2.0;
                [25.0 * t.cos() + noise(), 25.0 * t.sin() + noise()]
            })
            .collect();
        let c = fit_circle(&pts).unwrap();
        assert!((c.radius - 25.0).abs() < 1e-3, "{c:?}");
        let line: Vec<[f64; 2]> = (0..10).map(|i| [i as f64, 2.0 * i as f64]).collect();
        assert!(fit_circle(&line).is_none());
        assert!(fit_circle(&line[..2]).is_none());
    }
}
