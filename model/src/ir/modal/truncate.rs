//! Truncation of modal data: keeping the first eigenmodes and folding the dropped ones' static
//! response at the load points into correction modes, the change of basis that carries every
//! field along, and the generalised eigenproblem both use.

use super::{Correction, LoadCase, ModalData};

impl ModalData {
    /// Keep the first `n` eigenmodes. The dropped eigenmodes and the correction modes become
    /// `FOLD_BLOCKS` shapes per independent load case (the correction's and `loads`, the
    /// scene's elements' at this body, `Model::element_loads`): sum_k Phi_k (f_j . Phi_k) /
    /// omega_k^(2b), b = 1, 2, over every dropped mode and every correction mode. The first
    /// keeps the data's static response at the load points exactly (one coordinate per load,
    /// not a correction mode and the dropped eigenmodes' part of the same give apart); the
    /// second the dropped modes' first dynamic term, (omega / omega_k)^2 of the first (the
    /// same Krylov block as `correction_order = 2` in fe's correction modes).
    pub fn truncate(&mut self, n: usize, loads: &[LoadCase]) {
        let (m, e) = (self.modes(), self.eigenmodes());
        if n >= e {
            return;
        }
        let w2: Vec<f64> = self
            .frequencies
            .iter()
            .map(|f| (2.0 * std::f64::consts::PI * f).powi(2))
            .collect();
        // Columns over the dropped modes n..m: the static shapes of the load cases. The stored
        // correction participations are the points' w . direction (the checker holds them
        // so), so every load case reads its point.
        let cols: Vec<Vec<f64>> = self
            .correction
            .iter()
            .flat_map(|c| &c.loads)
            .chain(loads)
            .filter_map(|l| self.point(&l.point).map(|p| (l, p)))
            .flat_map(|(l, p)| {
                let w2 = &w2;
                (1..=FOLD_BLOCKS as i32).map(move |b| {
                    let c: Vec<f64> = (n..m)
                        .map(|k| l.participation(p, k) / w2[k].powi(b))
                        .collect();
                    // Unit columns: the second block is omega^2 (~1e7) smaller, and the
                    // dependence test below is relative.
                    let size = c.iter().map(|v| v * v).sum::<f64>().sqrt();
                    c.into_iter()
                        .map(|v| if size > 0.0 { v / size } else { 0.0 })
                        .collect()
                })
            })
            .collect();
        let folded = if cols.is_empty() {
            (nalgebra::DMatrix::zeros(m - n, 0), Vec::new())
        } else {
            let u = nalgebra::DMatrix::from_fn(m - n, cols.len(), |r, c| cols[c][r]);
            orthonormal_static_basis(&u, &w2[n..m])
        };
        let p = folded.1.len();
        let mut t = nalgebra::DMatrix::zeros(m, n + p);
        for k in 0..n {
            t[(k, k)] = 1.0;
        }
        t.view_mut((n, n), (m - n, p)).copy_from(&folded.0);
        let mut frequencies = self.frequencies[..n].to_vec();
        frequencies.extend(folded.1);
        self.change_basis(&t, frequencies);
        match &mut self.correction {
            Some(c) => {
                c.modes = p;
                c.participation.truncate(n * c.loads.len());
            }
            // Data without correction modes: the folded shapes are correction modes all the
            // same, so that `eigenmodes()` counts only eigenmodes.
            None if p > 0 => {
                self.correction = Some(Correction {
                    loads: Vec::new(),
                    modes: p,
                    participation: Vec::new(),
                })
            }
            None => {}
        }
    }

    /// Cut as a scene with `cutoff` Hz cuts it: the eigenmodes up to it (at least one) and the
    /// static response of the dropped and correction modes to `loads` (`truncate`).
    pub fn cut(&mut self, cutoff: f64, loads: &[LoadCase]) {
        let keep = self.frequencies[..self.eigenmodes()]
            .iter()
            .filter(|f| **f <= cutoff)
            .count()
            .max(1);
        self.truncate(keep, loads);
    }

    /// The eigenmodes alone, without the correction modes (to measure what they buy).
    pub fn without_correction(&self) -> ModalData {
        let mut d = self.clone();
        let e = d.eigenmodes();
        let m = d.modes();
        d.correction = None;
        let t = nalgebra::DMatrix::from_fn(m, e, |r, c| if r == c { 1.0 } else { 0.0 });
        let f = d.frequencies[..e].to_vec();
        d.change_basis(&t, f);
        d
    }

