//! In-place dense Cholesky for the symmetric positive definite block M1, on preallocated slices
//! (row-major). Written here because it runs every right-hand-side evaluation and must not
//! allocate; the generated back end emits its own fixed-size version.

/// Factor `a` (n x n, row-major) in place into L (lower triangle). Returns false if `a` is not
/// positive definite.
pub fn cholesky_in_place(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    true
}

/// Solve L L^T x = b in place (b becomes x), with L from `cholesky_in_place`.
pub fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_spd_system() {
        // A = B B^T + 3 I is SPD; check A x = b by multiplying back.
        let n = 5;
        let bm: Vec<f64> = (0..n * n)
            .map(|k| ((k * 7 % 11) as f64) / 11.0 - 0.4)
            .collect();
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                a[i * n + j] = (0..n).map(|k| bm[i * n + k] * bm[j * n + k]).sum::<f64>();
            }
            a[i * n + i] += 3.0;
        }
        let orig = a.clone();
        let rhs: Vec<f64> = (0..n).map(|i| i as f64 - 1.5).collect();
        let mut x = rhs.clone();
        assert!(cholesky_in_place(&mut a, n));
        cholesky_solve(&a, n, &mut x);
        for i in 0..n {
            let ax: f64 = (0..n).map(|j| orig[i * n + j] * x[j]).sum();
            assert!((ax - rhs[i]).abs() < 1e-13);
        }
        let mut not_pd = vec![1.0, 2.0, 2.0, 1.0];
        assert!(!cholesky_in_place(&mut not_pd, 2));
    }
}
