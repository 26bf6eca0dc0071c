//! M1 solved through its structure: mass-normalised modes make every modal block the identity,
//! and what couples them (the parts the tub carries at its mounts, the drum hanging on the
//! tub's bearing, the turning unbalances) has low rank. With D = diag(R, I) (R: the rigid
//! coordinates' constant 6 x 6 block), M1(phi) = D + U C(phi) U^T, U (n1 x r) an orthonormal
//! basis of every deviation's column space, found once from M1's harmonic form
//! (`codegen::mass`: M1 = A_0 + sum over rotors of cos/sin of 1 and 2 x its angle times
//! constant matrices), C(phi) = U^T (M1 - D) U assembled from r x r tables. Woodbury then
//! gives M1^-1 h = y - D^-1 U C (I + S C)^-1 U^T y, y = D^-1 h, S = U^T D^-1 U: O(n1 r + r^3)
//! in place of the Cholesky's n1^3 / 3 (n1 = 114, r = 30 on the elastic reference), exact to
//! round-off (no singular value of the deviation is dropped above round-off).

use nalgebra::DMatrix;
use washdyn_model::codegen::mass::{LOW_RANK_MIN_N1, MassHarmonics, fit};
use washdyn_model::equations::Equations;
use washdyn_model::linalg::{cholesky_in_place, cholesky_solve};
use washdyn_ode::lu::{lu_factor, lu_solve};

/// A direction of the deviations' column space is kept down to this share of the largest
/// singular value: round-off, so the solve stays exact.
const RANK_TOL: f64 = 1e-15;
/// The rigid coordinates that D keeps in a block of their own.
const RIGID: usize = 6;

/// A deviation projected on U: C = U^T A U and S C (r x r each, row-major).
type Projected = (Vec<f64>, Vec<f64>);

/// The low-rank form of M1 and its work arrays (allocated in `new`, never in `solve`).
#[derive(Clone, Debug)]
pub struct LowRankMass {
    n1: usize,
    r: usize,
    /// R's Cholesky factor (6 x 6).
    rigid: Vec<f64>,
    /// U (n1 x r, row-major) and V = D^-1 U.
    u: Vec<f64>,
    v: Vec<f64>,
    /// C(phi) = c0 + sum x_k c_k and S C(phi) = p0 + sum x_k p_k (r x r each, row-major).
    c0: Vec<f64>,
    p0: Vec<f64>,
    /// Per rotor: its ratio and four (C, S C) pairs for cos, sin, cos 2, sin 2.
    rotors: Vec<(f64, [Projected; 4])>,
    c: Vec<f64>,
    g: Vec<f64>,
    piv: Vec<usize>,
    t: Vec<f64>,
    w: Vec<f64>,
}

impl LowRankMass {
    /// For a scene whose M1 has the harmonic form and is large enough to gain; `None` else.
    pub fn new(eq: &Equations) -> Option<LowRankMass> {
        let n1 = eq.layout.n1;
        if n1 < LOW_RANK_MIN_N1 {
            return None;
        }
        Self::from_harmonics(&fit(eq)?, n1)
    }

    fn from_harmonics(f: &MassHarmonics, n1: usize) -> Option<LowRankMass> {
        let mat = |a: &[f64]| DMatrix::from_row_slice(n1, n1, a);
        let mut d = DMatrix::identity(n1, n1);
        let a0 = mat(&f.constant);
        d.view_mut((0, 0), (RIGID, RIGID))
            .copy_from(&a0.view((0, 0), (RIGID, RIGID)));
        let e0 = &a0 - &d;
        let terms: Vec<(f64, [DMatrix<f64>; 4])> =
            f.rotors().map(|(ratio, a)| (ratio, a.map(mat))).collect();
        // The deviations side by side: their joint column space.
        let mut wide = DMatrix::zeros(n1, n1 * (1 + 4 * terms.len()));
        wide.view_mut((0, 0), (n1, n1)).copy_from(&e0);
        for (k, m) in terms.iter().flat_map(|(_, a)| a).enumerate() {
            wide.view_mut((0, (k + 1) * n1), (n1, n1)).copy_from(m);
        }
        let svd = wide.svd(true, false);
        let top = svd.singular_values.max();
        let keep: Vec<usize> = (0..svd.singular_values.len())
            .filter(|&i| svd.singular_values[i] > RANK_TOL * n1 as f64 * top)
            .collect();
        let r = keep.len();
        let full_u = svd.u?;
        let u = DMatrix::from_fn(n1, r, |i, j| full_u[(i, keep[j])]);
        let mut rigid: Vec<f64> = (0..RIGID * RIGID)
            .map(|k| a0[(k / RIGID, k % RIGID)])
            .collect();
        if !cholesky_in_place(&mut rigid, RIGID) {
            return None;
        }
        let mut v = u.clone();
        for j in 0..r {
            let mut col: Vec<f64> = (0..RIGID).map(|i| v[(i, j)]).collect();
            cholesky_solve(&rigid, RIGID, &mut col);
            for i in 0..RIGID {
                v[(i, j)] = col[i];
            }
        }
        let s = u.transpose() * &v;
        let project = |m: &DMatrix<f64>| {
            let c = u.transpose() * m * &u;
            let p = &s * &c;
            (row_major(&c), row_major(&p))
        };
        let (c0, p0) = project(&e0);
        let rotors = terms
            .iter()
            .map(|(ratio, a)| (*ratio, [0, 1, 2, 3].map(|k| project(&a[k]))))
            .collect();
        Some(LowRankMass {
            n1,
            r,
            rigid,
            u: row_major(&u),
            v: row_major(&v),
            c0,
            p0,
            rotors,
            c: vec![0.0; r * r],
            g: vec![0.0; r * r],
            piv: vec![0; r],
            t: vec![0.0; r],
            w: vec![0.0; r],
        })
    }

