//! FE results -> modal data: the kept modes, the seed paper's elementary matrices over the
//! body's mass matrix (`consistent/mod.rs`, with the attached rigid parts through their CoG and
//! inertia), and the mode shapes at the named points (a rigid fit of each node set).

use crate::consistent::MassMatrix;
use crate::error::{Error, PipelineError, Within};
use crate::frd::Frd;
use crate::mesh::Mesh;
use std::collections::HashMap;
use washdyn_model::geom::f::{add, cross, sub};
use washdyn_model::ir::modal::{ElasticBodyKind, ModalData, ModalPoint, Support};

/// Which modes to keep.
#[derive(Clone, Copy, Debug)]
pub struct Keep {
    /// Modes below this (Hz) are rigid-body modes and dropped (free-free bodies).
    pub rigid_below_hz: f64,
    /// Keep elastic modes up to this frequency (Hz) ...
    pub max_hz: f64,
    /// ... and at most this many.
    pub max_modes: usize,
}

/// One mode's nodal translations by node id, and the rigid parts' rotations.
pub struct Shapes {
    pub frequency_hz: f64,
    pub w: HashMap<usize, [f64; 3]>,
    /// ROT NODE id -> rotation vector.
    pub rot: HashMap<usize, [f64; 3]>,
}

/// Pair the `.frd` modes with the `.dat` node prints (same order; the rigid parts' nodes, and
/// their ROT NODEs' rotations) and keep the wanted modes.
pub fn select(
    mesh: &Mesh,
    frd: &Frd,
    prints: &[Vec<(usize, [f64; 3])>],
    keep: Keep,
) -> Result<Vec<Shapes>, PipelineError> {
    if !prints.is_empty() && prints.len() != frd.modes.len() {
        return Err(PipelineError::PrintCount {
            dat: prints.len(),
            frd: frd.modes.len(),
        });
    }
    let rot_ids: Vec<usize> = mesh.rigid.iter().map(|r| r.rot_node).collect();
    let mut out = Vec::new();
    for i in kept(frd, keep) {
        let m = &frd.modes[i];
        let mut w: HashMap<usize, [f64; 3]> = m.disp.iter().copied().collect();
        let mut rot = HashMap::new();
        for &(id, v) in prints.get(i).into_iter().flatten() {
            if rot_ids.contains(&id) {
                rot.insert(id, v);
            } else {
                w.entry(id).or_insert(v);
            }
        }
        out.push(Shapes {
            frequency_hz: m.frequency_hz,
            w,
            rot,
        });
    }
    Ok(out)
}

/// The indices of the `.frd`'s modes that `keep` keeps, ascending.
pub fn kept(frd: &Frd, keep: Keep) -> Vec<usize> {
    let mut out = Vec::new();
    for (i, m) in frd.modes.iter().enumerate() {
        if m.frequency_hz < keep.rigid_below_hz {
            continue;
        }
        if m.frequency_hz > keep.max_hz || out.len() == keep.max_modes {
            break;
        }
        out.push(i);
    }
    out
}

/// Least-squares rigid motion of the nodes `ids` in one mode, as (translation at the nodes'
/// centroid, rotation, centroid). Rotations the nodes do not determine (one node, or about the
/// line through collinear nodes) are zero.
pub fn rigid_fit(
    mesh: &Mesh,
    ids: &[usize],
    w: &HashMap<usize, [f64; 3]>,
) -> Option<([f64; 3], [f64; 3], [f64; 3])> {
    let pts: Vec<([f64; 3], [f64; 3])> = ids
        .iter()
        .filter_map(|id| w.get(id).map(|v| (mesh.nodes[id - 1], *v)))
        .collect();
    if pts.is_empty() {
        return None;
    }
    let n = pts.len() as f64;
    let mut c = [0.0; 3];
    let mut u = [0.0; 3];
    for (x, v) in &pts {
        for i in 0..3 {
            c[i] += x[i] / n;
            u[i] += v[i] / n;
        }
    }
    // A theta = sum r x w, A = sum (|r|^2 E - r r^T).
    let mut a = nalgebra::Matrix3::<f64>::zeros();
    let mut b = nalgebra::Vector3::<f64>::zeros();
    for (x, v) in &pts {
        let r = sub(*x, c);
        let rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        for i in 0..3 {
            for j in 0..3 {
                a[(i, j)] += if i == j { rr } else { 0.0 } - r[i] * r[j];
            }
        }
        let t = cross(r, *v);
        for i in 0..3 {
            b[i] += t[i];
        }
    }
    let e = a.symmetric_eigen();
    let top = e.eigenvalues.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut theta = nalgebra::Vector3::zeros();
    for k in 0..3 {
        let lam = e.eigenvalues[k];
        if top > 0.0 && lam > 1e-8 * top {
            let v = e.eigenvectors.column(k);
            theta += v * (v.dot(&b) / lam);
        }
    }
    Some((u, [theta[0], theta[1], theta[2]], c))
}

