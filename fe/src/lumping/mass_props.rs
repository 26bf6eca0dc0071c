//! Mass, CoG and inertia: `MassProps` and how they combine, and the mass properties of the
//! continuous model from the element integrals. Separate from the lumping (`lumping/mod.rs`)
//! because they are the reference every mass model is checked against (ccx's `EMAS`, the HRZ
//! masses, the consistent mass matrix).

use super::{Rule, gauss, section_axes};
use crate::mesh::{Mesh, Section};

/// Mass, CoG and inertia tensor about the CoG.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProps {
    pub mass: f64,
    pub cog: [f64; 3],
    pub inertia: [[f64; 3]; 3],
}

impl MassProps {
    /// Of point masses `(m, x)`.
    pub fn of_points(points: impl Iterator<Item = (f64, [f64; 3])> + Clone) -> MassProps {
        let mass: f64 = points.clone().map(|(m, _)| m).sum();
        let mut cog = [0.0; 3];
        for (m, x) in points.clone() {
            for i in 0..3 {
                cog[i] += m * x[i] / mass;
            }
        }
        let mut inertia = [[0.0; 3]; 3];
        for (m, x) in points {
            let r = [x[0] - cog[0], x[1] - cog[1], x[2] - cog[2]];
            add_point_inertia(&mut inertia, m, r);
        }
        MassProps { mass, cog, inertia }
    }
    /// Two bodies as one, about their common CoG (parallel axes).
    pub fn combine(&self, o: &MassProps) -> MassProps {
        let mass = self.mass + o.mass;
        let cog: [f64; 3] =
            std::array::from_fn(|i| (self.mass * self.cog[i] + o.mass * o.cog[i]) / mass);
        let mut inertia = [[0.0; 3]; 3];
        for b in [self, o] {
            let r = [b.cog[0] - cog[0], b.cog[1] - cog[1], b.cog[2] - cog[2]];
            for i in 0..3 {
                for j in 0..3 {
                    inertia[i][j] += b.inertia[i][j];
                }
            }
            add_point_inertia(&mut inertia, b.mass, r);
        }
        MassProps { mass, cog, inertia }
    }
}

/// Add m (|r|^2 E - r r^T).
pub fn add_point_inertia(j: &mut [[f64; 3]; 3], m: f64, r: [f64; 3]) {
    let rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    for i in 0..3 {
        for k in 0..3 {
            j[i][k] += m * (if i == k { rr } else { 0.0 } - r[i] * r[k]);
        }
    }
}

/// The mass properties of the continuous (not lumped) model: element integrals of rho, rho x
/// and rho (x x^T + the section's own second moments) at ccx's Gauss points, plus every point
/// mass. What ccx's `EMAS` totals report.
pub fn consistent_mass_props(mesh: &Mesh) -> MassProps {
    mass_props_of(mesh, true)
}

/// The elements with density only, without point masses: what ccx's `EMAS` covers (it leaves
/// MASS elements out).
pub fn continuum_mass_props(mesh: &Mesh) -> MassProps {
    mass_props_of(mesh, false)
}

fn mass_props_of(mesh: &Mesh, points: bool) -> MassProps {
    let (mut m, mut s1, mut s2) = (0.0, [0.0; 3], [[0.0; 3]; 3]);
    let mut add = |dm: f64, p: [f64; 3], axes: &[([f64; 3], f64)]| {
        m += dm;
        for i in 0..3 {
            s1[i] += dm * p[i];
            for j in 0..3 {
                s2[i][j] += dm * p[i] * p[j];
                for (e, k2) in axes {
                    s2[i][j] += dm * k2 * e[i] * e[j];
                }
            }
        }
    };
    for part in &mesh.parts {
        let rho = part.section.material().map_or(0.0, |m| m.rho);
        for e in &part.elements {
            match part.section {
                Section::Mass { kg } if points => add(kg, mesh.nodes[e[0] - 1], &[]),
                Section::Mass { .. } => {}
                _ => gauss(mesh, &part.section, e, Rule::Ccx, |gp| {
                    add(rho * gp.dv, gp.x, &section_axes(&part.section, gp))
                }),
            }
        }
    }
    let cog = s1.map(|v| v / m);
    let mut inertia = [[0.0; 3]; 3];
    let c: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| s2[i][j] - m * cog[i] * cog[j]));
    let tr = c[0][0] + c[1][1] + c[2][2];
    for i in 0..3 {
        for j in 0..3 {
            inertia[i][j] = if i == j { tr } else { 0.0 } - c[i][j];
        }
    }
    MassProps {
        mass: m,
        cog,
        inertia,
    }
}
