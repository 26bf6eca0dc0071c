//! Element integration (shape functions, Gauss points, mass properties) and HRZ lumping
//! (Hinton, Rock and Zienkiewicz; Cook, Malkus and Plesha, "Concepts and Applications of Finite
//! Element Analysis", 3rd ed., 1989, sec. 13.3): each element's nodal mass is the diagonal of its
//! consistent mass matrix, scaled so the element keeps its total mass. The seed paper formed its
//! elementary matrices with these masses; we use the consistent mass (`consistent.rs`) and keep
//! HRZ for comparison.
//!
//! Point masses that belong to a rigid part are not lumped onto their nodes: they make up the
//! rigid part (mass, CoG, inertia), which enters the elementary matrices through the paper's
//! expansion with the part's rotation (ccx's ROT NODE). HRZ leaves out the rotary inertia of
//! shell and beam nodes (rho t^3 / 12 per area); the mass properties include it.

use crate::mesh::{Mesh, Section};
use washdyn_runtime::geom::f::{cross, norm};

/// Gauss-Legendre points and weights on [-1, 1].
const G3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];
const G2: [(f64, f64); 2] = [
    (-0.577_350_269_189_625_8, 1.0),
    (0.577_350_269_189_625_8, 1.0),
];

/// Which Gauss points integrate an element's mass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// 3 per direction: exact for straight-edged elements (the HRZ diagonal).
    Exact,
    /// ccx's own points: its e_c3d.f integrates the mass at the stiffness's points, and S8R is
    /// expanded into C3D20R (2 x 2 x 2), so a shell's in-plane integral takes 2 x 2 points;
    /// C3D20 and B32 (expanded into C3D20) take 3 per direction. The consistent mass matrix
    /// (`consistent.rs`) must be the one ccx normalised its modes with.
    Ccx,
}

impl Rule {
    /// Points and weights along one direction of an element of `section`.
    pub(crate) fn points(self, section: &Section) -> &'static [(f64, f64)] {
        match (self, section) {
            (Rule::Ccx, Section::Shell { .. } | Section::ReducedSolid { .. }) => &G2,
            _ => &G3,
        }
    }
}

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

/// Determinant of a 3 x 3 matrix (the isoparametric Jacobian).
pub fn det3(a: [[f64; 3]; 3]) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// S8R serendipity shape functions and their (xi, eta) derivatives; corners counter-clockwise
/// from (-1, -1), then the mid-sides of edges 1-2, 2-3, 3-4, 4-1.
pub fn quad8(xi: f64, eta: f64) -> ([f64; 8], [[f64; 2]; 8]) {
    const C: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    const M: [(f64, f64); 4] = [(0.0, -1.0), (1.0, 0.0), (0.0, 1.0), (-1.0, 0.0)];
    let mut n = [0.0; 8];
    let mut d = [[0.0; 2]; 8];
    for (k, &(a, b)) in C.iter().enumerate() {
        let (p, q) = (1.0 + a * xi, 1.0 + b * eta);
        let s = a * xi + b * eta - 1.0;
        n[k] = 0.25 * p * q * s;
        d[k] = [0.25 * a * q * (s + p), 0.25 * b * p * (s + q)];
    }
    for (k, &(a, b)) in M.iter().enumerate() {
        if a == 0.0 {
            n[4 + k] = 0.5 * (1.0 - xi * xi) * (1.0 + b * eta);
            d[4 + k] = [-xi * (1.0 + b * eta), 0.5 * b * (1.0 - xi * xi)];
        } else {
            n[4 + k] = 0.5 * (1.0 + a * xi) * (1.0 - eta * eta);
            d[4 + k] = [0.5 * a * (1.0 - eta * eta), -eta * (1.0 + a * xi)];
        }
    }
    (n, d)
}

/// C3D20 natural coordinates of the nodes in ccx (Abaqus) order.
pub const HEX20: [[f64; 3]; 20] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];

