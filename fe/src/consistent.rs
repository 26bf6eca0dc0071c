//! The body's mass as a matrix, for the seed paper's elementary matrices: the consistent mass
//! (element shape functions, the matrix ccx normalises its modes with) or the HRZ-lumped
//! diagonal (the paper's own choice, kept for comparison).
//!
//! With HRZ masses sum dm W^T W differs from the identity by a lumping error that grows with the
//! mode count (the tub: 4.5 % at 34 modes, 7.6 % at 50): higher modes vary within an element,
//! which a diagonal cannot see. The consistent scalar matrix M_ij = rho int N_i N_j dV (S8R:
//! rho t int N_i N_j dA over the mid-surface; B32: rho A int N_i N_j dL; point masses on their
//! node) is ccx's mass for the mid-surface translations, integrated at ccx's own Gauss points
//! (`Rule::Ccx`). ccx expands shells and beams into 3-D elements, so its mass also holds the
//! material off the mid-surface (the rotary inertia rho t^3 / 12, a share ~(t k)^2 / 12 of a mode
//! of wavenumber k: 1.3e-3 at the tub's 150th mode). We add it from the translations' slopes
//! (`Offset`: Kirchhoff shells, Euler-Bernoulli beams; a beam's torsion is not in the
//! translations and stays out).
//!
//! Attached rigid parts (point masses on a `*RIGID BODY`) enter through their mass, CoG and
//! inertia and ccx's ROT NODE rotation, the paper's expansion (fig. 3). The sums are sparse
//! products: M W per mode, then dense W_a^T (M W_b).

use crate::lumping::{Lumped, MassProps, RigidLump, Rule, gauss, rigid_parts, section_axes};
use crate::mesh::Mesh;
use crate::modal::Shapes;
use nalgebra::DMatrix;
use washdyn_runtime::geom::f::{add, cross, sub};
use washdyn_runtime::ir::modal::Elementary;

/// Where a mass matrix comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MassKind {
    Consistent,
    Hrz,
}

/// A body's scalar nodal mass matrix (the same for each translation component) and its rigid
/// parts.
#[derive(Clone, Debug)]
pub struct MassMatrix {
    pub kind: MassKind,
    /// Node ids of the rows (nodes with element mass or a point mass of their own), ascending.
    pub ids: Vec<usize>,
    /// Compressed rows, both triangles stored: row i holds cols[start[i]..start[i + 1]].
    start: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
    /// The shells' and beams' material off their reference surface or line.
    offsets: Vec<Offset>,
    /// The attached rigid parts (their point masses are not in the matrix).
    pub rigid: Vec<RigidLump>,
}

/// The material of a shell or beam off its reference surface or line, at one Gauss point and
/// section axis e (a shell's normal; a beam's two section axes): mass times squared distance
/// `weight` = rho dv k^2 (k^2 = t^2 / 12, or width^2 / 12 and height^2 / 12). A point at offset
/// z e moves by u + z d, d = sum_j B_j u_j: the axis turns with the slope of the normal
/// displacement (Kirchhoff, Euler-Bernoulli: delta n = -a^alpha (n . u_,alpha), with a^alpha the
/// surface's contravariant base). Over +-z it adds weight d_a d_b to g_ab and weight e_a d_b to
/// s_ab, nothing to c.
///
/// ccx's shells and beams turn their sections by rotations of their own (Mindlin, Timoshenko),
/// which on a coarse mesh exceed the slope of the translations: this catches half to 90 % of
/// ccx's rotary inertia (a 2 mm plate's 20th mode: 2.4e-3 of the modal mass -> 8e-4; the tub's 150th:
/// 1.3e-3 -> 5.7e-4); the translations do not tell more.
#[derive(Clone, Debug)]
struct Offset {
    weight: f64,
    axis: [f64; 3],
    /// (row index, B_j).
    b: Vec<(usize, M3)>,
}

type M3 = [[f64; 3]; 3];

