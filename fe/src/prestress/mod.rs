//! The geometric (stress) stiffness of a spinning body, assembled by us from ccx's static
//! centrifugal stresses.
//!
//! One ccx `*STATIC` solve carries the centrifugal load at the reference speed: `CENTRIF` on
//! every element with density, and on every point mass (`MASS` element) its own centrifugal
//! force m Omega^2 r_perp as a `*CLOAD` at its node (where the mass sits, also when the node
//! belongs to a rigid part). ccx prints the stresses at its integration points (`*EL PRINT,
//! GLOBAL=YES`) of the 3-D elements it solved: the C3D20R bricks it expands the shells into,
//! the beams' bricks, our own C3D20 and C3D20R solids; the `.frd` gives those bricks' nodes and
//! coordinates. Over each brick and Gauss point (ccx's own rule: 2 x 2 x 2 for C3D20R,
//! 3 x 3 x 3 for C3D20)
//!
//!   K_G(a, b) = (grad N_a)^T sigma (grad N_b) w det J  times the 3 x 3 identity,
//!
//! and projected on mode shapes at the same (expanded) nodes: K_G,kl = sum over Gauss points of
//! w det J sum_i (grad u_k,i)^T sigma (grad u_l,i), u_k,i the i-th component of mode k. This is
//! what ccx adds in a `*FREQUENCY` perturbation step after the same static step (its K_sigma),
//! up to the truncation to the kept modes. The stresses are ccx's own at its integration points
//! (7 digits in the `.dat`); its nodal stresses of the `.frd` (extrapolated, averaged between
//! elements) interpolated to the same points change the drum's K_G entries by up to 4.6e-3 of
//! the diagonal and its frequencies at 1400 rpm by up to 1.3e-4 (measured once).
//!
//! ccx's perturbation stiffness also changes the material stiffness about the deformed state
//! (sym(F0^T grad u) : C : sym(F0^T grad u), F0 = E + grad u0: e_c3d.f, wcoef.f). Its part
//! linear in the static displacement u0 (so in Omega^2), K_u, is assembled beside K_G
//! (`Prestress::stiffness`) and reported, not put in the modal data: on the thin drum sheets
//! grad u0 through the thickness comes from differences of the .frd's 6-digit displacements,
//! which split the drum's degenerate pairs by up to 1.4e-4; with it the reduced drum matches
//! ccx's prestressed frequencies as the old fit to its prestressed modes did (1.85e-3 worst of
//! the 10 kept modes at 1400 rpm; 3.2e-3 without). Its part quadratic in grad u0 is not in
//! ccx's answer as measured (it would move the brick drum's frequencies by 1.3e-2).
//!
//! A rigid part (`*RIGID BODY`) has no stress: the loads its point masses put on it make a
//! stiffness of their own, that of the part's second-order motion 0.5 theta x (theta x rho)
//! under them: theta^T [sum (F . rho) E - sym(F rho^T)] theta (rho from the REF node). It is the
//! K_G a stiff continuum carrying the same loads would have (the integral of its stress is
//! sum rho F^T), and it makes a rigid part's turning about the spin axis cost no energy against
//! its spin softening, as it must (`rigid_parts`). ccx 2.20's perturbation step has neither
//! this term nor the point masses' spin softening (measured: a beam with a rigid 4-mass disc
//! at its tip has the same prestressed frequencies with and without their loads), so the
//! comparison with ccx leaves both out (`point_mass_softening`).

mod gauss;
pub mod hex20;
#[cfg(test)]
mod tests;

use crate::deck::Deck;
use crate::error::{Error, PipelineError, Within};
use crate::mesh::{Mesh, Section};
use gauss::GaussSums;
use nalgebra::DMatrix;
use std::collections::HashMap;
use washdyn_model::geom::f::{dot, sub, unit};

/// Element set of every element with density: the centrifugal load and the stresses.
pub const LOADED: &str = "WD_SPIN";

/// The centrifugal field: speed (rad/s) about the unit `axis` through `axis_point`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Centrifugal {
    pub omega: f64,
    pub axis_point: [f64; 3],
    pub axis: [f64; 3],
}

