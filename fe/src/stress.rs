//! Modal stresses for recovery (the seed paper's Figure 12): ccx's stresses of each kept mode
//! at the surfaces. The modal data's shapes come from `*NODE FILE, OUTPUT=2D` (mid-surface
//! nodes), but 2-D stress output is the mid-surface stress, which for a shell in bending is
//! nearly zero (a cantilever S8R: sigma_xx 3e-4 Pa at the root against 6 MPa on its faces). So a
//! second solve of the same deck writes 3-D output: ccx's expanded shells and beams (20-node
//! bricks under the original element numbers), whose nodes lie on the faces. Each expanded node
//! belongs to the nearest node of its original element (a shell node's faces, a beam node's
//! section corners; solids are not expanded). Same deck, same eigenvectors; a mode whose
//! expanded displacements oppose the modal data's shapes is flipped.

use crate::frd::Frd;
use crate::mesh::Mesh;
use crate::modal::Shapes;
use std::collections::HashMap;

/// The stresses of the kept modes at the expanded nodes of each original node.
pub struct ModalStress {
    /// Original node id -> its expanded nodes (stress points).
    pub points: HashMap<usize, Vec<usize>>,
    /// Per kept mode: expanded node id -> (xx, yy, zz, xy, yz, zx), Pa per unit coordinate.
    pub per_mode: Vec<HashMap<usize, [f64; 6]>>,
    /// ccx's wall time, s.
    pub solve_s: f64,
}

/// Relative frequency window of one degenerate pair in the second solve.
const DEGENERATE: f64 = 1e-6;

/// The frequency deck of `mesh` writing 3-D displacements and stresses.
pub fn deck(mesh: &Mesh, modes: usize) -> crate::deck::Deck {
    let mut d = mesh.model_deck();
    d.line("*STEP")
        .line("*FREQUENCY")
        .line(&modes.to_string())
        .line("*NODE FILE")
        .line("U")
        .line("*EL FILE")
        .line("S")
        .line("*END STEP");
    d
}

/// Original node -> expanded nodes, by element: each node of ccx's element `k` goes to the
/// nearest node of our element `k` (numbered as `Mesh::model_deck` numbers them).
pub fn associate(mesh: &Mesh, frd: &Frd) -> Result<HashMap<usize, Vec<usize>>, String> {
    let ours: Vec<&Vec<usize>> = mesh.parts.iter().flat_map(|p| &p.elements).collect();
    let coords: HashMap<usize, [f64; 3]> = frd.nodes.iter().copied().collect();
    let mut out: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, exp) in &frd.elements {
        let orig = ours
            .get(k - 1)
            .ok_or_else(|| format!("ccx element {k} is not in the mesh"))?;
        for n in exp {
            let owner = if orig.contains(n) {
                *n
            } else {
                let x = coords
                    .get(n)
                    .ok_or_else(|| format!("expanded node {n} has no coordinates"))?;
                *orig
                    .iter()
                    .min_by(|a, b| {
                        let d = |id: usize| {
                            let p = mesh.nodes[id - 1];
                            (0..3).map(|i| (p[i] - x[i]).powi(2)).sum::<f64>()
                        };
                        d(**a).total_cmp(&d(**b))
                    })
                    .expect("elements have nodes")
            };
            let v = out.entry(owner).or_default();
            if !v.contains(n) {
                v.push(*n);
            }
        }
    }
    Ok(out)
}

