//! The mid-plane's points and their exact derivatives along a change of
//! the element unknowns (forward mode through the chain, docs/model.md
//! M10, M14), and the circle-fit radius of the shape samples with its
//! derivative along each sensitivity ([`radius_rows`]): what the
//! calibration's Jacobian and a scene's or a study's radius error bar
//! share.
//!
//! Inside element `i` the mid-plane in the element's own frame,
//! `l_i(x; K_i) = (x + u(x), w(x))`, is affine in the element's unknowns
//! `K_i` (the displacement fields are linear in them, M1). The finger-frame
//! point is `q(x) = p_{i-1} + R(theta_i) l_i(x)`, the chain angle
//! `theta_i` the sum of the previous elements' end angles
//! `eta_j = atan2(l_j'(L_j))`, and `p_i = q(L_i)`. Along a direction `dK`:
//!
//! ```text
//! dq(x)   = dp_{i-1} + R(theta_i) (dl_i(x) + dtheta_i J l_i(x)),   J (a, b) = (-b, a)
//! deta_i  = (t_x dt_z - t_z dt_x) / |t|^2,   t = l_i'(L_i),  dt = dl_i'(L_i)
//! ```
//!
//! with `dl_i` the linear part of the affine map, exact as
//! `(l_i(K_i + s dK_i) - l_i(K_i)) / s` for any `s` (to rounding). The
//! local curves come from [`Finger::midplane_curves`](crate::Finger::midplane_curves) rotated back by their
//! own frame: an element's `x^1` coefficient points along its root tangent
//! (`w'(0) = 0` in the element's frame), which gives `theta_i`.

use crate::circle_fit::{radius_tangents, Circle};
use crate::coefficients::Coefficients;
use crate::error::InputError;
use crate::finger::Finger;

use super::record::Sensitivities;

/// The local curves of every element (the element's own frame).
fn local_curves(finger: &Finger, k: &Coefficients) -> Result<Vec<Vec<[f64; 2]>>, InputError> {
    let curves = finger.midplane_curves(k)?;
    Ok(curves
        .iter()
        .map(|c| {
            let co = c.coefficients();
            let a = co.get(1).copied().unwrap_or([1.0, 0.0]);
            let th = a[1].atan2(a[0]);
            let (s, cs) = th.sin_cos();
            co.iter()
                .enumerate()
                .map(|(j, &p)| {
                    let v = if j == 0 { [0.0, 0.0] } else { p };
                    [cs * v[0] + s * v[1], -s * v[0] + cs * v[1]]
                })
                .collect()
        })
        .collect())
}

fn eval(c: &[[f64; 2]], x: f64) -> [f64; 2] {
    c.iter()
        .rev()
        .fold([0.0, 0.0], |a, q| [a[0] * x + q[0], a[1] * x + q[1]])
}

fn slope(c: &[[f64; 2]], x: f64) -> [f64; 2] {
    c.iter()
        .enumerate()
        .skip(1)
        .rev()
        .fold([0.0, 0.0], |a, (j, q)| {
            let j = j as f64;
            [a[0] * x + j * q[0], a[1] * x + j * q[1]]
        })
}

/// Where on the finger: an element and its local coordinate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Site {
    pub element: usize,
    pub x: f64,
}

/// The site at `s` mm from the root along the undeformed mid-plane (the
/// last element holds any `s` beyond the tip, clamped to its end).
pub(crate) fn site_at(lengths: &[f64], s: f64) -> Site {
    let mut start = 0.0;
    for (i, &l) in lengths.iter().enumerate() {
        if s <= start + l || i + 1 == lengths.len() {
            return Site {
                element: i,
                x: (s - start).clamp(0.0, l),
            };
        }
        start += l;
    }
    Site { element: 0, x: 0.0 }
}

/// The shape samples [`Finger::shape`] gives: the root, then `per` points
/// per element at `x = L j / per`.
pub(crate) fn shape_sites(lengths: &[f64], per: usize) -> Vec<Option<Site>> {
    let per = per.max(1);
    let mut v = vec![None];
    for (i, &l) in lengths.iter().enumerate() {
        for j in 1..=per {
            v.push(Some(Site {
                element: i,
                x: l * j as f64 / per as f64,
            }));
        }
    }
    v
}

