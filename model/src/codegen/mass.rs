//! M1 as a trigonometric polynomial of the rotor angles, for the scenes whose M1 is factorised at
//! run time. M1 depends on the drum angle only (checked by the dependency pass), and only through
//! the rotors turning with it: an unbalance's moving mass adds m J^T J with J linear in the cosine
//! and sine of its rotor's angle, the spinning drum's coupling R(theta) C is linear in them. So
//! M1(phi) = A_0 + sum_r (c_r A_1r + s_r A_2r + c2_r A_3r + s2_r A_4r) with theta_r = ratio_r phi
//! and constant matrices A. Spelled out entry by entry, the unbalances' dense block was 114 000
//! operations at 100 tub modes, and rustc ran out of 24 GB on it; as a table it is one
//! `MatVec` (a loop) and one copy into m1.
//!
//! The matrices are fitted to the derivation's own M1 at sampled angles (least squares, exact for
//! this form up to round-off) and checked at other angles; a scene whose M1 is not of this form
//! keeps the traced entries.

use crate::equations::{Drive, Equations};
use crate::scalar::Scalar;
use crate::symbolic::{Graph, Sym, trace};
use nalgebra::DMatrix;

/// From this n1 on, M1 is solved through its low-rank structure at run time (the runtime's
/// `mass.rs`) and the generated code gives h alone (`forces`); below it the Cholesky is as cheap.
pub const LOW_RANK_MIN_N1: usize = 24;

/// Relative bound on the fit's error at the check angles (of the largest |M1| entry). The fit of
/// an exact trigonometric polynomial lands at round-off (about 1e-15).
const FIT_TOL: f64 = 1e-12;

/// The fitted form: rotor ratios and A_0 (n1^2) and the table [A_1r A_2r A_3r A_4r]_r
/// (n1^2 x 4R, column-major).
pub struct MassHarmonics {
    pub ratios: Vec<f64>,
    pub constant: Vec<f64>,
    pub table: Vec<f64>,
    /// Rotors by decreasing count of entries they change.
    order: Vec<usize>,
}

fn m1_at(eq: &Equations, phi: f64) -> Vec<f64> {
    let (n1, n) = (eq.layout.n1, eq.layout.n());
    let d = Drive {
        phi,
        omega: 0.0,
        omega_dot: 0.0,
    };
    let z = vec![0.0; n];
    let (mut m1, mut h) = (vec![0.0; n1 * n1], vec![0.0; n]);
    eq.eval(&d, &z, &z, &mut m1, &mut h);
    m1
}

fn basis(ratios: &[f64], phi: f64) -> Vec<f64> {
    let mut b = vec![1.0];
    for r in ratios {
        let th = r * phi;
        b.extend([th.cos(), th.sin(), (2.0 * th).cos(), (2.0 * th).sin()]);
    }
    b
}

/// Fit M1(phi) of a scene, or `None` when it is not of the form (or constant: nothing to gain).
pub fn fit(eq: &Equations) -> Option<MassHarmonics> {
    let n1 = eq.layout.n1;
    let mut ratios: Vec<f64> = eq
        .unbalances
        .iter()
        .map(|u| u.ratio)
        .chain(eq.elastic_drum().map(|d| d.ratio))
        .filter(|r| *r != 0.0)
        .map(f64::abs)
        .collect();
    ratios.sort_by(f64::total_cmp);
    ratios.dedup();
    if ratios.is_empty() {
        return None;
    }
    let k = 1 + 4 * ratios.len();
    // Angles spread over many drum turns (an irrational step), 4 per unknown.
    let phis: Vec<f64> = (0..4 * k).map(|i| 0.3 + 2.399_963 * i as f64).collect();
    let samples: Vec<Vec<f64>> = phis.iter().map(|&p| m1_at(eq, p)).collect();
    let rows: Vec<Vec<f64>> = phis.iter().map(|&p| basis(&ratios, p)).collect();
    let a = DMatrix::from_fn(phis.len(), k, |i, j| rows[i][j]);
    let b = DMatrix::from_fn(phis.len(), n1 * n1, |i, e| samples[i][e]);
    let coef = a.svd(true, true).solve(&b, 1e-12).ok()?;
    let scale = samples.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut constant = vec![0.0; n1 * n1];
    let mut table = vec![0.0; n1 * n1 * (k - 1)];
    let mut varies = false;
    for e in 0..n1 * n1 {
        // An entry that never changes keeps its exact value; a varying one its fitted
        // harmonics, with round-off-sized coefficients set to 0 so the table stays sparse.
        if samples.iter().all(|s| s[e] == samples[0][e]) {
            constant[e] = samples[0][e];
            continue;
        }
        varies = true;
        constant[e] = coef[(0, e)];
        for j in 1..k {
            let c = coef[(j, e)];
            table[(j - 1) * n1 * n1 + e] = if c.abs() <= 1e-14 * scale { 0.0 } else { c };
        }
    }
    if !varies {
        return None;
    }
    let e = n1 * n1;
    let width = |r: usize| {
        (0..e)
            .filter(|&i| (0..4).any(|c| table[(4 * r + c) * e + i] != 0.0))
            .count()
    };
    let mut order: Vec<usize> = (0..ratios.len()).collect();
    order.sort_by_key(|&r| std::cmp::Reverse(width(r)));
    let fitted = MassHarmonics {
        ratios,
        constant,
        table,
        order,
    };
    // Check at angles the fit did not see.
    for i in 0..8 {
        let phi = -1.7 + 0.913 * i as f64;
        let m1 = m1_at(eq, phi);
        let f = fitted.m1(phi);
        let err = m1
            .iter()
            .zip(&f)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        // NaN fails too.
        if err.is_nan() || err > FIT_TOL * scale {
            return None;
        }
    }
    Some(fitted)
}