/// Solve `mesh`'s deck with 3-D output (`<dir>/<job>.inp`, `solve_modes` eigenmodes) and
/// return the stresses of `kept` (matched by frequency, signs aligned with their shapes).
pub fn modal_stresses(
    mesh: &Mesh,
    dir: &std::path::Path,
    job: &str,
    solve_modes: usize,
    kept: &[Shapes],
) -> Result<ModalStress, String> {
    let crate::modal::Solved { run, frd, .. } =
        crate::modal::solve_deck(mesh, &deck(mesh, solve_modes), dir, job)?;
    if frd.stresses.len() != frd.modes.len() {
        return Err(format!(
            "{job}.frd: {} stress blocks for {} modes",
            frd.stresses.len(),
            frd.modes.len()
        ));
    }
    let points = associate(mesh, &frd)?;
    let mut per_mode = Vec::with_capacity(kept.len());
    for s in kept {
        // A degenerate pair (a body with 3-fold symmetry, as the drum's three arms and
        // lifters) may come out of the second solve turned within its plane: match the kept
        // shape by the least-squares combination of every mode at its frequency.
        let near: Vec<usize> = frd
            .modes
            .iter()
            .enumerate()
            .filter(|(_, m)| (m.frequency_hz - s.frequency_hz).abs() <= DEGENERATE * s.frequency_hz)
            .map(|(i, _)| i)
            .collect();
        if near.is_empty() {
            return Err(format!(
                "{job}: no mode at {} Hz in the 3-D solve (another deck?)",
                s.frequency_hz
            ));
        }
        let disp: Vec<HashMap<usize, [f64; 3]>> = near
            .iter()
            .map(|&i| frd.modes[i].disp.iter().copied().collect())
            .collect();
        let n = near.len();
        let (mut g, mut b, mut ww) = (
            nalgebra::DMatrix::<f64>::zeros(n, n),
            nalgebra::DVector::<f64>::zeros(n),
            0.0,
        );
        for (orig, exp) in &points {
            if let Some(w) = s.w.get(orig) {
                for e in exp {
                    let u: Vec<[f64; 3]> = match disp.iter().map(|d| d.get(e).copied()).collect() {
                        Some(u) => u,
                        None => continue,
                    };
                    ww += w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
                    for j in 0..n {
                        b[j] += (0..3).map(|x| w[x] * u[j][x]).sum::<f64>();
                        for k in 0..n {
                            g[(j, k)] += (0..3).map(|x| u[j][x] * u[k][x]).sum::<f64>();
                        }
                    }
                }
            }
        }
        let c = g.clone().cholesky().map(|ch| ch.solve(&b)).ok_or_else(|| {
            format!(
                "{job}: the modes at {} Hz have no displacement at the shape's nodes",
                s.frequency_hz
            )
        })?;
        let (dot, uu) = (c.dot(&b), (c.transpose() * &g * &c)[(0, 0)]);
        // The faces move with the mid-surface up to the rotation through the thickness: a
        // correlation far from 1 is another mode, not a sign or a turned pair.
        let corr = dot / (ww * uu).sqrt().max(f64::MIN_POSITIVE);
        if corr < 0.99 {
            return Err(format!(
                "{job}: mode at {} Hz correlates {corr:.3} with the modal data's (another solve?)",
                s.frequency_hz
            ));
        }
        // Mass-orthonormal modes of one pair: a unit combination is mass-normalised too.
        let c = c.normalize();
        let mut m: HashMap<usize, [f64; 6]> = HashMap::new();
        for (j, &i) in near.iter().enumerate() {
            for (id, v) in &frd.stresses[i] {
                let e = m.entry(*id).or_insert([0.0; 6]);
                for x in 0..6 {
                    e[x] += c[j] * v[x];
                }
            }
        }
        per_mode.push(m);
    }
    Ok(ModalStress {
        points,
        per_mode,
        solve_s: run.wall_s,
    })
}

/// The stresses of the correction modes, formed as their shapes are: ccx's 3-D static
/// solutions of the same load cases (on the same support), less the eigenmodes' share
/// (sum_k S_k (f_j . Phi_k) / omega_k^2, `Corrected::share`, with the eigenmodes' stresses
/// `eigen`), combined as the shapes (`Corrected::combination`). A free body's rigid motion
/// carries no stress.
pub fn correction_stresses(
    mesh: &Mesh,
    dir: &std::path::Path,
    job: &str,
    modes: &[Shapes],
    eigen: &ModalStress,
    c: &crate::correction::Corrected,
) -> Result<Vec<HashMap<usize, [f64; 6]>>, String> {
    let frd = crate::modal::solve_deck(
        mesh,
        &crate::correction::static_deck(mesh, &c.forces, &c.support, true),
        dir,
        job,
    )?
    .frd;
    let j = c.forces.len();
    if frd.static_stresses.len() != j {
        return Err(format!(
            "{job}.frd: {} stress blocks for {j} load cases",
            frd.static_stresses.len()
        ));
    }
    let residual: Vec<HashMap<usize, [f64; 6]>> = frd
        .static_stresses
        .iter()
        .enumerate()
        .map(|(col, block)| {
            let mut m: HashMap<usize, [f64; 6]> = block.iter().copied().collect();
            for (k, sk) in eigen.per_mode.iter().enumerate().take(modes.len()) {
                let a = c.share[(k, col)];
                for (id, v) in m.iter_mut() {
                    if let Some(s) = sk.get(id) {
                        for x in 0..6 {
                            v[x] -= a * s[x];
                        }
                    }
                }
            }
            m
        })
        .collect();
    Ok((0..c.combination.ncols())
        .map(|col| {
            let mut out: HashMap<usize, [f64; 6]> = HashMap::new();
            for (r, m) in residual.iter().enumerate() {
                let a = c.combination[(r, col)];
                for (id, v) in m {
                    let e = out.entry(*id).or_insert([0.0; 6]);
                    for x in 0..6 {
                        e[x] += a * v[x];
                    }
                }
            }
            out
        })
        .collect())
}

/// Von Mises stress of (xx, yy, zz, xy, yz, zx).
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let [xx, yy, zz, xy, yz, zx] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (xy * xy + yz * yz + zx * zx))
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn von_mises_of_textbook_states() {
        // Uniaxial: sigma; pure shear tau: sqrt(3) tau; hydrostatic: 0.
        assert!((von_mises(&[5.0, 0.0, 0.0, 0.0, 0.0, 0.0]) - 5.0).abs() < 1e-12);
        assert!((von_mises(&[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]) - 2.0 * 3f64.sqrt()).abs() < 1e-12);
        assert!(von_mises(&[7.0, 7.0, 7.0, 0.0, 0.0, 0.0]).abs() < 1e-12);
    }
}
