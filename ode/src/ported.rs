//! The implicit methods' iteration matrix for a second-order system whose coordinates split
//! into q1 (n1, full mass matrix M1: the tub, drum and rotor) and q2 (n2, unit mass, own terms
//! diagonal: a body's modes on a fixed frame, the cabinet) that meet only through r port
//! coordinates p = B2^T q2 (the elements' attachment points on q2's body). Then
//!
//!   dh/dq = T^T E_q T + diag(0, d_q),  dh/dq' = T^T E_v T + diag(0, d_v),  T = diag(I, B2^T),
//!
//! with E over [q1; p] (na = n1 + r), and the mass-form matrix of `iteration.rs`,
//! W = d^2 M - c d dh/dq' - c^2 dh/dq = T^T F T + diag(0, Delta) with
//! F = d^2 diag(M1, 0) - c d E_v - c^2 E_q and Delta = d^2 - c d d_v - c^2 d_q (a vector).
//! With y = B2^T x2 the solve of W x = t reduces to the na x na system
//!
//!   [F11, F1p; G Fp1, I + G Fpp] [x1; y] = [t1; B2^T Delta^-1 t2],  G = B2^T Delta^-1 B2,
//!
//! and x2 = Delta^-1 (t2 - B2 (Fp1 x1 + Fpp y)): an LU of na instead of n (on the reference's
//! `elastic`, 140 against 324), exact in exact arithmetic (any solution of the reduced system
//! gives y = B2^T x2 by construction, so nothing is approximated).
//!
//! Trailing first-order element states z (nz, a friction damper's deflection) join q1 in the
//! reduced system, after the ports: [q1; p; z], na = n1 + r + nz, unit "mass" on z. They meet
//! q2 only through the ports too (an element reads and loads its markers), so the elimination
//! is the same. Generalized-alpha advances z with its velocity update, so dh/dz and dz'/dz
//! stand in E_v's z columns and dz'/dq in E_q's z rows.

use super::lu::{SingularMatrix, lu_factor, lu_solve};

/// What a ported system gives at a point (`OdeSystem::ported_jacobians`), row-major.
#[derive(Clone, Debug, Default)]
pub struct PortedJacobian {
    pub n1: usize,
    pub r: usize,
    pub n2: usize,
    /// Trailing first-order states (0: the system is [q; q'] alone).
    pub nz: usize,
    /// M1, n1 x n1.
    pub m1: Vec<f64>,
    /// dh/dq and dh/dq' over [q1; p; z], na x na (z's rows: dz'/dq, dz'/dq'; z's columns in
    /// `ev`: dh/dz, dz'/dz).
    pub eq: Vec<f64>,
    pub ev: Vec<f64>,
    /// The diagonals of q2's own terms in dh2/dq2 and dh2/dq2' (length n2).
    pub dq: Vec<f64>,
    pub dv: Vec<f64>,
    /// B2, n2 x r: port k reads p_k = sum_i b2[i r + k] q2_i.
    pub b2: Vec<f64>,
}

impl PortedJacobian {
    /// Work arrays for the shape (allocates).
    pub fn new(n1: usize, r: usize, n2: usize, nz: usize) -> Self {
        let na = n1 + r + nz;
        PortedJacobian {
            n1,
            r,
            n2,
            nz,
            m1: vec![0.0; n1 * n1],
            eq: vec![0.0; na * na],
            ev: vec![0.0; na * na],
            dq: vec![0.0; n2],
            dv: vec![0.0; n2],
            b2: vec![0.0; n2 * r],
        }
    }

    pub fn na(&self) -> usize {
        self.n1 + self.r + self.nz
    }

    /// Row i of B2: how q2's coordinate i moves the ports.
    fn b2_row(&self, i: usize) -> &[f64] {
        &self.b2[i * self.r..(i + 1) * self.r]
    }