impl Centrifugal {
    pub fn new(omega: f64, axis_point: [f64; 3], axis: [f64; 3]) -> Centrifugal {
        Centrifugal {
            omega,
            axis_point,
            axis: unit(axis),
        }
    }
    /// (E - e e^T) (x - axis_point): the distance vector from the axis.
    pub fn off_axis(&self, x: [f64; 3]) -> [f64; 3] {
        let r = sub(x, self.axis_point);
        let along = dot(r, self.axis);
        std::array::from_fn(|i| r[i] - along * self.axis[i])
    }
    /// The centrifugal force on `kg` at `x`, N.
    pub fn force(&self, kg: f64, x: [f64; 3]) -> [f64; 3] {
        self.off_axis(x).map(|r| kg * self.omega * self.omega * r)
    }
}

/// Every point mass's centrifugal force at its node (masses on one node summed), by node id.
pub fn point_mass_loads(mesh: &Mesh, c: &Centrifugal) -> Vec<(usize, [f64; 3])> {
    let mut out: Vec<(usize, [f64; 3])> = Vec::new();
    for part in &mesh.parts {
        let Section::Mass { kg } = part.section else {
            continue;
        };
        for e in &part.elements {
            let f = c.force(kg, mesh.nodes[e[0] - 1]);
            match out.iter_mut().find(|(id, _)| *id == e[0]) {
                Some((_, v)) => (0..3).for_each(|i| v[i] += f[i]),
                None => out.push((e[0], f)),
            }
        }
    }
    out.sort_unstable_by_key(|x| x.0);
    out
}

/// Define the element set `LOADED` in `d` (model data: before the first step).
pub fn loaded_set(d: &mut Deck, mesh: &Mesh) {
    let loaded: Vec<&str> = mesh
        .parts
        .iter()
        .filter(|p| p.section.material().is_some())
        .map(|p| p.name.as_str())
        .collect();
    d.line(&format!("*ELSET, ELSET={LOADED}"));
    for chunk in loaded.chunks(8) {
        d.line(&chunk.join(", "));
    }
}

/// Write a step's centrifugal loads at `c` (the deck has `loaded_set`): the `*DLOAD` `CENTRIF`
/// on `LOADED` and the point masses' `*CLOAD`s. Returns the `*DLOAD` data line (a perturbation
/// step repeats it for ccx's spin softening).
pub fn write_loads(d: &mut Deck, mesh: &Mesh, c: &Centrifugal) -> String {
    let e = c.axis;
    let p = c.axis_point;
    let dload = format!(
        "{LOADED}, CENTRIF, {:e}, {:e}, {:e}, {:e}, {:e}, {:e}, {:e}",
        c.omega * c.omega,
        p[0],
        p[1],
        p[2],
        e[0],
        e[1],
        e[2]
    );
    d.line("*DLOAD").line(&dload);
    let masses = point_mass_loads(mesh, c);
    if !masses.is_empty() {
        d.line("*CLOAD");
        for (id, f) in masses {
            for (k, v) in f.iter().enumerate() {
                if *v != 0.0 {
                    d.line(&format!("{id}, {}, {v:.12e}", k + 1));
                }
            }
        }
    }
    dload
}

/// The static deck of the centrifugal prestress: one `*STATIC` step with the loads of
/// `write_loads`, ccx's 3-D nodes and bricks (`*NODE FILE` / `U`, with the nodal stresses
/// `*EL FILE` / `S` for a look in a viewer) and the stresses at the integration points in the
/// `.dat`, in global axes.
pub fn deck(mesh: &Mesh, c: &Centrifugal) -> Deck {
    let mut d = mesh.model_deck();
    loaded_set(&mut d, mesh);
    d.line("*STEP").line("*STATIC");
    write_loads(&mut d, mesh, c);
    d.line("*NODE FILE")
        .line("U")
        .line("*EL FILE")
        .line("S")
        .line(&format!("*EL PRINT, ELSET={LOADED}, GLOBAL=YES"))
        .line("S")
        .line("*END STEP");
    d
}

