//! A rigid part of its own on the ground frame: a friction damper's moving part (the seed
//! paper's "two independent bodies"). Its coordinates are its small rigid motion about its rest
//! place, mass-normalised so that it joins subsystem 2 with M2 = E (constant, never factorised):
//! xi = sqrt(m) x for the CoG's translation (global axes) and xi = sqrt(J) theta for the
//! rotation about the two axes normal to the rod (a rod has no torsion stiffness in its
//! bearings; the torsion is left out as the massless element leaves it out). Its markers' rows
//! are those of rigid-body modes, so every element, the Jacobians and the energy balance treat
//! it as they treat a modal body's point.

use super::kinematics::ModalRows;
use crate::geom::{V, f};
use crate::ir::MovingPart;
use crate::scalar::Scalar;

/// A rigid body with constant mass in subsystem 2.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidPart {
    /// Its first coordinate in q.
    pub start: usize,
    pub mass: f64,
    /// About the CoG, about each of `normals`.
    pub inertia: f64,
    pub cog: [f64; 3],
    /// The rod's axis at rest (unit) and two unit normals to it (the rotation coordinates).
    pub axis: [f64; 3],
    pub normals: [[f64; 3]; 2],
}

impl RigidPart {
    /// Coordinates: three translations, two rotations.
    pub const N: usize = 5;

    /// The moving part of a damper from `a` to `b`, its coordinates from `start`.
    pub fn new(p: &MovingPart, a: [f64; 3], b: [f64; 3], start: usize) -> Self {
        let axis = f::unit(f::sub(b, a));
        // A normal: the global axis least aligned with the rod, made orthogonal.
        let k = (0..3)
            .min_by(|&i, &j| axis[i].abs().total_cmp(&axis[j].abs()))
            .expect("three axes");
        let mut e = [0.0; 3];
        e[k] = 1.0;
        let n1 = f::unit(f::cross(axis, e));
        let n2 = f::cross(axis, n1);
        RigidPart {
            start,
            mass: p.mass,
            inertia: p.inertia,
            cog: f::add(a, f::scale(f::sub(b, a), p.cog)),
            axis,
            normals: [n1, n2],
        }
    }

    /// The rows of the point `p` (rest, global): the translation per unit coordinate
    /// (e_a / sqrt(m); n_i x (p - cog) / sqrt(J)) and the rotation (0; n_i / sqrt(J)).
    pub fn rows(&self, p: [f64; 3]) -> ModalRows {
        let (sm, sj) = (self.mass.sqrt(), self.inertia.sqrt());
        let r = f::sub(p, self.cog);
        let mut w = Vec::with_capacity(Self::N);
        let mut phi = Vec::with_capacity(Self::N);
        for a in 0..3 {
            let mut e = [0.0; 3];
            e[a] = 1.0 / sm;
            w.push(e);
            phi.push([0.0; 3]);
        }
        for n in self.normals {
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
        let [n1, n2] = part.normals;
        for (x, y) in [(n1, n2), (n1, part.axis), (n2, part.axis)] {
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
