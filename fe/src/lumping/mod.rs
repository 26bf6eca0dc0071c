//! HRZ lumping (Hinton, Rock and Zienkiewicz; Cook, Malkus and Plesha, "Concepts and
//! Applications of Finite Element Analysis", 3rd ed., 1989, sec. 13.3): each element's nodal mass
//! is the diagonal of its consistent mass matrix, scaled so the element keeps its total mass. The
//! seed paper formed its elementary matrices with these masses; we use the consistent mass
//! (`consistent/mod.rs`) and keep HRZ for comparison.
//!
//! Point masses that belong to a rigid part are not lumped onto their nodes: they make up the
//! rigid part (mass, CoG, inertia), which enters the elementary matrices through the paper's
//! expansion with the part's rotation (ccx's ROT NODE). HRZ leaves out the rotary inertia of
//! shell and beam nodes (rho t^3 / 12 per area); the mass properties include it.
//!
//! The element integration it rests on (shape functions, Gauss points) is in `integration.rs`,
//! the mass properties in `mass_props.rs`; both are re-exported here.

mod integration;
mod mass_props;

pub use integration::{HEX20, Rule, det3, hex20, hex20_jacobian, quad8};
pub(crate) use integration::{gauss, section_axes};
pub use mass_props::{MassProps, add_point_inertia, consistent_mass_props, continuum_mass_props};

use crate::mesh::{Mesh, Section};

/// A rigid part's lumped inertia: mass, CoG and inertia tensor about the CoG (global axes).
#[derive(Clone, Debug, PartialEq)]
pub struct RigidLump {
    pub nset: String,
    pub ref_node: usize,
    pub rot_node: usize,
    pub mass: f64,
    pub cog: [f64; 3],
    pub inertia: [[f64; 3]; 3],
}

/// Nodal masses of a mesh plus its rigid parts.
#[derive(Clone, Debug, PartialEq)]
pub struct Lumped {
    /// kg per node, index = node id - 1 (0 for nodes without mass).
    pub node_mass: Vec<f64>,
    pub rigid: Vec<RigidLump>,
}

/// Consistent-mass diagonal (per unit density) and element volume of one element.
fn element_diag(mesh: &Mesh, section: &Section, nodes: &[usize]) -> (Vec<f64>, f64) {
    let (mut diag, mut vol) = (vec![0.0; nodes.len()], 0.0);
    gauss(mesh, section, nodes, Rule::Exact, |gp| {
        vol += gp.dv;
        for (k, nk) in gp.n.iter().enumerate() {
            diag[k] += nk * nk * gp.dv;
        }
    });
    (diag, vol)
}

/// The rigid parts of `mesh` (the point masses on each `*RIGID BODY` set as one mass, CoG and
/// inertia) and the other point masses, (node id, kg).
pub fn rigid_parts(mesh: &Mesh) -> (Vec<RigidLump>, Vec<(usize, f64)>) {
    let rigid_nodes: Vec<&[usize]> = mesh
        .rigid
        .iter()
        .map(|r| mesh.nsets.get(&r.nset).map_or(&[][..], |v| &v[..]))
        .collect();
    let mut rigid_points: Vec<Vec<(f64, [f64; 3])>> = vec![Vec::new(); mesh.rigid.len()];
    let mut free = Vec::new();
    for part in &mesh.parts {
        if let Section::Mass { kg } = part.section {
            for e in &part.elements {
                let id = e[0];
                match rigid_nodes.iter().position(|ns| ns.contains(&id)) {
                    Some(i) => rigid_points[i].push((kg, mesh.nodes[id - 1])),
                    None => free.push((id, kg)),
                }
            }
        }
    }
    let rigid = mesh
        .rigid
        .iter()
        .zip(rigid_points)
        .map(|(r, pts)| {
            let p = if pts.is_empty() {
                MassProps {
                    mass: 0.0,
                    cog: mesh.nodes[r.ref_node - 1],
                    inertia: [[0.0; 3]; 3],
                }
            } else {
                MassProps::of_points(pts.into_iter())
            };
            RigidLump {
                nset: r.nset.clone(),
                ref_node: r.ref_node,
                rot_node: r.rot_node,
                mass: p.mass,
                cog: p.cog,
                inertia: p.inertia,
            }
        })
        .collect();
    (rigid, free)
}

