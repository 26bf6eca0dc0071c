//! Static correction (residual flexibility) modes. A point load bends a thin rail or panel
//! locally, and no eigenmode of an affordable basis holds that dent: the cabinet's 60 modes to
//! 86 Hz answer the springs' preloads 26-36 % short. ccx solves the body statically under a
//! unit force or moment at each load point (the consistent nodal load of the modal point's rigid
//! fit), the eigenmodes' share is removed, Psi_r = Psi - sum_k Phi_k (f . Phi_k) / omega_k^2
//! (stiffness- and consistent-mass-orthogonal to every eigenmode, exactly: it is the
//! M-orthogonal projection in ccx's own mass, Phi_k^T M Psi = Phi_k^T K Psi / omega_k^2), and the
//! residual shapes are made orthonormal on their own: K_rr = Psi_r^T f (exact: K Psi = f) and
//! M_rr with the consistent mass (`consistent/mod.rs`), as the rest of the modal data.
//!
//! With `order` 2 a second solve follows, K X = M Psi_r (the next Krylov block), less the
//! eigenmodes' share: the static give answers a dropped mode driven at omega with 1, where it
//! answers (1 - (omega / omega_k)^2)^-1, and X holds the term in (omega / omega_k)^2. Both
//! blocks are made orthonormal together; their K-block stays exact, a^T K X_b = a^T f_b.
//!
//! A free body (the tub) has no static solution to a load that is not in equilibrium, and ccx
//! has no inertia relief, so we apply it ourselves: the load less the rigid-body inertia it
//! drives, f - M Phi_r (Phi_r^T M Phi_r)^-1 Phi_r^T f (Phi_r the six rigid motions about the
//! CoG, with the consistent M and the rigid parts), is self-equilibrated; ccx solves it on a
//! statically determinate 3-2-1 support (three far-apart nodes: no reaction, no constraint
//! stress); the rigid motion the support adds is removed by making the result M-orthogonal to
//! Phi_r. That is the elastic (mean-axis) response the free-free modes describe.

use crate::consistent::MassMatrix;
use crate::error::{Error, PipelineError, Within};
use crate::mesh::Mesh;
use crate::modal::{Shapes, point_reading_full};
use nalgebra::DMatrix;
use std::collections::{BTreeMap, HashMap};
use washdyn_model::geom::f::{cross, norm, sub};
use washdyn_model::ir::modal::{LoadCase, LoadKind, generalised_eigen};

/// Nodal loads: (node id, value). A rigid part's ROT NODE carries a moment.
pub type Loads = Vec<(usize, [f64; 3])>;

/// The correction modes of a body and the eigenmodes' generalised forces of the load cases.
pub struct Corrected {
    /// Mass-normalised (consistent mass) residual shapes, frequencies ascending.
    pub shapes: Vec<Shapes>,
    /// f_j . Phi_k of the unit loads, row k (eigenmode), column j (load case), row-major.
    pub participation: Vec<f64>,
    /// ccx's wall time for the static steps, s.
    pub solve_s: f64,
    /// The loads ccx solved: the unit loads, for a free body less their inertia relief (then,
    /// with order 2, the second block's M Psi_r).
    pub forces: Vec<Loads>,
    /// The support ccx held a free body with: (node, dof) of a 3-2-1 support; empty otherwise.
    pub support: Vec<(usize, usize)>,
    /// The eigenmodes' share removed from each static solution, (Phi_k . f_j) / omega_k^2
    /// (eigenmode x load case).
    pub share: DMatrix<f64>,
    /// Correction mode c = sum_j combination[(j, c)] Psi_r,j.
    pub combination: DMatrix<f64>,
    /// Free body: the largest support reaction over the largest nodal load of a load case
    /// (zero for a self-equilibrated load, up to ccx's solver).
    pub reaction: Option<f64>,
    /// With `stresses`: each load case's stresses at the expanded nodes (the same solve).
    pub static_stresses: Vec<Vec<(usize, [f64; 6])>>,
    /// With `stresses`: each load case's displacements at all of ccx's 3-D nodes, and ccx's
    /// 3-D elements (a spinning body's geometric stiffness integrates them, `prestress.rs`).
    pub statics_3d: Vec<Vec<(usize, [f64; 3])>>,
    pub elements_3d: Vec<(usize, Vec<usize>)>,
}

