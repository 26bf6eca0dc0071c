//! The tub's counterweights as bodies of their own (issue 52; the seed paper's closing remedy
//! for the even orders: "a more detailed representation of the connection between the tub and
//! the concrete counterweight ... currently modeled as a rigid link"). Where a scene names
//! `counterweights`, each is a rigid body on its bolted joints to the tub and its mass leaves
//! the tub's; elsewhere it stays in the tub's mass, as today.

use super::{M3, Model, Tub, V3};
use crate::geom::f;
use serde::{Deserialize, Serialize};

/// A rigid counterweight: its mass properties (the tub's `mass`, `cog` and `inertia` include
/// them; a scene with `counterweights` takes them out).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Counterweight {
    pub name: String,
    /// kg
    pub mass: f64,
    /// Centre of gravity at rest, m.
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub cog: V3,
    /// Inertia tensor about the CoG in global axes, kg m^2.
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub inertia: M3,
}

/// One bolt of a counterweight to the tub, as a joint with a preloaded bolt's characteristic
/// curve along its axis (`elements/bolted_joint.rs`) and a stiff shear path with a Coulomb limit
/// across it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoltedJoint {
    pub name: String,
    /// The counterweight it holds (a `counterweights` entry).
    pub counterweight: String,
    /// Where the bolt passes the interface, at rest (on the tub; a point of the tub's mesh
    /// where the tub is elastic).
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub point: V3,
    /// The bolt's axis, from the tub into the counterweight (normalised by the derivation).
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub axis: V3,
    /// Preload, N: given, or from the tightening torque (`torque`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preload: Option<f64>,
    /// The tightening torque and the thread that turns it into a preload (VDI 2230 R13).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque: Option<Tightening>,
    /// Axial stiffness of the bolt, N/m.
    pub bolt_stiffness: f64,
    /// Stiffness of the clamped members under the bolt (the compression cone), N/m.
    pub member_stiffness: f64,
    /// Stiffness across the bolt while the interface sticks, N/m (each tangent direction).
    pub shear_stiffness: f64,
    /// The bolt's own stiffness across the interface, N/m: its shank bent over the clamp
    /// length as a guided cantilever (12 E I / L^3), in parallel with the interface. It is all
    /// that locates a lifted joint across its axis.
    #[serde(default)]
    pub bolt_bending_stiffness: f64,
    /// Coefficient of friction of the interface (the Coulomb limit mu x the clamp force).
    pub friction: f64,
    /// Viscous damping along and across the bolt, N s/m.
    #[serde(default)]
    pub damping: f64,
    /// Diameter of the clamped interface under the bolt, m (VDI 2230's cone at the interface,
    /// D_A): the clamp as a disc resists the members' relative tilt (k_m D^2 / 16 until its
    /// edge lifts at F_m D / 8) and twist (k_t D^2 / 8 until it slips at mu F_m D / 3). 0: a
    /// point joint, forces only.
    #[serde(default)]
    pub interface_diameter: f64,
}

/// A tightening torque on a metric thread (VDI 2230 Part 1, eq. R13).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tightening {
    /// N m.
    pub moment: f64,
    /// Thread pitch and pitch diameter, m.
    pub pitch: f64,
    pub pitch_diameter: f64,
    /// Friction in the thread and under the head.
    pub thread_friction: f64,
    pub head_friction: f64,
    /// The head's mean friction diameter, m.
    pub head_diameter: f64,
}

impl BoltedJoint {
    /// The preload, N: `preload`, or the torque's (the checker asks for exactly one).
    pub fn preload(&self) -> f64 {
        let (declared, per) = self.preload_parts();
        declared * per
    }

    /// The preload as declared and its newtons per unit: (`preload`, 1), or the torque and
    /// the preload of 1 N m (VDI 2230's relation is linear in the torque). The elements keep
    /// the two apart so that a free torque stays a parameter of the generated code.
    pub fn preload_parts(&self) -> (f64, f64) {
        match (self.preload, self.torque) {
            (Some(p), _) => (p, 1.0),
            (None, Some(t)) => (
                t.moment,
                crate::elements::bolted_joint::preload_from_torque(
                    1.0,
                    t.pitch,
                    t.pitch_diameter,
                    t.thread_friction,
                    t.head_friction,
                    t.head_diameter,
                ),
            ),
            (None, None) => (0.0, 1.0),
        }
    }
}

impl Model {
    /// The tub without its counterweights (a scene with `counterweights`): the mass, CoG and
    /// inertia about the new CoG that remain once each counterweight's are taken out
    /// (parallel axes).
    pub fn bare_tub(&self) -> Tub {
        let t = &self.tub;
        let mass = t.mass - self.counterweights.iter().map(|w| w.mass).sum::<f64>();
        let mut cog = [0.0; 3];
        for a in 0..3 {
            let moment: f64 = self.counterweights.iter().map(|w| w.mass * w.cog[a]).sum();
            cog[a] = (t.mass * t.cog[a] - moment) / mass;
        }
        // Each body's inertia about `cog`: its own plus m (|d|^2 E - d d^T).
        let about = |m: f64, c: V3, j: &M3| -> M3 {
            let d = f::sub(c, cog);
            let dd = f::dot(d, d);
            let mut out = *j;
            for r in 0..3 {
                for s in 0..3 {
                    out[r][s] += m * (if r == s { dd } else { 0.0 } - d[r] * d[s]);
                }
            }
            out
        };
        let mut inertia = about(t.mass, t.cog, &t.inertia);
        for w in &self.counterweights {
            let j = about(w.mass, w.cog, &w.inertia);
            for r in 0..3 {
                for s in 0..3 {
                    inertia[r][s] -= j[r][s];
                }
            }
        }
        Tub { mass, cog, inertia }
    }
}
