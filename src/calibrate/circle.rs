//! The derivative of the least-squares circle fit ([`fit_circle`], paper
//! Sec. 4.7) with respect to the points, by implicit differentiation.
//!
//! The fit minimises `F(c, r) = 1/2 sum_k (|q_k - c| - r)^2` over the
//! centre `c` and radius `r`. At its minimum the gradient `g(theta; q)`
//! vanishes (`theta = (c, r)`), so a change `dq` of the points moves the
//! fit by `dtheta = -H^-1 (dg/dq) dq` with `H` the full Hessian of `F` in
//! `theta` (not the Gauss-Newton one: the model's mid-plane is no exact
//! circle, its residuals `e_k = d_k - r` are not zero). With
//! `d_k = |q_k - c|`, `u_k = (q_k - c) / d_k` and `P_k = I - u_k u_k^T`:
//!
//! ```text
//! g     = sum_k e_k (-u_k, -1)
//! H     = sum_k [[u_k u_k^T + e_k P_k / d_k, u_k], [u_k^T, 1]]
//! dg    = sum_k [(-u_k, -1) (u_k . dq_k) - e_k (P_k dq_k / d_k, 0)]
//! ```

use crate::circle_fit::{fit_circle, Circle};

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
