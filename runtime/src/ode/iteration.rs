//! The iteration matrix d I - c J of the implicit methods (sdirk4: d = 1, c = h gamma;
//! rodas4: d = 1 / (h gamma), c = 1), factorised once per step size and solved with many
//! times. For a mechanical system in first-order form, J = [[0, I], [A, B]] with
//! A = dq''/dq and B = dq''/dq': the 2n x 2n system reduces to the n x n one
//! (d^2 I - c d B - c^2 A) x2 = d b2 + c A b1, x1 = (b1 + c x2) / d, which is what
//! generalized-alpha iterates on, so every implicit method factorises n x n and the LU
//! costs an eighth of the full one.

use super::lu::{SingularMatrix, lu_factor, lu_solve};

pub struct IterationMatrix {
    dim: usize,
    /// n when the system is y = [q; q'] with f = [q'; q''].
    half: Option<usize>,
    lu: Vec<f64>,
    piv: Vec<usize>,
    tmp: Vec<f64>,
    c: f64,
    d: f64,
}

impl IterationMatrix {
    /// For a system of dimension `dim` (work arrays for the full form, allocated here).
    pub fn new(dim: usize) -> Self {
        IterationMatrix {
            dim,
            half: None,
            lu: vec![0.0; dim * dim],
            piv: vec![0; dim],
            tmp: vec![0.0; dim],
            c: 0.0,
            d: 1.0,
        }
    }

    /// Whether the system is second order with `half` positions (`OdeSystem::second_order`,
    /// known at `init`): the reduced form is used then. Never allocates.
    pub fn set_second_order(&mut self, half: Option<usize>) {
        self.half = half.filter(|&n| 2 * n == self.dim);
    }

    /// Factorise d I - c J (J row-major dim x dim; for a second-order system only its lower
    /// rows [A, B] are read: the upper ones are [0, I] by construction).
    pub fn factor(&mut self, jac: &[f64], d: f64, c: f64) -> Result<(), SingularMatrix> {
        self.c = c;
        self.d = d;
        match self.half {
            None => {
                let n = self.dim;
                for (w, j) in self.lu[..n * n].iter_mut().zip(jac) {
                    *w = -c * j;
                }
                for i in 0..n {
                    self.lu[i * n + i] += d;
                }
                lu_factor(&mut self.lu, n, &mut self.piv)
            }
            Some(n) => {
                let m = 2 * n;
                for i in 0..n {
                    let row = &jac[(n + i) * m..(n + i + 1) * m];
                    for j in 0..n {
                        self.lu[i * n + j] = -c * c * row[j] - c * d * row[n + j];
                    }
                    self.lu[i * n + i] += d * d;
                }
                lu_factor(&mut self.lu[..n * n], n, &mut self.piv[..n])
            }
        }
    }

    /// Solve (d I - c J) x = b in place, with the J the factorisation was made with.
    pub fn solve(&mut self, jac: &[f64], b: &mut [f64]) {
        match self.half {
            None => lu_solve(&self.lu, self.dim, &self.piv, b),
            Some(n) => {
                let m = 2 * n;
                let (b1, b2) = b.split_at_mut(n);
                for i in 0..n {
                    let row = &jac[(n + i) * m..(n + i) * m + n];
                    let a_b1: f64 = row.iter().zip(b1.iter()).map(|(a, x)| a * x).sum();
                    self.tmp[i] = self.d * b2[i] + self.c * a_b1;
                }
                lu_solve(&self.lu[..n * n], n, &self.piv[..n], &mut self.tmp[..n]);
                for i in 0..n {
                    b2[i] = self.tmp[i];
                    b1[i] = (b1[i] + self.c * b2[i]) / self.d;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reduced solve against the full 2n x 2n LU of the same matrix (an independent path:
    /// no reduction), for both scalings the methods use.
    #[test]
    fn reduced_solve_matches_full_lu() {
        let n = 5;
        let m = 2 * n;
        let mut jac = vec![0.0; m * m];
        for i in 0..n {
            jac[i * m + n + i] = 1.0;
            for j in 0..m {
                jac[(n + i) * m + j] = ((i * 7 + j * 3) as f64 * 0.71).sin() * 40.0;
            }
        }
        for (d, c) in [(1.0, 0.013), (1.0 / (0.25 * 0.02), 1.0)] {
            let b: Vec<f64> = (0..m).map(|i| (i as f64 * 1.3).cos()).collect();
            let mut full = IterationMatrix::new(m);
            let mut red = IterationMatrix::new(m);
            red.set_second_order(Some(n));
            full.factor(&jac, d, c).unwrap();
            red.factor(&jac, d, c).unwrap();
            let (mut x1, mut x2) = (b.clone(), b.clone());
            full.solve(&jac, &mut x1);
            red.solve(&jac, &mut x2);
            let scale = x1.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for i in 0..m {
                // Both are backward stable: they agree to a few ulps of the solution's size
                // (measured 1e-15 relative).
                assert!(
                    (x1[i] - x2[i]).abs() <= 1e-12 * scale,
                    "{i}: {} vs {}",
                    x1[i],
                    x2[i]
                );
            }
        }
    }
}
