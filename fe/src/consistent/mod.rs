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
//!
//! This file holds the matrix and how it is built from the mesh; what it is applied to lives
//! beside it: mode shapes (the elementary matrices and the mass inner products,
//! `elementary.rs`) and rigid motions (mass properties, rigid inertia and the inertial load of
//! a rigid motion, `rigid_body.rs`).

mod elementary;
mod rigid_body;

use crate::lumping::{Lumped, RigidLump, Rule, gauss, rigid_parts, section_axes};
use crate::mesh::Mesh;
use nalgebra::DMatrix;
use washdyn_model::geom::f::{add, cross, sub};

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

    /// The inertial load M u of the field `u` (per component, over the rows) whose rigid parts
    /// move with `part` (CoG translation, rotation): nodal forces at the rows (the offsets'
    /// share included), and per rigid part its force at the REF NODE and its moment about the
    /// REF NODE at the ROT NODE, as ccx takes loads on a `*RIGID BODY`.
    pub(crate) fn load_of(
        &self,
        mesh: &Mesh,
        u: &[Vec<f64>; 3],
        part: impl Fn(&RigidLump) -> ([f64; 3], [f64; 3]),
    ) -> Vec<(usize, [f64; 3])> {
        let n = self.ids.len();
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
            let (w, theta) = part(r);
            let force = w.map(|x| r.mass * x);
            let spin: [f64; 3] = std::array::from_fn(|a| dot(r.inertia[a], theta));
            let arm = sub(r.cog, mesh.nodes[r.ref_node - 1]);
            out.push((r.ref_node, force));
            out.push((r.rot_node, add(cross(arm, force), spin)));
        }
        out
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
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
pub(crate) mod tests;
