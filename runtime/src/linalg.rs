//! In-place dense Cholesky for the symmetric positive definite block M1, on preallocated slices
//! (row-major). Written here because it runs every right-hand-side evaluation and must not
//! allocate, and because the generator traces the same code into its fixed-size version.

use crate::scalar::Scalar;

/// Factor `a` (n x n, row-major) in place into L (lower triangle), over any scalar: the
/// interpreter runs it on f64, the generator traces it into straight-line code. Branch-free, so
/// a matrix that is not positive definite shows as a non-positive or NaN diagonal
/// (`cholesky_in_place` checks).
pub fn cholesky_factor<T: Scalar>(a: &mut [T], n: usize) {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
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
}

/// Factor in place and report whether `a` was positive definite.
pub fn cholesky_in_place(a: &mut [f64], n: usize) -> bool {
    cholesky_factor(a, n);
    (0..n).all(|j| a[j * n + j] > 0.0)
}

/// Solve L L^T x = b in place (b becomes x), with L from `cholesky_factor`.
pub fn cholesky_solve<T: Scalar>(l: &[T], n: usize, b: &mut [T]) {
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

/// y += A x, A column-major as `C` columns of `R` rows: the kernel generated code calls for a
/// constant modal table (`Scalar::mat_vec`; the same order of operations as its f64 loop, so
/// the back ends agree to the bit). Fixed sizes let the compiler unroll and vectorise the
/// columns (an axpy per column).
#[inline]
pub fn mat_vec<const R: usize, const C: usize>(a: &[[f64; R]; C], x: &[f64; C], y: &mut [f64; R]) {
    for (col, xj) in a.iter().zip(x) {
        for (yi, aij) in y.iter_mut().zip(col) {
            *yi += *xj * *aij;
        }
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

    /// The kernel generated code calls gives the interpreter's `Scalar::mat_vec` to the bit
    /// (what lets the back ends agree to round-off on the modal projections).
    #[test]
    fn generated_kernel_equals_the_scalar_loop_bit_for_bit() {
        use crate::scalar::Scalar;
        let mut s = 0.3f64;
        let mut r = || {
            s = (s * 997.0 + 0.123).fract();
            s - 0.5
        };
        let a: [[f64; 7]; 5] = std::array::from_fn(|_| std::array::from_fn(|_| r() * 1e3));
        let x: [f64; 5] = std::array::from_fn(|_| r());
        let y0: [f64; 7] = std::array::from_fn(|_| r());
        let mut y = y0;
        mat_vec(&a, &x, &mut y);
        let flat: Vec<f64> = a.iter().flatten().copied().collect();
        let mut z = y0;
        f64::mat_vec(&flat, &x, &mut z);
        assert_eq!(y, z);
        assert_ne!(y, y0);
    }
}
