//! Tests of problem-owned linear algebra: a problem solving its own Newton systems.

use super::*;

/// [`Rosenbrock`] keeping its Hessian as what it is, 2 x 2 diagonal blocks,
/// and factorising them itself (explicit inverses; a block is positive
/// definite when its leading entry and determinant are positive). Counts
/// its factorisations.
struct BlockRosenbrock {
    inner: Rosenbrock,
    /// `(h00, h10, h11)` per block.
    h: Vec<[f64; 3]>,
    /// The inverse of each shifted block, same layout.
    inv: Vec<[f64; 3]>,
    factorizations: usize,
}

impl BlockRosenbrock {
    fn new(n: usize) -> Self {
        BlockRosenbrock {
            inner: Rosenbrock { n },
            h: vec![[0.0; 3]; n / 2],
            inv: vec![[0.0; 3]; n / 2],
            factorizations: 0,
        }
    }
}

impl Energy for BlockRosenbrock {
    fn dim(&self) -> usize {
        self.inner.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.inner.energy(x)
    }
}
impl Gradient for BlockRosenbrock {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.inner.gradient(x, g)
    }
}
impl Hessian for BlockRosenbrock {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        for (k, b) in self.h.iter_mut().enumerate() {
            let (u, v) = (x[2 * k], x[2 * k + 1]);
            *b = [1200.0 * u * u - 400.0 * v + 2.0, -400.0 * u, 200.0];
        }
        self.inner.gradient(x, g)
    }
}
impl LinearSystem for BlockRosenbrock {
    fn diagonal_range(&self) -> (f64, f64) {
        self.h.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), b| {
            (lo.min(b[0]).min(b[2]), hi.max(b[0].abs()).max(b[2].abs()))
        })
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.factorizations += 1;
        let mut inertia = Inertia::default();
        for (k, (b, inv)) in self.h.iter().zip(&mut self.inv).enumerate() {
            let (a, c, d) = (b[0] + tau, b[1], b[2] + tau);
            if !(a.is_finite() && c.is_finite() && d.is_finite()) {
                return Err(FactorError::NonFinite { block: k });
            }
            let det = a * d - c * c;
            if kind == PivotKind::Cholesky && !(a > 0.0 && det > 0.0) {
                return Err(FactorError::NotPositiveDefinite { index: 2 * k });
            }
            if det == 0.0 {
                return Err(FactorError::Singular { block: k });
            }
            *inv = [d / det, -c / det, a / det];
            match (det > 0.0, a > 0.0) {
                (true, true) => inertia.positive += 2,
                (true, false) => inertia.negative += 2,
                _ => {
                    inertia.positive += 1;
                    inertia.negative += 1;
                }
            }
        }
        Ok(inertia)
    }
    fn solve(&mut self, b: &mut [f64]) {
        for (k, inv) in self.inv.iter().enumerate() {
            let (p, q) = (b[2 * k], b[2 * k + 1]);
            b[2 * k] = inv[0] * p + inv[1] * q;
            b[2 * k + 1] = inv[1] * p + inv[2] * q;
        }
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        for (k, h) in self.h.iter().enumerate() {
            let (p, q) = (x[2 * k], x[2 * k + 1]);
            out[2 * k] = h[0] * p + h[1] * q;
            out[2 * k + 1] = h[1] * p + h[2] * q;
        }
    }
}

/// [`Rosenbrock`] with its Hessian as a [`Semiseparable`] without coupling
/// (2 x 2 blocks, block diagonal).
struct SemiRosenbrock {
    inner: Rosenbrock,
    h: Semiseparable,
}

impl Energy for SemiRosenbrock {
    fn dim(&self) -> usize {
        self.inner.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.inner.energy(x)
    }
}
impl Gradient for SemiRosenbrock {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.inner.gradient(x, g)
    }
}
impl Hessian for SemiRosenbrock {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        for k in 0..self.inner.n / 2 {
            let (u, v) = (x[2 * k], x[2 * k + 1]);
            let off = -400.0 * u;
            self.h
                .set_block(k, &[1200.0 * u * u - 400.0 * v + 2.0, off, off, 200.0]);
        }
        self.h.clear_coupling();
        self.inner.gradient(x, g)
    }
}
impl LinearSystem for SemiRosenbrock {
    fn diagonal_range(&self) -> (f64, f64) {
        self.h.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.h.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.h.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.h.apply(x, out)
    }
}

/// The equivalent of a problem solving its own Newton systems: a problem
/// with its own (block-diagonal) linear algebra takes the same path as the
/// same objective written densely and wrapped in [`Dense`].
#[test]
fn a_problem_can_solve_its_own_newton_systems() {
    let n = 10;
    // the standard start, and one where H is indefinite (h00 < 0)
    let indefinite: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 0.3 } else { 1.0 }).collect();
    let mut shifted = false;
    for (start, opts) in [
        (rosenbrock_start(n), NewtonOptions::default()),
        (indefinite.clone(), NewtonOptions::default()),
        (
            indefinite,
            NewtonOptions {
                eager_full_steps: false,
                ..NewtonOptions::default()
            },
        ),
    ] {
        let mut own = Track::new(BlockRosenbrock::new(n));
        let mut x = start.clone();
        let r = Newton::new(n, opts).minimize(&mut own, &mut x);
        assert!(r.converged(), "{r}");
        shifted |= r.max_shift > 0.0;
        assert_eq!(own.p.factorizations, r.factorizations);
        let mut dense = Dense::new(Track::new(Rosenbrock { n }));
        let mut xd = start.clone();
        let rd = Newton::new(n, opts).minimize(&mut dense, &mut xd);
        assert!(rd.converged());
        assert_same_path(
            (&own.iterates, &x, &r),
            (&dense.problem.iterates, &xd, &rd),
            1e-12,
            1e-12,
        );
        assert!(max_abs_diff(&x, &xd) <= 1e-12, "{x:?} vs {xd:?}");
        assert!(max_abs_diff(&x, &vec![1.0; n]) < 1e-9);
        // the same blocks through Semiseparable (no coupling)
        let mut semi = Track::new(SemiRosenbrock {
            inner: Rosenbrock { n },
            h: Semiseparable::new(2, n / 2),
        });
        let mut xs = start.clone();
        let rs = Newton::new(n, opts).minimize(&mut semi, &mut xs);
        assert!(rs.converged(), "{rs}");
        assert_same_path(
            (&semi.iterates, &xs, &rs),
            (&dense.problem.iterates, &xd, &rd),
            1e-12,
            1e-12,
        );
    }
    assert!(shifted, "the shifted factorisations ran");
}
