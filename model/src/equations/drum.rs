//! The spinning elastic drum: its modes turn with the drum (drum frame, angle phi) on a frame
//! that rides on the tub's bearing point (design-notes: "the kinematics to keep"). Its rigid
//! mass and spin are the tub's attached part and a rotor; this file holds what its modes add.
//!
//! Drum point x (relative to the mount B, drum frame), tub components:
//! rho = s_B + d + (theta x) R x + R (x + W q), d, theta the tub's elastic motion at B.
//! Every sum over the drum's nodes is a fixed matrix computed here from the elementary
//! matrices (seed paper), in the drum frame; per evaluation only R(phi) turns them.

use super::bodies::rotate;
use super::kinematics::{MarkerDef, Wrench};
use super::{BodyState, Drive, ModalBody};
use crate::geom::V;
use crate::scalar::{Scalar, mat_vec_from};

/// `e~`, the cross-product matrix of e.
fn tilde(e: [f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -e[2], e[1]], [e[2], 0.0, -e[0]], [-e[1], e[0], 0.0]]
}

fn mat_mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

/// The elastic drum's modal terms.
#[derive(Clone, Debug, PartialEq)]
pub struct ElasticDrum {
    pub modes: ModalBody,
    pub axis: [f64; 3],
    pub ratio: f64,
    /// The tub point B that carries the drum.
    pub mount: MarkerDef,
    /// Frame velocity Jacobian at B: per column of q1 (translation, rotation).
    frame: Vec<([f64; 3], [f64; 3])>,
    /// Per mode k (drum frame): C_k = sum dm W_k, X_k = sum dm x x W_k.
    c: Vec<[f64; 3]>,
    x: Vec<[f64; 3]>,
    /// sum dm W_k^T e~ W_l and sum dm W_k^T e~e~ W_l (n x n).
    ge: Vec<f64>,
    gee: Vec<f64>,
    /// sum dm W_k^T e~ x and sum dm W_k^T e~e~ x: the drum's own tangential and centrifugal
    /// load per unit Omega' and Omega^2.
    fe: Vec<f64>,
    fee: Vec<f64>,
    /// sum dm W_k x (e~ x): the frame's Coriolis coupling into the modes.
    qe: Vec<[f64; 3]>,
    /// Moments about B of the modal inertia: sum dm x x (e~ W_k), sum dm x x (e~e~ W_k), and the
    /// lever terms sum dm W_k x (e~e~ x).
    pe: Vec<[f64; 3]>,
    pee: Vec<[f64; 3]>,
    qee: Vec<[f64; 3]>,
    /// K_G / Omega^2 (n x n), when the scene has `centrifugal_stiffening`.
    pub stiffening: Option<Vec<f64>>,
    /// The modal rows' constant coefficients as one table (n x (8 + 2n), column-major) over
    /// x = [g_t (3), 2 Omega beta'_d (3), Omega', Omega^2, Omega' q + 2 Omega q' (n),
    /// Omega^2 q (n)]: columns C, Q_e, -f_e, -f_ee, -G_e, -(G_ee + K_G / Omega^2).
    rows_table: Vec<f64>,
    /// The reaction's force and moment (6 x 3n) over [Omega' q + 2 Omega q', Omega^2 q,
    /// Omega' q]: -(e x C), -P_e; -(e x e x C), -(P_ee + Q_ee); 0, -Q_e.
    reaction_table: Vec<f64>,
    /// sum_k C_k q_k (3 x n): the lever of the drum's weight.
    c_table: Vec<f64>,
}

