//! Element integration: Gauss rules, the S8R, C3D20 and B32 shape functions, and the visit of
//! an element's Gauss points with their positions, volume weights and tangents. Separate from
//! the lumping (`lumping/mod.rs`) because everything that integrates over the mesh uses it: HRZ
//! lumping, the mass properties (`mass_props.rs`) and the consistent mass matrix
//! (`consistent/mod.rs`).

use crate::mesh::{Mesh, Section};
use washdyn_model::geom::f::{cross, norm};

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
    /// (`consistent/mod.rs`) must be the one ccx normalised its modes with.
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