    /// p = B2^T w over q2's coordinates, w_i = `w(i, v_i)`, into `p` (length r).
    fn ports_of(&self, v: &[f64], w: impl Fn(usize, f64) -> f64, p: &mut [f64]) {
        p.fill(0.0);
        for (i, &x) in v.iter().enumerate() {
            let x = w(i, x);
            for (pa, b) in p.iter_mut().zip(self.b2_row(i)) {
                *pa += b * x;
            }
        }
    }

    /// (B2 e)_i: the load on q2's coordinate i of port loads `e` (length r).
    fn port_load(&self, i: usize, e: &[f64]) -> f64 {
        self.b2_row(i).iter().zip(e).map(|(b, x)| b * x).sum()
    }

    /// The dense M (M2 = I, unit on z), dh/dq and dh/dq' over [q1; q2; z] ((n + nz)^2, n = n1
    /// + n2) the pieces stand for: what the tests hold the ported pieces to.
    pub fn expand(&self, m: &mut [f64], hq: &mut [f64], hqd: &mut [f64]) {
        let (n1, r, n2, na) = (self.n1, self.r, self.n2, self.na());
        let nn = n1 + n2;
        let n = nn + self.nz;
        // T's rows of coordinate i over [q1; p; z]: e_i on q1 and z, b2 row on p.
        let t = |i: usize, a: usize| -> f64 {
            if i < n1 {
                f64::from(u8::from(i == a))
            } else if i >= nn {
                f64::from(u8::from(a == i - nn + n1 + r))
            } else if (n1..n1 + r).contains(&a) {
                self.b2[(i - n1) * r + (a - n1)]
            } else {
                0.0
            }
        };
        m.fill(0.0);
        for i in 0..n1 {
            m[i * n..i * n + n1].copy_from_slice(&self.m1[i * n1..(i + 1) * n1]);
        }
        for (e, h, d) in [
            (&self.eq, &mut *hq, &self.dq),
            (&self.ev, &mut *hqd, &self.dv),
        ] {
            for i in 0..n {
                for j in 0..n {
                    let mut s = 0.0;
                    for a in 0..na {
                        let ti = t(i, a);
                        if ti == 0.0 {
                            continue;
                        }
                        for b in 0..na {
                            s += ti * e[a * na + b] * t(j, b);
                        }
                    }
                    h[i * n + j] = s;
                }
            }
            for k in 0..n2 {
                h[(n1 + k) * n + n1 + k] += d[k];
            }
        }
        for k in n1..n {
            m[k * n + k] = 1.0;
        }
    }
}

/// The reduced factorisation and its work arrays (sized once, by `reserve`).
#[derive(Clone, Debug, Default)]
pub(crate) struct PortedLu {
    /// The reduced matrix, then its LU (na x na).
    k: Vec<f64>,
    piv: Vec<usize>,
    /// F's port rows [Fp1, Fpp] (r x na), kept for x2.
    fp: Vec<f64>,
    /// G = B2^T Delta^-1 B2 (r x r).
    g: Vec<f64>,
    delta: Vec<f64>,
    /// Vectors of length na (two) and n2.
    u: Vec<f64>,
    e: Vec<f64>,
    t2: Vec<f64>,
    c: f64,
    d: f64,
}

impl PortedLu {
    /// Work arrays for `j`'s shape; allocates only when they grow (the first `init`).
    pub fn reserve(&mut self, j: &PortedJacobian) {
        let (r, na, n2) = (j.r, j.na(), j.n2);
        let grow = |v: &mut Vec<f64>, len: usize| {
            if v.len() < len {
                v.resize(len, 0.0);
            }
        };
        grow(&mut self.k, na * na);
        grow(&mut self.fp, r * na);
        grow(&mut self.g, r * r);
        grow(&mut self.delta, n2);
        grow(&mut self.u, na);
        grow(&mut self.e, na);
        grow(&mut self.t2, n2);
        if self.piv.len() < na {
            self.piv.resize(na, 0);
        }
    }

