//! Modal stresses for recovery (the seed paper's Figure 12): ccx's stresses of each kept mode
//! at the surfaces. ccx's 2-D output (`*NODE FILE, OUTPUT=2D`) gives the shapes at the
//! mid-surface nodes, but its 2-D stress is the mid-surface stress, which for a shell in bending
//! is nearly zero (a cantilever S8R: sigma_xx 3e-4 Pa at the root against 6 MPa on its faces).
//! So a body whose stresses are recovered is solved once with 3-D output: ccx's expanded shells
//! and beams (20-node bricks under the original element numbers), whose face nodes carry the
//! surface stresses. Each expanded node belongs to the nearest node of its original element (a
//! shell node's faces, a beam node's section corners; solids are not expanded), and the shape
//! at an original node is the mean of its expanded nodes over the thickness (`mid_surface`),
//! as ccx's own 2-D output forms it.

use crate::error::PipelineError;
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

/// Original node -> expanded nodes, by element: each node of ccx's element `k` goes to the
/// nearest node of our element `k` (numbered as `Mesh::model_deck` numbers them).
pub fn associate(mesh: &Mesh, frd: &Frd) -> Result<HashMap<usize, Vec<usize>>, PipelineError> {
    let ours: Vec<&Vec<usize>> = mesh.parts.iter().flat_map(|p| &p.elements).collect();
    let coords: HashMap<usize, [f64; 3]> = frd.nodes.iter().copied().collect();
    let mut out: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, exp) in &frd.elements {
        let orig = ours
            .get(k - 1)
            .ok_or(PipelineError::UnknownElement { element: *k })?;
        for n in exp {
            let owner = if orig.contains(n) {
                *n
            } else {
                let x = coords
                    .get(n)
                    .ok_or(PipelineError::NoCoordinates { node: *n })?;
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

/// Replace the expanded nodes' displacements of a 3-D solve (every mode and static step of
/// `frd`) by the original nodes' and return which expanded nodes each original node has. As
/// ccx's own 2-D output forms them, found by comparing the two: a shell corner's three nodes
/// through the thickness (faces and middle) weigh 1, 4, 1 and a shell mid-side's two faces 1, 1
/// (the mean over the thickness of a quadratic and a linear field); a beam node is the mean of
/// its section's four corners (an end node's four mid-edge nodes left out); a solid's node is
/// its own. Measured against ccx's 2-D output: 2.1e-6 relative on the tub's 110 modes (the
/// last printed digit; the plain mean of a shell corner's three was 1e-4 off on its 2 kHz
/// modes), and on the cabinet's beams (the plain mean of eight 1e-4 off).
///
/// Returns the expanded nodes of each original node, and the 3-D displacements it replaced
/// (every node ccx wrote, per mode and per static step), which a spinning body's geometric
/// stiffness integrates over ccx's bricks (`prestress.rs`).
pub fn mid_surface(
    mesh: &Mesh,
    frd: &mut Frd,
) -> Result<(HashMap<usize, Vec<usize>>, Unfolded), PipelineError> {
    let points = associate(mesh, frd)?;
    let coords: HashMap<usize, [f64; 3]> = frd.nodes.iter().copied().collect();
    // Per original node: (expanded node, weight); the middle node sits at the original node.
    let weights: Vec<(usize, Vec<(usize, f64)>)> = points
        .iter()
        .map(|(&orig, exp)| {
            let x0 = mesh.nodes[orig - 1];
            let dist: Vec<f64> = exp
                .iter()
                .map(|e| {
                    coords.get(e).map_or(f64::INFINITY, |p| {
                        (0..3).map(|i| (p[i] - x0[i]).powi(2)).sum()
                    })
                })
                .collect();
            let far = dist
                .iter()
                .copied()
                .filter(|v| v.is_finite())
                .fold(0.0, f64::max);
            let at_node = |d: f64| d < 1e-4 * far;
            let middle = exp.len() > 1 && dist.iter().any(|d| at_node(*d));
            let mut sorted = dist.clone();
            sorted.sort_by(f64::total_cmp);
            let w = exp
                .iter()
                .zip(&dist)
                .map(|(e, &d)| {
                    let a = if middle {
                        // A shell corner: faces 1, middle 4.
                        if at_node(d) { 4.0 } else { 1.0 }
                    } else if exp.len() == 8 {
                        // A beam's end node: the section's four corners (the farthest), not
                        // its mid-edge nodes.
                        if d >= sorted[4] { 1.0 } else { 0.0 }
                    } else {
                        1.0
                    };
                    (*e, a)
                })
                .collect();
            (orig, w)
        })
        .collect();
    let original = mesh.nodes.len();
    let fold = |disp: &mut Vec<(usize, [f64; 3])>| -> Vec<(usize, [f64; 3])> {
        let by: HashMap<usize, [f64; 3]> = disp.iter().copied().collect();
        let mut out: Vec<(usize, [f64; 3])> = disp
            .iter()
            .filter(|(id, _)| *id <= original && !points.contains_key(id))
            .copied()
            .collect();
        for (orig, w) in &weights {
            let (mut u, mut sum) = ([0.0; 3], 0.0);
            for (e, a) in w {
                if let Some(v) = by.get(e) {
                    for x in 0..3 {
                        u[x] += a * v[x];
                    }
                    sum += a;
                }
            }
            if sum > 0.0 {
                out.push((*orig, u.map(|v| v / sum)));
            }
        }
        out.sort_unstable_by_key(|x| x.0);
        std::mem::replace(disp, out)
    };
    let unfolded = Unfolded {
        modes: frd.modes.iter_mut().map(|m| fold(&mut m.disp)).collect(),
        statics: frd.statics.iter_mut().map(fold).collect(),
    };
    Ok((points, unfolded))
}

/// A 3-D solve's displacements at all of ccx's nodes (expanded ones included), as it wrote
/// them: per mode and per static step, in file order.
#[derive(Clone, Debug, Default)]
pub struct Unfolded {
    pub modes: Vec<Vec<(usize, [f64; 3])>>,
    pub statics: Vec<Vec<(usize, [f64; 3])>>,
}

/// The stresses of the kept modes `kept` (selected from `frd`'s modes, in order) of the 3-D
/// solve that gave their shapes (`Mesh::frequency_deck(.., true)`, `mid_surface`'s `points`).
pub fn modal_stresses(
    frd: &Frd,
    points: HashMap<usize, Vec<usize>>,
    kept: &[Shapes],
    solve_s: f64,
) -> Result<ModalStress, PipelineError> {
    if frd.stresses.len() != frd.modes.len() {
        return Err(PipelineError::StressBlocks {
            blocks: frd.stresses.len(),
            cases: frd.modes.len(),
            what: "modes",
        });
    }
    let mut next = 0;
    let mut per_mode = Vec::with_capacity(kept.len());
    for s in kept {
        // `modal::select` copies the frequency of the mode it keeps: the same value.
        let i = (next..frd.modes.len())
            .find(|&i| frd.modes[i].frequency_hz == s.frequency_hz)
            .ok_or(PipelineError::NoModeAt { hz: s.frequency_hz })?;
        next = i + 1;
        per_mode.push(frd.stresses[i].iter().copied().collect());
    }
    Ok(ModalStress {
        points,
        per_mode,
        solve_s,
    })
}

/// The stresses of the correction modes, formed as their shapes are: ccx's 3-D static
/// solutions of the same load cases (on the same support), less the eigenmodes' share
/// (sum_k S_k (f_j . Phi_k) / omega_k^2, `Corrected::share`, with the eigenmodes' stresses
/// `eigen`), combined as the shapes (`Corrected::combination`). A free body's rigid motion
/// carries no stress.
pub fn correction_stresses(
    modes: &[Shapes],
    eigen: &ModalStress,
    c: &crate::correction::Corrected,
) -> Result<Vec<HashMap<usize, [f64; 6]>>, PipelineError> {
    let j = c.forces.len();
    if c.static_stresses.len() != j {
        return Err(PipelineError::StressBlocks {
            blocks: c.static_stresses.len(),
            cases: j,
            what: "load cases",
        });
    }
    let residual: Vec<HashMap<usize, [f64; 6]>> = c
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