/// One brick of ccx's 3-D model with its prestress.
#[derive(Clone, Debug)]
pub struct Brick {
    /// ccx's element number (an expanded shell or beam keeps its own).
    pub number: usize,
    /// Nodes in ccx's order (`hex20::NODES`).
    pub nodes: [usize; 20],
    /// Stress (xx, yy, zz, xy, yz, zx) at each Gauss point, in ccx's order, Pa.
    pub stress: Vec<[f64; 6]>,
    /// Lame's constants (lambda, mu) of its material, Pa.
    pub lame: (f64, f64),
}

/// The prestressed body at the reference speed.
#[derive(Clone, Debug)]
pub struct Prestress {
    pub centrifugal: Centrifugal,
    pub bricks: Vec<Brick>,
    /// Coordinates of the bricks' nodes.
    pub coords: HashMap<usize, [f64; 3]>,
    /// The static displacement at the bricks' nodes, m.
    pub u0: HashMap<usize, [f64; 3]>,
    /// The point masses' loads (`point_mass_loads`).
    pub loads: Vec<(usize, [f64; 3])>,
    /// ccx's wall time, s.
    pub solve_s: f64,
}

/// ccx's 20-node bricks among the elements of an `.frd` (3-D output), nodes in ccx's order,
/// by element number.
pub fn bricks_of(elements: &[(usize, Vec<usize>)]) -> HashMap<usize, [usize; 20]> {
    elements
        .iter()
        .filter(|(_, n)| n.len() == 20)
        .map(|(k, n)| (*k, std::array::from_fn(|a| n[hex20::FRD_ORDER[a]])))
        .collect()
}

impl Prestress {
    /// Read ccx's answer to `deck`: the `.frd`'s bricks and nodes, the `.dat`'s stresses.
    pub fn read(
        c: &Centrifugal,
        mesh: &Mesh,
        frd: &crate::frd::Frd,
        dat: &str,
        solve_s: f64,
    ) -> Result<Prestress, Error> {
        let all = bricks_of(&frd.elements);
        // Our element k (numbered as `Mesh::model_deck` numbers them) is ccx's k.
        let lame: Vec<Option<(f64, f64)>> = mesh
            .parts
            .iter()
            .flat_map(|p| {
                let l = p.section.material().map(|m| {
                    let mu = m.e / (2.0 * (1.0 + m.nu));
                    (2.0 * mu * m.nu / (1.0 - 2.0 * m.nu), mu)
                });
                std::iter::repeat_n(l, p.elements.len())
            })
            .collect();
        let stresses = crate::dat::element_stresses(dat, LOADED)?;
        if stresses.is_empty() {
            return Err(PipelineError::NoPrestress { set: LOADED }.into());
        }
        let mut bricks = Vec::with_capacity(stresses.len());
        for (number, stress) in stresses {
            let nodes = *all
                .get(&number)
                .ok_or(PipelineError::NotABrick { element: number })?;
            if hex20::rule_of(stress.len()).is_none() {
                return Err(PipelineError::IntegrationPoints {
                    element: number,
                    points: stress.len(),
                }
                .into());
            }
            let lame = lame
                .get(number - 1)
                .copied()
                .flatten()
                .ok_or(PipelineError::NoMaterial { element: number })?;
            bricks.push(Brick {
                number,
                nodes,
                stress,
                lame,
            });
        }
        let used: std::collections::HashSet<usize> = bricks.iter().flat_map(|b| b.nodes).collect();
        let coords: HashMap<usize, [f64; 3]> = frd
            .nodes
            .iter()
            .filter(|(id, _)| used.contains(id))
            .copied()
            .collect();
        if coords.len() != used.len() {
            return Err(PipelineError::LacksCoordinates.into());
        }
        let u0: HashMap<usize, [f64; 3]> = frd
            .statics
            .first()
            .ok_or(PipelineError::NoStatics)?
            .iter()
            .filter(|(id, _)| used.contains(id))
            .copied()
            .collect();
        if u0.len() != used.len() {
            return Err(PipelineError::LacksStatics.into());
        }
        Ok(Prestress {
            centrifugal: *c,
            bricks,
            coords,
            u0,
            loads: point_mass_loads(mesh, c),
            solve_s,
        })
    }