    /// Factorise the reduced matrix of d^2 M - c d dh/dq' - c^2 dh/dq (the first-order
    /// methods' `solve`).
    pub fn factor(&mut self, j: &PortedJacobian, d: f64, c: f64) -> Result<(), SingularMatrix> {
        self.c = c;
        self.d = d;
        self.factor_mass(j, d * d, c * d, c * c)
    }

    /// Factorise the reduced matrix of a M - b dh/dq' - e dh/dq (`solve_mass`;
    /// generalized-alpha's Newton matrix M - beta' h gamma dh/dq' - beta' h^2 beta dh/dq).
    pub fn factor_mass(
        &mut self,
        j: &PortedJacobian,
        a: f64,
        b: f64,
        e: f64,
    ) -> Result<(), SingularMatrix> {
        let (n1, r, n2, na) = (j.n1, j.r, j.n2, j.na());
        let k = &mut self.k[..na * na];
        for ((w, eq), ev) in k.iter_mut().zip(&j.eq).zip(&j.ev) {
            *w = -b * ev - e * eq;
        }
        for i in 0..n1 {
            for (w, m) in k[i * na..i * na + n1]
                .iter_mut()
                .zip(&j.m1[i * n1..(i + 1) * n1])
            {
                *w += a * m;
            }
        }
        for i in n1 + r..na {
            k[i * na + i] += a;
        }
        for i in 0..n2 {
            let v = a - b * j.dv[i] - e * j.dq[i];
            if v == 0.0 || !v.is_finite() {
                return Err(SingularMatrix { column: n1 + i });
            }
            self.delta[i] = v;
        }
        let fp = &mut self.fp[..r * na];
        fp.copy_from_slice(&k[n1 * na..(n1 + r) * na]);
        let g = &mut self.g[..r * r];
        g.fill(0.0);
        for i in 0..n2 {
            let row = j.b2_row(i);
            let inv = 1.0 / self.delta[i];
            for a in 0..r {
                let s = row[a] * inv;
                if s != 0.0 {
                    for (gv, b) in g[a * r..(a + 1) * r].iter_mut().zip(row) {
                        *gv += s * b;
                    }
                }
            }
        }
        // The port rows: G [Fp1, Fpp] + [0, I].
        for a in 0..r {
            let out = &mut k[(n1 + a) * na..(n1 + a + 1) * na];
            out.fill(0.0);
            for l in 0..r {
                let s = g[a * r + l];
                if s != 0.0 {
                    for (o, f) in out.iter_mut().zip(&fp[l * na..(l + 1) * na]) {
                        *o += s * f;
                    }
                }
            }
            out[n1 + a] += 1.0;
        }
        lu_factor(k, na, &mut self.piv[..na])
    }

    /// Solve (d I - c J) x = b in place for b = [b_q; b_v] (length 2n), J the first-order
    /// Jacobian the pieces stand for: the mass form's right-hand side t = d M b_v + c dh/dq b_q,
    /// the reduced solve for x_v, then x_q = (b_q + c x_v) / d (`iteration.rs`).
    pub fn solve(&mut self, j: &PortedJacobian, b: &mut [f64]) {
        debug_assert_eq!(j.nz, 0, "the first-order methods' form is [q; q'] alone");
        let (n1, n2, na) = (j.n1, j.n2, j.na());
        let n = n1 + n2;
        let (c, d) = (self.c, self.d);
        let (bq, bv) = b.split_at_mut(n);
        let (u, e, t2) = (&mut self.u[..na], &mut self.e[..na], &mut self.t2[..n2]);
        // u = T b_q, e = E_q u.
        u[..n1].copy_from_slice(&bq[..n1]);
        j.ports_of(&bq[n1..], |_, x| x, &mut u[n1..]);
        for a in 0..na {
            e[a] = j.eq[a * na..(a + 1) * na]
                .iter()
                .zip(u.iter())
                .map(|(x, y)| x * y)
                .sum();
        }
        // t1 = d M1 b_v1 + c e1 (into u's first n1), t2 = d b_v2 + c (B2 e_p + d_q b_q2).
        for i in 0..n1 {
            let mb: f64 = j.m1[i * n1..(i + 1) * n1]
                .iter()
                .zip(&bv[..n1])
                .map(|(x, y)| x * y)
                .sum();
            u[i] = d * mb + c * e[i];
        }
        for i in 0..n2 {
            t2[i] = d * bv[n1 + i] + c * (j.port_load(i, &e[n1..]) + j.dq[i] * bq[n1 + i]);
        }
        // u's first n1 hold t1, t2 the rest: the reduced solve of W x = t into b_v.
        bv[n1..].copy_from_slice(t2);
        bv[..n1].copy_from_slice(&u[..n1]);
        self.solve_mass(j, bv);
        for i in 0..n {
            bq[i] = (bq[i] + c * bv[i]) / d;
        }
    }

