//! Elastic bodies in the equations: a body's modal coordinates with their stiffness, modal
//! damping and weight, and the mode-shape rows its markers use. So far the cabinet (subsystem 2:
//! no rigid DOF, mass-normalised modes, so M2 = E).

use super::kinematics::ModalRows;
use crate::dual::Dual;
use crate::ir::Elastic;
use crate::ir::loads::ElementLoad;
use crate::ir::modal::{Curves, MAX_CURVE_MODES, ModalData, point_at};
use crate::scalar::Scalar;

/// A body's modes as the derivation uses them.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalBody {
    pub name: String,
    /// First index of the body's coordinates in q.
    pub start: usize,
    pub n: usize,
    /// omega_k^2, (rad/s)^2.
    pub omega2: Vec<f64>,
    /// 2 zeta omega_k, 1/s (modal damping).
    pub damping: Vec<f64>,
    /// The body's weight on each mode, sum dm W_k . g, N per unit modal coordinate.
    pub weight: Vec<f64>,
    /// The support springs' share of `damping` (the cabinet's feet): 2 omega_k zeta_s s_k,
    /// with s_k the mode's strain-energy share in them; `None` without `support_damping`
    /// (the feet's damping is then not told apart from the structure's).
    pub support_damping: Option<Vec<f64>>,
    /// The characteristic curves when the scene switches them on.
    pub curves: Option<CurveTerms>,
    data: crate::ir::modal::ModalData,
}

/// A body's characteristic curves in its kept coordinates: the chosen file modes are
/// q_c = T_c q (T_c: rows of the truncation's basis, or unit rows), their force enters h as
/// -T_c^T f_nl(q_c), so a truncated or folded basis carries the curves by the same Ritz
/// projection as every other term.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveTerms {
    pub curves: Curves,
    /// T_c column-major (n_c rows): `Scalar::mat_vec`'s layout for q_c = T_c q.
    t: Vec<f64>,
    /// T_c^T column-major (n rows), i.e. T_c row by row: for T_c^T f.
    tt: Vec<f64>,
}

impl CurveTerms {
    fn new(curves: &Curves, d: &ModalData) -> Self {
        let (n, nc) = (d.modes(), curves.modes.len());
        let row = |r: usize| -> Vec<f64> {
            let m = curves.modes[r];
            match &d.basis {
                Some(b) => b[m * n..(m + 1) * n].to_vec(),
                None => (0..n).map(|j| if j == m { 1.0 } else { 0.0 }).collect(),
            }
        };
        let rows: Vec<Vec<f64>> = (0..nc).map(row).collect();
        CurveTerms {
            curves: curves.clone(),
            t: (0..n)
                .flat_map(|j| rows.iter().map(move |r| r[j]))
                .collect(),
            tt: rows.concat(),
        }
    }

    /// Chosen modes (at least one: the checker's rule).
    pub fn chosen_modes(&self) -> usize {
        self.curves.modes.len()
    }

    /// q_c = T_c q into the first `len()` entries.
    fn chosen<T: Scalar>(&self, q: &[T]) -> [T; MAX_CURVE_MODES] {
        let mut qc = [T::zero(); MAX_CURVE_MODES];
        T::mat_vec(&self.t, q, &mut qc[..self.chosen_modes()]);
        qc
    }

    /// h -= T_c^T f_nl(T_c q) over the body's own coordinates `q` and rows `h`.
    pub fn add<T: Scalar>(&self, q: &[T], h: &mut [T]) {
        let nc = self.chosen_modes();
        let qc = self.chosen(q);
        let mut f = [T::zero(); MAX_CURVE_MODES];
        self.curves.force_into(&qc[..nc], &mut f[..nc]);
        let neg = f.map(|x| -x);
        T::mat_vec(&self.tt, &neg[..nc], h);
    }

    /// The power of the curves' force at velocities `v`: -(T_c v) . f_nl(T_c q), W.
    pub fn power(&self, q: &[f64], v: &[f64]) -> f64 {
        let nc = self.chosen_modes();
        let (qc, vc) = (self.chosen(q), self.chosen(v));
        let mut f = [0.0; MAX_CURVE_MODES];
        self.curves.force_into(&qc[..nc], &mut f[..nc]);
        -(0..nc).map(|r| vc[r] * f[r]).sum::<f64>()
    }