impl MassHarmonics {
    /// Each rotor's angle ratio to the drum and its four matrices (n1^2, M1's row-major
    /// order), the coefficients of cos, sin, cos 2, sin 2 of the rotor angle.
    pub fn rotors(&self) -> impl Iterator<Item = (f64, [&[f64]; 4])> {
        let e = self.constant.len();
        self.ratios.iter().enumerate().map(move |(r, &ratio)| {
            let a = |c: usize| &self.table[(4 * r + c) * e..(4 * r + c + 1) * e];
            (ratio, [a(0), a(1), a(2), a(3)])
        })
    }

    /// M1 at phi over any scalar (`Sym` records the table as one `MatVec`).
    pub fn m1<T: Scalar>(&self, phi: T) -> Vec<T> {
        let mut m1: Vec<T> = self.constant.iter().map(|v| T::c(*v)).collect();
        let e = m1.len();
        // One table per rotor, the widest block first: a rotor's moving mass couples only the
        // columns that carry it (the motor's not the drum's modes), and the symbolic MatVec
        // drops the rows a rotor leaves zero.
        for &r in &self.order {
            let th = phi * self.ratios[r];
            let (c, s) = (th.cos(), th.sin());
            let x = [c, s, c * c - s * s, s * c * 2.0];
            T::mat_vec(&self.table[4 * r * e..4 * (r + 1) * e], &x, &mut m1);
        }
        m1
    }

    /// The traced M1 over the generated function's inputs (q, q', phi, omega, omega'), so its
    /// code shares their names.
    pub fn trace(&self, n: usize) -> (Graph, Vec<Sym>) {
        let (m1, g) = trace(|| {
            let inputs: Vec<Sym> = (0..2 * n + 3).map(|_| Sym::input()).collect();
            self.m1(inputs[2 * n])
        });
        (g, m1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn elastic() -> Equations {
        let src = include_str!("../../../models/data/reference.toml");
        let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/data");
        let m = crate::ir::toml_file::load_str(src, "reference.toml", &data).unwrap();
        Equations::new(&m, &m.scene(Some("elastic")).unwrap())
    }

    /// The fitted M1 is the derivation's M1 at angles and speeds neither the fit nor its check
    /// used (the derivation's M1 ignores the speed: checked by the generator's dependency pass),
    /// to round-off of the largest entry; the drum's and the motor's angles both appear.
    #[test]
    fn fitted_mass_matrix_is_the_derivations_at_other_angles() {
        let eq = elastic();
        let f = fit(&eq).expect("the elastic scene's M1 is a trigonometric polynomial");
        assert_eq!(f.ratios, vec![1.0, 11.25]);
        let (n1, n) = (eq.layout.n1, eq.layout.n());
        let mut worst = 0.0f64;
        let mut scale = 0.0f64;
        for i in 0..20 {
            let phi = 123.4 + 17.77 * i as f64;
            let d = Drive {
                phi,
                omega: 50.0 + i as f64,
                omega_dot: 3.0,
            };
            let q: Vec<f64> = (0..n).map(|k| 1e-3 * (k as f64).sin()).collect();
            let (mut m1, mut h) = (vec![0.0; n1 * n1], vec![0.0; n]);
            eq.eval(&d, &q, &q, &mut m1, &mut h);
            let fm = f.m1(phi);
            for (a, b) in m1.iter().zip(&fm) {
                worst = worst.max((a - b).abs());
                scale = scale.max(a.abs());
            }
        }
        // Measured 1.6e-15 of the largest entry.
        assert!(worst <= 1e-14 * scale, "{worst:e} of {scale}");
    }
}
