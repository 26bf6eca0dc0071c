//! Elastic bodies in the equations: a body's modal coordinates with their stiffness, modal
//! damping and weight, and the mode-shape rows its markers use. So far the cabinet (subsystem 2:
//! no rigid DOF, mass-normalised modes, so M2 = E).

use super::kinematics::ModalRows;
use crate::ir::Elastic;
use crate::ir::modal::point_at;
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
    data: crate::ir::modal::ModalData,
}

impl ModalBody {
    /// From a checked, resolved `elastic` entry; its coordinates start at `start`. With a
    /// scene's `cutoff` (Hz) only the eigenmodes up to it are kept (at least one), and the
    /// static correction modes.
    pub fn new(e: &Elastic, start: usize, gravity: [f64; 3], cutoff: Option<f64>) -> Self {
        let mut d = e.data.clone().expect("checked: modal data resolved");
        if let Some(fc) = cutoff {
            let e = d.eigenmodes();
            let keep = d.frequencies[..e]
                .iter()
                .filter(|f| **f <= fc)
                .count()
                .max(1);
            d.truncate(keep);
        }
        let n = d.modes();
        let w: Vec<f64> = d
            .frequencies
            .iter()
            .map(|f| 2.0 * std::f64::consts::PI * f)
            .collect();
        ModalBody {
            name: e.name.clone(),
            start,
            n,
            omega2: w.iter().map(|w| w * w).collect(),
            damping: w.iter().map(|w| 2.0 * e.damping * w).collect(),
            weight: (0..n)
                .map(|k| (0..3).map(|a| d.elementary.c[a][k] * gravity[a]).sum())
                .collect(),
            data: d,
        }
    }

    /// The rows of the modal point at `p` (checked to exist).
    pub fn rows(&self, p: [f64; 3]) -> ModalRows {
        let pt = point_at(&self.data, p).expect("checked: a modal point at every marker");
        ModalRows {
            start: self.start,
            w: (0..self.n)
                .map(|k| [pt.w[0][k], pt.w[1][k], pt.w[2][k]])
                .collect(),
            phi: (0..self.n)
                .map(|k| [pt.phi[0][k], pt.phi[1][k], pt.phi[2][k]])
                .collect(),
        }
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