    /// dh/dq of `add` into `hq` (row-major, `dim` columns, the body's block at `at`):
    /// -T_c^T H T_c with H the energy's Hessian in the chosen modes (one pass over duals).
    pub fn add_jacobian(&self, q: &[f64], hq: &mut [f64], dim: usize, at: usize) {
        let nc = self.chosen_modes();
        let n = self.tt.len() / nc.max(1);
        let qc = self.chosen(q);
        let qd: [Dual<MAX_CURVE_MODES>; MAX_CURVE_MODES] =
            std::array::from_fn(|r| Dual::seed(qc[r], r));
        let mut f = [Dual::<MAX_CURVE_MODES>::c(0.0); MAX_CURVE_MODES];
        self.curves.force_into(&qd[..nc], &mut f[..nc]);
        // HT = H T_c, row by row, then -T_c^T HT, skipping the modes no chosen row touches.
        let t_row = |r: usize| &self.tt[r * n..(r + 1) * n];
        for i in 0..n {
            if (0..nc).all(|r| t_row(r)[i] == 0.0) {
                continue;
            }
            for j in 0..n {
                let mut v = 0.0;
                for r in 0..nc {
                    let tri = t_row(r)[i];
                    if tri == 0.0 {
                        continue;
                    }
                    let hs: f64 = (0..nc).map(|s| f[r].d[s] * t_row(s)[j]).sum();
                    v += tri * hs;
                }
                hq[(at + i) * dim + at + j] -= v;
            }
        }
    }
}

/// Each kept mode's damping ratio: the entry's `damping`, moved towards `support_damping` by
/// the mode's share of strain energy in the support springs (modal strain energy method), plus
/// the Rayleigh term `stiffness_damping` omega_k / 2. `d` is the data as the scene keeps it
/// (truncated, correction modes included): each of its modes gets its own share.
pub fn modal_damping(e: &Elastic, d: &crate::ir::modal::ModalData) -> Vec<f64> {
    let share = match e.support_damping {
        Some(_) => d.support_energy(),
        None => vec![0.0; d.modes()],
    };
    let zs = e.support_damping.unwrap_or(e.damping);
    d.frequencies
        .iter()
        .zip(share)
        .map(|(f, s)| {
            e.damping + (zs - e.damping) * s + e.stiffness_damping * std::f64::consts::PI * f
        })
        .collect()
}

impl ModalBody {
    /// From a checked, resolved `elastic` entry and the data the scene runs (`d`: its `data`,
    /// or the tub's `bare` data); its coordinates start at `start`. With a
    /// scene's `cutoff` (Hz) only the eigenmodes up to it are kept (at least one), the static
    /// correction modes, and the dropped modes' static response to `loads` (the scene's
    /// elements' loads on this body, `Model::element_loads`).
    /// `curves`: whether the scene switches the entry's characteristic curves on.
    pub fn new(
        e: &Elastic,
        d: &crate::ir::modal::ModalData,
        start: usize,
        gravity: [f64; 3],
        (cutoff, curves): (Option<f64>, bool),
        loads: &[ElementLoad],
    ) -> Self {
        let mut d = d.clone();
        if let Some(fc) = cutoff {
            let cases: Vec<_> = loads.iter().filter_map(|l| l.case(&d)).collect();
            d.cut(fc, &cases);
        }
        let n = d.modes();
        let w: Vec<f64> = d
            .frequencies
            .iter()
            .map(|f| 2.0 * std::f64::consts::PI * f)
            .collect();
        let zeta = modal_damping(e, &d);
        let support_damping = e.support_damping.map(|zs| {
            w.iter()
                .zip(d.support_energy())
                .map(|(w, s)| 2.0 * w * zs * s)
                .collect()
        });
        ModalBody {
            name: e.name.clone(),
            start,
            n,
            omega2: w.iter().map(|w| w * w).collect(),
            damping: w.iter().zip(&zeta).map(|(w, z)| 2.0 * z * w).collect(),
            support_damping,
            curves: e
                .curves_data
                .as_ref()
                .filter(|_| curves)
                .map(|c| CurveTerms::new(c, &d)),
            weight: (0..n)
                .map(|k| (0..3).map(|a| d.elementary.c[a][k] * gravity[a]).sum())
                .collect(),
            data: d,
        }
    }

    /// The rows of the modal point at `p` (checked to exist).
    pub fn rows(&self, p: [f64; 3]) -> ModalRows {
        let pt = point_at(&self.data, p).expect("checked: a modal point at every marker");
        ModalRows::new(
            self.start,
            (0..self.n)
                .map(|k| [pt.w[0][k], pt.w[1][k], pt.w[2][k]])
                .collect(),
            (0..self.n)
                .map(|k| [pt.phi[0][k], pt.phi[1][k], pt.phi[2][k]])
                .collect(),
        )
    }