    /// Solve W x = t in place (t of length n + nz), W the matrix of the last factorisation:
    /// u = [t1; B2^T Delta^-1 t2; tz], [x1; y; xz] = K^-1 u,
    /// x2 = Delta^-1 (t2 - B2 (Fp1 x1 + Fpp y + Fpz xz)).
    pub fn solve_mass(&mut self, j: &PortedJacobian, t: &mut [f64]) {
        let (n1, r, n2, na) = (j.n1, j.r, j.n2, j.na());
        let (u, e) = (&mut self.u[..na], &mut self.e[..na]);
        let (t1, rest) = t.split_at_mut(n1);
        let (t2, tz) = rest.split_at_mut(n2);
        u[..n1].copy_from_slice(t1);
        u[n1 + r..].copy_from_slice(tz);
        let delta = &self.delta[..n2];
        j.ports_of(t2, |i, x| x / delta[i], &mut u[n1..n1 + r]);
        lu_solve(&self.k[..na * na], na, &self.piv[..na], u);
        // w = Fp [x1; y] (into e's port part), x2 = Delta^-1 (t2 - B2 w).
        for a in 0..r {
            e[n1 + a] = self.fp[a * na..(a + 1) * na]
                .iter()
                .zip(u.iter())
                .map(|(x, y)| x * y)
                .sum();
        }
        for i in 0..n2 {
            t2[i] = (t2[i] - j.port_load(i, &e[n1..])) / self.delta[i];
        }
        t1.copy_from_slice(&u[..n1]);
        tz.copy_from_slice(&u[n1 + r..]);
    }
}

/// The ported pieces and their factorisation for a second-order system of n positions and nz
/// trailing states, made (allocating) only when the shape is new; `None` where the system is
/// not ported or the reduced system would not be smaller (n1 + r >= n).
pub(crate) fn prepare<S: super::OdeSystem + ?Sized>(
    slot: &mut Option<(PortedJacobian, PortedLu)>,
    sys: &S,
    n: Option<usize>,
    nz: usize,
) {
    let shape = match (n, sys.ported_shape()) {
        (Some(n), Some((n1, r))) if n1 <= n && n1 + r < n => Some((n1, r, n - n1)),
        _ => None,
    };
    let Some((n1, r, n2)) = shape else {
        *slot = None;
        return;
    };
    match slot {
        Some((j, _)) if (j.n1, j.r, j.n2, j.nz) == (n1, r, n2, nz) => {}
        slot => {
            let j = PortedJacobian::new(n1, r, n2, nz);
            let mut lu = PortedLu::default();
            lu.reserve(&j);
            *slot = Some((j, lu));
        }
    }
}