/// The consistent mass matrix of `mesh` (point masses of rigid parts as rigid parts).
pub fn consistent(mesh: &Mesh) -> MassMatrix {
    let (rigid, free) = rigid_parts(mesh);
    let (mut t, offsets) = elements(mesh);
    t.extend(free.into_iter().map(|(id, kg)| (id, id, kg)));
    MassMatrix::from_triplets(MassKind::Consistent, t, offsets, rigid)
}

/// The consistent mass matrix with every point mass on its own node, rigid part or not (to
/// check the paper's expansion against plain sums).
pub fn consistent_point_masses_as_nodes(mesh: &Mesh) -> MassMatrix {
    let (mut t, offsets) = elements(mesh);
    for part in &mesh.parts {
        if let crate::mesh::Section::Mass { kg } = part.section {
            t.extend(part.elements.iter().map(|e| (e[0], e[0], kg)));
        }
    }
    MassMatrix::from_triplets(MassKind::Consistent, t, offsets, Vec::new())
}

/// The HRZ-lumped masses as a diagonal matrix (no rotary inertia).
pub fn hrz(lumped: &Lumped) -> MassMatrix {
    let t = lumped
        .node_mass
        .iter()
        .enumerate()
        .filter(|(_, m)| **m != 0.0)
        .map(|(i, m)| (i + 1, i + 1, *m))
        .collect();
    MassMatrix::from_triplets(MassKind::Hrz, t, Vec::new(), lumped.rigid.clone())
}

/// An offset before its rows are known: B_j by node id.
type RawOffset = (f64, [f64; 3], Vec<(usize, M3)>);

/// rho int N_i N_j dV of every element with density, as (row id, column id, value), and the
/// shells' and beams' offsets.
fn elements(mesh: &Mesh) -> (Vec<(usize, usize, f64)>, Vec<RawOffset>) {
    let (mut t, mut offsets) = (Vec::new(), Vec::new());
    for part in &mesh.parts {
        let Some(rho) = part.section.material().map(|m| m.rho) else {
            continue;
        };
        for e in &part.elements {
            let k = e.len();
            let mut me = vec![0.0; k * k];
            gauss(mesh, &part.section, e, Rule::Ccx, |gp| {
                for i in 0..k {
                    let a = rho * gp.dv * gp.n[i];
                    for j in i..k {
                        me[i * k + j] += a * gp.n[j];
                    }
                }
                // The turning of each section axis e: d = sum_j b_j (e . u_j) with
                // b_j = -sum_alpha N_j,alpha a^alpha.
                let axes = section_axes(&part.section, gp);
                if axes.is_empty() {
                    return;
                }
                let dims = if gp.tangents[1] == [0.0; 3] { 1 } else { 2 };
                let dual = contravariant(&gp.tangents, dims);
                for (axis, k2) in axes {
                    let op = e
                        .iter()
                        .zip(gp.dn)
                        .map(|(id, d)| {
                            let b: [f64; 3] = std::array::from_fn(|r| {
                                -(0..dims).map(|a| d[a] * dual[a][r]).sum::<f64>()
                            });
                            (
                                *id,
                                std::array::from_fn(|r| std::array::from_fn(|c| b[r] * axis[c])),
                            )
                        })
                        .collect();
                    offsets.push((rho * gp.dv * k2, axis, op));
                }
            });
            for i in 0..k {
                for j in 0..i {
                    me[i * k + j] = me[j * k + i];
                }
            }
            for i in 0..k {
                for j in 0..k {
                    t.push((e[i], e[j], me[i * k + j]));
                }
            }
        }
    }
    (t, offsets)
}

/// The contravariant base a^alpha of the first `dims` tangents (a^alpha . x_beta = delta).
fn contravariant(t: &[[f64; 3]; 2], dims: usize) -> Vec<[f64; 3]> {
    if dims == 1 {
        let l2 = dot(t[0], t[0]);
        return vec![t[0].map(|v| v / l2)];
    }
    let (g11, g12, g22) = (dot(t[0], t[0]), dot(t[0], t[1]), dot(t[1], t[1]));
    let det = g11 * g22 - g12 * g12;
    let (i11, i12, i22) = (g22 / det, -g12 / det, g11 / det);
    vec![
        std::array::from_fn(|c| i11 * t[0][c] + i12 * t[1][c]),
        std::array::from_fn(|c| i12 * t[0][c] + i22 * t[1][c]),
    ]
}