/// C3D20 shape functions and derivatives at (xi, eta, zeta).
pub fn hex20(p: [f64; 3]) -> ([f64; 20], [[f64; 3]; 20]) {
    let mut n = [0.0; 20];
    let mut d = [[0.0; 3]; 20];
    for (k, c) in HEX20.iter().enumerate() {
        let f: [f64; 3] = std::array::from_fn(|i| 1.0 + c[i] * p[i]);
        match c.iter().position(|&v| v == 0.0) {
            None => {
                let s = c[0] * p[0] + c[1] * p[1] + c[2] * p[2] - 2.0;
                n[k] = 0.125 * f[0] * f[1] * f[2] * s;
                for i in 0..3 {
                    let (j, l) = ((i + 1) % 3, (i + 2) % 3);
                    d[k][i] = 0.125 * c[i] * f[j] * f[l] * (s + f[i]);
                }
            }
            Some(z) => {
                let (j, l) = ((z + 1) % 3, (z + 2) % 3);
                let g = 1.0 - p[z] * p[z];
                n[k] = 0.25 * g * f[j] * f[l];
                d[k][z] = -0.5 * p[z] * f[j] * f[l];
                d[k][j] = 0.25 * g * c[j] * f[l];
                d[k][l] = 0.25 * g * f[j] * c[l];
            }
        }
    }
    (n, d)
}

/// The C3D20 Jacobian d x / d (xi, eta, zeta) from the shape-function derivatives `d` and the
/// node positions `x(k)`.
pub fn hex20_jacobian(d: &[[f64; 3]; 20], x: impl Fn(usize) -> [f64; 3]) -> [[f64; 3]; 3] {
    let mut j = [[0.0; 3]; 3];
    for (k, dk) in d.iter().enumerate() {
        let xk = x(k);
        for r in 0..3 {
            for s in 0..3 {
                j[r][s] += dk[r] * xk[s];
            }
        }
    }
    j
}

/// One Gauss point of an element, as `gauss` visits it.
pub(crate) struct GaussPoint<'a> {
    /// Shape function values.
    pub n: &'a [f64],
    /// Shells: d N / d (xi, eta); beams: (d N / d xi, 0); solids: empty.
    pub dn: &'a [[f64; 2]],
    /// Position.
    pub x: [f64; 3],
    /// Volume weight, m^3 (shells times thickness, beams times section area).
    pub dv: f64,
    /// Shells: d x / d xi, d x / d eta; beams: d x / d xi, 0.
    pub tangents: [[f64; 3]; 2],
}

