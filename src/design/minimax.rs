//! The step of the design ascent: within a box of steps (the trust region
//! cut by the variables' bounds), the step `d` that maximises the smallest
//! linearised margin `min_i (m_i + g_i . d)`, a linear programme in
//! `(d, t)` with at most three design variables, solved exactly by its
//! vertices.
//!
//! The feasible set `{lo <= d <= hi, t <= m_i + g_i . d}` has vertices and
//! `t` is bounded above on it, so the maximum is attained at a vertex: `n +
//! 1` independent active constraints, of which some variables sit at a
//! bound of the box and, with `k` variables free, `k + 1` margins are equal
//! to `t`. Every such choice is solved as a small linear system; each
//! candidate step inside the box is scored by its true smallest linearised
//! margin (over every margin), so a wrong or degenerate choice can only
//! lose, never win. Margins that cannot be the smallest anywhere in the box
//! are dropped before the enumeration.

/// The most design variables (eps0, the mounting angle, the overlap).
const MAX_VARIABLES: usize = 3;

/// The step in `lo <= d <= hi` (per variable; `lo <= 0 <= hi`) that
/// maximises `min_i (m[i] + g[i] . d)`, and that maximum. `g[i]` has one
/// entry per variable (at most [`MAX_VARIABLES`]; a margin without a full
/// gradient row is left out). With no margins the step is zero and the
/// value `+inf`.
pub(super) fn linear_minimax(m: &[f64], g: &[Vec<f64>], lo: &[f64], hi: &[f64]) -> (Vec<f64>, f64) {
    let n = lo.len().min(hi.len()).min(MAX_VARIABLES);
    let value = |d: &[f64]| {
        m.iter()
            .zip(g)
            .filter(|(_, gi)| gi.len() >= n)
            .map(|(mi, gi)| mi + gi.iter().zip(d).map(|(a, b)| a * b).sum::<f64>())
            .fold(f64::INFINITY, f64::min)
    };
    let mut best = (vec![0.0; n], value(&vec![0.0; n]));
    if m.is_empty() || n == 0 {
        return best;
    }
    // an upper bound on the optimum, and the margins that can reach it
    let range = |gi: &[f64], pick: fn(f64, f64) -> f64| -> f64 {
        (0..n).map(|j| pick(gi[j] * lo[j], gi[j] * hi[j])).sum()
    };
    let full: Vec<usize> = (0..m.len().min(g.len()))
        .filter(|&i| g[i].len() >= n)
        .collect();
    let upper = full
        .iter()
        .map(|&i| m[i] + range(&g[i], f64::max))
        .fold(f64::INFINITY, f64::min);
    let live: Vec<usize> = full
        .into_iter()
        .filter(|&i| m[i] + range(&g[i], f64::min) <= upper)
        .collect();
    // every assignment of the variables: free, at lo, at hi
    for code in 0..3usize.pow(n as u32) {
        let mut d = vec![0.0; n];
        let mut free = Vec::with_capacity(n);
        let mut c = code;
        for j in 0..n {
            match c % 3 {
                0 => free.push(j),
                1 => d[j] = lo[j],
                _ => d[j] = hi[j],
            }
            c /= 3;
        }
        let k = free.len();
        for_each_subset(live.len(), k + 1, &mut |rows| {
            // sum_{j free} g_ij d_j - t = -(m_i + sum_{j fixed} g_ij d_j)
            let mut a = [[0.0; MAX_VARIABLES + 2]; MAX_VARIABLES + 1];
            for (r, &ri) in rows.iter().enumerate() {
                let i = live[ri];
                for (col, &j) in free.iter().enumerate() {
                    a[r][col] = g[i][j];
                }
                a[r][k] = -1.0;
                let fixed: f64 = (0..n)
                    .filter(|j| !free.contains(j))
                    .map(|j| g[i][j] * d[j])
                    .sum();
                a[r][k + 1] = -(m[i] + fixed);
            }
            let Some(x) = solve_small(&mut a, k + 1) else {
                return;
            };
            let mut step = d.clone();
            for (col, &j) in free.iter().enumerate() {
                let v = x[col];
                // inside the box, to rounding
                let slack = 1e-12 * (hi[j] - lo[j]).abs().max(1e-300);
                if !(v >= lo[j] - slack && v <= hi[j] + slack) {
                    return;
                }
                step[j] = v.clamp(lo[j], hi[j]);
            }
            let t = value(&step);
            if t > best.1 {
                best = (step, t);
            }
        });
    }
    best
}

/// Calls `f` with every increasing choice of `size` indices from `0..len`.
fn for_each_subset(len: usize, size: usize, f: &mut dyn FnMut(&[usize])) {
    fn walk(
        start: usize,
        len: usize,
        chosen: &mut Vec<usize>,
        size: usize,
        f: &mut dyn FnMut(&[usize]),
    ) {
        if chosen.len() == size {
            f(chosen);
            return;
        }
        for i in start..len {
            if len - i < size - chosen.len() {
                break;
            }
            chosen.push(i);
            walk(i + 1, len, chosen, size, f);
            chosen.pop();
        }
    }
    if size <= len {
        walk(0, len, &mut Vec::with_capacity(size), size, f);
    }
}

