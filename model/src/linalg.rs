//! In-place dense Cholesky for the symmetric positive definite block M1, on preallocated slices
//! (row-major). Written here because it runs every right-hand-side evaluation and must not
//! allocate, and because the generator traces the same code into its fixed-size version.

use crate::scalar::Scalar;

/// Factor `a` (n x n, row-major) in place into L (lower triangle, with L^T mirrored into the
/// upper one), over any scalar: the interpreter runs it on f64, the generator traces it into
/// straight-line code. Branch-free, so a matrix that is not positive definite shows as a
/// non-positive or NaN diagonal (`cholesky_in_place` checks).
///
/// Right-looking: after column j, the trailing rows take -l_ij l_kj, read from row j's upper
/// part, so the inner loop runs over contiguous memory without a dependency chain and
/// vectorises. Every entry sees the same subtractions in the same order as the textbook
/// left-looking dot products, so the bits are theirs.
pub fn cholesky_factor<T: Scalar>(a: &mut [T], n: usize) {
    for j in 0..n {
        let d = a[j * n + j].sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let v = a[i * n + j] / d;
            a[i * n + j] = v;
            a[j * n + i] = v;
        }
        let (top, rest) = a.split_at_mut((j + 1) * n);
        let lj = &top[j * n + j + 1..(j + 1) * n];
        for (r, row) in rest.chunks_exact_mut(n).enumerate() {
            let lij = lj[r];
            for (x, l) in row[j + 1..=j + 1 + r].iter_mut().zip(lj) {
                *x -= lij * *l;
            }
        }
    }
}

/// Factor in place and report whether `a` was positive definite.
pub fn cholesky_in_place(a: &mut [f64], n: usize) -> bool {
    cholesky_factor(a, n);
    (0..n).all(|j| a[j * n + j] > 0.0)
}

/// Solve L L^T x = b in place (b becomes x), with L (and its mirror L^T in the upper triangle)
/// from `cholesky_factor`. The forward sweep is column-oriented over the contiguous rows of
/// L^T (same operations in the same order as the row-oriented one).
pub fn cholesky_solve<T: Scalar>(l: &[T], n: usize, b: &mut [T]) {
    for i in 0..n {
        let x = b[i] / l[i * n + i];
        b[i] = x;
        for (bk, lki) in b[i + 1..n].iter_mut().zip(&l[i * n + i + 1..(i + 1) * n]) {
            *bk -= *lki * x;
        }
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for (lk, bk) in l[i * n + i + 1..(i + 1) * n].iter().zip(&b[i + 1..n]) {
            s -= *lk * *bk;
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

    /// The right-looking factor and the column-oriented sweep give the textbook left-looking
    /// dot products' bits (written out here), so the reordering changed no result.
    #[test]
    fn reordered_factor_and_solve_equal_the_textbook_loops_bit_for_bit() {
        let n = 9;
        let mut s = 0.7f64;
        let mut r = || {
            s = (s * 991.0 + 0.37).fract();
            s - 0.5
        };
        let b: Vec<f64> = (0..n * n).map(|_| r()).collect();
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                a[i * n + j] = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum::<f64>()
                    + if i == j { 0.1 } else { 0.0 };
            }
        }
        let rhs: Vec<f64> = (0..n).map(|_| r()).collect();
        // Textbook: left-looking factor, row-oriented sweeps.
        let mut l = a.clone();
        for j in 0..n {
            let mut d = l[j * n + j];
            for k in 0..j {
                d -= l[j * n + k] * l[j * n + k];
            }
            let d = d.sqrt();
            l[j * n + j] = d;
            for i in j + 1..n {
                let mut s = l[i * n + j];
                for k in 0..j {
                    s -= l[i * n + k] * l[j * n + k];
                }
                l[i * n + j] = s / d;
            }
        }
        let mut x = rhs.clone();
        for i in 0..n {
            let mut s = x[i];
            for k in 0..i {
                s -= l[i * n + k] * x[k];
            }
            x[i] = s / l[i * n + i];
        }
        for i in (0..n).rev() {
            let mut s = x[i];
            for k in i + 1..n {
                s -= l[k * n + i] * x[k];
            }
            x[i] = s / l[i * n + i];
        }
        let mut f = a.clone();
        cholesky_factor(&mut f, n);
        for i in 0..n {
            for j in 0..=i {
                assert_eq!(f[i * n + j], l[i * n + j], "L[{i}][{j}]");
                assert_eq!(f[j * n + i], l[i * n + j], "mirror of L[{i}][{j}]");
            }
        }
        let mut y = rhs.clone();
        cholesky_solve(&f, n, &mut y);
        assert_eq!(y, x);
    }
}
