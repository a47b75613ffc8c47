//! The solvers' iterations must not touch the heap: after the workspace is
//! built (and, for bordered solves, after the first call), repeated solves
//! perform zero allocations. Checked with a counting global allocator;
//! this file holds a single test so no other test allocates concurrently.

use fpc_newton::{
    Bordered, BorderedEval, Energy, Gradient, Hessian, LinearBackend, Newton, NewtonOptions,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Chain of tilted double wells with nearest-neighbour and all-to-all
/// weak coupling (dense Hessian, indefinite near 0):
/// `sum x_i^4/4 - x_i^2/2 - t x_i + 1/4 sum (x_{i+1}-x_i)^2 + 0.1/n (sum x_i)^2`.
struct Chain {
    n: usize,
    tilt: f64,
}

impl Energy for Chain {
    fn dim(&self) -> usize {
        self.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        let s: f64 = x.iter().sum();
        let mut f = 0.1 / self.n as f64 * s * s;
        for i in 0..self.n {
            f += x[i].powi(4) / 4.0 - x[i] * x[i] / 2.0 - self.tilt * x[i];
            if i + 1 < self.n {
                f += 0.25 * (x[i + 1] - x[i]).powi(2);
            }
        }
        f
    }
}

impl Gradient for Chain {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let s: f64 = x.iter().sum();
        for i in 0..self.n {
            g[i] = x[i].powi(3) - x[i] - self.tilt + 0.2 / self.n as f64 * s;
        }
        for i in 0..self.n - 1 {
            let d = 0.5 * (x[i + 1] - x[i]);
            g[i + 1] += d;
            g[i] -= d;
        }
        self.energy(x)
    }
}

impl Hessian for Chain {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let n = self.n;
        h.fill(0.2 / n as f64);
        for i in 0..n {
            h[i * (n + 1)] += 3.0 * x[i] * x[i] - 1.0;
        }
        for i in 0..n - 1 {
            h[i * (n + 1)] += 0.5;
            h[(i + 1) * (n + 1)] += 0.5;
            h[i + (i + 1) * n] -= 0.5;
            h[(i + 1) + i * n] -= 0.5;
        }
        self.gradient(x, g)
    }
}

/// The same chain with the tilt as load `lambda` and target `x_{n-1} = t`.
struct ChainTarget {
    chain: Chain,
    t: f64,
}

impl Bordered for ChainTarget {
    fn dim(&self) -> usize {
        self.chain.n
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval) -> bool {
        let n = self.chain.n;
        self.chain.tilt = lambda;
        self.chain.hessian(x, &mut out.g, &mut out.h);
        out.g_lambda.fill(-1.0);
        out.c = x[n - 1] - self.t;
        out.c_x.fill(0.0);
        out.c_x[n - 1] = 1.0;
        out.c_lambda = 0.0;
        true
    }
}

#[test]
fn repeated_solves_do_not_allocate() {
    for (n, backend) in [
        (32, LinearBackend::Auto),
        (32, LinearBackend::Faer),
        (200, LinearBackend::Auto),
    ] {
        let mut newton = Newton::new(n, NewtonOptions::default().with_backend(backend));
        let mut p = Chain { n, tilt: 0.5 };
        let start: Vec<f64> = (0..n).map(|i| 0.1 + 0.01 * (i as f64).sin()).collect();
        let mut x = start.clone();
        // Warm-up (the bordered workspace is allocated on first use).
        let r = newton.minimize(&mut p, &mut x);
        assert!(r.converged(), "n = {n}, {backend:?}: {r}");
        let eq = x.clone();
        // Bordered solves warm-started from the equilibrium at tilt 0.5,
        // with the last coordinate prescribed a little further.
        let mut bt = ChainTarget {
            chain: Chain { n, tilt: 0.0 },
            t: eq[n - 1] + 0.05,
        };
        let mut xb = eq.clone();
        let mut lambda = 0.5;
        let r = newton.solve_bordered(&mut bt, &mut xb, &mut lambda);
        assert!(r.converged(), "{r}");

        let before = ALLOCS.load(Ordering::Relaxed);
        let mut shifted = 0.0f64;
        for k in 0..10 {
            x.copy_from_slice(&start);
            p.tilt = 0.5 + 0.01 * k as f64;
            let r = newton.minimize(&mut p, &mut x);
            assert!(r.converged());
            shifted = shifted.max(r.max_shift);
            xb.copy_from_slice(&eq);
            lambda = 0.5;
            bt.t = eq[n - 1] + 0.01 * k as f64;
            assert!(newton
                .solve_bordered(&mut bt, &mut xb, &mut lambda)
                .converged());
        }
        let after = ALLOCS.load(Ordering::Relaxed);
        assert_eq!(
            after - before,
            0,
            "n = {n}, {backend:?}: allocations inside solves"
        );
        assert!(shifted > 0.0, "the shifted-Cholesky path was exercised");
    }
}
