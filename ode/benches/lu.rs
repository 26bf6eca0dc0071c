//! The dense LU of the implicit methods' iteration matrix at the sizes the reference's scenes
//! give it (n = 48: `full` in first-order form; n = 324: `elastic`'s mass form; n = 392: the
//! 2 kHz scene's), blocked against the column-at-a-time loop it replaced: the speed-ups
//! docs/performance.md quotes come from one run of this bench
//! (`cargo bench -p washdyn-ode --bench lu`).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use washdyn_ode::lu::lu_factor;

/// The factorisation before blocking: one column at a time, each row below updated right away
/// as a zipped axpy (the same pivoting and the same operations in the same order).
fn unblocked(a: &mut [f64], n: usize, piv: &mut [usize]) {
    for k in 0..n {
        let mut p = k;
        let mut max = a[k * n + k].abs();
        for i in k + 1..n {
            let v = a[i * n + k].abs();
            if v > max {
                max = v;
                p = i;
            }
        }
        piv[k] = p;
        if p != k {
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
            }
        }
        let inv = 1.0 / a[k * n + k];
        let (top, below) = a.split_at_mut((k + 1) * n);
        let pivot = &top[k * n + k + 1..(k + 1) * n];
        for row in below.chunks_exact_mut(n) {
            let l = row[k] * inv;
            row[k] = l;
            if l != 0.0 {
                for (x, u) in row[k + 1..].iter_mut().zip(pivot) {
                    *x -= l * u;
                }
            }
        }
    }
}

/// A dense matrix that needs pivoting (deterministic, no two rows alike).
fn matrix(n: usize) -> Vec<f64> {
    (0..n * n)
        .map(|k| {
            let (i, j) = ((k / n) as f64, (k % n) as f64);
            (1.3 * i + 0.7 * j + 0.1 * i * j).sin() + if i == j { 0.5 } else { 0.0 }
        })
        .collect()
}

fn lu(c: &mut Criterion) {
    for n in [48, 324, 392] {
        let a = matrix(n);
        // Both give the same bits: the same operations in the same order.
        let (mut x, mut y, mut px, mut py) = (a.clone(), a.clone(), vec![0; n], vec![0; n]);
        lu_factor(&mut x, n, &mut px).unwrap();
        unblocked(&mut y, n, &mut py);
        assert!(x == y && px == py, "n = {n}: the factors differ");
        let mut g = c.benchmark_group("lu_factor");
        let mut w = a.clone();
        let mut piv = vec![0; n];
        g.bench_with_input(BenchmarkId::new("blocked", n), &n, |b, &n| {
            b.iter(|| {
                w.copy_from_slice(&a);
                lu_factor(black_box(&mut w), n, &mut piv).unwrap();
            })
        });
        g.bench_with_input(BenchmarkId::new("unblocked", n), &n, |b, &n| {
            b.iter(|| {
                w.copy_from_slice(&a);
                unblocked(black_box(&mut w), n, &mut piv);
            })
        });
        g.finish();
    }
}

criterion_group!(benches, lu);
criterion_main!(benches);