/// The points at `sites` (`None`: the root) and, for every direction of
/// `dks`, their derivatives: `(points, derivs[direction][site])`.
#[allow(clippy::type_complexity)]
pub(crate) fn points_and_tangents(
    finger: &Finger,
    k: &Coefficients,
    dks: &[Coefficients],
    sites: &[Option<Site>],
) -> Result<(Vec<[f64; 2]>, Vec<Vec<[f64; 2]>>), InputError> {
    let lengths = finger.element_lengths();
    let ne = lengths.len();
    let base = local_curves(finger, k)?;
    // the chain's frames
    let mut theta = vec![0.0; ne];
    let mut root = vec![[0.0; 2]; ne];
    for i in 1..ne {
        let t = slope(&base[i - 1], lengths[i - 1]);
        theta[i] = theta[i - 1] + t[1].atan2(t[0]);
        let e = eval(&base[i - 1], lengths[i - 1]);
        let (s, c) = theta[i - 1].sin_cos();
        root[i] = [
            root[i - 1][0] + c * e[0] - s * e[1],
            root[i - 1][1] + s * e[0] + c * e[1],
        ];
    }
    let point = |i: usize, l: [f64; 2]| {
        let (s, c) = theta[i].sin_cos();
        [
            root[i][0] + c * l[0] - s * l[1],
            root[i][1] + s * l[0] + c * l[1],
        ]
    };
    let points = sites
        .iter()
        .map(|st| match st {
            None => [0.0, 0.0],
            Some(st) => point(st.element, eval(&base[st.element], st.x)),
        })
        .collect();
    let mut derivs = Vec::with_capacity(dks.len());
    for dk in dks {
        let big = dk.as_slice().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if big == 0.0 {
            derivs.push(vec![[0.0; 2]; sites.len()]);
            continue;
        }
        let scale = 1e-2 / big;
        let mut moved = k.clone();
        for (m, d) in moved.as_mut_slice().iter_mut().zip(dk.as_slice()) {
            *m += scale * d;
        }
        let shifted = local_curves(finger, &moved)?;
        let lin: Vec<Vec<[f64; 2]>> = shifted
            .iter()
            .zip(&base)
            .map(|(a, b)| {
                a.iter()
                    .zip(b)
                    .map(|(p, q)| [(p[0] - q[0]) / scale, (p[1] - q[1]) / scale])
                    .collect()
            })
            .collect();
        // forward through the chain
        let mut dtheta = vec![0.0; ne];
        let mut droot = vec![[0.0; 2]; ne];
        let dpoint = |i: usize, dtheta: &[f64], droot: &[[f64; 2]], x: f64| {
            let l = eval(&base[i], x);
            let dl = eval(&lin[i], x);
            let v = [dl[0] - dtheta[i] * l[1], dl[1] + dtheta[i] * l[0]];
            let (s, c) = theta[i].sin_cos();
            [
                droot[i][0] + c * v[0] - s * v[1],
                droot[i][1] + s * v[0] + c * v[1],
            ]
        };
        for i in 1..ne {
            let t = slope(&base[i - 1], lengths[i - 1]);
            let dt = slope(&lin[i - 1], lengths[i - 1]);
            dtheta[i] = dtheta[i - 1] + (t[0] * dt[1] - t[1] * dt[0]) / (t[0] * t[0] + t[1] * t[1]);
            droot[i] = dpoint(i - 1, &dtheta, &droot, lengths[i - 1]);
        }
        derivs.push(
            sites
                .iter()
                .map(|st| match st {
                    None => [0.0, 0.0],
                    Some(st) => dpoint(st.element, &dtheta, &droot, st.x),
                })
                .collect(),
        );
    }
    Ok((points, derivs))
}

/// The circle fit of the shape samples of `coefficients` (`per` per
/// element, as [`Finger::shape`] gives them and a solve with `shape` set
/// fits) and the derivative of its radius along each row of `sens` (the
/// sensitivities of that equilibrium): `None` when no circle fits (a
/// straight mid-plane) or the fit's Hessian is singular.
pub(crate) fn radius_rows(
    finger: &Finger,
    coefficients: &Coefficients,
    sens: &Sensitivities,
    per: usize,
) -> Result<Option<(Circle, Vec<f64>)>, InputError> {
    let dks: Vec<Coefficients> = sens.rows.iter().map(|r| r.coefficients.clone()).collect();
    let sites = shape_sites(finger.element_lengths(), per);
    let (pts, dpts) = points_and_tangents(finger, coefficients, &dks, &sites)?;
    Ok(radius_tangents(&pts, &dpts))
}
