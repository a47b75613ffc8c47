//! The structured factorisation alone: `Semiseparable::factor` (Cholesky
//! pivots) and `solve` on a coupled matrix of 4 x 4 blocks, the CCM's
//! block size, at the element counts of the standard solve (8) and of the
//! 0.01 mm configuration's levels (27, 54).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use fpc_newton::{PivotKind, Semiseparable};

/// A positive definite coupled matrix (diagonally dominant blocks, small
/// coupling), filled from a fixed sequence.
fn matrix(blocks: usize) -> Semiseparable {
    let n = 4;
    let mut m = Semiseparable::new(n, blocks);
    let mut t = 0.0f64;
    let mut next = || {
        t += 1.0;
        (t * 0.618_033_988_749_895).fract() - 0.5
    };
    for k in 0..blocks {
        let mut b = [0.0; 16];
        for c in 0..n {
            for r in 0..=c {
                let v = next();
                b[r + n * c] = v;
                b[c + n * r] = v;
            }
            b[c + n * c] += 3.0;
        }
        m.set_block(k, &b);
        let (mut u, mut w) = ([0.0; 4], [0.0; 4]);
        for i in 0..n {
            u[i] = 0.2 * next();
            w[i] = 0.2 * next();
        }
        m.set_coupling(k, &u, &w);
    }
    m
}

fn factor(c: &mut Criterion) {
    let mut g = c.benchmark_group("semiseparable");
    for blocks in [8, 27, 54] {
        let mut m = matrix(blocks);
        g.bench_function(BenchmarkId::new("factor", blocks), |bch| {
            bch.iter(|| m.factor(black_box(0.0), PivotKind::Cholesky).unwrap())
        });
        // (factorised here too, so that the solve runs on its own as well)
        m.factor(0.0, PivotKind::Cholesky).unwrap();
        let rhs: Vec<f64> = (0..4 * blocks).map(|i| (i as f64).cos()).collect();
        let mut x = rhs.clone();
        g.bench_function(BenchmarkId::new("solve", blocks), |bch| {
            bch.iter(|| {
                x.copy_from_slice(&rhs);
                m.solve(black_box(&mut x));
            })
        });
    }
    g.finish();
}

criterion_group!(benches, factor);
criterion_main!(benches);
