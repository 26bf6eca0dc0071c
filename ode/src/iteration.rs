//! The iteration matrix d I - c J of the implicit methods (sdirk4: d = 1, c = h gamma;
//! rodas4: d = 1 / (h gamma), c = 1), factorised once per step size and solved with many
//! times. For a mechanical system in first-order form, J = [[0, I], [A, B]] with
//! A = dq''/dq and B = dq''/dq': the 2n x 2n system reduces to the n x n one
//! (d^2 I - c d B - c^2 A) x2 = d b2 + c A b1, x1 = (b1 + c x2) / d, which is what
//! generalized-alpha iterates on, so every implicit method factorises n x n and the LU
//! costs an eighth of the full one. When the system gives M, dh/dq and dh/dq' instead
//! (`OdeSystem::mass_jacobians`: A = M^-1 dh/dq, B = M^-1 dh/dq'), the same system times M,
//! (d^2 M - c d dh/dq' - c^2 dh/dq) x2 = d M b2 + c dh/dq b1, is factorised: no M^-1 is
//! formed (2n solves with M per Jacobian).

use super::OdeSystem;
use super::lu::{SingularMatrix, lu_factor, lu_solve};
use super::ported::{PortedJacobian, PortedLu};

pub struct IterationMatrix {
    dim: usize,
    /// n when the system is y = [q; q'] with f = [q'; q''].
    half: Option<usize>,
    /// M, dh/dq, dh/dq' (n x n each) of the last `jacobian`, when the system gave them.
    mass: [Vec<f64>; 3],
    mass_form: bool,
    /// The ported pieces and their reduced LU, when the system is ported (`set_ported`).
    ported: Option<(PortedJacobian, PortedLu)>,
    /// The last `jacobian` gave the ported pieces.
    ported_form: bool,
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
            mass: [(); 3].map(|_| vec![0.0; (dim / 2) * (dim / 2)]),
            mass_form: false,
            ported: None,
            ported_form: false,
            c: 0.0,
            d: 1.0,
        }
    }

    /// Whether the system is second order with `half` positions (`OdeSystem::second_order`,
    /// known at `init`): the reduced form is used then. Never allocates.
    pub fn set_second_order(&mut self, half: Option<usize>) {
        self.half = half.filter(|&n| 2 * n == self.dim);
    }

    /// Whether the system is ported (`OdeSystem::ported_shape`, known at `init`, after
    /// `set_second_order`): the reduced solve of `ported.rs` is used then, when it is smaller.
    /// Allocates only the first time (or when the shape changes).
    pub fn set_ported<S: OdeSystem + ?Sized>(&mut self, sys: &S) {
        super::ported::prepare(&mut self.ported, sys, self.half, 0);
    }

    /// The last `jacobian` gave the ported pieces (the reduced solve is in use).
    #[cfg(test)]
    pub fn is_ported(&self) -> bool {
        self.ported_form
    }

    /// The Jacobian at (t, y): the ported pieces when the system is ported, else M, dh/dq, dh/dq' kept here when a second-order system gives
    /// them, else J into `jac` (`OdeSystem::jacobian`). `false`: neither is analytic (the
    /// caller differences J into `jac`).
    pub fn jacobian<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        jac: &mut [f64],
    ) -> bool {
        self.ported_form = match &mut self.ported {
            Some((j, _)) => sys.ported_jacobians(t, y, j),
            None => false,
        };
        if self.ported_form {
            return true;
        }
        let [m, hq, hqd] = &mut self.mass;
        self.mass_form = self.half.is_some() && sys.mass_jacobians(t, y, m, hq, hqd);
        self.mass_form || sys.jacobian(t, y, jac)
    }

    /// Factorise d I - c J (J row-major dim x dim; for a second-order system only its lower
    /// rows [A, B] are read: the upper ones are [0, I] by construction), or its mass form.
    /// `jac` must have been filled after the last `jacobian` if that returned no mass form.
    pub fn factor(&mut self, jac: &[f64], d: f64, c: f64) -> Result<(), SingularMatrix> {
        self.c = c;
        self.d = d;
        if let (true, Some((j, lu))) = (self.ported_form, &mut self.ported) {
            return lu.factor(j, d, c);
        }
        if let (true, Some(n)) = (self.mass_form, self.half) {
            let [m, hq, hqd] = &self.mass;
            for i in 0..n * n {
                self.lu[i] = d * d * m[i] - c * d * hqd[i] - c * c * hq[i];
            }
            return lu_factor(&mut self.lu[..n * n], n, &mut self.piv[..n]);
        }
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
        if let (true, Some((j, lu))) = (self.ported_form, &mut self.ported) {
            lu.solve(j, b);
            return;
        }
        if let (true, Some(n)) = (self.mass_form, self.half) {
            let [m, hq, _] = &self.mass;
            let (b1, b2) = b.split_at_mut(n);
            for i in 0..n {
                let (mr, kr) = (&m[i * n..(i + 1) * n], &hq[i * n..(i + 1) * n]);
                let mb: f64 = mr.iter().zip(b2.iter()).map(|(a, x)| a * x).sum();
                let kb: f64 = kr.iter().zip(b1.iter()).map(|(a, x)| a * x).sum();
                self.tmp[i] = self.d * mb + self.c * kb;
            }
            lu_solve(&self.lu[..n * n], n, &self.piv[..n], &mut self.tmp[..n]);
            for i in 0..n {
                b2[i] = self.tmp[i];
                b1[i] = (b1[i] + self.c * b2[i]) / self.d;
            }
            return;
        }
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
            let worst = (0..m).fold(0.0f64, |a, i| a.max((x1[i] - x2[i]).abs() / scale));
            println!("d {d}, c {c}: reduced against full LU {worst:.1e}");
            for i in 0..m {
                // Both are backward stable: they agree to a few ulps of the solution's size
                // (measured 3.7e-16 relative).
                assert!(
                    (x1[i] - x2[i]).abs() <= 5e-15 * scale,
                    "{i}: {} vs {}",
                    x1[i],
                    x2[i]
                );
            }
        }
    }

    /// A system that gives M, dh/dq, dh/dq' (the mass form) and J = [[0, I], [M^-1 dh/dq,
    /// M^-1 dh/dq']] with M^-1 from nalgebra (an independent path).
    struct MassForm {
        n: usize,
        m: Vec<f64>,
        hq: Vec<f64>,
        hqd: Vec<f64>,
    }

    impl OdeSystem for MassForm {
        fn dim(&self) -> usize {
            2 * self.n
        }
        fn rhs(&mut self, _t: f64, _y: &[f64], _dy: &mut [f64]) {}
        fn second_order(&self) -> Option<usize> {
            Some(self.n)
        }
        fn jacobian(&mut self, _t: f64, _y: &[f64], jac: &mut [f64]) -> bool {
            let n = self.n;
            let m = 2 * n;
            let minv = nalgebra::DMatrix::from_row_slice(n, n, &self.m)
                .try_inverse()
                .unwrap();
            let a = &minv * nalgebra::DMatrix::from_row_slice(n, n, &self.hq);
            let b = &minv * nalgebra::DMatrix::from_row_slice(n, n, &self.hqd);
            jac.fill(0.0);
            for i in 0..n {
                jac[i * m + n + i] = 1.0;
                for j in 0..n {
                    jac[(n + i) * m + j] = a[(i, j)];
                    jac[(n + i) * m + n + j] = b[(i, j)];
                }
            }
            true
        }
        fn mass_jacobians(
            &mut self,
            _t: f64,
            _y: &[f64],
            m: &mut [f64],
            hq: &mut [f64],
            hqd: &mut [f64],
        ) -> bool {
            m.copy_from_slice(&self.m);
            hq.copy_from_slice(&self.hq);
            hqd.copy_from_slice(&self.hqd);
            true
        }
    }

    /// The mass form (d^2 M - c d dh/dq' - c^2 dh/dq, no M^-1) against the full 2n x 2n LU of
    /// d I - c J with J formed through nalgebra's inverse of M.
    #[test]
    fn mass_form_solve_matches_full_lu_of_the_first_order_jacobian() {
        let n = 5;
        let mm = 2 * n;
        let f = |i: usize, j: usize, s: f64| ((i * 7 + j * 3) as f64 * s).sin();
        let mut sys = MassForm {
            n,
            // Symmetric positive definite: diagonal 3 + off-diagonal below 1 / n.
            m: (0..n * n)
                .map(|k| {
                    let (i, j) = (k / n, k % n);
                    if i == j {
                        3.0
                    } else {
                        0.15 * f(i.min(j), i.max(j), 0.3)
                    }
                })
                .collect(),
            hq: (0..n * n).map(|k| 400.0 * f(k / n, k % n, 0.71)).collect(),
            hqd: (0..n * n).map(|k| 20.0 * f(k / n, k % n, 1.3)).collect(),
        };
        let y = vec![0.0; mm];
        let mut jac = vec![0.0; mm * mm];
        for (d, c) in [(1.0, 0.013), (1.0 / (0.25 * 0.02), 1.0)] {
            let b: Vec<f64> = (0..mm).map(|i| (i as f64 * 1.3).cos()).collect();
            let mut full = IterationMatrix::new(mm);
            let mut mass = IterationMatrix::new(mm);
            mass.set_second_order(Some(n));
            assert!(sys.jacobian(0.0, &y, &mut jac));
            full.factor(&jac, d, c).unwrap();
            let mut unused = vec![f64::NAN; mm * mm];
            assert!(mass.jacobian(&mut sys, 0.0, &y, &mut unused));
            mass.factor(&unused, d, c).unwrap();
            let (mut x1, mut x2) = (b.clone(), b.clone());
            full.solve(&jac, &mut x1);
            mass.solve(&unused, &mut x2);
            let scale = x1.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let worst = (0..mm).fold(0.0f64, |a, i| a.max((x1[i] - x2[i]).abs() / scale));
            eprintln!("d {d}, c {c}: {worst:.1e}");
            for i in 0..mm {
                // Backward stable both: a few ulps of the solution's size (measured 5.1e-16).
                assert!(
                    (x1[i] - x2[i]).abs() <= 5e-15 * scale,
                    "{i}: {} vs {}",
                    x1[i],
                    x2[i]
                );
            }
        }
    }
}