/// One set of shapes at the matrix's rows, per component: W_a (rows x modes).
type Dense = [DMatrix<f64>; 3];

impl MassMatrix {
    fn from_triplets(
        kind: MassKind,
        mut t: Vec<(usize, usize, f64)>,
        offsets: Vec<RawOffset>,
        rigid: Vec<RigidLump>,
    ) -> MassMatrix {
        t.sort_unstable_by_key(|&(r, c, _)| (r, c));
        let mut ids: Vec<usize> = t.iter().map(|x| x.0).collect();
        ids.dedup();
        let index = |id: usize| ids.binary_search(&id).expect("every column is a row");
        let (mut start, mut cols, mut vals) = (vec![0], Vec::new(), Vec::<f64>::new());
        let mut last: Option<(usize, usize)> = None;
        for (r, c, v) in t {
            if last == Some((r, c)) {
                *vals.last_mut().expect("a value") += v;
                continue;
            }
            if last.is_some_and(|(lr, _)| lr != r) {
                start.push(cols.len());
            }
            cols.push(index(c));
            vals.push(v);
            last = Some((r, c));
        }
        start.push(cols.len());
        let offsets = offsets
            .into_iter()
            .map(|(weight, axis, b)| Offset {
                weight,
                axis,
                b: b.into_iter().map(|(id, v)| (index(id), v)).collect(),
            })
            .collect();
        MassMatrix {
            kind,
            ids,
            start,
            cols,
            vals,
            offsets,
            rigid,
        }
    }

    /// Stored nonzeros (both triangles).
    pub fn nonzeros(&self) -> usize {
        self.vals.len()
    }