/// Node set of a free body's 3-2-1 support (for its reaction prints).
const SUPPORT_SET: &str = "WD_SUPPORT";

/// The static deck of the load cases (one `*STATIC` step each) on `support` ((node, dof) held
/// besides the mesh's own boundary), with 2-D displacement output, or with 3-D displacements
/// and stresses (`stress`).
pub fn static_deck(
    mesh: &Mesh,
    forces: &[Loads],
    support: &[(usize, usize)],
    stress: bool,
) -> crate::deck::Deck {
    let mut d = mesh.model_deck();
    if !support.is_empty() {
        let mut ids: Vec<usize> = support.iter().map(|s| s.0).collect();
        ids.sort_unstable();
        ids.dedup();
        d.nset(SUPPORT_SET, &ids);
        d.line("*BOUNDARY");
        for (id, dof) in support {
            d.line(&format!("{id}, {dof}, {dof}"));
        }
    }
    for f in forces {
        d.line("*STEP").line("*STATIC").line("*CLOAD, OP=NEW");
        for (id, v) in f {
            for (c, x) in v.iter().enumerate() {
                if *x != 0.0 {
                    d.line(&format!("{id}, {}, {x:.12e}", c + 1));
                }
            }
        }
        if stress {
            d.line("*NODE FILE").line("U").line("*EL FILE").line("S");
        } else {
            d.line("*NODE FILE, OUTPUT=2D").line("U");
        }
        if !mesh.rigid.is_empty() {
            d.line("*NODE PRINT, NSET=WD_PRINT").line("U");
        }
        if !support.is_empty() {
            d.line(&format!("*NODE PRINT, NSET={SUPPORT_SET}"))
                .line("RF");
        }
        d.line("*END STEP");
    }
    d
}

/// Nodal loads of a unit load case at the modal point (`set`, `position`): R_i^T d for a
/// force, T_i^T d for a moment (`modal::point_reading_full`).
fn nodal_load(
    mesh: &Mesh,
    set: &str,
    position: [f64; 3],
    load: &LoadCase,
) -> Result<Loads, PipelineError> {
    let d = load.direction;
    Ok(point_reading_full(mesh, set, position)?
        .into_iter()
        .map(|(id, r, t)| {
            let m = match load.kind {
                LoadKind::Force => r,
                LoadKind::Moment => t,
            };
            (
                id,
                std::array::from_fn(|c| (0..3).map(|a| m[a][c] * d[a]).sum()),
            )
        })
        .collect())
}

/// The work of loads `f` on shape `s`: translations at nodes, rotations at ROT NODEs.
pub fn work(s: &Shapes, f: &[(usize, [f64; 3])]) -> f64 {
    f.iter()
        .map(|(id, v)| {
            s.w.get(id)
                .or_else(|| s.rot.get(id))
                .map_or(0.0, |u| u[0] * v[0] + u[1] * v[1] + u[2] * v[2])
        })
        .sum()
}

/// `f` less its inertia relief: f - M u_r with u_r the rigid acceleration f drives,
/// a + alpha x (x - c), m a = sum f, I alpha = sum (x - c) x f (about the CoG c; moments at
/// ROT NODEs count as they are). The result is self-equilibrated.
pub fn relieved(mesh: &Mesh, mass: &MassMatrix, f: &[(usize, [f64; 3])]) -> Loads {
    let p = mass.rigid_inertia(mesh);
    let rot_nodes: Vec<usize> = mass.rigid.iter().map(|r| r.rot_node).collect();
    let (mut force, mut moment) = ([0.0; 3], [0.0; 3]);
    for (id, v) in f {
        if rot_nodes.contains(id) {
            moment = add3(moment, *v);
        } else {
            force = add3(force, *v);
            moment = add3(moment, cross(sub(mesh.nodes[id - 1], p.cog), *v));
        }
    }
    let a = force.map(|x| x / p.mass);
    let i = nalgebra::Matrix3::from_fn(|r, c| p.inertia[r][c]);
    let alpha = i
        .try_inverse()
        .expect("a body with mass has an invertible inertia")
        * nalgebra::Vector3::from_column_slice(&moment);
    let inertial = mass.rigid_motion_load(mesh, a, [alpha[0], alpha[1], alpha[2]], p.cog);
    let mut out: BTreeMap<usize, [f64; 3]> = f.iter().copied().collect();
    for (id, v) in inertial {
        let e = out.entry(id).or_insert([0.0; 3]);
        for c in 0..3 {
            e[c] -= v[c];
        }
    }
    out.into_iter().collect()
}