    /// Express the data in new coordinates q_old = T q_new (T: modes x new modes) whose
    /// stiffness is diagonal with `frequencies`: every field is linear or bilinear in the shapes.
    fn change_basis(&mut self, t: &nalgebra::DMatrix<f64>, frequencies: Vec<f64>) {
        let (m, n) = t.shape();
        if self.file_modes.is_none() {
            self.file_modes = Some(self.own_modes());
        }
        let row = |v: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|j| (0..m).map(|k| v[k] * t[(k, j)]).sum())
                .collect()
        };
        let square = |v: &[f64]| -> Vec<f64> {
            let a = nalgebra::DMatrix::from_row_slice(m, m, v);
            let b = t.transpose() * a * t;
            (0..n * n).map(|i| b[(i / n, i % n)]).collect()
        };
        let file = match &self.basis {
            Some(b) => nalgebra::DMatrix::from_row_slice(b.len() / m, m, b) * t,
            None => t.clone(),
        };
        self.basis = Some(
            (0..file.nrows() * n)
                .map(|i| file[(i / n, i % n)])
                .collect(),
        );
        let e = &mut self.elementary;
        let has_g = e.has_g();
        for a in 0..3 {
            e.c[a] = row(&e.c[a]);
            for b in 0..3 {
                e.s[a][b] = row(&e.s[a][b]);
                if has_g {
                    e.g[a][b] = square(&e.g[a][b]);
                }
            }
        }
        for p in &mut self.points {
            for a in 0..3 {
                p.w[a] = row(&p.w[a]);
                p.phi[a] = row(&p.phi[a]);
            }
        }
        if let Some(k) = &mut self.geometric_stiffness {
            k.per_omega2 = square(&k.per_omega2);
        }
        self.frequencies = frequencies;
    }
}

/// Relative size below which a static shape adds nothing new (it lies in the others' span).
pub const DEPENDENT_SHAPE: f64 = 1e-10;

/// Krylov blocks a truncation folds the dropped modes into: 2, the static give and its first
/// dynamic term. With one, the `elastic` scene's tub and cabinet missed the 400-mode cabinet
/// at 1100 rpm by 1.3e-2 on the accelerations; with two, 2.7e-3 (docs/truncation.md).
pub const FOLD_BLOCKS: usize = 2;

/// The span of the columns of `u` (coordinates in modes with unit modal mass and stiffness
/// `w2`) as an orthonormal, stiffness-diagonal basis: (basis columns, their frequencies in Hz,
/// ascending). Directions whose modal mass is below `DEPENDENT_SHAPE` of the largest are dropped.
pub fn orthonormal_static_basis(
    u: &nalgebra::DMatrix<f64>,
    w2: &[f64],
) -> (nalgebra::DMatrix<f64>, Vec<f64>) {
    let k = nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(w2));
    let mass = u.transpose() * u;
    let stiff = u.transpose() * k * u;
    let (b, lambda) = generalised_eigen(&mass, &stiff);
    let basis = u * b;
    let f = lambda
        .iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    (basis, f)
}

/// Solve K x = lambda M x in the span where M (symmetric, semi-definite) is not negligible:
/// (X with X^T M X = E and X^T K X = diag(lambda), lambda ascending).
pub fn generalised_eigen(
    mass: &nalgebra::DMatrix<f64>,
    stiff: &nalgebra::DMatrix<f64>,
) -> (nalgebra::DMatrix<f64>, Vec<f64>) {
    let me = nalgebra::SymmetricEigen::new(0.5 * (mass + mass.transpose()));
    let top = me.eigenvalues.iter().fold(0.0f64, |a, v| a.max(*v));
    let keep: Vec<usize> = (0..me.eigenvalues.len())
        .filter(|&i| top > 0.0 && me.eigenvalues[i] > DEPENDENT_SHAPE * top)
        .collect();
    let b = nalgebra::DMatrix::from_fn(mass.nrows(), keep.len(), |r, c| {
        me.eigenvectors[(r, keep[c])] / me.eigenvalues[keep[c]].sqrt()
    });
    let a = b.transpose() * stiff * &b;
    let ke = nalgebra::SymmetricEigen::new(0.5 * (&a + a.transpose()));
    let mut order: Vec<usize> = (0..keep.len()).collect();
    order.sort_by(|&i, &j| ke.eigenvalues[i].total_cmp(&ke.eigenvalues[j]));
    let x = nalgebra::DMatrix::from_fn(mass.nrows(), keep.len(), |r, c| {
        (0..keep.len())
            .map(|l| b[(r, l)] * ke.eigenvectors[(l, order[c])])
            .sum()
    });
    (x, order.iter().map(|&i| ke.eigenvalues[i]).collect())
}