impl ElasticDrum {
    /// `mount` is the drum rotor's tub point (on its axis); `n1` the size of subsystem 1.
    pub fn new(
        modes: ModalBody,
        axis: [f64; 3],
        ratio: f64,
        mount: MarkerDef,
        n1: usize,
        stiffening: bool,
    ) -> Self {
        let d = modes.data();
        let n = modes.n;
        let b = mount.point;
        let el = &d.elementary;
        // sum dm x_a W_b,k with x relative to B.
        let sx = |a: usize, bb: usize, k: usize| el.s[a][bb][k] - b[a] * el.c[bb][k];
        let g = |a: usize, bb: usize, k: usize, l: usize| el.g[a][bb][k * n + l];
        let et = tilde(axis);
        let eet = mat_mul(et, et);
        let c: Vec<[f64; 3]> = (0..n).map(|k| [0, 1, 2].map(|a| el.c[a][k])).collect();
        // sum dm (A x)_a W_b,k for a constant matrix A: sum_d A_ad sx(d, b).
        let ax_w = |a_m: [[f64; 3]; 3], k: usize| -> [[f64; 3]; 3] {
            let mut out = [[0.0; 3]; 3];
            for (a, row) in out.iter_mut().enumerate() {
                for (bb, v) in row.iter_mut().enumerate() {
                    *v = (0..3).map(|dd| a_m[a][dd] * sx(dd, bb, k)).sum();
                }
            }
            out
        };
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        // sum dm (u x v) with u_a v_b given as the 3x3 sum t[a][b]: eps_cab t[a][b].
        let cross_sum =
            |t: [[f64; 3]; 3]| [t[1][2] - t[2][1], t[2][0] - t[0][2], t[0][1] - t[1][0]];
        let transpose = |t: [[f64; 3]; 3]| [0, 1, 2].map(|i| [0, 1, 2].map(|j| t[j][i]));
        let mut x = Vec::new();
        let (mut qe, mut qee, mut pe, mut pee) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut fe, mut fee) = (Vec::new(), Vec::new());
        for k in 0..n {
            // t[a][b] = sum dm x_a W_b.
            let t = ax_w(id, k);
            x.push(cross_sum(t));
            // W x (A x): sum dm W_a (A x)_b = transpose of ax_w.
            qe.push(cross_sum(transpose(ax_w(et, k))));
            qee.push(cross_sum(transpose(ax_w(eet, k))));
            // x x (A W): sum dm x_a (A W)_b = sum_c t[a][c] A_bc.
            let xa = |a_m: [[f64; 3]; 3]| {
                let mut o = [[0.0; 3]; 3];
                for (a, row) in o.iter_mut().enumerate() {
                    for (bb, v) in row.iter_mut().enumerate() {
                        *v = (0..3).map(|cc| t[a][cc] * a_m[bb][cc]).sum();
                    }
                }
                o
            };
            pe.push(cross_sum(xa(et)));
            pee.push(cross_sum(xa(eet)));
            // W^T A x = sum_ab A_ab sum dm W_a x_b = sum_ab A_ab t[b][a].
            let wax = |a_m: [[f64; 3]; 3]| -> f64 {
                (0..3)
                    .flat_map(|a| (0..3).map(move |bb| (a, bb)))
                    .map(|(a, bb)| a_m[a][bb] * t[bb][a])
                    .sum()
            };
            fe.push(wax(et));
            fee.push(wax(eet));
        }
        let quad = |a_m: [[f64; 3]; 3]| -> Vec<f64> {
            (0..n * n)
                .map(|i| {
                    let (k, l) = (i / n, i % n);
                    (0..3)
                        .flat_map(|a| (0..3).map(move |bb| (a, bb)))
                        .map(|(a, bb)| a_m[a][bb] * g(a, bb, k, l))
                        .sum()
                })
                .collect()
        };
        let frame = mount
            .jacobian(n1)
            .expect("the drum's mount is on the floating tub");
        let stiffening = if stiffening {
            d.geometric_stiffness.as_ref().map(|k| k.per_omega2.clone())
        } else {
            None
        };
        let mut drum = ElasticDrum {
            ge: quad(et),
            gee: quad(eet),
            modes,
            axis,
            ratio,
            mount,
            frame,
            c,
            x,
            fe,
            fee,
            qe,
            pe,
            pee,
            qee,
            stiffening,
            rows_table: Vec::new(),
            reaction_table: Vec::new(),
            c_table: Vec::new(),
        };
        drum.tables();
        drum
    }

    /// The constant tables of `add` from the per-mode sums.
    fn tables(&mut self) {
        let n = self.modes.n;
        let e = self.axis;
        let cross = crate::geom::f::cross;
        let mut rows = Vec::with_capacity(n * (8 + 2 * n));
        for a in 0..3 {
            rows.extend((0..n).map(|k| self.c[k][a]));
        }
        for a in 0..3 {
            rows.extend((0..n).map(|k| self.qe[k][a]));
        }
        rows.extend(self.fe.iter().map(|v| -v));
        rows.extend(self.fee.iter().map(|v| -v));
        for l in 0..n {
            rows.extend((0..n).map(|k| -self.ge[k * n + l]));
        }
        let kg = |i: usize| self.stiffening.as_ref().map_or(0.0, |kg| kg[i]);
        for l in 0..n {
            rows.extend((0..n).map(|k| -(self.gee[k * n + l] + kg(k * n + l))));
        }
        let mut reaction = Vec::with_capacity(18 * n);
        let col = |f: [f64; 3], m: [f64; 3]| [f, m].concat();
        for k in 0..n {
            let ec = cross(e, self.c[k]);
            reaction.extend(col(ec.map(|v| -v), self.pe[k].map(|v| -v)));
        }
        for k in 0..n {
            let eec = cross(e, cross(e, self.c[k]));
            let m = crate::geom::f::add(self.pee[k], self.qee[k]);
            reaction.extend(col(eec.map(|v| -v), m.map(|v| -v)));
        }
        for k in 0..n {
            reaction.extend(col([0.0; 3], self.qe[k].map(|v| -v)));
        }
        self.rows_table = rows;
        self.reaction_table = reaction;
        self.c_table = self.c.iter().flatten().copied().collect();
    }

    /// The M1 couplings of the drum's modes with the frame that carries it, v_j . R C_k +
    /// omega_j . R X_k (they turn with phi), and the modal terms in h.
    pub fn add<T: Scalar>(
        &self,
        b: &BodyState<T>,
        d: &Drive<T>,
        g: V<T>,
        m1: Option<&mut [T]>,
        n1: usize,
        h: &mut [T],
    ) {
        let (start, n) = (self.modes.start, self.modes.n);
        let e = V::<T>::c(self.axis);
        let th = d.phi * self.ratio;
        let (cs, sn) = (th.cos(), th.sin());
        let rot = |v: V<T>| rotate(e, cs, sn, v);
        let rot_t = |v: V<T>| rotate(e, cs, -sn, v);
        let om = d.omega * self.ratio;
        let omd = d.omega_dot * self.ratio;
        let om2 = om * om;

        // M1 (when asked for): frame columns j against drum modes k.
        if let Some(m1) = m1 {
            for k in 0..n {
                let (rc, rx) = (rot(V::c(self.c[k])), rot(V::c(self.x[k])));
                for (j, (vj, wj)) in self.frame.iter().enumerate() {
                    let (zv, zw) = (*vj == [0.0; 3], *wj == [0.0; 3]);
                    if zv && zw {
                        continue;
                    }
                    let mut v = T::zero();
                    if !zv {
                        v += V::<T>::c(*vj).dot(rc);
                    }
                    if !zw {
                        v += V::<T>::c(*wj).dot(rx);
                    }
                    m1[j * n1 + start + k] += v;
                    m1[(start + k) * n1 + j] += v;
                }
            }
        }

        // The frame's small rotation and its rate (tub rigid + elastic at B), in drum axes.
        let (mut beta, mut betad) = self.mount.frame_rotation(b);
        if let Some(r) = &self.mount.modal {
            beta = beta + r.motion(b.q).1;
            betad = betad + r.motion(b.qd).1;
        }
        let beta_d = rot_t(beta);
        let betad_d = rot_t(betad);
        let g_d = rot_t(g);
        let gt = g_d - beta_d.cross(g_d);
        let q = &b.q[start..start + n];
        let qd = &b.qd[start..start + n];

        // Modal rows: weight (turning with the drum), own tangential and centrifugal load,
        // the frame's Coriolis, Coriolis and spin softening of the modes, the stress
        // stiffening (one table, `rows_table`), and their stiffness and damping.
        let two_om = om * T::c(2.0);
        let bd = betad_d.scale(two_om);
        let x8 = [
            gt.0[0], gt.0[1], gt.0[2], bd.0[0], bd.0[1], bd.0[2], omd, om2,
        ];
        let acc = |k: usize| omd * q[k] + two_om * qd[k];
        let hm = &mut h[start..start + n];
        let (head, rest) = self.rows_table.split_at(8 * n);
        T::mat_vec(head, &x8, hm);
        mat_vec_from(&rest[..n * n], n, acc, hm);
        mat_vec_from(&rest[n * n..], n, |k| om2 * q[k], hm);
        self.modes.add_elastic(b.q, b.qd, h);

        // Reaction on the tub at B (drum axes, then turned): the modes' inertia force and its
        // moment about B, and the lever of the drum's weight and centrifugal load.
        let mut fm = [T::zero(); 6];
        let t = &self.reaction_table;
        mat_vec_from(&t[..6 * n], n, acc, &mut fm);
        mat_vec_from(&t[6 * n..12 * n], n, |k| om2 * q[k], &mut fm);
        mat_vec_from(&t[12 * n..], n, |k| omd * q[k], &mut fm);
        let mut cq = [T::zero(); 3];
        T::mat_vec(&self.c_table, q, &mut cq);
        let f = V([fm[0], fm[1], fm[2]]);
        let mo = V([fm[3], fm[4], fm[5]]) + V(cq).cross(g_d);
        let w = Wrench {
            force: rot(f),
            moment: rot(mo),
        };
        self.mount.apply(b, &w, V::zero(), h);
    }
}