/// The mode shapes at `position` of the node set `nset`: the rigid fit of the set, per mode.
pub fn point(
    mesh: &Mesh,
    nset: &str,
    position: [f64; 3],
    modes: &[Shapes],
) -> Result<ModalPoint, PipelineError> {
    let ids = mesh
        .nsets
        .get(nset)
        .ok_or_else(|| PipelineError::NoNodeSet {
            set: nset.to_string(),
        })?;
    let n = modes.len();
    let mut w: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; n]);
    let mut phi: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; n]);
    let mut used = 0;
    for (k, m) in modes.iter().enumerate() {
        let (u, th, c) = rigid_fit(mesh, ids, &m.w).ok_or_else(|| PipelineError::NoShapeInSet {
            set: nset.to_string(),
        })?;
        used = ids.iter().filter(|id| m.w.contains_key(id)).count();
        let wp = add(u, cross(th, sub(position, c)));
        for a in 0..3 {
            w[a][k] = wp[a];
            phi[a][k] = th[a];
        }
    }
    Ok(ModalPoint {
        name: nset.to_string(),
        position,
        nodes: used,
        w,
        phi,
    })
}

/// Per node of a set, the 3 x 3 blocks R_i and T_i with w_p = sum_i R_i u_i (translation at
/// the point) and phi_p = sum_i T_i u_i (rotation).
pub type Reading = Vec<(usize, [[f64; 3]; 3], [[f64; 3]; 3])>;

/// How the modal point at `position` of node set `nset` reads the nodes: w_p = sum_i R_i u_i,
/// phi_p = sum_i T_i u_i (the rigid fit is linear in the nodal displacements). Returns
/// (node, R_i, T_i) per node. A force F at the point does the work of nodal forces R_i^T F, a
/// moment C that of T_i^T C: the consistent loads that the equations apply through the point's
/// W and Phi.
pub fn point_reading_full(
    mesh: &Mesh,
    nset: &str,
    position: [f64; 3],
) -> Result<Reading, PipelineError> {
    let ids = mesh
        .nsets
        .get(nset)
        .ok_or_else(|| PipelineError::NoNodeSet {
            set: nset.to_string(),
        })?;
    let mut out = Vec::with_capacity(ids.len());
    for &id in ids {
        let (mut r, mut t) = ([[0.0; 3]; 3], [[0.0; 3]; 3]);
        for d in 0..3 {
            let mut w: HashMap<usize, [f64; 3]> = ids.iter().map(|&i| (i, [0.0; 3])).collect();
            w.get_mut(&id).expect("in the set")[d] = 1.0;
            let (u, th, c) = rigid_fit(mesh, ids, &w).expect("the set has nodes");
            let wp = add(u, cross(th, sub(position, c)));
            for a in 0..3 {
                r[a][d] = wp[a];
                t[a][d] = th[a];
            }
        }
        out.push((id, r, t));
    }
    Ok(out)
}

/// Per node of a set, the 3 x 3 block R_i with w_p = sum_i R_i u_i.
pub type TranslationReading = Vec<(usize, [[f64; 3]; 3])>;

/// The translation part of `point_reading_full`: (node, R_i) with w_p = sum_i R_i u_i.
pub fn point_reading(
    mesh: &Mesh,
    nset: &str,
    position: [f64; 3],
) -> Result<TranslationReading, PipelineError> {
    Ok(point_reading_full(mesh, nset, position)?
        .into_iter()
        .map(|(id, r, _)| (id, r))
        .collect())
}

/// Everything for one body's modal data file.
pub struct Import<'a> {
    pub body: ElasticBodyKind,
    pub support: Support,
    pub source: String,
    pub mesh: &'a Mesh,
    /// The mass the elementary matrices and the mass properties are formed with.
    pub mass: &'a MassMatrix,
    pub modes: &'a [Shapes],
    /// (node set, point) of every marker and sensor on the body.
    pub points: &'a [(&'a str, [f64; 3])],
}

impl Import<'_> {
    pub fn modal_data(&self) -> Result<ModalData, PipelineError> {
        let props = self.mass.mass_props(self.mesh);
        let points = self
            .points
            .iter()
            .map(|(set, p)| point(self.mesh, set, *p, self.modes))
            .collect::<Result<_, _>>()?;
        Ok(ModalData {
            body: self.body,
            support: self.support,
            source: self.source.clone(),
            frequencies: self.modes.iter().map(|m| m.frequency_hz).collect(),
            mass: props.mass,
            cog: props.cog,
            inertia: props.inertia,
            elementary: self.mass.elementary(self.mesh, self.modes)?,
            points,
            geometric_stiffness: None,
            correction: None,
            basis: None,
            file_modes: None,
            support_springs: Vec::new(),
        })
    }
}