fn add3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Remove from `s` its rigid part in the mass `mass`: s - (v + omega x (x - c)) with
/// [m E, 0; 0, I] [v; omega] = [sum dm s; sum dm (x - c) x s] (about the CoG c), so that the
/// result is M-orthogonal to the six rigid motions.
pub fn remove_rigid_motion(
    mesh: &Mesh,
    mass: &MassMatrix,
    s: &mut Shapes,
) -> Result<(), PipelineError> {
    let p = mass.rigid_inertia(mesh);
    let el = mass.elementary(mesh, std::slice::from_ref(s))?;
    let lin: [f64; 3] = std::array::from_fn(|a| el.c[a][0]);
    // sum dm (x - c) x s: eps_abc (s[b][c] - c_b lin_c).
    let first = |b: usize, c: usize| el.s[b][c][0] - p.cog[b] * lin[c];
    let ang = [
        first(1, 2) - first(2, 1),
        first(2, 0) - first(0, 2),
        first(0, 1) - first(1, 0),
    ];
    let i = nalgebra::Matrix3::from_fn(|r, c| p.inertia[r][c]);
    let om = i.try_inverse().ok_or(PipelineError::SingularInertia)?
        * nalgebra::Vector3::from_column_slice(&ang);
    let (v, om) = (lin.map(|x| x / p.mass), [om[0], om[1], om[2]]);
    for (id, u) in s.w.iter_mut() {
        let r = add3(v, cross(om, sub(mesh.nodes[id - 1], p.cog)));
        for c in 0..3 {
            u[c] -= r[c];
        }
    }
    for u in s.rot.values_mut() {
        for c in 0..3 {
            u[c] -= om[c];
        }
    }
    Ok(())
}

/// A statically determinate (3-2-1) support of a free body: three structural nodes far apart
/// (the farthest from the centroid, the farthest from it, the farthest from the line through
/// both; not in a rigid part), holding 3, 2 and 1 translations chosen so that the six
/// constraints fix the six rigid motions best (largest determinant).
pub fn determinate_support(mesh: &Mesh) -> Result<Vec<(usize, usize)>, PipelineError> {
    let in_rigid: Vec<usize> = mesh
        .rigid
        .iter()
        .flat_map(|r| mesh.nsets.get(&r.nset).into_iter().flatten().copied())
        .collect();
    let mut nodes: Vec<usize> = mesh
        .parts
        .iter()
        .filter(|p| p.section.material().is_some())
        .flat_map(|p| p.elements.iter().flatten().copied())
        .filter(|id| !in_rigid.contains(id))
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    if nodes.len() < 3 {
        return Err(PipelineError::FewNodes);
    }
    let x = |id: usize| mesh.nodes[id - 1];
    let mut centre = [0.0; 3];
    for &id in &nodes {
        centre = add3(centre, x(id).map(|v| v / nodes.len() as f64));
    }
    let far = |from: &dyn Fn([f64; 3]) -> f64| -> usize {
        *nodes
            .iter()
            .max_by(|a, b| from(x(**a)).total_cmp(&from(x(**b))))
            .expect("nodes")
    };
    let a = far(&|p| norm(sub(p, centre)));
    let b = far(&|p| norm(sub(p, x(a))));
    let ab = sub(x(b), x(a));
    let c = far(&|p| norm(cross(sub(p, x(a)), ab)));
    let len = norm(ab);
    if norm(cross(sub(x(c), x(a)), ab)) < 1e-6 * len * len {
        return Err(PipelineError::Collinear);
    }
    // Rows: constrained (node, dof); columns: translations and rotations (times len) about A.
    let row = |id: usize, dof: usize| -> [f64; 6] {
        let r = sub(x(id), x(a));
        let mut v = [0.0; 6];
        v[dof] = 1.0;
        for k in 0..3 {
            let mut e = [0.0; 3];
            e[k] = len;
            v[3 + k] = cross(e, r)[dof] / len;
        }
        v
    };
    let mut best: Option<(f64, Vec<(usize, usize)>)> = None;
    for skip_b in 0..3 {
        for keep_c in 0..3 {
            let mut s: Vec<(usize, usize)> = (0..3).map(|d| (a, d)).collect();
            s.extend((0..3).filter(|&d| d != skip_b).map(|d| (b, d)));
            s.push((c, keep_c));
            let m = DMatrix::from_fn(6, 6, |i, j| row(s[i].0, s[i].1)[j]);
            let det = m.determinant().abs();
            if best.as_ref().is_none_or(|(d, _)| det > *d) {
                best = Some((det, s));
            }
        }
    }
    let (det, s) = best.expect("nine candidates");
    if det < 1e-6 {
        return Err(PipelineError::NoSupport { det });
    }
    Ok(s.into_iter().map(|(id, d)| (id, d + 1)).collect())
}

