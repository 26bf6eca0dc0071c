//! Static correction (residual flexibility) modes. A point load bends a thin rail or panel
//! locally, and no eigenmode of an affordable basis holds that dent: the cabinet's 60 modes to
//! 86 Hz answer the springs' preloads 26-36 % short. ccx solves the body statically under a
//! unit force at each load point (the consistent nodal load of the modal point's rigid fit), the
//! eigenmodes' share is removed, Psi_r = Psi - sum_k Phi_k (f . Phi_k) / omega_k^2 (stiffness-
//! and consistent-mass-orthogonal to every eigenmode, exactly), and the residual shapes are
//! made orthonormal on their own: K_rr = Psi_r^T f (exact: K Psi = f) and M_rr over the HRZ
//! masses, as the rest of the modal data. The body needs a support (a free-free tub has no
//! static solution without inertia relief).

use crate::lumping::Lumped;
use crate::mesh::Mesh;
use crate::modal::{Shapes, elementary, point_reading};
use std::collections::HashMap;
use washdyn_runtime::ir::modal::{LoadCase, generalised_eigen};

/// The correction modes of a body and the eigenmodes' generalised forces of the load cases.
pub struct Corrected {
    /// Mass-normalised (HRZ) residual shapes, frequencies ascending.
    pub shapes: Vec<Shapes>,
    /// f_j . Phi_k, row k (eigenmode), column j (load case), row-major.
    pub participation: Vec<f64>,
    /// ccx's wall time for the static steps, s.
    pub solve_s: f64,
    /// The load cases' nodal forces.
    pub forces: Vec<Vec<(usize, [f64; 3])>>,
    /// Correction mode c = sum_j combination[(j, c)] Psi_r,j.
    pub combination: nalgebra::DMatrix<f64>,
}

/// The static deck of the load cases (one `*STATIC` step each), with 2-D displacement output,
/// or with 3-D displacements and stresses (`stress`).
pub fn static_deck(
    mesh: &Mesh,
    forces: &[Vec<(usize, [f64; 3])>],
    stress: bool,
) -> crate::deck::Deck {
    let mut d = mesh.model_deck();
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
            if !mesh.rigid.is_empty() {
                d.line("*NODE PRINT, NSET=WD_PRINT").line("U");
            }
        }
        d.line("*END STEP");
    }
    d
}

/// Nodal forces of a unit force `direction` at the modal point (`set`, `position`).
fn nodal_load(
    mesh: &Mesh,
    set: &str,
    position: [f64; 3],
    direction: [f64; 3],
) -> Result<Vec<(usize, [f64; 3])>, String> {
    Ok(point_reading(mesh, set, position)?
        .into_iter()
        .map(|(id, r)| {
            (
                id,
                std::array::from_fn(|d| (0..3).map(|a| r[a][d] * direction[a]).sum()),
            )
        })
        .collect())
}

fn dot(w: &HashMap<usize, [f64; 3]>, f: &[(usize, [f64; 3])]) -> f64 {
    f.iter()
        .map(|(id, v)| {
            w.get(id)
                .map_or(0.0, |u| u[0] * v[0] + u[1] * v[1] + u[2] * v[2])
        })
        .sum()
}

/// The correction modes for `loads` (points named in `points`) of `mesh` with eigenmodes
/// `modes`; the static deck is `<dir>/<job>.inp`.
pub fn correction_modes(
    mesh: &Mesh,
    lumped: &Lumped,
    modes: &[Shapes],
    points: &[(&str, [f64; 3])],
    loads: &[LoadCase],
    dir: &std::path::Path,
    job: &str,
) -> Result<Corrected, String> {
    let forces = loads
        .iter()
        .map(|l| {
            let p = points
                .iter()
                .find(|(n, _)| *n == l.point)
                .ok_or_else(|| format!("load case at `{}`: no such point", l.point))?;
            nodal_load(mesh, p.0, p.1, l.direction)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let d = static_deck(mesh, &forces, false);
    let solved = crate::modal::solve_deck(mesh, &d, dir, job)?;
    if solved.frd.statics.len() != loads.len() {
        return Err(format!(
            "{job}: ccx wrote {} static results for {} load cases",
            solved.frd.statics.len(),
            loads.len()
        ));
    }
    let rot_ids: Vec<usize> = mesh.rigid.iter().map(|r| r.rot_node).collect();
    let (n, j) = (modes.len(), loads.len());
    let w2: Vec<f64> = modes
        .iter()
        .map(|m| (2.0 * std::f64::consts::PI * m.frequency_hz).powi(2))
        .collect();
    let mut participation = vec![0.0; n * j];
    for (k, m) in modes.iter().enumerate() {
        for (c, f) in forces.iter().enumerate() {
            participation[k * j + c] = dot(&m.w, f);
        }
    }
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
        for (k, m) in modes.iter().enumerate() {
            let a = participation[k * j + c] / w2[k];
            for (id, u) in w.iter_mut() {
                if let Some(p) = m.w.get(id) {
                    for x in 0..3 {
                        u[x] -= a * p[x];
                    }
                }
            }
            for (id, u) in rot.iter_mut() {
                if let Some(p) = m.rot.get(id) {
                    for x in 0..3 {
                        u[x] -= a * p[x];
                    }
                }
            }
        }
        residual.push(Shapes {
            frequency_hz: 0.0,
            w,
            rot,
        });
    }
    let stiff = nalgebra::DMatrix::from_fn(j, j, |a, b| {
        0.5 * (dot(&residual[a].w, &forces[b]) + dot(&residual[b].w, &forces[a]))
    });
    let el = elementary(mesh, lumped, &residual)?;
    let mass = nalgebra::DMatrix::from_fn(j, j, |a, b| {
        (0..3).map(|x| el.g[x][x][a * j + b]).sum::<f64>()
    });
    let (x, lambda) = generalised_eigen(&mass, &stiff);
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
        solve_s: solved.run.wall_s,
        forces,
        combination: x,
    })
}