    /// The rank of M1's deviation from D.
    pub fn rank(&self) -> usize {
        self.r
    }

    /// x <- M1(phi)^-1 x (length n1). False when I + S C is singular (M1 is not invertible).
    pub fn solve(&mut self, phi: f64, x: &mut [f64]) -> bool {
        let (n1, r) = (self.n1, self.r);
        // y = D^-1 h.
        cholesky_solve(&self.rigid, RIGID, &mut x[..RIGID]);
        // C(phi) and I + S C(phi).
        self.c.copy_from_slice(&self.c0);
        self.g.copy_from_slice(&self.p0);
        for (ratio, mats) in &self.rotors {
            let th = ratio * phi;
            let (s1, c1) = th.sin_cos();
            let xs = [c1, s1, c1 * c1 - s1 * s1, 2.0 * s1 * c1];
            for ((c, p), x) in mats.iter().zip(xs) {
                axpy(x, c, &mut self.c);
                axpy(x, p, &mut self.g);
            }
        }
        for i in 0..r {
            self.g[i * r + i] += 1.0;
        }
        // t = U^T y.
        self.t.fill(0.0);
        for (row, &yi) in self.u.chunks_exact(r).zip(&x[..n1]) {
            axpy(yi, row, &mut self.t);
        }
        if lu_factor(&mut self.g, r, &mut self.piv).is_err() {
            return false;
        }
        lu_solve(&self.g, r, &self.piv, &mut self.t);
        // w = C (I + S C)^-1 t, x = y - V w.
        for (w, row) in self.w.iter_mut().zip(self.c.chunks_exact(r)) {
            *w = dot(row, &self.t);
        }
        for (xi, row) in x[..n1].iter_mut().zip(self.v.chunks_exact(r)) {
            *xi -= dot(row, &self.w);
        }
        true
    }
}

/// y += a x (iterators: no bounds checks, so it vectorises).
fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    for (y, x) in y.iter_mut().zip(x) {
        *y += a * x;
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn row_major(m: &DMatrix<f64>) -> Vec<f64> {
    let (rows, cols) = m.shape();
    (0..rows * cols).map(|k| m[(k / cols, k % cols)]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use washdyn_model::equations::Drive;

    /// The low-rank solve against the Cholesky of the derivation's own M1 (the interpreter's
    /// solve) on the reference's elastic scene, at angles the harmonic fit never saw: the same
    /// q'' to round-off, with the deviation's rank far below n1.
    #[test]
    fn low_rank_solve_is_the_cholesky_solve() {
        let src = include_str!("../../models/data/reference.toml");
        let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/data");
        let m = washdyn_model::ir::toml_file::load_str(src, "reference.toml", &data).unwrap();
        let eq = Equations::new(&m, &m.scene(Some("elastic")).unwrap());
        let (n1, n) = (eq.layout.n1, eq.layout.n());
        let mut lr = LowRankMass::new(&eq).expect("the elastic scene's M1 has the form");
        // Measured: rank 30 of n1 = 114.
        assert!(lr.rank() <= 40 && lr.rank() < n1, "rank {}", lr.rank());
        let mut worst = 0.0f64;
        for i in 0..12 {
            let phi = 0.37 + 5.123 * i as f64;
            let d = Drive {
                phi,
                omega: 80.0,
                omega_dot: 2.0,
            };
            let (mut m1, mut h) = (vec![0.0; n1 * n1], vec![0.0; n]);
            let q = vec![0.0; n];
            eq.eval(&d, &q, &q, &mut m1, &mut h);
            let b: Vec<f64> = (0..n1).map(|k| (1.3 * k as f64 + phi).sin()).collect();
            let mut want = b.clone();
            assert!(cholesky_in_place(&mut m1, n1));
            cholesky_solve(&m1, n1, &mut want);
            let mut got = b;
            assert!(lr.solve(phi, &mut got));
            let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (g, w) in got.iter().zip(&want) {
                worst = worst.max((g - w).abs() / scale);
            }
        }
        eprintln!("low-rank against Cholesky: {worst:.2e}");
        // Measured: 4.1e-14 of the largest entry.
        assert!(worst < 1e-12, "{worst:e}");
    }
}
