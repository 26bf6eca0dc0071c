//! One end of a friction damper whose moving part is a body of its own (`ir::MovingPart`, a
//! scene's `damper_mass.<name>`): the rubber bearing between a body (tub or cabinet) and the
//! part. The bearing is a rotary spring-damper about the axes normal to the rod, as in the
//! massless element, and here elastic in translation too (stiffness k, damping k D / C: the
//! rubber's ratio of the rotary law). At the rod's end (`Axial::Spring`) it holds the part in
//! every direction; at the housing (`Axial::Friction`) the part slides along the rod against the
//! arctan friction and the bearing holds it across the rod only.
//!
//! As k grows and the part's mass and inertia vanish, the part's two ends follow the two
//! bodies, its rotation becomes the rod's tilt and the two joints are the massless element
//! (tests/damper_mass.rs holds a run-up to that).

use super::{Element, friction_force};
use crate::equations::{Drive, Marker, MarkerDef, Wrench, rest_axis};
use crate::geom::V;
use crate::ir;
use crate::scalar::Scalar;

/// What holds the part along the rod at this end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Axial {
    /// The rubber bearing's translational stiffness (the rod's end).
    Spring,
    /// The housing's arctan friction (N, s/m).
    Friction { f_max: f64, slope: f64 },
}

#[derive(Clone, Debug, PartialEq)]
pub struct DamperJoint {
    pub name: String,
    /// On the body the damper is attached to.
    pub a: MarkerDef,
    /// On the damper's moving part, at the same rest point.
    pub b: MarkerDef,
    /// The rod's axis at rest (unit, from the damper's end a to its end b).
    pub n0: [f64; 3],
    /// Translational stiffness (N/m) and damping (N s/m).
    pub k: f64,
    pub c: f64,
    pub bearing_stiffness: f64,
    pub bearing_damping: f64,
    pub axial: Axial,
}

impl DamperJoint {
    /// The two joints of damper `d` with its moving part: at end a the rod's bearing (`body_a`
    /// on d.a's body, `part_a` on the part), at end b the housing (`body_b`, `part_b`).
    pub fn pair(
        d: &ir::FrictionDamper,
        (body_a, part_a): (MarkerDef, MarkerDef),
        (body_b, part_b): (MarkerDef, MarkerDef),
    ) -> [DamperJoint; 2] {
        let mp = d
            .moving_part
            .as_ref()
            .expect("checked: the damper has its part");
        let n0 = rest_axis(d.a.point, d.b.point);
        let k = mp.translational_stiffness;
        let c = if d.bearing_stiffness > 0.0 {
            k * d.bearing_damping / d.bearing_stiffness
        } else {
            0.0
        };
        let joint = |name: String, a, b, axial| DamperJoint {
            name,
            a,
            b,
            n0,
            k,
            c,
            bearing_stiffness: d.bearing_stiffness,
            bearing_damping: d.bearing_damping,
            axial,
        };
        [
            joint(format!("{}.rod", d.name), body_a, part_a, Axial::Spring),
            joint(
                format!("{}.housing", d.name),
                body_b,
                part_b,
                Axial::Friction {
                    f_max: d.f_max,
                    slope: d.slope,
                },
            ),
        ]
    }
}

impl Element for DamperJoint {
    const ELASTIC: bool = true;
    const DISSIPATIVE: bool = true;

    fn name(&self) -> &str {
        &self.name
    }

    fn markers(&self) -> (&MarkerDef, &MarkerDef) {
        (&self.a, &self.b)
    }

    fn wrenches<T: Scalar>(
        &self,
        a: &Marker<T>,
        b: &Marker<T>,
        exact: bool,
        _d: &Drive<T>,
        _z: &[T],
    ) -> (Wrench<T>, Wrench<T>) {
        // The part relative to the body; the rod's axis turns with the part (exact) or stays
        // at rest (linearised: then only the friction law is nonlinear).
        let (dx, dv) = (b.pos - a.pos, b.vel - a.vel);
        let n0 = V::<T>::c(self.n0);
        let n = if exact {
            let n = n0 + b.rot.cross(n0);
            n.scale(T::c(1.0) / n.norm())
        } else {
            n0
        };
        let (xa, va) = (n.dot(dx), n.dot(dv));
        let across = (dx - n.scale(xa)) * self.k + (dv - n.scale(va)) * self.c;
        let along = match self.axial {
            Axial::Spring => xa * self.k + va * self.c,
            Axial::Friction { f_max, slope } => friction_force(f_max, slope, va),
        };
        // On the part: back towards the body; the bearing's moment about the normals.
        let force = -(across + n.scale(along));
        let moment = -((b.rot - a.rot) * self.bearing_stiffness
            + (b.angvel - a.angvel) * self.bearing_damping)
            .reject(n);
        (
            Wrench {
                force: -force,
                moment: -moment,
            },
            Wrench { force, moment },
        )
    }
}
