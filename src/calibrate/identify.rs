//! What the data determine: the covariance of the fitted values, their
//! correlations, and the singular values of the column-scaled Jacobian
//! with a verdict naming the combination of parameters the data leave
//! badly determined.
//!
//! With `J` the Jacobian of the weighted residuals at the fit, each column
//! is divided by its norm (`J_s = J S^-1`, so that no unit or size of a
//! parameter decides), and `J_s = U Sigma V^T`. A singular value small
//! against the largest means that moving the parameters along the right
//! singular vector `v` (in the scaled unknowns, `dtheta_k = v_k / S_k`
//! per unit) changes the fit by only that much: the data determine that
//! combination badly. The covariance is `(J^T J)^-1 = S^-1 V Sigma^-2 V^T
//! S^-1`; it does not exist when a singular value vanishes.

use nalgebra::DMatrix;
use serde::Serialize;

/// Below this ratio to the largest singular value a direction is not
/// identifiable (zero to the rounding of the exact Jacobian).
pub const UNIDENTIFIABLE_RATIO: f64 = 1e-7;
/// Below this ratio a direction is poorly determined: its standard error
/// exceeds the best determined one's by more than a factor 1000.
pub const POORLY_DETERMINED_RATIO: f64 = 1e-3;

/// The verdict on the data's power over the parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Every direction is determined.
    Identifiable,
    /// The weakest direction's singular value is below
    /// [`POORLY_DETERMINED_RATIO`] of the largest.
    PoorlyDetermined,
    /// The weakest is below [`UNIDENTIFIABLE_RATIO`]: the data cannot tell
    /// that combination of parameters apart.
    NotIdentifiable,
}

/// One parameter's share of a weak direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Component {
    /// The unknown's label.
    pub name: String,
    /// Its entry of the right singular vector (scaled unknowns).
    pub weight: f64,
    /// The change of the parameter, in its unit, per unit along the
    /// direction (`weight / column norm`).
    pub per_unit: f64,
}

/// The identifiability analysis.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identifiability {
    /// The Jacobian's column norms (the scaling).
    pub column_norms: Vec<f64>,
    /// Singular values of the column-scaled Jacobian, largest first.
    pub singular_values: Vec<f64>,
    /// The smallest over the largest.
    pub ratio: f64,
    /// The verdict.
    pub verdict: Verdict,
    /// The weakest direction's dominant parameters (entries of at least a
    /// fifth of the largest, largest first).
    pub weakest: Vec<Component>,
    /// The verdict in words.
    pub message: String,
}

/// The analysis of Jacobian `j` (rows by unknowns) with unknowns `names`,
/// and the covariance `(J^T J)^-1` where it exists.
pub(crate) fn analyse(
    j: &DMatrix<f64>,
    names: &[String],
) -> (Identifiability, Option<DMatrix<f64>>) {
    let n = j.ncols();
    let norms: Vec<f64> = (0..n).map(|k| j.column(k).norm()).collect();
    let mut js = j.clone();
    for (k, &s) in norms.iter().enumerate() {
        let f = if s > 0.0 { 1.0 / s } else { 0.0 };
        js.column_mut(k).scale_mut(f);
    }
    // the thin SVD of J_s (its right vectors only)
    let svd = js.clone().svd(false, true);
    let v_t = svd.v_t.clone().unwrap_or_else(|| DMatrix::identity(n, n));
    let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
    order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
    let sv: Vec<f64> = order.iter().map(|&i| svd.singular_values[i]).collect();
    // fewer rows than unknowns: the missing singular values are zero
    let mut sv_full = sv.clone();
    sv_full.resize(n, 0.0);
    let largest = sv_full.first().copied().unwrap_or(0.0);
    let smallest = sv_full.last().copied().unwrap_or(0.0);
    let ratio = if largest > 0.0 {
        smallest / largest
    } else {
        0.0
    };
    let verdict = if ratio < UNIDENTIFIABLE_RATIO {
        Verdict::NotIdentifiable
    } else if ratio < POORLY_DETERMINED_RATIO {
        Verdict::PoorlyDetermined
    } else {
        Verdict::Identifiable
    };
    // the weakest direction
    let weak: Vec<f64> = if norms.contains(&0.0) {
        // a parameter the data do not see at all
        (0..n)
            .map(|k| if norms[k] == 0.0 { 1.0 } else { 0.0 })
            .collect()
    } else if sv.len() < n {
        // rank-deficient by shape: any null vector of J_s
        null_vector(&js)
    } else {
        let i = *order.last().unwrap_or(&0);
        (0..n).map(|k| v_t[(i, k)]).collect()
    };
    let big = weak.iter().fold(0.0f64, |m, w| m.max(w.abs()));
    let mut weakest: Vec<Component> = (0..n)
        .filter(|&k| big > 0.0 && weak[k].abs() >= 0.2 * big)
        .map(|k| Component {
            name: names[k].clone(),
            weight: weak[k],
            per_unit: if norms[k] > 0.0 {
                weak[k] / norms[k]
            } else {
                0.0
            },
        })
        .collect();
    weakest.sort_by(|a, b| b.weight.abs().total_cmp(&a.weight.abs()));
    let combo = weakest
        .iter()
        .map(|c| format!("{:+.3} {}", c.weight, c.name))
        .collect::<Vec<_>>()
        .join(" ");
    let message = match verdict {
        Verdict::Identifiable => format!(
            "identifiable: the smallest singular value of the scaled Jacobian is {ratio:.2e} of the largest; the weakest combination is {combo}"
        ),
        Verdict::PoorlyDetermined => format!(
            "poorly determined: the combination {combo} (scaled parameters) moves the fit by only {ratio:.2e} of the best determined one; its parameters' errors are large and strongly correlated"
        ),
        Verdict::NotIdentifiable => format!(
            "not identifiable: the data cannot tell apart the combination {combo} (scaled parameters; singular value ratio {ratio:.2e}); fix one of {} or add data that separates them",
            weakest.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", ")
        ),
    };
    // the covariance, where it exists
    let cov = if verdict == Verdict::NotIdentifiable || sv.len() < n {
        None
    } else {
        let mut c = DMatrix::<f64>::zeros(n, n);
        for (idx, &i) in order.iter().enumerate() {
            let s2 = sv[idx] * sv[idx];
            for a in 0..n {
                for b in 0..n {
                    c[(a, b)] += v_t[(i, a)] * v_t[(i, b)] / s2;
                }
            }
        }
        for a in 0..n {
            for b in 0..n {
                c[(a, b)] /= norms[a] * norms[b];
            }
        }
        c.iter().all(|v| v.is_finite()).then_some(c)
    };
    (
        Identifiability {
            column_norms: norms,
            singular_values: sv_full,
            ratio,
            verdict,
            weakest,
            message,
        },
        cov,
    )
}

/// A unit vector of the null space of a matrix with fewer rows than
/// columns (the last right singular vector of the square, padded matrix).
fn null_vector(js: &DMatrix<f64>) -> Vec<f64> {
    let n = js.ncols();
    let mut sq = DMatrix::<f64>::zeros(n, n);
    sq.rows_mut(0, js.nrows().min(n))
        .copy_from(&js.rows(0, js.nrows().min(n)));
    let svd = sq.svd(false, true);
    let v_t = svd.v_t.unwrap_or_else(|| DMatrix::identity(n, n));
    let i = (0..n)
        .min_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]))
        .unwrap_or(0);
    (0..n).map(|k| v_t[(i, k)]).collect()
}