    /// Fails unless ccx's 3-D model of another solve of the same mesh (its `.frd`'s elements)
    /// has the same bricks with the same nodes: shapes at its nodes can then be integrated over
    /// these bricks.
    pub fn same_bricks(
        &self,
        elements: &[(usize, Vec<usize>)],
        what: &str,
    ) -> Result<(), PipelineError> {
        let theirs = bricks_of(elements);
        for b in &self.bricks {
            if theirs.get(&b.number) != Some(&b.nodes) {
                return Err(PipelineError::OtherExpansion {
                    what: what.to_string(),
                    element: b.number,
                });
            }
        }
        Ok(())
    }

    /// The geometric stiffness projected on `shapes` (each its displacements at ccx's 3-D
    /// nodes, every node of every brick), at the reference speed (divide by its Omega^2 for
    /// per Omega^2), n x n and symmetric, in two parts:
    /// - the stress stiffness, sum w det J (grad u_k)^T sigma (grad u_l);
    /// - the initial-displacement stiffness to first order in the static displacement u0,
    ///   sum w det J [e_k : C : sym(G0^T grad u_l) + sym(G0^T grad u_k) : C : e_l], e = sym(grad u),
    ///   G0 = grad u0: the change of the material stiffness about the deformed state
    ///   (sym(F0^T grad u) : C : sym(F0^T grad u), F0 = E + G0, as ccx's perturbation step forms
    ///   it, e_c3d.f with wcoef.f) that is linear in Omega^2.
    pub fn stiffness(
        &self,
        shapes: &[&[(usize, [f64; 3])]],
    ) -> Result<(DMatrix<f64>, DMatrix<f64>), PipelineError> {
        let (rows, u) = self.shapes_at_nodes(shapes)?;
        let stride = 3 * shapes.len();
        let mut sums = GaussSums::new(shapes.len());
        let mut local = vec![0.0; 20 * stride];
        for brick in &self.bricks {
            let x: [[f64; 3]; 20] = std::array::from_fn(|i| self.coords[&brick.nodes[i]]);
            let u0: [[f64; 3]; 20] = std::array::from_fn(|i| self.u0[&brick.nodes[i]]);
            for (i, id) in brick.nodes.iter().enumerate() {
                let r = rows[id];
                local[i * stride..(i + 1) * stride]
                    .copy_from_slice(&u[r * stride..(r + 1) * stride]);
            }
            let rule = hex20::rule_of(brick.stress.len()).expect("checked on reading");
            for ((p, w), s) in rule.iter().zip(&brick.stress) {
                let (g, det) = hex20::spatial_gradient(&x, *p).ok_or(PipelineError::Jacobian {
                    element: brick.number,
                })?;
                sums.point(&g, w * det, s, &u0, &local, brick.lame);
            }
        }
        Ok(sums.finish())
    }

    /// `shapes` gathered by node: the rows of the bricks' nodes (node id -> row) and u, where
    /// u[row * 3n + 3k + c] is component c of shape k at the row's node. Fails if a shape
    /// lacks a node.
    fn shapes_at_nodes(
        &self,
        shapes: &[&[(usize, [f64; 3])]],
    ) -> Result<(HashMap<usize, usize>, Vec<f64>), PipelineError> {
        let rows: HashMap<usize, usize> = self
            .coords
            .keys()
            .enumerate()
            .map(|(i, id)| (*id, i))
            .collect();
        let stride = 3 * shapes.len();
        let mut u = vec![f64::NAN; rows.len() * stride];
        for (k, s) in shapes.iter().enumerate() {
            for (id, v) in s.iter() {
                if let Some(&r) = rows.get(id) {
                    u[r * stride + 3 * k..r * stride + 3 * k + 3].copy_from_slice(v);
                }
            }
        }
        if let Some(i) = u.iter().position(|v| v.is_nan()) {
            let id = rows.iter().find(|(_, r)| **r == i / stride).map(|x| *x.0);
            return Err(PipelineError::NoDisplacement {
                shape: (i % stride) / 3,
                node: id,
            });
        }
        Ok((rows, u))
    }
}

