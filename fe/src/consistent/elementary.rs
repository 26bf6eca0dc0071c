//! The mass matrix applied to mode shapes: the seed paper's elementary matrices, the mass inner
//! products of two sets of shapes and the normalisation error, with the attached rigid parts
//! through the paper's expansion. Separate from the matrix (`mod.rs`) as the products the modal
//! data is formed with, dense over the modes where the matrix is sparse.

use super::{MassMatrix, dot};
use crate::error::PipelineError;
use crate::lumping::RigidLump;
use crate::mesh::Mesh;
use crate::modal::Shapes;
use nalgebra::DMatrix;
use washdyn_model::geom::f::{add, cross, sub};
use washdyn_model::ir::modal::Elementary;

/// One set of shapes at the matrix's rows, per component: W_a (rows x modes).
type Dense = [DMatrix<f64>; 3];
impl MassMatrix {
    /// The shapes at the rows, per component; every row needs a shape.
    fn dense(&self, modes: &[Shapes]) -> Result<Dense, PipelineError> {
        let mut w: Dense = std::array::from_fn(|_| DMatrix::zeros(self.ids.len(), modes.len()));
        for (k, m) in modes.iter().enumerate() {
            for (i, id) in self.ids.iter().enumerate() {
                let v =
                    m.w.get(id)
                        .ok_or(PipelineError::NoShapeAtMass { node: *id })?;
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
    /// The elementary matrices of `modes` (seed paper): c[a][k] = 1^T M W_a,k,
    /// s[a][b][k] = x_a^T M W_b,k, g[a][b][k n + l] = W_a,k^T M W_b,l, plus, for each rigid part
    /// of mass m, CoG c and second moments J about c, moving with W_c + theta x rho (the paper's
    /// expansion, fig. 3): m W_c,a; m c_a W_c,b + (theta x J_a)_b with J_a = row a of J;
    /// m W_c,a,k W_c,b,l + sum_df eps_acd eps_bef theta_c,k theta_e,l J_df.
    pub fn elementary(&self, mesh: &Mesh, modes: &[Shapes]) -> Result<Elementary, PipelineError> {
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
    ) -> Result<(), PipelineError> {
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
    pub fn inner(
        &self,
        mesh: &Mesh,
        a: &[Shapes],
        b: &[Shapes],
    ) -> Result<DMatrix<f64>, PipelineError> {
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

    /// The inertial load M s of a shape as nodal loads (`load_of`): what a second static
    /// solve K x = M s needs for the next Krylov vector of the correction modes.
    pub fn shape_load(
        &self,
        mesh: &Mesh,
        s: &Shapes,
    ) -> Result<Vec<(usize, [f64; 3])>, PipelineError> {
        let w = self.dense(std::slice::from_ref(s))?;
        let u: [Vec<f64>; 3] = std::array::from_fn(|a| w[a].column(0).iter().copied().collect());
        let parts = self
            .rigid
            .iter()
            .filter(|r| r.mass > 0.0)
            .map(|r| Ok((r.rot_node, rigid_motion(mesh, r, s)?)))
            .collect::<Result<Vec<_>, PipelineError>>()?;
        Ok(self.load_of(mesh, &u, |r| {
            parts
                .iter()
                .find(|p| p.0 == r.rot_node)
                .expect("`load_of` asks for the parts with mass, as `parts` holds them")
                .1
        }))
    }

    /// max |W^T M W - E| of `modes`: how far the matrix is from the one ccx normalised with.
    pub fn normalisation_error(&self, mesh: &Mesh, modes: &[Shapes]) -> Result<f64, PipelineError> {
        let p = self.inner(mesh, modes, modes)?;
        Ok((0..p.nrows())
            .flat_map(|k| (0..p.ncols()).map(move |l| (k, l)))
            .map(|(k, l)| (p[(k, l)] - if k == l { 1.0 } else { 0.0 }).abs())
            .fold(0.0, f64::max))
    }
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
fn rigid_motion(
    mesh: &Mesh,
    r: &RigidLump,
    s: &Shapes,
) -> Result<([f64; 3], [f64; 3]), PipelineError> {
    let theta = *s
        .rot
        .get(&r.rot_node)
        .ok_or(PipelineError::NoRotation { node: r.rot_node })?;
    let w_ref =
        *s.w.get(&r.ref_node)
            .ok_or(PipelineError::NoReference { node: r.ref_node })?;
    let arm = sub(r.cog, mesh.nodes[r.ref_node - 1]);
    Ok((add(w_ref, cross(theta, arm)), theta))
}