/// Solves the `s x s` system whose augmented rows are `a` (column `s` the
/// right-hand side) by Gaussian elimination with partial pivoting; `None`
/// when it is singular to rounding.
fn solve_small(
    a: &mut [[f64; MAX_VARIABLES + 2]; MAX_VARIABLES + 1],
    s: usize,
) -> Option<Vec<f64>> {
    let scale = a[..s]
        .iter()
        .flat_map(|r| r[..s].iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    for col in 0..s {
        let p = (col..s).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[p][col].abs() <= 1e-13 * scale {
            return None;
        }
        a.swap(col, p);
        let pivot = a[col];
        for row in a[col + 1..s].iter_mut() {
            let f = row[col] / pivot[col];
            for (v, p) in row[col..=s].iter_mut().zip(&pivot[col..=s]) {
                *v -= f * p;
            }
        }
    }
    let mut x = vec![0.0; s];
    for r in (0..s).rev() {
        let tail: f64 = (r + 1..s).map(|c| a[r][c] * x[c]).sum();
        x[r] = (a[r][s] - tail) / a[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::linear_minimax;

    /// The smallest linearised margin at `d`.
    fn value(m: &[f64], g: &[Vec<f64>], d: &[f64]) -> f64 {
        m.iter()
            .zip(g)
            .map(|(mi, gi)| mi + gi.iter().zip(d).map(|(a, b)| a * b).sum::<f64>())
            .fold(f64::INFINITY, f64::min)
    }

    /// Against brute force: a fine grid of the box (and its vertices) can
    /// never beat the programme's step, and comes within the grid's
    /// resolution of it; the step lies in the box and scores what it
    /// claims. Random margins, gradients and boxes in one to three
    /// variables, seeded.
    #[test]
    fn no_grid_step_beats_the_programme() {
        let mut rng = fastrand::Rng::with_seed(7);
        for case in 0..300 {
            let n = 1 + case % 3;
            let count = 1 + rng.usize(0..12);
            let m: Vec<f64> = (0..count).map(|_| rng.f64() * 2.0 - 1.0).collect();
            let g: Vec<Vec<f64>> = (0..count)
                .map(|_| (0..n).map(|_| (rng.f64() * 2.0 - 1.0) * 10.0).collect())
                .collect();
            let lo: Vec<f64> = (0..n).map(|_| -rng.f64() * 0.3).collect();
            let hi: Vec<f64> = (0..n).map(|_| rng.f64() * 0.3).collect();
            let (d, t) = linear_minimax(&m, &g, &lo, &hi);
            for j in 0..n {
                assert!(d[j] >= lo[j] && d[j] <= hi[j], "case {case}: {d:?}");
            }
            assert!((value(&m, &g, &d) - t).abs() <= 1e-12 * (1.0 + t.abs()));
            let per = if n == 3 { 40 } else { 120 };
            let mut grid_best = f64::NEG_INFINITY;
            let total = (per + 1usize).pow(n as u32);
            for code in 0..total {
                let mut c = code;
                let p: Vec<f64> = (0..n)
                    .map(|j| {
                        let s = (c % (per + 1)) as f64 / per as f64;
                        c /= per + 1;
                        lo[j] + s * (hi[j] - lo[j])
                    })
                    .collect();
                grid_best = grid_best.max(value(&m, &g, &p));
            }
            assert!(
                grid_best <= t + 1e-12,
                "case {case}: grid {grid_best} > {t}"
            );
            // one grid cell moves a margin by at most |g|_1 times the cell
            let cell: f64 = g
                .iter()
                .map(|gi| {
                    gi.iter()
                        .zip(lo.iter().zip(&hi))
                        .map(|(a, (l, h))| a.abs() * (h - l) / per as f64)
                        .sum::<f64>()
                })
                .fold(0.0, f64::max);
            assert!(
                t <= grid_best + cell + 1e-12,
                "case {case}: {t} vs grid {grid_best} + {cell}"
            );
        }
    }

    /// Two margins with opposite slopes in one variable meet where they
    /// cross: the closed form.
    #[test]
    fn two_crossing_margins_meet_at_their_crossing() {
        let (d, t) = linear_minimax(&[1.0, 2.0], &[vec![2.0], vec![-1.0]], &[-1.0], &[1.0]);
        // 1 + 2d = 2 - d at d = 1/3
        assert!((d[0] - 1.0 / 3.0).abs() < 1e-15);
        assert!((t - 5.0 / 3.0).abs() < 1e-15);
        // a box that stops short of the crossing: its bound
        let (d, t) = linear_minimax(&[1.0, 2.0], &[vec![2.0], vec![-1.0]], &[-0.1], &[0.1]);
        assert_eq!(d, vec![0.1]);
        assert!((t - 1.2).abs() < 1e-15);
    }
}