/// Visit the Gauss points of one element. `Rule::Exact` is exact for the mass of
/// straight-edged elements: 3 x 3 (S8R), 3 x 3 x 3 (C3D20), 3 (B32).
pub(crate) fn gauss(
    mesh: &Mesh,
    section: &Section,
    nodes: &[usize],
    rule: Rule,
    mut visit: impl FnMut(&GaussPoint),
) {
    let g = rule.points(section);
    let x = |k: usize| mesh.nodes[nodes[k] - 1];
    let at = |n: &[f64]| -> [f64; 3] {
        let mut p = [0.0; 3];
        for (k, nk) in n.iter().enumerate() {
            for i in 0..3 {
                p[i] += nk * x(k)[i];
            }
        }
        p
    };
    match section {
        Section::Shell { thickness, .. } => {
            for &(a, wa) in g {
                for &(b, wb) in g {
                    let (n, d) = quad8(a, b);
                    let mut t = [[0.0; 3]; 2];
                    for k in 0..8 {
                        for i in 0..3 {
                            t[0][i] += d[k][0] * x(k)[i];
                            t[1][i] += d[k][1] * x(k)[i];
                        }
                    }
                    visit(&GaussPoint {
                        n: &n,
                        dn: &d,
                        x: at(&n),
                        dv: norm(cross(t[0], t[1])) * wa * wb * thickness,
                        tangents: t,
                    });
                }
            }
        }
        Section::Solid { .. } | Section::ReducedSolid { .. } => {
            for &(a, wa) in g {
                for &(b, wb) in g {
                    for &(c, wc) in g {
                        let (n, d) = hex20([a, b, c]);
                        let j = hex20_jacobian(&d, x);
                        visit(&GaussPoint {
                            n: &n,
                            dn: &[],
                            x: at(&n),
                            dv: det3(j).abs() * wa * wb * wc,
                            tangents: [[0.0; 3]; 2],
                        });
                    }
                }
            }
        }
        Section::Beam { width, height, .. } => {
            for &(a, wa) in g {
                let n = [0.5 * a * (a - 1.0), 1.0 - a * a, 0.5 * a * (a + 1.0)];
                let dn = [[a - 0.5, 0.0], [-2.0 * a, 0.0], [a + 0.5, 0.0]];
                let mut t = [0.0; 3];
                for k in 0..3 {
                    for i in 0..3 {
                        t[i] += dn[k][0] * x(k)[i];
                    }
                }
                visit(&GaussPoint {
                    n: &n,
                    dn: &dn,
                    x: at(&n),
                    dv: norm(t) * wa * width * height,
                    tangents: [t, [0.0; 3]],
                });
            }
        }
        Section::Mass { .. } | Section::Ground { .. } => {}
    }
}

/// The through-section second moments of a shell or beam at a Gauss point, per unit volume:
/// (axis e, k^2) with sum_sections int r r^T dA / A = sum e e^T k^2: a shell's normal with
/// t^2 / 12; a beam's section axes p (along `normal`, `width`) and q with width^2 / 12 and
/// height^2 / 12. The material at a distance from the mid-surface or axis: what ccx's
/// expanded 3-D elements carry beyond the reference surface's translations.
pub(crate) fn section_axes(section: &Section, gp: &GaussPoint) -> Vec<([f64; 3], f64)> {
    match section {
        Section::Shell { thickness, .. } => {
            let c = cross(gp.tangents[0], gp.tangents[1]);
            let l = norm(c);
            vec![(c.map(|v| v / l), thickness * thickness / 12.0)]
        }
        Section::Beam {
            width,
            height,
            normal,
            ..
        } => {
            let (p, q) = beam_axes(gp.tangents[0], *normal);
            vec![(p, width * width / 12.0), (q, height * height / 12.0)]
        }
        _ => Vec::new(),
    }
}

/// A beam's section axes at tangent `t`: p = `normal` made normal to t (ccx's 1-direction),
/// q = t x p.
pub(crate) fn beam_axes(t: [f64; 3], normal: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let l = norm(t);
    let t = t.map(|v| v / l);
    let d = normal[0] * t[0] + normal[1] * t[1] + normal[2] * t[2];
    let p: [f64; 3] = std::array::from_fn(|i| normal[i] - d * t[i]);
    let lp = norm(p);
    let p = p.map(|v| v / lp);
    (p, cross(t, p))
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

    fn steel() -> Material {
        Material {
            name: "STEEL".into(),
            e: 210e9,
            nu: 0.3,
            rho: 7850.0,
        }
    }

    #[test]
    fn shape_functions_partition_unity_and_interpolate_nodes() {
        let (n, d) = quad8(0.3, -0.6);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        assert!(d.iter().map(|v| v[0]).sum::<f64>().abs() < 1e-14);
        let (n, d) = hex20([0.2, -0.7, 0.4]);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        for i in 0..3 {
            assert!(d.iter().map(|v| v[i]).sum::<f64>().abs() < 1e-14);
        }
        for (k, c) in HEX20.iter().enumerate() {
            let (n, _) = hex20(*c);
            for (j, v) in n.iter().enumerate() {
                assert!((v - if j == k { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
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
