//! The dense LU of the implicit methods' iteration matrix at the sizes the reference's scenes
//! give it (n = 48: `full` in first-order form; n = 324: `elastic`'s mass form), against the
//! indexed triple loop it replaced: the speed-up the doc comment of `lu_factor` quotes comes
//! from one run of this bench (`cargo bench -p washdyn-ode --bench lu`).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use washdyn_ode::lu::lu_factor;

/// The factorisation before the vectorised row update: the same pivoting and the same
/// operations, indexed (bounds-checked, so the update does not vectorise).
fn indexed(a: &mut [f64], n: usize, piv: &mut [usize]) {
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
        for i in k + 1..n {
            let l = a[i * n + k] * inv;
            a[i * n + k] = l;
            if l != 0.0 {
                for j in k + 1..n {
                    a[i * n + j] -= l * a[k * n + j];
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
    for n in [48, 324] {
        let a = matrix(n);
        // Both give the same bits: the same operations in the same order.
        let (mut x, mut y, mut px, mut py) = (a.clone(), a.clone(), vec![0; n], vec![0; n]);
        lu_factor(&mut x, n, &mut px).unwrap();
        indexed(&mut y, n, &mut py);
        assert!(x == y && px == py, "n = {n}: the factors differ");
        let mut g = c.benchmark_group("lu_factor");
        let mut w = a.clone();
        let mut piv = vec![0; n];
        g.bench_with_input(BenchmarkId::new("vectorised", n), &n, |b, &n| {
            b.iter(|| {
                w.copy_from_slice(&a);
                lu_factor(black_box(&mut w), n, &mut piv).unwrap();
            })
        });
        g.bench_with_input(BenchmarkId::new("indexed", n), &n, |b, &n| {
            b.iter(|| {
                w.copy_from_slice(&a);
                indexed(black_box(&mut w), n, &mut piv);
            })
        });
        g.finish();
    }
}

criterion_group!(benches, lu);
criterion_main!(benches);
