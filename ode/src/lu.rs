//! Dense LU factorisation with partial pivoting, in place on a row-major slice. Allocation-free:
//! the implicit integrator factors I - h*gamma*J once per step size and solves with it many
//! times (Newton iterations, error filtering). The factorisation is blocked: at the elastic
//! scenes' sizes (n = 324) the column-at-a-time loop streamed the whole matrix through the
//! cache once per column, and the iteration matrix's LU was 38 % of an implicit step.

/// An exactly zero pivot: the matrix is singular (column index of the failing pivot).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SingularMatrix {
    pub column: usize,
}

/// Columns factored per block. A block's trailing update passes over each row of the matrix
/// once instead of once per column, which is what makes large n fast (module doc).
const BLOCK: usize = 32;
/// Columns of the trailing matrix updated together: a block's 32 pivot rows over 128 columns
/// (32 KB) stay in L1 while every row below passes through.
const TILE: usize = 128;

/// Factors the n x n row-major matrix `a` in place into L (unit lower, below the diagonal) and
/// U (on and above it), with row interchanges recorded in `piv` (row k was swapped with
/// row `piv[k]` at step k).
///
/// Right-looking and blocked (LAPACK's getrf): a panel of `BLOCK` columns is eliminated with
/// whole-row swaps, its rows of U follow by forward substitution, and the rows below take the
/// panel's updates tile by tile. Every entry still receives the same updates in the same order
/// as in the textbook loop (`reference` in the tests), so the factors are the same bits; only
/// the memory traffic changes. `cargo bench -p washdyn-ode --bench lu` measures it.
pub fn lu_factor(a: &mut [f64], n: usize, piv: &mut [usize]) -> Result<(), SingularMatrix> {
    debug_assert_eq!(a.len(), n * n);
    debug_assert_eq!(piv.len(), n);
    // Up to two blocks the matrix is one panel: the textbook loop, which at n = 48 the
    // blocked pass was 1.28x slower than (the bench).
    let block = if n <= 2 * BLOCK { n } else { BLOCK };
    let mut kb = 0;
    while kb < n {
        let ke = (kb + block).min(n);
        factor_panel(a, n, kb, ke, piv)?;
        if ke < n {
            forward_substitute(a, n, kb, ke);
            update_trailing(a, n, kb, ke);
        }
        kb = ke;
    }
    Ok(())
}

/// Unblocked elimination of columns kb..ke over rows kb..n: pivot search, whole-row swap, and
/// each row's update restricted to the panel's columns.
fn factor_panel(
    a: &mut [f64],
    n: usize,
    kb: usize,
    ke: usize,
    piv: &mut [usize],
) -> Result<(), SingularMatrix> {
    for k in kb..ke {
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
        let (top, below) = a.split_at_mut((k + 1) * n);
        let pivot = &top[k * n + k + 1..k * n + ke];
        for row in below.chunks_exact_mut(n) {
            let l = row[k] * inv;
            row[k] = l;
            if l != 0.0 {
                for (x, u) in row[k + 1..ke].iter_mut().zip(pivot) {
                    *x -= l * u;
                }
            }
        }
    }
    Ok(())
}

/// The panel's rows of U right of it: U12 = L11^-1 A12, row after row.
fn forward_substitute(a: &mut [f64], n: usize, kb: usize, ke: usize) {
    for k in kb..ke {
        let (top, below) = a.split_at_mut((k + 1) * n);
        let u = &top[k * n + ke..(k + 1) * n];
        for row in below[..(ke - k - 1) * n].chunks_exact_mut(n) {
            let l = row[k];
            if l != 0.0 {
                for (x, u) in row[ke..].iter_mut().zip(u) {
                    *x -= l * u;
                }
            }
        }
    }
}

/// A22 -= L21 U12 for the rows below the panel, in column tiles; the panel's columns are taken
/// four at a time when all four multipliers are non-zero (one load and store of each entry for
/// four updates, subtracted in column order as the textbook loop does).
fn update_trailing(a: &mut [f64], n: usize, kb: usize, ke: usize) {
    let (top, below) = a.split_at_mut(ke * n);
    let u12 = &top[kb * n..];
    let nb = ke - kb;
    let mut j0 = ke;
    while j0 < n {
        let j1 = (j0 + TILE).min(n);
        let u = |k: usize| &u12[k * n + j0..k * n + j1];
        for row in below.chunks_exact_mut(n) {
            let (left, right) = row.split_at_mut(ke);
            let (l, x) = (&left[kb..], &mut right[j0 - ke..j1 - ke]);
            let mut k = 0;
            while k < nb {
                if k + 4 <= nb
                    && l[k] != 0.0
                    && l[k + 1] != 0.0
                    && l[k + 2] != 0.0
                    && l[k + 3] != 0.0
                {
                    let (l0, l1, l2, l3) = (l[k], l[k + 1], l[k + 2], l[k + 3]);
                    let (u0, u1, u2, u3) = (u(k), u(k + 1), u(k + 2), u(k + 3));
                    for (j, x) in x.iter_mut().enumerate() {
                        let mut v = *x;
                        v -= l0 * u0[j];
                        v -= l1 * u1[j];
                        v -= l2 * u2[j];
                        v -= l3 * u3[j];
                        *x = v;
                    }
                    k += 4;
                } else {
                    let lk = l[k];
                    if lk != 0.0 {
                        for (x, u) in x.iter_mut().zip(u(k)) {
                            *x -= lk * u;
                        }
                    }
                    k += 1;
                }
            }
        }
        j0 = j1;
    }
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

    /// The textbook loop (one column at a time, every row updated right away): what the
    /// blocked factorisation must equal bit for bit.
    fn reference(a: &mut [f64], n: usize, piv: &mut [usize]) {
        for k in 0..n {
            let mut p = k;
            for i in k + 1..n {
                if a[i * n + k].abs() > a[p * n + k].abs() {
                    p = i;
                }
            }
            piv[k] = p;
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
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

    /// Sizes around the block and tile edges, dense and with zeros scattered in (the iteration
    /// matrices have whole zero blocks, which take the one-column path): the same bits.
    #[test]
    fn blocked_factors_are_the_textbook_bits() {
        for n in [1, 5, 31, 32, 33, 97, 161, 200] {
            for sparse in [false, true] {
                let a: Vec<f64> = (0..n * n)
                    .map(|k| {
                        let (i, j) = ((k / n) as f64, (k % n) as f64);
                        let v = (1.3 * i + 0.7 * j + 0.1 * i * j).sin();
                        if i == j {
                            v + 0.5
                        } else if sparse && (k * 7919) % 5 < 2 {
                            0.0
                        } else {
                            v
                        }
                    })
                    .collect();
                let (mut x, mut y) = (a.clone(), a);
                let (mut px, mut py) = (vec![0; n], vec![0; n]);
                lu_factor(&mut x, n, &mut px).unwrap();
                reference(&mut y, n, &mut py);
                assert_eq!(px, py, "n = {n}");
                let same = x
                    .iter()
                    .zip(&y)
                    .all(|(a, b)| a.to_bits() == b.to_bits() || a == b);
                assert!(same, "n = {n}, sparse {sparse}: the factors differ");
            }
        }
    }

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