    /// y = M x for a vector over the rows.
    fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        for i in 0..self.ids.len() {
            let r = self.start[i]..self.start[i + 1];
            y[i] = self.cols[r.clone()]
                .iter()
                .zip(&self.vals[r])
                .map(|(&j, v)| v * x[j])
                .sum();
        }
    }

    /// M X, column by column.
    fn mul(&self, x: &DMatrix<f64>) -> DMatrix<f64> {
        let mut y = DMatrix::zeros(x.nrows(), x.ncols());
        for k in 0..x.ncols() {
            let (xc, mut yc) = (x.column(k), y.column_mut(k));
            self.mul_vec(xc.as_slice(), yc.as_mut_slice());
        }
        y
    }

    /// The shapes at the rows, per component; every row needs a shape.
    fn dense(&self, modes: &[Shapes]) -> Result<Dense, String> {
        let mut w: Dense = std::array::from_fn(|_| DMatrix::zeros(self.ids.len(), modes.len()));
        for (k, m) in modes.iter().enumerate() {
            for (i, id) in self.ids.iter().enumerate() {
                let v =
                    m.w.get(id)
                        .ok_or_else(|| format!("node {id} has mass but no mode shape"))?;
                for a in 0..3 {
                    w[a][(i, k)] = v[a];
                }
            }
        }
        Ok(w)
    }

    /// The offsets' motion per unit offset, times sqrt(weight): D_a (offsets x modes).
    fn offset_motion(&self, w: &Dense) -> Dense {
        let n = w[0].ncols();
        let mut d: Dense = std::array::from_fn(|_| DMatrix::zeros(self.offsets.len(), n));
        for (v, o) in self.offsets.iter().enumerate() {
            let sq = o.weight.sqrt();
            for k in 0..n {
                let mut m = [0.0; 3];
                for (i, b) in &o.b {
                    for a in 0..3 {
                        m[a] += (0..3).map(|c| b[a][c] * w[c][(*i, k)]).sum::<f64>();
                    }
                }
                for a in 0..3 {
                    d[a][(v, k)] = sq * m[a];
                }
            }
        }
        d
    }

    /// M applied to the rows' positions: (M 1, M x_a) per row.
    fn moments(&self, mesh: &Mesh) -> (Vec<f64>, [Vec<f64>; 3]) {
        let n = self.ids.len();
        let mut one = vec![0.0; n];
        self.mul_vec(&vec![1.0; n], &mut one);
        let x = std::array::from_fn(|a| {
            let xa: Vec<f64> = self.ids.iter().map(|id| mesh.nodes[id - 1][a]).collect();
            let mut y = vec![0.0; n];
            self.mul_vec(&xa, &mut y);
            y
        });
        (one, x)
    }

    /// The whole body's mass, CoG and inertia about the CoG: 1^T M 1, x^T M 1, x_a^T M x_b
    /// (integrals of rho, rho x, rho x x^T at the same Gauss points as
    /// `lumping::consistent_mass_props`), plus the rigid parts.
    pub fn mass_props(&self, mesh: &Mesh) -> MassProps {
        let (one, mx) = self.moments(mesh);
        let mass: f64 = one.iter().sum();
        let pos = |i: usize| mesh.nodes[self.ids[i] - 1];
        let cog: [f64; 3] =
            std::array::from_fn(|a| (0..one.len()).map(|i| pos(i)[a] * one[i]).sum::<f64>() / mass);
        // Second moments about the CoG: x_a^T M x_b - m c_a c_b.
        let c: [[f64; 3]; 3] = std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                (0..one.len()).map(|i| pos(i)[a] * mx[b][i]).sum::<f64>() - mass * cog[a] * cog[b]
                    + self
                        .offsets
                        .iter()
                        .map(|o| o.weight * o.axis[a] * o.axis[b])
                        .sum::<f64>()
            })
        });
        let tr = c[0][0] + c[1][1] + c[2][2];
        let inertia = std::array::from_fn(|a| {
            std::array::from_fn(|b| if a == b { tr } else { 0.0 } - c[a][b])
        });
        let mut p = MassProps { mass, cog, inertia };
        for r in self.rigid.iter().filter(|r| r.mass > 0.0) {
            p = p.combine(&MassProps {
                mass: r.mass,
                cog: r.cog,
                inertia: r.inertia,
            });
        }
        p
    }

    /// The rigid motions' mass as this matrix has it: `mass_props`' mass and CoG, and the
    /// inertia about the CoG of its rotations (the mass properties less what no translation
    /// shows: a beam's torsion). Inertia relief and the rigid part of a shape use it, so that
    /// they match the matrix exactly.
    pub fn rigid_inertia(&self, mesh: &Mesh) -> MassProps {
        let p = self.mass_props(mesh);
        let rot: Vec<usize> = self.rigid.iter().map(|r| r.rot_node).collect();
        let mut inertia = [[0.0; 3]; 3];
        for b in 0..3 {
            let mut e = [0.0; 3];
            e[b] = 1.0;
            let mut m = [0.0; 3];
            for (id, f) in self.rigid_motion_load(mesh, [0.0; 3], e, p.cog) {
                let t = if rot.contains(&id) {
                    f
                } else {
                    cross(sub(mesh.nodes[id - 1], p.cog), f)
                };
                m = add(m, t);
            }
            for a in 0..3 {
                inertia[a][b] = m[a];
            }
        }
        // Symmetric up to round-off; make it so.
        for a in 0..3 {
            for b in 0..a {
                let v = 0.5 * (inertia[a][b] + inertia[b][a]);
                inertia[a][b] = v;
                inertia[b][a] = v;
            }
        }
        MassProps { inertia, ..p }
    }

    /// The elementary matrices of `modes` (seed paper): c[a][k] = 1^T M W_a,k,
    /// s[a][b][k] = x_a^T M W_b,k, g[a][b][k n + l] = W_a,k^T M W_b,l, plus, for each rigid part
    /// of mass m, CoG c and second moments J about c, moving with W_c + theta x rho (the paper's
    /// expansion, fig. 3): m W_c,a; m c_a W_c,b + (theta x J_a)_b with J_a = row a of J;
    /// m W_c,a,k W_c,b,l + sum_df eps_acd eps_bef theta_c,k theta_e,l J_df.
    pub fn elementary(&self, mesh: &Mesh, modes: &[Shapes]) -> Result<Elementary, String> {
        let n = modes.len();
        let w = self.dense(modes)?;
        let mw: Dense = std::array::from_fn(|a| self.mul(&w[a]));
        let (one, mx) = self.moments(mesh);
        let c: [Vec<f64>; 3] = std::array::from_fn(|a| {
            (0..n)
                .map(|k| w[a].column(k).iter().zip(&one).map(|(x, y)| x * y).sum())
                .collect()
        });
        let s: [[Vec<f64>; 3]; 3] = std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                (0..n)
                    .map(|k| w[b].column(k).iter().zip(&mx[a]).map(|(x, y)| x * y).sum())
                    .collect()
            })
        });
        let g: [[Vec<f64>; 3]; 3] = std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                let p = w[a].tr_mul(&mw[b]);
                (0..n * n).map(|i| p[(i / n, i % n)]).collect()
            })
        });
        let mut el = Elementary { c, s, g };
        if !self.offsets.is_empty() {
            let d = self.offset_motion(&w);
            let e: [Vec<f64>; 3] = std::array::from_fn(|a| {
                self.offsets
                    .iter()
                    .map(|o| o.weight.sqrt() * o.axis[a])
                    .collect()
            });
            for a in 0..3 {
                for b in 0..3 {
                    for k in 0..n {
                        el.s[a][b][k] += d[b]
                            .column(k)
                            .iter()
                            .zip(&e[a])
                            .map(|(x, y)| x * y)
                            .sum::<f64>();
                    }
                    let p = d[a].tr_mul(&d[b]);
                    for (i, v) in el.g[a][b].iter_mut().enumerate() {
                        *v += p[(i / n, i % n)];
                    }
                }
            }
        }
        self.add_rigid_parts(mesh, modes, &mut el)?;
        Ok(el)
    }

    fn add_rigid_parts(
        &self,
        mesh: &Mesh,
        modes: &[Shapes],
        el: &mut Elementary,
    ) -> Result<(), String> {
        let n = modes.len();
        for r in self.rigid.iter().filter(|r| r.mass > 0.0) {
            let j = second_moments(&r.inertia);
            let motion: Vec<([f64; 3], [f64; 3])> = modes
                .iter()
                .map(|s| rigid_motion(mesh, r, s))
                .collect::<Result<_, _>>()?;
            for (k, (wc, th)) in motion.iter().enumerate() {
                for a in 0..3 {
                    el.c[a][k] += r.mass * wc[a];
                    let tj = cross(*th, j[a]);
                    for b in 0..3 {
                        el.s[a][b][k] += r.mass * r.cog[a] * wc[b] + tj[b];
                    }
                }
            }
            // sum dm (theta_k x rho)_a (theta_l x rho)_b = (theta_k~ J theta_l~^T)_ab.
            for k in 0..n {
                let (wk, tk) = motion[k];
                let tkj = matmul(skew(tk), j);
                for l in 0..n {
                    let (wl, tl) = motion[l];
                    let rot = matmul(tkj, transpose(skew(tl)));
                    for a in 0..3 {
                        for b in 0..3 {
                            el.g[a][b][k * n + l] += r.mass * wk[a] * wl[b] + rot[a][b];
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// The mass inner products A^T M B of two sets of shapes (every component, rigid parts
    /// included: m W_c,k . W_c,l + theta_k^T I theta_l).
    pub fn inner(&self, mesh: &Mesh, a: &[Shapes], b: &[Shapes]) -> Result<DMatrix<f64>, String> {
        let (wa, wb) = (self.dense(a)?, self.dense(b)?);
        let mut p = DMatrix::zeros(a.len(), b.len());
        for c in 0..3 {
            p += wa[c].tr_mul(&self.mul(&wb[c]));
        }
        if !self.offsets.is_empty() {
            let (da, db) = (self.offset_motion(&wa), self.offset_motion(&wb));
            for c in 0..3 {
                p += da[c].tr_mul(&db[c]);
            }
        }
        for r in self.rigid.iter().filter(|r| r.mass > 0.0) {
            let ma: Vec<_> = a
                .iter()
                .map(|s| rigid_motion(mesh, r, s))
                .collect::<Result<_, _>>()?;
            let mb: Vec<_> = b
                .iter()
                .map(|s| rigid_motion(mesh, r, s))
                .collect::<Result<_, _>>()?;
            for (k, (wk, tk)) in ma.iter().enumerate() {
                for (l, (wl, tl)) in mb.iter().enumerate() {
                    let mut v = r.mass * dot(*wk, *wl);
                    for x in 0..3 {
                        for y in 0..3 {
                            v += tk[x] * r.inertia[x][y] * tl[y];
                        }
                    }
                    p[(k, l)] += v;
                }
            }
        }
        Ok(p)
    }

    /// max |W^T M W - E| of `modes`: how far the matrix is from the one ccx normalised with.
    pub fn normalisation_error(&self, mesh: &Mesh, modes: &[Shapes]) -> Result<f64, String> {
        let p = self.inner(mesh, modes, modes)?;
        Ok((0..p.nrows())
            .flat_map(|k| (0..p.ncols()).map(move |l| (k, l)))
            .map(|(k, l)| (p[(k, l)] - if k == l { 1.0 } else { 0.0 }).abs())
            .fold(0.0, f64::max))
    }

    /// The inertial load M u of the rigid motion u(x) = v + omega x (x - centre): nodal forces
    /// at the rows, and per rigid part (REF NODE, force; ROT NODE, moment about the REF NODE).
    pub fn rigid_motion_load(
        &self,
        mesh: &Mesh,
        v: [f64; 3],
        omega: [f64; 3],
        centre: [f64; 3],
    ) -> Vec<(usize, [f64; 3])> {
        let n = self.ids.len();
        let u: [Vec<f64>; 3] = std::array::from_fn(|a| {
            self.ids
                .iter()
                .map(|id| add(v, cross(omega, sub(mesh.nodes[id - 1], centre)))[a])
                .collect()
        });
        let mut f: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; n]);
        for a in 0..3 {
            self.mul_vec(&u[a], &mut f[a]);
        }
        // The offsets: d = sum_j B_j u_j; the load on node j is weight B_j^T d.
        for o in &self.offsets {
            let mut d = [0.0; 3];
            for (j, b) in &o.b {
                for r in 0..3 {
                    d[r] += (0..3).map(|c| b[r][c] * u[c][*j]).sum::<f64>();
                }
            }
            for (j, b) in &o.b {
                for c in 0..3 {
                    f[c][*j] += o.weight * (0..3).map(|r| b[r][c] * d[r]).sum::<f64>();
                }
            }
        }
        let mut out: Vec<(usize, [f64; 3])> = self
            .ids
            .iter()
            .enumerate()
            .map(|(i, id)| (*id, [f[0][i], f[1][i], f[2][i]]))
            .collect();
        for r in self.rigid.iter().filter(|r| r.mass > 0.0) {
            let force = add(v, cross(omega, sub(r.cog, centre))).map(|x| r.mass * x);
            let spin: [f64; 3] = std::array::from_fn(|a| dot(r.inertia[a], omega));
            let arm = sub(r.cog, mesh.nodes[r.ref_node - 1]);
            out.push((r.ref_node, force));
            out.push((r.rot_node, add(cross(arm, force), spin)));
        }
        out
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn skew(t: [f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -t[2], t[1]], [t[2], 0.0, -t[0]], [-t[1], t[0], 0.0]]
}

fn transpose(a: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

fn matmul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// Second moments J = sum dm r r^T about the CoG from the inertia tensor I = tr(J) E - J.
fn second_moments(i: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let half_tr = 0.5 * (i[0][0] + i[1][1] + i[2][2]);
    std::array::from_fn(|a| std::array::from_fn(|b| if a == b { half_tr } else { 0.0 } - i[a][b]))
}

/// A rigid part's motion in one mode: translation of its CoG and rotation.
fn rigid_motion(mesh: &Mesh, r: &RigidLump, s: &Shapes) -> Result<([f64; 3], [f64; 3]), String> {
    let theta = *s
        .rot
        .get(&r.rot_node)
        .ok_or_else(|| format!("no rotation printed for ROT NODE {}", r.rot_node))?;
    let w_ref =
        *s.w.get(&r.ref_node)
            .ok_or_else(|| format!("no displacement for REF NODE {}", r.ref_node))?;
    let arm = sub(r.cog, mesh.nodes[r.ref_node - 1]);
    Ok((add(w_ref, cross(theta, arm)), theta))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::lumping::{HEX20, consistent_mass_props};
    use crate::mesh::{Material, Rigid, Section};

    fn steel() -> Material {
        Material {
            name: "STEEL".into(),
            e: 210e9,
            nu: 0.3,
            rho: 7850.0,
        }
    }

    /// A curved S8R patch, a skewed C3D20, a B32 (`beam`) and point masses (one free, two on
    /// a rigid part).
    pub(crate) fn mixed(beam: bool) -> Mesh {
        let mut m = Mesh::new("mixed");
        let q: Vec<usize> = [
            [0.0, 0.0, 0.0],
            [0.2, 0.0, 0.01],
            [0.2, 0.1, 0.0],
            [0.0, 0.12, 0.0],
            [0.1, 0.0, 0.02],
            [0.2, 0.05, 0.01],
            [0.1, 0.11, 0.01],
            [0.0, 0.06, -0.01],
        ]
        .iter()
        .map(|p| m.node(*p))
        .collect();
        m.part(
            "S",
            Section::Shell {
                thickness: 0.002,
                material: steel(),
            },
        )
        .elements
        .push(q);
        let h: Vec<usize> = HEX20
            .iter()
            .map(|c| {
                m.node([
                    0.3 + 0.05 * c[0] + 0.01 * c[1] * c[2],
                    0.04 * c[1],
                    0.03 * c[2] + 0.005 * c[0],
                ])
            })
            .collect();
        m.part("B", Section::Solid { material: steel() })
            .elements
            .push(h);
        if beam {
            let b: Vec<usize> = [[0.0, 0.0, 0.1], [0.1, 0.01, 0.1], [0.2, 0.0, 0.12]]
                .iter()
                .map(|p| m.node(*p))
                .collect();
            m.part(
                "L",
                Section::Beam {
                    width: 0.01,
                    height: 0.02,
                    normal: [0.0, 0.0, 1.0],
                    material: steel(),
                },
            )
            .elements
            .push(b);
        }
        let pm: Vec<usize> = [[0.5, 0.0, 0.0], [0.6, 0.1, 0.0], [0.55, -0.1, 0.05]]
            .iter()
            .map(|p| m.node(*p))
            .collect();
        m.part("P", Section::Mass { kg: 0.3 }).elements = pm.iter().map(|&i| vec![i]).collect();
        m.add_to_set("R", &pm[1..]);
        let r = m.fresh_node([0.58, 0.0, 0.02]);
        let rot = m.fresh_node([0.58, 0.0, 0.02]);
        m.rigid.push(Rigid {
            nset: "R".into(),
            ref_node: r,
            rot_node: rot,
        });
        m
    }

    #[test]
    fn mass_props_equal_the_element_integrals_and_the_matrix_is_symmetric() {
        // Two paths: 1^T M 1, x^T M 1, x_a^T M x_b (the assembled matrix; sum N = 1 and
        // sum N x = x) against `consistent_mass_props`' direct integrals of rho, rho x,
        // rho x x^T at the same points.
        let m = mixed(true);
        let mm = consistent(&m);
        let (a, b) = (mm.mass_props(&m), consistent_mass_props(&m));
        assert!((a.mass - b.mass).abs() < 1e-14 * b.mass, "{a:?} {b:?}");
        for i in 0..3 {
            assert!((a.cog[i] - b.cog[i]).abs() < 1e-15, "{a:?} {b:?}");
            for j in 0..3 {
                assert!(
                    (a.inertia[i][j] - b.inertia[i][j]).abs() < 1e-14 * b.inertia[i][i],
                    "{a:?} {b:?}"
                );
            }
        }
        for i in 0..mm.ids.len() {
            for p in mm.start[i]..mm.start[i + 1] {
                let j = mm.cols[p];
                let back = (mm.start[j]..mm.start[j + 1])
                    .find(|&q| mm.cols[q] == i)
                    .expect("symmetric pattern");
                assert_eq!(mm.vals[p], mm.vals[back]);
            }
        }
    }

    #[test]
    fn elementary_of_rigid_motions_are_the_mass_properties() {
        // Under a rigid translation e_a every sum collapses to a mass property: c = m e_a,
        // g_ab = m delta_ab; under a rotation about the CoG the modal mass is theta^T I theta
        // (shells' rotary inertia included; no beam: its torsion is not in the translations).
        let m = mixed(false);
        let mm = consistent(&m);
        let p = mm.mass_props(&m);
        let shapes: Vec<Shapes> = (0..6)
            .map(|k| {
                let (v, th) = if k < 3 {
                    (
                        std::array::from_fn(|a| if a == k { 1.0 } else { 0.0 }),
                        [0.0; 3],
                    )
                } else {
                    (
                        [0.0; 3],
                        std::array::from_fn(|a| if a == k - 3 { 1.0 } else { 0.0 }),
                    )
                };
                let w = (1..=m.nodes.len())
                    .map(|id| (id, add(v, cross(th, sub(m.nodes[id - 1], p.cog)))))
                    .collect();
                let rot = m.rigid.iter().map(|r| (r.rot_node, th)).collect();
                Shapes {
                    frequency_hz: 0.0,
                    w,
                    rot,
                }
            })
            .collect();
        let el = mm.elementary(&m, &shapes).unwrap();
        let inner = mm.inner(&m, &shapes, &shapes).unwrap();
        for a in 0..3 {
            assert!((el.c[a][a] - p.mass).abs() < 1e-13 * p.mass);
            for k in 0..6 {
                let want = if k < 3 {
                    if k == a { p.mass } else { 0.0 }
                } else {
                    0.0
                };
                assert!((el.c[a][k] - want).abs() < 1e-13 * p.mass, "c[{a}][{k}]");
            }
        }
        for k in 0..6 {
            for l in 0..6 {
                let want = match (k < 3, l < 3) {
                    (true, true) if k == l => p.mass,
                    (false, false) => p.inertia[k - 3][l - 3],
                    _ => 0.0,
                };
                let tr: f64 = (0..3).map(|a| el.g[a][a][k * 6 + l]).sum();
                assert!((tr - want).abs() < 1e-12, "g {k} {l}: {tr} vs {want}");
                assert!((inner[(k, l)] - want).abs() < 1e-12, "inner {k} {l}");
            }
        }
        // The inertial load of a rigid motion: its resultant is m a and its moment about the
        // CoG I alpha.
        let (v, om) = ([0.3, -0.2, 0.5], [1.0, 2.0, -0.5]);
        let f = mm.rigid_motion_load(&m, v, om, p.cog);
        let rot_nodes: Vec<usize> = m.rigid.iter().map(|r| r.rot_node).collect();
        let (mut force, mut moment) = ([0.0; 3], [0.0; 3]);
        for (id, x) in &f {
            if rot_nodes.contains(id) {
                moment = add(moment, *x);
            } else {
                force = add(force, *x);
                moment = add(moment, cross(sub(m.nodes[id - 1], p.cog), *x));
            }
        }
        for a in 0..3 {
            assert!((force[a] - p.mass * v[a]).abs() < 1e-12);
            let ia: f64 = (0..3).map(|b| p.inertia[a][b] * om[b]).sum();
            assert!((moment[a] - ia).abs() < 1e-12, "{moment:?}");
        }
    }
}