/// A body's FE model solved by ccx: the run, its modes and the rigid parts' rotations.
pub struct Solved {
    pub run: crate::ccx::CcxRun,
    pub frd: Frd,
    /// The `.dat`'s node prints per mode (`Mesh::printed_nodes`).
    pub prints: Vec<Vec<(usize, [f64; 3])>>,
    pub dat: String,
    /// A 3-D solve's expanded nodes of each original node (`stress::mid_surface`).
    pub expanded: Option<HashMap<usize, Vec<usize>>>,
    /// A 3-D solve's displacements at all of ccx's nodes, when asked to keep them
    /// (`solve_keeping_3d`).
    pub unfolded: Option<crate::stress::Unfolded>,
}

/// Write `mesh`'s frequency deck for `modes` eigenmodes as `<dir>/<job>.inp`, run ccx, read back.
/// With `stresses` the solve writes 3-D output with the stresses (`Mesh::frequency_deck`), its
/// shapes are put at the original nodes (`stress::mid_surface`) and `expanded` says where the
/// stresses are.
pub fn solve(
    mesh: &Mesh,
    dir: &std::path::Path,
    job: &str,
    modes: usize,
    stresses: bool,
) -> Result<Solved, Error> {
    solve_with(mesh, dir, job, modes, stresses, false)
}

/// `solve` with 3-D output, keeping the displacements at ccx's 3-D nodes (`Solved::unfolded`)
/// beside the shapes at the original nodes: a spinning body's geometric stiffness integrates
/// them over ccx's bricks.
pub fn solve_keeping_3d(
    mesh: &Mesh,
    dir: &std::path::Path,
    job: &str,
    modes: usize,
) -> Result<Solved, Error> {
    solve_with(mesh, dir, job, modes, true, true)
}

fn solve_with(
    mesh: &Mesh,
    dir: &std::path::Path,
    job: &str,
    modes: usize,
    stresses: bool,
    keep: bool,
) -> Result<Solved, Error> {
    let mut s = solve_deck(mesh, &mesh.frequency_deck(modes, stresses), dir, job)?;
    if stresses {
        let (points, unfolded) = crate::stress::mid_surface(mesh, &mut s.frd)?;
        s.expanded = Some(points);
        if keep {
            s.unfolded = Some(unfolded);
        }
    }
    Ok(s)
}

/// Write `deck` (of `mesh`, with its output requests) as `<dir>/<job>.inp`, run ccx, and read
/// the modes and the node prints back.
pub fn solve_deck(
    mesh: &Mesh,
    deck: &crate::deck::Deck,
    dir: &std::path::Path,
    job: &str,
) -> Result<Solved, Error> {
    let text = deck.text();
    let deck = dir.join(format!("{job}.inp"));
    std::fs::write(&deck, text).map_err(Error::io(&deck))?;
    let run = crate::ccx::run(&deck)?;
    read_solved(mesh, run, job)
}

/// The results of a finished ccx `run` of `job` on `mesh`: its field file, its `.dat` and the
/// rigid parts' prints.
pub fn read_solved(mesh: &Mesh, run: crate::ccx::CcxRun, job: &str) -> Result<Solved, Error> {
    let read = |p: std::path::PathBuf| std::fs::read_to_string(&p).map_err(Error::io(p));
    let frd = crate::frd::parse(&read(run.frd())?).within(|| format!("{job}.frd"))?;
    let dat = read(run.dat())?;
    let prints = if mesh.rigid.is_empty() {
        Vec::new()
    } else {
        crate::dat::node_prints(&dat, "WD_PRINT").within(|| format!("{job}.dat"))?
    };
    Ok(Solved {
        run,
        frd,
        prints,
        dat,
        expanded: None,
        unfolded: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_fit_recovers_a_rigid_motion_and_leaves_undetermined_rotation_zero() {
        let mut m = Mesh::new("t");
        let ids: Vec<usize> = [
            [0.0, 0.0, 0.0],
            [0.1, 0.0, 0.0],
            [0.0, 0.2, 0.0],
            [0.0, 0.0, 0.3],
        ]
        .iter()
        .map(|p| m.node(*p))
        .collect();
        let (u0, th0) = ([1e-3, -2e-3, 0.5e-3], [0.01, -0.02, 0.03]);
        let w: HashMap<usize, [f64; 3]> = ids
            .iter()
            .map(|&id| (id, add(u0, cross(th0, m.nodes[id - 1]))))
            .collect();
        let (u, th, c) = rigid_fit(&m, &ids, &w).unwrap();
        let at_origin = add(u, cross(th, sub([0.0; 3], c)));
        for i in 0..3 {
            assert!((th[i] - th0[i]).abs() < 1e-14);
            assert!((at_origin[i] - u0[i]).abs() < 1e-15);
        }
        // Two nodes on the x axis: the rotation about x is not seen, so it is zero.
        let (_, th, _) = rigid_fit(&m, &ids[..2], &w).unwrap();
        assert!(
            th[0].abs() < 1e-15 && (th[2] - th0[2]).abs() < 1e-14,
            "{th:?}"
        );
    }
}