    /// The modal data (kept modes only).
    pub fn data(&self) -> &crate::ir::modal::ModalData {
        &self.data
    }

    /// The body's own terms in h on a fixed frame (the cabinet): weight minus omega^2 q and
    /// 2 zeta omega q' (M = E for mass-normalised modes: ccx's normalisation, the one its
    /// frequencies belong to).
    pub fn add<T: Scalar>(&self, q: &[T], qd: &[T], h: &mut [T]) {
        for k in 0..self.n {
            h[self.start + k] += T::c(self.weight[k]);
        }
        self.add_elastic(q, qd, h);
    }

    /// Stiffness and modal damping only (a moving frame brings its own weight terms).
    pub fn add_elastic<T: Scalar>(&self, q: &[T], qd: &[T], h: &mut [T]) {
        for k in 0..self.n {
            let i = self.start + k;
            h[i] -= q[i] * self.omega2[k] + qd[i] * self.damping[k];
        }
        if let Some(c) = &self.curves {
            let r = self.start..self.start + self.n;
            c.add(&q[r.clone()], &mut h[r]);
        }
    }

    /// The Jacobians of `add_elastic`: dh/dq -= diag(omega^2), dh/dq' -= diag(2 zeta omega)
    /// (row-major n x n).
    pub fn add_elastic_jacobian(&self, hq: &mut [f64], hqd: &mut [f64], n: usize) {
        for k in 0..self.n {
            let i = self.start + k;
            hq[i * n + i] -= self.omega2[k];
            hqd[i * n + i] -= self.damping[k];
        }
    }

    /// The curves' part of dh/dq (row-major `dim` columns), at the body's coordinates in `q`
    /// (the whole state): not diagonal, so subsystem 2 with curves declines the ported form.
    pub fn add_curves_jacobian(&self, q: &[f64], hq: &mut [f64], dim: usize) {
        if let Some(c) = &self.curves {
            c.add_jacobian(&q[self.start..self.start + self.n], hq, dim, self.start);
        }
    }

    /// The same terms into the diagonals `dq`, `dv` of a subsystem starting at coordinate
    /// `offset` (the ported form's subsystem 2).
    pub fn add_elastic_diagonal(&self, dq: &mut [f64], dv: &mut [f64], offset: usize) {
        for k in 0..self.n {
            let i = self.start + k - offset;
            dq[i] -= self.omega2[k];
            dv[i] -= self.damping[k];
        }
    }

    /// sum dm W_k per mode (3-vectors).
    pub fn weight_sums(&self) -> Vec<[f64; 3]> {
        let c = &self.data.elementary.c;
        (0..self.n).map(|k| [c[0][k], c[1][k], c[2][k]]).collect()
    }

