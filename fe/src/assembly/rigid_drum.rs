//! The drum as the full-mesh deck carries it: rigid, its FE mass as six point masses with its
//! mass, CoG and inertia (`point_cloud`), its unbalance as a prescribed rotating force
//! (`unbalance_force`). Separate from the deck (`deck.rs`) as the two closed forms it relies on,
//! each with its test.

use nalgebra::{Complex, SymmetricEigen};
use washdyn_model::geom::f::cross;

/// Six point masses of total `mass` with CoG `cog` and inertia tensor `inertia` (about the
/// CoG): m / 6 at cog +- d_k e_k along the principal axes of the second moments J = tr(I) / 2 E
/// - I (J = sum m r r^T), with 2 (m / 6) d_k^2 = J_k.
pub fn point_cloud(mass: f64, cog: [f64; 3], inertia: [[f64; 3]; 3]) -> Vec<([f64; 3], f64)> {
    let tr = 0.5 * (inertia[0][0] + inertia[1][1] + inertia[2][2]);
    let j = nalgebra::Matrix3::from_fn(|a, b| if a == b { tr } else { 0.0 } - inertia[a][b]);
    let e = SymmetricEigen::new(j);
    let mut out = Vec::new();
    for k in 0..3 {
        let d = (3.0 * e.eigenvalues[k].max(0.0) / mass).sqrt();
        let v = e.eigenvectors.column(k);
        for s in [1.0, -1.0] {
            out.push((std::array::from_fn(|a| cog[a] + s * d * v[a]), mass / 6.0));
        }
    }
    out
}

/// The complex amplitude of an unbalance's force (N) at drum speed omega (rad/s), for
/// f(t) = Re[F e^{i phi}]: m (ratio omega)^2 (r0 - i e x r0), r0 its radius vector at angle 0
/// (`UnbalanceDef::motion`: radial = r0 cos + (e x r0) sin).
pub(super) fn unbalance_force(
    mass: f64,
    ratio: f64,
    e: [f64; 3],
    r0: [f64; 3],
    omega: f64,
) -> [Complex<f64>; 3] {
    let w2 = mass * (ratio * omega).powi(2);
    let t = cross(e, r0);
    std::array::from_fn(|a| Complex::new(w2 * r0[a], -w2 * t[a]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn point_cloud_reproduces_mass_cog_and_inertia() {
        let inertia = [[0.21, 0.01, -0.02], [0.01, 0.33, 0.0], [-0.02, 0.0, 0.32]];
        let cog = [-0.1, 0.01, 0.45];
        let pts = point_cloud(8.4, cog, inertia);
        let p = crate::lumping::MassProps::of_points(pts.iter().map(|(x, m)| (*m, *x)));
        assert!((p.mass - 8.4).abs() < 1e-12);
        for a in 0..3 {
            assert!((p.cog[a] - cog[a]).abs() < 1e-14);
            for b in 0..3 {
                assert!((p.inertia[a][b] - inertia[a][b]).abs() < 1e-13, "{a}{b}");
            }
        }
    }

    #[test]
    fn unbalance_force_turns_with_the_drum() {
        // r0 = +z at angle 0, axis +x: at phi = 90 deg the force points along -y (e x z = -y).
        let f = unbalance_force(0.6, 1.0, [1.0, 0.0, 0.0], [0.0, 0.0, 0.24], 10.0);
        let at = |phi: f64| -> [f64; 3] {
            std::array::from_fn(|a| (f[a] * Complex::from_polar(1.0, phi)).re)
        };
        let q = at(PI / 2.0);
        assert!(
            (q[1] + 0.6 * 0.24 * 100.0).abs() < 1e-12 && q[2].abs() < 1e-12,
            "{q:?}"
        );
        let z = at(0.0);
        assert!((z[2] - 14.4).abs() < 1e-12);
    }
}
