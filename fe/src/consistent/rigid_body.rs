//! The mass matrix applied to rigid motions: the body's mass properties, the rigid inertia the
//! matrix itself implies, and the inertial load of a rigid motion (inertia relief, the rigid
//! part of a shape). Separate from the matrix (`mod.rs`) and from its products with mode shapes
//! (`elementary.rs`): these are what the correction modes and the checks against ccx's mass use.

use super::MassMatrix;
use crate::lumping::MassProps;
use crate::mesh::Mesh;
use washdyn_model::geom::f::{add, cross, sub};

impl MassMatrix {
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
    /// The inertial load M u of the rigid motion u(x) = v + omega x (x - centre): nodal forces
    /// at the rows, and per rigid part (REF NODE, force; ROT NODE, moment about the REF NODE).
    pub fn rigid_motion_load(
        &self,
        mesh: &Mesh,
        v: [f64; 3],
        omega: [f64; 3],
        centre: [f64; 3],
    ) -> Vec<(usize, [f64; 3])> {
        let u: [Vec<f64>; 3] = std::array::from_fn(|a| {
            self.ids
                .iter()
                .map(|id| add(v, cross(omega, sub(mesh.nodes[id - 1], centre)))[a])
                .collect()
        });
        self.load_of(mesh, &u, |r| {
            (add(v, cross(omega, sub(r.cog, centre))), omega)
        })
    }
}
