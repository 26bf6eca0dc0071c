//! A rigid body of its own on the ground frame, mass-normalised so that it joins subsystem 2
//! with M2 = E (constant, never factorised): xi = sqrt(m) x for the CoG's translation (global
//! axes) and xi = sqrt(J_k) theta_k for the small rotation about each principal axis k. Two
//! kinds share it:
//! - a friction damper's moving part (the seed paper's "two independent bodies"): two rotations
//!   about the axes normal to the rod (a rod has no torsion stiffness in its bearings; the
//!   torsion is left out as the massless element leaves it out);
//! - a counterweight on its bolts (issue 52): all three rotations about its principal axes.
//!   Its mass is constant whatever the drum's angle, so it belongs with M2 rather than with the
//!   drum-dependent M1; it meets the tub only through its joints' forces, as the cabinet does.
//!
//! Its markers' rows are those of rigid-body modes, so every element, the Jacobians and the
//! energy balance treat it as they treat a modal body's point.

use super::kinematics::ModalRows;
use crate::geom::{V, f};
use crate::ir::{Counterweight, MovingPart};
use crate::scalar::Scalar;

/// A rigid body with constant mass in subsystem 2.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidPart {
    /// Its first coordinate in q.
    pub start: usize,
    pub mass: f64,
    pub cog: [f64; 3],
    /// The rotation coordinates: each a unit axis and the inertia about it through the CoG
    /// (principal axes: the kinetic energy is |xi'|^2 / 2).
    pub rotations: Vec<([f64; 3], f64)>,
}

impl RigidPart {
    /// The moving part of a damper from `a` to `b`, its coordinates from `start`: three
    /// translations, two rotations about the rod's normals.
    pub fn new(p: &MovingPart, a: [f64; 3], b: [f64; 3], start: usize) -> Self {
        let [n1, n2] = f::normals(f::unit(f::sub(b, a)));
        RigidPart {
            start,
            mass: p.mass,
            cog: f::add(a, f::scale(f::sub(b, a), p.cog)),
            rotations: vec![(n1, p.inertia), (n2, p.inertia)],
        }
    }

    /// A counterweight, its coordinates from `start`: three translations, three rotations
    /// about its principal axes of inertia.
    pub fn counterweight(w: &Counterweight, start: usize) -> Self {
        let j = nalgebra::Matrix3::from_fn(|r, c| w.inertia[r][c]);
        let e = nalgebra::SymmetricEigen::new(j);
        let rotations = (0..3)
            .map(|k| {
                let v = e.eigenvectors.column(k);
                ([v[0], v[1], v[2]], e.eigenvalues[k])
            })
            .collect();
        RigidPart {
            start,
            mass: w.mass,
            cog: w.cog,
            rotations,
        }
    }

    /// Its number of coordinates.
    pub fn n(&self) -> usize {
        3 + self.rotations.len()
    }

    /// The rows of the point `p` (rest, global): the translation per unit coordinate
    /// (e_a / sqrt(m); n_k x (p - cog) / sqrt(J_k)) and the rotation (0; n_k / sqrt(J_k)).
    pub fn rows(&self, p: [f64; 3]) -> ModalRows {
        let sm = self.mass.sqrt();
        let r = f::sub(p, self.cog);
        let mut w = Vec::with_capacity(self.n());
        let mut phi = Vec::with_capacity(self.n());
        for a in 0..3 {
            let mut e = [0.0; 3];
            e[a] = 1.0 / sm;
            w.push(e);
            phi.push([0.0; 3]);
        }
        for &(n, j) in &self.rotations {
            let sj = j.sqrt();
            w.push(f::scale(f::cross(n, r), 1.0 / sj));
            phi.push(f::scale(n, 1.0 / sj));
        }
        ModalRows::new(self.start, w, phi)
    }

    /// Its own term in h: the weight on the translations, sqrt(m) g (its inertia is E in M2;
    /// it has no stiffness of its own).
    pub fn add<T: Scalar>(&self, g: V<T>, h: &mut [T]) {
        let sm = self.mass.sqrt();
        for a in 0..3 {
            h[self.start + a] += g.0[a] * sm;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rows are a rigid body's: a point's velocity from the coordinates' rates is
    /// v + omega x r, and the kinetic energy of the mass-normalised coordinates, |xi'|^2 / 2,
    /// is m |v|^2 / 2 + J |omega|^2 / 2 (the normals are orthonormal to the axis).
    #[test]
    fn rows_are_rigid_motion() {
        let mp = MovingPart {
            mass: 0.55,
            inertia: 1.7e-3,
            translational_stiffness: 5e5,
            cog: 0.3,
        };
        let (a, b) = ([0.18, 0.18, 0.20], [0.18, 0.27, 0.03]);
        let part = RigidPart::new(&mp, a, b, 0);
        let (n1, n2) = (part.rotations[0].0, part.rotations[1].0);
        let axis = f::unit(f::sub(b, a));
        for (x, y) in [(n1, n2), (n1, axis), (n2, axis)] {
            assert!(f::dot(x, y).abs() < 1e-15);
        }
        let xi = [0.3, -0.2, 0.5, 0.7, -0.4];
        let (v, om) = (
            [
                0.3 / 0.55f64.sqrt(),
                -0.2 / 0.55f64.sqrt(),
                0.5 / 0.55f64.sqrt(),
            ],
            f::add(
                f::scale(n1, 0.7 / 1.7e-3f64.sqrt()),
                f::scale(n2, -0.4 / 1.7e-3f64.sqrt()),
            ),
        );
        for p in [a, b, part.cog] {
            let rows = part.rows(p);
            let (w, phi) = rows.motion(&xi);
            let expect = f::add(v, f::cross(om, f::sub(p, part.cog)));
            for c in 0..3 {
                assert!((w.0[c] - expect[c]).abs() < 1e-14, "{p:?}");
                assert!((phi.0[c] - om[c]).abs() < 1e-14);
            }
        }
        let t: f64 = xi.iter().map(|x| x * x / 2.0).sum();
        let t_body = 0.55 * f::dot(v, v) / 2.0 + 1.7e-3 * f::dot(om, om) / 2.0;
        assert!((t - t_body).abs() < 1e-14 * t);
    }
}