    /// M1 blocks of a floating frame's modes (the tub): with the frame's rigid columns 0..6 about
    /// p0, sum dm W_k on translation, sum dm (x0 - p0) x W_k on rotation, and E on the modes
    /// (ccx's normalisation, as for the stiffness).
    pub fn add_frame_mass(&self, m1: &mut [f64], n1: usize, p0: [f64; 3]) {
        let el = &self.data.elementary;
        for k in 0..self.n {
            let j = self.start + k;
            let t = |a: usize, b: usize| el.s[a][b][k] - p0[a] * el.c[b][k];
            let x = [t(1, 2) - t(2, 1), t(2, 0) - t(0, 2), t(0, 1) - t(1, 0)];
            for a in 0..3 {
                m1[a * n1 + j] += el.c[a][k];
                m1[j * n1 + a] += el.c[a][k];
                m1[(3 + a) * n1 + j] += x[a];
                m1[j * n1 + 3 + a] += x[a];
            }
            m1[j * n1 + j] += 1.0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::BodyRef;
    use crate::ir::modal::{ModalData, SupportSpring, tests::tiny};
    use std::f64::consts::PI;

    /// `tiny` (modes at 10 and 20 Hz; FOOT_1 moves 1 m along z per unit of mode 0 only) on a
    /// vertical spring that stores half of mode 0's strain energy: k w^2 = omega_0^2 / 2.
    fn on_a_foot() -> ModalData {
        let mut d = tiny();
        d.support_springs = vec![SupportSpring {
            point: "FOOT_1".into(),
            stiffness: [0.0, 0.0, 0.5 * (2.0 * PI * 10.0f64).powi(2)],
        }];
        d
    }

    fn entry(d: ModalData, support: Option<f64>, beta: f64) -> Elastic {
        Elastic {
            name: BodyRef::Cabinet.name().into(),
            file: "cabinet.modal.toml".into(),
            modes: None,
            damping: 0.02,
            support_damping: support,
            stiffness_damping: beta,
            curves: None,
            curves_data: None,
            bare: None,
            bare_data: None,
            data: Some(d),
        }
    }

    #[test]
    fn each_mode_gets_its_support_share_of_damping_and_the_rayleigh_term() {
        let d = on_a_foot();
        // Closed form: e = (0.5, 0) from the spring above.
        assert_eq!(d.support_energy(), vec![0.5, 0.0]);
        let b = ModalBody::new(
            &entry(d.clone(), Some(0.06), 1e-3),
            &d,
            0,
            [0.0; 3],
            (None, false),
            &[],
        );
        let w = [2.0 * PI * 10.0, 2.0 * PI * 20.0];
        // zeta_k = 0.02 + (0.06 - 0.02) e_k + beta omega_k / 2.
        let zeta = [
            0.02 + 0.04 * 0.5 + 1e-3 * w[0] / 2.0,
            0.02 + 1e-3 * w[1] / 2.0,
        ];
        for k in 0..2 {
            assert!((b.damping[k] - 2.0 * zeta[k] * w[k]).abs() < 1e-12, "{k}");
        }
        // Without the new keys: every mode has `damping` (old files and models unchanged).
        let b = ModalBody::new(
            &entry(d.clone(), None, 0.0),
            &d,
            0,
            [0.0; 3],
            (None, false),
            &[],
        );
        for k in 0..2 {
            assert_eq!(b.damping[k], 2.0 * 0.02 * w[k]);
        }
    }

    /// Six modes, the last a static correction mode for a load at P; a vertical spring at P.
    fn with_correction() -> ModalData {
        let n = 6;
        let mut d = tiny();
        let eye: Vec<f64> = (0..n * n)
            .map(|i| if i / n == i % n { 1.0 } else { 0.0 })
            .collect();
        d.frequencies = vec![5.0, 8.0, 13.0, 21.0, 34.0, 80.0];
        d.elementary.c = std::array::from_fn(|_| vec![0.0; n]);
        d.elementary.s = std::array::from_fn(|_| std::array::from_fn(|_| vec![0.0; n]));
        d.elementary.g = std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                if a == 2 && b == 2 {
                    eye.clone()
                } else {
                    vec![0.0; n * n]
                }
            })
        });
        let wz = vec![0.3, -0.2, 0.5, 0.1, -0.4, 0.7];
        d.points = vec![crate::ir::modal::ModalPoint {
            name: "P".into(),
            position: [0.0; 3],
            nodes: 1,
            w: [vec![0.0; n], vec![0.0; n], wz.clone()],
            phi: std::array::from_fn(|_| vec![0.0; n]),
        }];
        d.correction = Some(crate::ir::modal::Correction {
            loads: vec![toml::from_str("point = \"P\"\ndirection = [0.0, 0.0, 1.0]").unwrap()],
            modes: 1,
            participation: wz[..5].to_vec(),
        });
        d.support_springs = vec![SupportSpring {
            point: "P".into(),
            stiffness: [0.0, 0.0, 100.0],
        }];
        d
    }

    #[test]
    fn the_share_follows_truncation_into_the_folded_and_correction_modes() {
        let full = with_correction();
        assert_eq!(crate::ir::modal::problems(&full), Vec::<String>::new());
        // Keep the eigenmodes up to 10 Hz: 2 eigenmodes and 2 folded shapes (one load, two
        // Krylov blocks) of modes 3-6 (the dropped eigenmodes and the correction mode).
        let b = ModalBody::new(
            &entry(full.clone(), Some(0.06), 0.0),
            &full,
            0,
            [0.0; 3],
            (Some(10.0), false),
            &[],
        );
        let d = b.data();
        assert_eq!(d.modes(), 4);
        // Independent path: the spring's stiffness in the file's modes, K_s = W^T k W, carried
        // into the kept coordinates by the basis T (q_file = T q): e_j = (T^T K_s T)_jj /
        // omega_j^2.
        let (m, n) = (full.modes(), d.modes());
        let t = d.basis.as_ref().unwrap();
        let wz = &full.points[0].w[2];
        let e = d.support_energy();
        for j in 0..n {
            let x: f64 = (0..m).map(|r| wz[r] * t[r * n + j]).sum();
            let expect = 100.0 * x * x / (2.0 * PI * d.frequencies[j]).powi(2);
            assert!(
                (e[j] - expect).abs() < 1e-12 * expect.max(1e-12),
                "{j}: {e:?}"
            );
            let zeta = 0.02 + 0.04 * e[j];
            let w = 2.0 * PI * d.frequencies[j];
            assert!((b.damping[j] - 2.0 * zeta * w).abs() < 1e-12 * w);
        }
        // The kept eigenmodes' shares are the file's.
        assert_eq!(e[..2], full.support_energy()[..2]);
    }

    /// A model with the elastic cabinet of `modal` (written next to it) and `keys` in its entry;
    /// the loader's errors as "line: message".
    fn load(modal: &ModalData, keys: &str) -> Result<crate::ir::Model, Vec<String>> {
        let dir = std::env::temp_dir().join(format!(
            "washdyn-support-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("cab.modal.toml"), modal.to_toml()).unwrap();
        let src = format!(
            "name = \"m\"\n[tub]\nmass = 1.0\ncog = [0.0, 0.0, 0.5]\n\
             inertia = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n\
             [speed]\ntable = [[0.0, 0.0], [1.0, 100.0]]\n\
             [[elastic]]\nname = \"cabinet\"\nfile = \"cab.modal.toml\"\n{keys}"
        );
        let r = crate::ir::toml_file::load_str(&src, "m.toml", &dir);
        let _ = std::fs::remove_dir_all(&dir);
        r.map_err(|e| {
            e.errors
                .iter()
                .map(|l| format!("{}: {}", l.line, l.message))
                .collect()
        })
    }

    #[test]
    fn the_loader_reads_the_new_keys_and_the_checker_names_them() {
        // The serde form round-trips, and old files and entries (no new keys) load.
        let d = on_a_foot();
        let back: ModalData = toml::from_str(&d.to_toml()).unwrap();
        assert_eq!(back, d);
        let m = load(&tiny(), "damping = 0.02\n").unwrap();
        assert_eq!(m.elastic[0].support_damping, None);
        assert_eq!(m.elastic[0].stiffness_damping, 0.0);
        let m = load(&d, "support_damping = 0.06\nstiffness_damping = 2e-4\n").unwrap();
        assert_eq!(m.elastic[0].support_damping, Some(0.06));
        assert_eq!(m.elastic[0].stiffness_damping, 2e-4);

        // Out of range: each error on its own line (the entry's keys start at line 11).
        let e = load(&d, "support_damping = 1.5\nstiffness_damping = -1.0\n").unwrap_err();
        assert_eq!(e.len(), 2, "{e:?}");
        assert!(
            e[0].starts_with("11: ") && e[0].contains("support_damping"),
            "{e:?}"
        );
        assert!(
            e[1].starts_with("12: ") && e[1].contains("stiffness_damping"),
            "{e:?}"
        );
        // Support damping needs springs in the data.
        let e = load(&tiny(), "support_damping = 0.06\n").unwrap_err();
        assert!(
            e[0].starts_with("11: ") && e[0].contains("lists no support_springs"),
            "{e:?}"
        );
        // The data's own rules: a spring at no point, at a multi-node point, with a negative
        // stiffness, or storing more than a mode's strain energy.
        let mut bad = d.clone();
        bad.support_springs[0].point = "NOWHERE".into();
        let e = load(&bad, "").unwrap_err();
        assert!(
            e[0].contains("support_springs[0]: no point `NOWHERE`"),
            "{e:?}"
        );
        let mut bad = d.clone();
        bad.points[0].nodes = 3;
        let e = load(&bad, "").unwrap_err();
        assert!(e[0].contains("reads 3 nodes"), "{e:?}");
        let mut bad = d.clone();
        bad.support_springs[0].stiffness[0] = -1.0;
        let e = load(&bad, "").unwrap_err();
        assert!(e[0].contains("support_springs[0].stiffness"), "{e:?}");
        let mut bad = d;
        bad.support_springs[0].stiffness[2] *= 2.0 * 1.01;
        let e = load(&bad, "").unwrap_err();
        assert!(e[0].contains("mode 0 would store 1.0100"), "{e:?}");
    }
}