/// The correction modes for `loads` (points named in `points`) of `mesh` with eigenmodes
/// `modes`; a `free` body gets inertia relief and a 3-2-1 support. The static deck is
/// `<dir>/<job>.inp`; with `stresses` its 3-D output also gives the load cases' stresses.
#[allow(clippy::too_many_arguments)]
pub fn correction_modes(
    mesh: &Mesh,
    mass: &MassMatrix,
    modes: &[Shapes],
    points: &[(&str, [f64; 3])],
    loads: &[LoadCase],
    free: bool,
    stresses: bool,
    order: usize,
    dir: &std::path::Path,
    job: &str,
) -> Result<Corrected, Error> {
    let unit = loads
        .iter()
        .map(|l| {
            let p = points.iter().find(|(n, _)| *n == l.point).ok_or_else(|| {
                PipelineError::NoLoadPoint {
                    point: l.point.clone(),
                }
            })?;
            nodal_load(mesh, p.0, p.1, l)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let (forces, support) = if free {
        let f: Vec<Loads> = unit.iter().map(|f| relieved(mesh, mass, f)).collect();
        (f, determinate_support(mesh)?)
    } else {
        (unit.clone(), Vec::new())
    };
    let (n, j) = (modes.len(), loads.len());
    let mut participation = vec![0.0; n * j];
    for (k, m) in modes.iter().enumerate() {
        for (c, f) in unit.iter().enumerate() {
            participation[k * j + c] = work(m, f);
        }
    }
    let mut solved = residuals(
        mesh, mass, modes, &forces, &support, free, stresses, dir, job,
    )?;
    let mut forces = forces;
    if order >= 2 {
        // The next Krylov block: K X2 = M Psi_r, each load scaled by its shape's Rayleigh
        // quotient so that X2 comes out the size of Psi_r (the shapes' own eigenproblem below
        // would drop a block 1e-13 smaller as dependent).
        let m = mass.inner(mesh, &solved.shapes, &solved.shapes)?;
        let next = solved
            .shapes
            .iter()
            .zip(&forces)
            .enumerate()
            .map(|(c, (s, f))| {
                let scale = work(s, f) / m[(c, c)];
                let l: Loads = mass
                    .shape_load(mesh, s)?
                    .into_iter()
                    .map(|(id, v)| (id, v.map(|x| scale * x)))
                    .collect();
                Ok(if free { relieved(mesh, mass, &l) } else { l })
            })
            .collect::<Result<Vec<Loads>, PipelineError>>()?;
        solved.append(residuals(
            mesh,
            mass,
            modes,
            &next,
            &support,
            free,
            stresses,
            dir,
            &format!("{job}_2"),
        )?);
        forces.extend(next);
    }
    let residual = &solved.shapes;
    let cases = forces.len();
    let stiff = DMatrix::from_fn(cases, cases, |a, b| {
        0.5 * (work(&residual[a], &forces[b]) + work(&residual[b], &forces[a]))
    });
    let m_rr = mass.inner(mesh, residual, residual)?;
    let (x, lambda) = generalised_eigen(&m_rr, &stiff);
    let shapes = (0..lambda.len())
        .map(|c| {
            let mut w: HashMap<usize, [f64; 3]> = HashMap::new();
            let mut rot: HashMap<usize, [f64; 3]> = HashMap::new();
            for (r, s) in residual.iter().enumerate() {
                let a = x[(r, c)];
                for (map, src) in [(&mut w, &s.w), (&mut rot, &s.rot)] {
                    for (id, u) in src {
                        let e = map.entry(*id).or_insert([0.0; 3]);
                        for i in 0..3 {
                            e[i] += a * u[i];
                        }
                    }
                }
            }
            Shapes {
                frequency_hz: lambda[c].max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
                w,
                rot,
            }
        })
        .collect();
    Ok(Corrected {
        shapes,
        participation,
        solve_s: solved.solve_s,
        forces,
        support,
        share: solved.share,
        combination: x,
        reaction: solved.reaction,
        static_stresses: solved.static_stresses,
        statics_3d: solved.statics_3d,
        elements_3d: solved.elements_3d,
    })
}

/// One static solve of `forces` (on `support`): the residual shapes Psi_r (less a free
/// body's rigid motion and the eigenmodes' share) and what the solve leaves for stresses.
struct Residuals {
    shapes: Vec<Shapes>,
    share: DMatrix<f64>,
    reaction: Option<f64>,
    solve_s: f64,
    static_stresses: Vec<Vec<(usize, [f64; 6])>>,
    statics_3d: Vec<Vec<(usize, [f64; 3])>>,
    elements_3d: Vec<(usize, Vec<usize>)>,
}

impl Residuals {
    /// The load cases of `next` after this solve's, as one solve of both would give them.
    fn append(&mut self, next: Residuals) {
        let (n, j) = self.share.shape();
        let share = DMatrix::from_fn(n, j + next.share.ncols(), |k, c| {
            if c < j {
                self.share[(k, c)]
            } else {
                next.share[(k, c - j)]
            }
        });
        self.share = share;
        self.shapes.extend(next.shapes);
        self.reaction = match (self.reaction, next.reaction) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
        self.solve_s += next.solve_s;
        self.static_stresses.extend(next.static_stresses);
        self.statics_3d.extend(next.statics_3d);
    }
}

#[allow(clippy::too_many_arguments)]
fn residuals(
    mesh: &Mesh,
    mass: &MassMatrix,
    modes: &[Shapes],
    forces: &[Loads],
    support: &[(usize, usize)],
    free: bool,
    stresses: bool,
    dir: &std::path::Path,
    job: &str,
) -> Result<Residuals, Error> {
    let d = static_deck(mesh, forces, support, stresses);
    let mut solved = crate::modal::solve_deck(mesh, &d, dir, job)?;
    let statics_3d = if stresses {
        crate::stress::mid_surface(mesh, &mut solved.frd)?.1.statics
    } else {
        Vec::new()
    };
    if solved.frd.statics.len() != forces.len() {
        return Err(PipelineError::StaticCount {
            job: job.to_string(),
            results: solved.frd.statics.len(),
            cases: forces.len(),
        }
        .into());
    }
    let reaction = if support.is_empty() {
        None
    } else {
        // ccx's RF at a node is K u there: the reaction plus the node's own load.
        let rf = crate::dat::reactions(&solved.dat, SUPPORT_SET).within(|| format!("{job}.dat"))?;
        let mut worst = 0.0f64;
        for (r, f) in rf.iter().zip(forces) {
            let top = f
                .iter()
                .flat_map(|x| x.1)
                .fold(0.0f64, |m, v| m.max(v.abs()));
            for (id, v) in r {
                let own = f.iter().find(|x| x.0 == *id).map_or([0.0; 3], |x| x.1);
                for c in 0..3 {
                    worst = worst.max((v[c] - own[c]).abs() / top);
                }
            }
        }
        // ccx prints 7 digits: measured 1e-6 on a test body.
        if worst > 1e-4 {
            return Err(PipelineError::NotInEquilibrium {
                job: job.to_string(),
                worst,
            }
            .into());
        }
        Some(worst)
    };
    let rot_ids: Vec<usize> = mesh.rigid.iter().map(|r| r.rot_node).collect();
    let (n, j) = (modes.len(), forces.len());
    let w2: Vec<f64> = modes
        .iter()
        .map(|m| (2.0 * std::f64::consts::PI * m.frequency_hz).powi(2))
        .collect();
    // The share of the loads as solved: the same as the unit loads' for eigenmodes orthogonal
    // to the rigid motions; this one makes Psi_r exactly K-orthogonal to them.
    let share = DMatrix::from_fn(n, j, |k, c| work(&modes[k], &forces[c]) / w2[k]);
    // The residual shapes Psi_r.
    let mut residual = Vec::with_capacity(j);
    for (c, disp) in solved.frd.statics.iter().enumerate() {
        let mut w: HashMap<usize, [f64; 3]> = disp.iter().copied().collect();
        let mut rot = HashMap::new();
        for &(id, v) in solved.prints.get(c).into_iter().flatten() {
            if rot_ids.contains(&id) {
                rot.insert(id, v);
            } else {
                w.entry(id).or_insert(v);
            }
        }
        let mut s = Shapes {
            frequency_hz: 0.0,
            w,
            rot,
        };
        if free {
            remove_rigid_motion(mesh, mass, &mut s)?;
        }
        for (k, m) in modes.iter().enumerate() {
            let a = share[(k, c)];
            for (map, src) in [(&mut s.w, &m.w), (&mut s.rot, &m.rot)] {
                for (id, u) in map.iter_mut() {
                    if let Some(p) = src.get(id) {
                        for x in 0..3 {
                            u[x] -= a * p[x];
                        }
                    }
                }
            }
        }
        residual.push(s);
    }
    Ok(Residuals {
        shapes: residual,
        share,
        reaction,
        solve_s: solved.run.wall_s,
        static_stresses: solved.frd.static_stresses,
        statics_3d,
        elements_3d: if stresses {
            solved.frd.elements
        } else {
            Vec::new()
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::consistent::{consistent, tests::mixed};

    #[test]
    fn relieved_loads_are_in_equilibrium_and_the_support_fixes_the_rigid_motions() {
        // A unit force off the CoG and a moment on the rigid part: less their inertia relief
        // (with the rigid part, the shells' rotary inertia, a free point mass), the resultant
        // and the moment vanish to round-off.
        let m = mixed(true);
        let mass = consistent(&m);
        let rot = m.rigid[0].rot_node;
        let f = vec![(1, [0.3, -1.0, 0.5]), (rot, [0.0, 0.2, 0.1])];
        let r = relieved(&m, &mass, &f);
        let (mut force, mut moment) = ([0.0; 3], [0.0; 3]);
        for (id, v) in &r {
            if *id == rot {
                moment = add3(moment, *v);
            } else {
                force = add3(force, *v);
                moment = add3(moment, cross(m.nodes[id - 1], *v));
            }
        }
        assert!(
            force.iter().chain(&moment).all(|x| x.abs() < 1e-14),
            "{force:?} {moment:?}"
        );
        // 3 + 2 + 1 translations on three distinct structural nodes, not on the rigid part.
        let s = determinate_support(&m).unwrap();
        assert_eq!(s.len(), 6);
        let mut ids: Vec<usize> = s.iter().map(|x| x.0).collect();
        ids.dedup();
        assert_eq!(ids.len(), 3);
        assert!(ids.iter().all(|id| !m.nsets["R"].contains(id)));
    }
}