/// HRZ-lumped nodal masses and the rigid parts of `mesh`.
pub fn lump(mesh: &Mesh) -> Lumped {
    let mut node_mass = vec![0.0; mesh.nodes.len()];
    let (rigid, free) = rigid_parts(mesh);
    for (id, kg) in free {
        node_mass[id - 1] += kg;
    }
    for part in &mesh.parts {
        if part.section.material().is_none() {
            continue;
        }
        for e in &part.elements {
            let rho = part.section.material().map_or(0.0, |m| m.rho);
            let (diag, vol) = element_diag(mesh, &part.section, e);
            let sum: f64 = diag.iter().sum();
            if sum <= 0.0 {
                continue;
            }
            for (k, &id) in e.iter().enumerate() {
                node_mass[id - 1] += rho * vol * diag[k] / sum;
            }
        }
    }
    Lumped { node_mass, rigid }
}

impl Lumped {
    /// The whole lumped body's mass properties.
    pub fn mass_props(&self, mesh: &Mesh) -> MassProps {
        let nodes = self
            .node_mass
            .iter()
            .zip(&mesh.nodes)
            .filter(|(m, _)| **m > 0.0)
            .map(|(m, x)| (*m, *x));
        let mut p = MassProps::of_points(nodes);
        for r in &self.rigid {
            if r.mass > 0.0 {
                p = p.combine(&MassProps {
                    mass: r.mass,
                    cog: r.cog,
                    inertia: r.inertia,
                });
            }
        }
        p
    }
}

/// Total element mass by exact-rule integration of each element (no lumping), for checks.
pub fn element_mass(mesh: &Mesh) -> f64 {
    let mut m = 0.0;
    for part in &mesh.parts {
        for e in &part.elements {
            m += match part.section {
                Section::Mass { kg } => kg,
                _ => {
                    let rho = part.section.material().map_or(0.0, |m| m.rho);
                    rho * element_diag(mesh, &part.section, e).1
                }
            };
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Material;
    use washdyn_model::geom::f::norm;

    fn steel() -> Material {
        Material {
            name: "STEEL".into(),
            e: 210e9,
            nu: 0.3,
            rho: 7850.0,
        }
    }

    #[test]
    fn hrz_of_a_flat_quad8_gives_the_textbook_ratio() {
        // Cook et al. 1989, sec. 13.3: HRZ for the 8-node serendipity quad puts 3/76 of the mass
        // on each corner and 16/76 on each mid-side node.
        let mut m = Mesh::new("quad");
        let pts = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.5, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 0.5, 0.0],
        ];
        let ids: Vec<usize> = pts.iter().map(|p| m.node(*p)).collect();
        m.part(
            "S",
            Section::Shell {
                thickness: 0.01,
                material: steel(),
            },
        )
        .elements
        .push(ids);
        let l = lump(&m);
        let total = 7850.0 * 2.0 * 0.01;
        assert!((l.node_mass.iter().sum::<f64>() - total).abs() < 1e-12 * total);
        for k in 0..4 {
            assert!((l.node_mass[k] / total - 3.0 / 76.0).abs() < 1e-12);
            assert!((l.node_mass[4 + k] / total - 16.0 / 76.0).abs() < 1e-12);
        }
    }

    #[test]
    fn hrz_of_a_box_hex20_keeps_mass_and_centre_with_positive_masses() {
        // A 0.2 x 0.1 x 0.05 m steel box as one C3D20: the mass is exact and the CoG central;
        // unlike row-sum lumping (negative corner masses for C3D20), HRZ keeps every mass
        // positive.
        let (a, b, c) = (0.2, 0.1, 0.05);
        let mut m = Mesh::new("box");
        let ids: Vec<usize> = HEX20
            .iter()
            .map(|p| m.node([a / 2.0 * p[0], b / 2.0 * p[1], c / 2.0 * p[2]]))
            .collect();
        m.part("B", Section::Solid { material: steel() })
            .elements
            .push(ids);
        let l = lump(&m);
        assert!(l.node_mass.iter().all(|&v| v > 0.0));
        let p = l.mass_props(&m);
        let mass = 7850.0 * a * b * c;
        assert!((p.mass - mass).abs() < 1e-12 * mass);
        assert!(norm(p.cog) < 1e-15);
    }
}
