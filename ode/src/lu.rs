//! Dense LU factorisation with partial pivoting, in place on a row-major slice. Small and
//! allocation-free: the implicit integrator factors I - h*gamma*J once per step size and
//! solves with it many times (Newton iterations, error filtering).

/// An exactly zero pivot: the matrix is singular (column index of the failing pivot).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SingularMatrix {
    pub column: usize,
}

/// Factors the n x n row-major matrix `a` in place into L (unit lower, below the diagonal) and
/// U (on and above it), with row interchanges recorded in `piv` (row k was swapped with
/// row `piv[k]` at step k).
pub fn lu_factor(a: &mut [f64], n: usize, piv: &mut [usize]) -> Result<(), SingularMatrix> {
    debug_assert_eq!(a.len(), n * n);
    debug_assert_eq!(piv.len(), n);
    for k in 0..n {
        // Partial pivoting: the largest magnitude in column k at or below the diagonal.
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
        if max == 0.0 {
            return Err(SingularMatrix { column: k });
        }
        if p != k {
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
            }
        }
        let inv = 1.0 / a[k * n + k];
        // The pivot row and the rows below it as separate slices: the update of each row is
        // a zipped axpy without bounds checks (the same operations in the same order as the
        // indexed loop, so the same bits). `cargo bench -p washdyn-ode --bench lu`: 1.38x at
        // n = 48; none at n = 324 (the elastic scene's iteration matrix, 9.8 ms both), where
        // the updates stream the 0.8 MB matrix from memory: only a blocked LU would gain.
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
    Ok(())
}

/// Solves A x = b in place (`b` becomes x) with the factors from [`lu_factor`].
pub fn lu_solve(lu: &[f64], n: usize, piv: &[usize], b: &mut [f64]) {
    debug_assert_eq!(b.len(), n);
    // Apply the row interchanges in the order they were made, then L (unit diagonal).
    for (k, &p) in piv.iter().enumerate() {
        if p != k {
            b.swap(k, p);
        }
    }
    for i in 1..n {
        let mut s = b[i];
        for j in 0..i {
            s -= lu[i * n + j] * b[j];
        }
        b[i] = s;
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for j in i + 1..n {
            s -= lu[i * n + j] * b[j];
        }
        b[i] = s / lu[i * n + i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mat_vec(a: &[f64], n: usize, x: &[f64]) -> Vec<f64> {
        (0..n)
            .map(|i| (0..n).map(|j| a[i * n + j] * x[j]).sum())
            .collect()
    }

    /// A matrix with a zero leading entry needs a row swap; we pick x, form b = A x and recover x.
    #[test]
    fn solves_a_system_that_needs_pivoting() {
        let n = 4;
        let a = vec![
            0.0, 2.0, 1.0, -1.0, //
            3.0, 1.0, 0.0, 2.0, //
            1.0, -1.0, 4.0, 0.5, //
            2.0, 0.0, 1.0, 5.0,
        ];
        let x = [1.0, -2.0, 0.5, 3.0];
        let mut b = mat_vec(&a, n, &x);
        let mut lu = a.clone();
        let mut piv = vec![0; n];
        lu_factor(&mut lu, n, &mut piv).unwrap();
        lu_solve(&lu, n, &piv, &mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-14, "{b:?}");
        }
    }

    /// The Hilbert matrix of order 6 is badly conditioned (cond ~ 1.5e7); the residual of the
    /// computed solution must still be at rounding level relative to |A| |x| (backward
    /// stability of Gaussian elimination with partial pivoting; |A|_inf < 2.5 here).
    #[test]
    fn small_residual_on_hilbert_matrix() {
        let n = 6;
        let a: Vec<f64> = (0..n * n)
            .map(|k| 1.0 / ((k / n + k % n + 1) as f64))
            .collect();
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 1.0).collect();
        let mut x = rhs.clone();
        let mut lu = a.clone();
        let mut piv = vec![0; n];
        lu_factor(&mut lu, n, &mut piv).unwrap();
        lu_solve(&lu, n, &piv, &mut x);
        let r = mat_vec(&a, n, &x);
        let xmax = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(xmax > 1e3, "the test needs a large solution, got {xmax}");
        for i in 0..n {
            let bound = 100.0 * f64::EPSILON * 2.5 * xmax;
            assert!((r[i] - rhs[i]).abs() < bound, "residual {}", r[i] - rhs[i]);
        }
    }

    #[test]
    fn reports_an_exactly_zero_pivot() {
        // Second row is twice the first: elimination leaves an exact zero.
        let mut a = vec![1.0, 2.0, 2.0, 4.0];
        let mut piv = vec![0; 2];
        assert_eq!(
            lu_factor(&mut a, 2, &mut piv),
            Err(SingularMatrix { column: 1 })
        );
        let mut z = vec![0.0; 9];
        let mut piv = vec![0; 3];
        assert_eq!(
            lu_factor(&mut z, 3, &mut piv),
            Err(SingularMatrix { column: 0 })
        );
    }
}