/// M v (M = diag(M1, I), unit on the states too) into `out`: generalized-alpha's Newton
/// residual in forces.
pub(crate) fn mass_times(j: &PortedJacobian, v: &[f64], out: &mut [f64]) {
    let n1 = j.n1;
    for i in 0..n1 {
        out[i] = j.m1[i * n1..(i + 1) * n1]
            .iter()
            .zip(&v[..n1])
            .map(|(m, x)| m * x)
            .sum();
    }
    out[n1..].copy_from_slice(&v[n1..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::OdeSystem;
    use crate::iteration::IterationMatrix;

    /// A ported system with pseudo-random pieces, also giving its dense mass form (`expand`):
    /// the dense LU of `iteration.rs` is the independent path the reduced solve is held to.
    struct Ported {
        j: PortedJacobian,
        ported: bool,
    }

    fn pieces(n1: usize, r: usize, n2: usize, nz: usize) -> PortedJacobian {
        let mut j = PortedJacobian::new(n1, r, n2, nz);
        let s = |k: usize, a: f64| ((k as f64) * a).sin();
        // M1 symmetric positive definite: A A^T + n1 I.
        for i in 0..n1 {
            for l in 0..n1 {
                let v: f64 = (0..n1)
                    .map(|k| s(i * 7 + k, 0.37) * s(l * 7 + k, 0.37))
                    .sum();
                j.m1[i * n1 + l] = v + if i == l { n1 as f64 } else { 0.0 };
            }
        }
        let na = j.na();
        for k in 0..na * na {
            j.eq[k] = -50.0 * s(k, 0.73) - if k % (na + 1) == 0 { 400.0 } else { 0.0 };
            j.ev[k] = -2.0 * s(k, 1.31);
        }
        for i in 0..n2 {
            // Modal stiffness (omega^2) and damping (2 zeta omega), negated as in h.
            let w = 10.0 + 40.0 * i as f64;
            j.dq[i] = -w * w;
            j.dv[i] = -0.04 * w;
        }
        for k in 0..n2 * r {
            j.b2[k] = s(k, 0.91) * 0.3;
        }
        j
    }

    impl OdeSystem for Ported {
        fn dim(&self) -> usize {
            2 * (self.j.n1 + self.j.n2)
        }
        fn rhs(&mut self, _t: f64, _y: &[f64], _dy: &mut [f64]) {}
        fn second_order(&self) -> Option<usize> {
            Some(self.j.n1 + self.j.n2)
        }
        fn mass_jacobians(
            &mut self,
            _t: f64,
            _y: &[f64],
            m: &mut [f64],
            hq: &mut [f64],
            hqd: &mut [f64],
        ) -> bool {
            self.j.expand(m, hq, hqd);
            true
        }
        fn ported_shape(&self) -> Option<(usize, usize)> {
            self.ported.then_some((self.j.n1, self.j.r))
        }
        fn ported_jacobians(&mut self, _t: f64, _y: &[f64], j: &mut PortedJacobian) -> bool {
            j.clone_from(&self.j);
            true
        }
    }

    /// The reduced solve against the dense mass form's LU of the same matrix, for both
    /// scalings the methods use (sdirk4: d = 1, c = h gamma; rodas4: d = 1 / (h gamma),
    /// c = 1), with a port repeated too (B2 with two equal columns: rank r - 3).
    #[test]
    fn reduced_solve_matches_the_dense_mass_form() {
        for (n1, r, n2) in [(5, 3, 9), (7, 12, 20), (4, 6, 10), (1, 1, 2)] {
            let n = n1 + n2;
            let mut j = pieces(n1, r, n2, 0);
            if r == 6 {
                // Ports 3..6 read the same coordinates as ports 0..3.
                for i in 0..n2 {
                    for a in 0..3 {
                        j.b2[i * r + 3 + a] = j.b2[i * r + a];
                    }
                }
            }
            let mut dense_sys = Ported {
                j: j.clone(),
                ported: false,
            };
            let mut ported_sys = Ported { j, ported: true };
            let y = vec![0.0; 2 * n];
            let mut jac = vec![0.0; 4 * n * n];
            for (d, c) in [(1.0, 0.013), (1.0 / (0.25 * 0.002), 1.0)] {
                let mut dense = IterationMatrix::new(2 * n);
                dense.set_second_order(Some(n));
                let mut ported = IterationMatrix::new(2 * n);
                ported.set_second_order(Some(n));
                ported.set_ported(&ported_sys);
                assert!(dense.jacobian(&mut dense_sys, 0.0, &y, &mut jac));
                assert!(ported.jacobian(&mut ported_sys, 0.0, &y, &mut jac));
                assert!(ported.is_ported());
                dense.factor(&jac, d, c).unwrap();
                ported.factor(&jac, d, c).unwrap();
                let b: Vec<f64> = (0..2 * n).map(|i| (i as f64 * 1.3).cos()).collect();
                let (mut x1, mut x2) = (b.clone(), b.clone());
                dense.solve(&jac, &mut x1);
                ported.solve(&jac, &mut x2);
                let scale = x1.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                let worst = (0..2 * n).fold(0.0f64, |a, i| a.max((x1[i] - x2[i]).abs() / scale));
                println!(
                    "n1 {n1}, r {r}, n2 {n2}, d {d:.0}, c {c}: ported against dense {worst:.1e}"
                );
                // Both backward stable on well-conditioned matrices: measured 5.8e-16 at the
                // worst (7, 12, 20); the bound is about 10x that.
                assert!(worst < 5e-15, "{worst:e}");
            }
        }
    }

    /// generalized-alpha's form, a M - b dh/dq' - e dh/dq with b^2 != a e (no (d, c) pair
    /// gives it), solved in n-space against the dense LU of the expanded matrix, with and
    /// without trailing states (n = n1 + n2 + nz).
    #[test]
    fn mass_solve_matches_the_dense_lu() {
        for (n1, r, n2, nz) in [(5, 3, 9, 0), (7, 12, 20, 0), (5, 3, 9, 2), (7, 12, 20, 4)] {
            let n = n1 + n2 + nz;
            let j = pieces(n1, r, n2, nz);
            let (mut m, mut hq, mut hv) = (vec![0.0; n * n], vec![0.0; n * n], vec![0.0; n * n]);
            j.expand(&mut m, &mut hq, &mut hv);
            let (a, b, e) = (1.0, 0.8 * 0.002 * 0.6, 0.8 * 0.002 * 0.002 * 0.3);
            let mut w: Vec<f64> = (0..n * n)
                .map(|k| a * m[k] - b * hv[k] - e * hq[k])
                .collect();
            let mut piv = vec![0; n];
            lu_factor(&mut w, n, &mut piv).unwrap();
            let t: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let mut x_dense = t.clone();
            lu_solve(&w, n, &piv, &mut x_dense);
            let mut lu = PortedLu::default();
            lu.reserve(&j);
            lu.factor_mass(&j, a, b, e).unwrap();
            let mut x = t.clone();
            lu.solve_mass(&j, &mut x);
            let scale = x_dense.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let worst = (0..n).fold(0.0f64, |s, i| s.max((x[i] - x_dense[i]).abs() / scale));
            println!(
                "n1 {n1}, r {r}, n2 {n2}, nz {nz}: ported mass solve against dense {worst:.1e}"
            );
            // Measured 7.9e-16 at the worst (7, 12, 20); the bound is about 6x that.
            assert!(worst < 5e-15, "{worst:e}");
            // M v through the pieces against the dense M.
            let mut mv = vec![0.0; n];
            mass_times(&j, &t, &mut mv);
            for i in 0..n {
                let d: f64 = (0..n).map(|k| m[i * n + k] * t[k]).sum();
                assert!((mv[i] - d).abs() <= 1e-13 * d.abs().max(1.0), "{i}");
            }
        }
    }
}