/// The rigid parts' geometric stiffness on `modes` (n x n): per part, the loads of its point
/// masses (`loads`, at the reference speed) acting through its rotation theta (the ROT NODE's):
/// theta_k^T [sum (F . rho) E - sym(F rho^T)] theta_l, rho from the part's REF node.
pub fn rigid_parts(
    mesh: &Mesh,
    loads: &[(usize, [f64; 3])],
    modes: &[crate::modal::Shapes],
) -> Result<DMatrix<f64>, PipelineError> {
    let n = modes.len();
    let mut k = DMatrix::<f64>::zeros(n, n);
    for r in &mesh.rigid {
        let members = mesh.nsets.get(&r.nset).map_or(&[][..], |v| &v[..]);
        let x0 = mesh.nodes[r.ref_node - 1];
        let mut kr = [[0.0; 3]; 3];
        for (id, f) in loads.iter().filter(|(id, _)| members.contains(id)) {
            let rho = sub(mesh.nodes[id - 1], x0);
            let fr = dot(*f, rho);
            for i in 0..3 {
                kr[i][i] += fr;
                for j in 0..3 {
                    kr[i][j] -= 0.5 * (f[i] * rho[j] + rho[i] * f[j]);
                }
            }
        }
        if kr.iter().flatten().all(|v| *v == 0.0) {
            continue;
        }
        let theta = modes
            .iter()
            .map(|m| {
                m.rot.get(&r.rot_node).copied().ok_or_else(|| {
                    let set = r.nset.clone();
                    PipelineError::NoRigidRotation { set }
                })
            })
            .collect::<Result<Vec<[f64; 3]>, PipelineError>>()?;
        for p in 0..n {
            for q in 0..n {
                let mut v = 0.0;
                for i in 0..3 {
                    for j in 0..3 {
                        v += theta[p][i] * kr[i][j] * theta[q][j];
                    }
                }
                k[(p, q)] += v;
            }
        }
    }
    Ok(k)
}

/// The point masses' spin softening per Omega^2 on `modes` (n x n): sum m (P w_k) . w_l at
/// their nodes, P = E - e e^T. Part of the elementary matrices' S_perp; ccx's perturbation step
/// leaves it out, so a comparison with ccx adds it back.
pub fn point_mass_softening(
    mesh: &Mesh,
    modes: &[crate::modal::Shapes],
    axis: [f64; 3],
) -> Result<DMatrix<f64>, PipelineError> {
    let e = unit(axis);
    let n = modes.len();
    let mut s = DMatrix::<f64>::zeros(n, n);
    for part in &mesh.parts {
        let Section::Mass { kg } = part.section else {
            continue;
        };
        for el in &part.elements {
            let w = modes
                .iter()
                .map(|m| {
                    let v =
                        *m.w.get(&el[0])
                            .ok_or(PipelineError::NoShapeAtPointMass { node: el[0] })?;
                    let along = dot(v, e);
                    Ok((v, std::array::from_fn(|i| v[i] - along * e[i])))
                })
                .collect::<Result<Vec<([f64; 3], [f64; 3])>, PipelineError>>()?;
            for p in 0..n {
                for q in 0..n {
                    s[(p, q)] += kg * dot(w[p].1, w[q].0);
                }
            }
        }
    }
    Ok(s)
}

/// Solve the prestress deck of `mesh` at `c` as `<dir>/<job>.inp` and read it.
pub fn solve(
    mesh: &Mesh,
    c: &Centrifugal,
    dir: &std::path::Path,
    job: &str,
) -> Result<(Prestress, crate::frd::Frd), Error> {
    let path = dir.join(format!("{job}.inp"));
    std::fs::write(&path, deck(mesh, c).text()).map_err(Error::io(&path))?;
    let run = crate::ccx::run(&path)?;
    let read = |p: std::path::PathBuf| std::fs::read_to_string(&p).map_err(Error::io(p));
    let frd = crate::frd::parse(&read(run.frd())?).within(|| format!("{job}.frd"))?;
    let dat = read(run.dat())?;
    let p = Prestress::read(c, mesh, &frd, &dat, run.wall_s).within(|| job.to_string())?;
    Ok((p, frd))
}
