//! The model IR: one plain description of a machine that both front ends (the TOML loader and the
//! `machine!` macro) fill and both back ends (interpreter, code generator) consume.
//!
//! Frame: origin at the centre of the cabinet's base, x along the drum axis towards the door, y to
//! the left seen from the front, z up. SI units throughout. All points and directions are given in
//! this global frame, in the rest (reference) configuration.
//!
//! The types by concept: the bodies and what they carry (`bodies.rs`), the force elements
//! (`force_elements.rs`), the sensors (`sensors.rs`), the scenes and the effects they switch
//! (`scenes.rs`); here the machine as a whole (`Model`) and its speed profile.

pub mod attachments;
mod bodies;
pub mod check;
mod counterweights;
pub mod exact;
pub mod files;
mod force_elements;
pub mod loads;
pub mod modal;
pub mod param;
mod scenes;
mod sensors;
pub mod toml_file;

pub use bodies::{Attach, BodyRef, Cabinet, DRUM, Elastic, MOTOR, Rotor, Tub, Unbalance};
pub use counterweights::{BoltedJoint, Counterweight, Tightening};
pub use force_elements::{
    Contact, DEFAULT_BREAKAWAY, FrictionDamper, FrictionLaw, Gasket, LinearDamper, LossFactor,
    MovingPart, Spring,
};
pub use scenes::{Effect, EffectNames, EffectSet, Integrator, MODE_MARGIN, Scene, SceneSolver};
pub use sensors::{Sensor, SensorKind};

use serde::{Deserialize, Serialize};

/// 3-vector in the global frame.
pub type V3 = [f64; 3];
/// 3x3 matrix, row-major.
pub type M3 = [[f64; 3]; 3];
/// 6x6 matrix, row-major, ordering (x, y, z, rx, ry, rz).
pub type M6 = [[f64; 6]; 6];

/// A whole machine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    pub name: String,
    /// Gravity vector, m/s^2 (the reference machine: [0, 0, -9.81]).
    #[serde(default = "default_gravity")]
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub gravity: V3,
    /// The suspended tub assembly: 6 rigid DOF (subsystem 1).
    pub tub: Tub,
    /// The cabinet: the fixed ground frame unless an `elastic` entry gives it modes.
    #[serde(default)]
    pub cabinet: Cabinet,
    /// Elastic bodies: modal data files for the tub, the drum and the cabinet.
    #[serde(default)]
    pub elastic: Vec<Elastic>,
    /// Rotors turning with prescribed speed about axes fixed in the tub (drum, motor rotor).
    #[serde(default)]
    pub rotors: Vec<Rotor>,
    /// Point masses carried by rotors.
    #[serde(default)]
    pub unbalances: Vec<Unbalance>,
    /// Drum speed over time; a rotor turns at `ratio` times this.
    pub speed: SpeedProfile,
    #[serde(default)]
    pub springs: Vec<Spring>,
    #[serde(default)]
    pub dampers: Vec<LinearDamper>,
    #[serde(default)]
    pub friction_dampers: Vec<FrictionDamper>,
    #[serde(default)]
    pub gaskets: Vec<Gasket>,
    /// Tub-cabinet contacts, simulated where a scene names the effect `contact`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contacts: Vec<Contact>,
    /// The tub's counterweights, bodies of their own on their bolts where a scene names
    /// `counterweights` (in the tub's mass elsewhere).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub counterweights: Vec<Counterweight>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bolted_joints: Vec<BoltedJoint>,
    #[serde(default)]
    pub sensors: Vec<Sensor>,
    /// Named selections of effects; an empty list means the one scene `full`.
    #[serde(default)]
    pub scenes: Vec<Scene>,
    /// Parameters (paths, `param.rs`) the generated code takes as inputs instead of folding
    /// them in as literals (Modelica's `parameter` against `constant`): a study varies them on
    /// one build. Only numbers that enter the force vector directly can be free; the code
    /// generator proves it or refuses.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub free: Vec<String>,
}

pub fn default_gravity() -> V3 {
    [0.0, 0.0, -9.81]
}

/// Prescribed drum speed: a piecewise-linear rpm(t) table, inline or from a CSV file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedProfile {
    /// (time s, drum rpm) pairs, strictly increasing in time; constant beyond the ends.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub table: Vec<[f64; 2]>,
    /// CSV with columns time_s, rpm (header optional); relative to the model file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub csv: Option<String>,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Model {
    /// The rotor named `name` (`DRUM`, `MOTOR`).
    pub fn rotor(&self, name: &str) -> Option<&Rotor> {
        self.rotors.iter().find(|r| r.name == name)
    }

    /// The drum's rotor.
    pub fn drum(&self) -> Option<&Rotor> {
        self.rotor(DRUM)
    }

    /// The names of the friction dampers that have a moving part (`damper_mass.<name>`).
    pub fn massive_dampers(&self) -> Vec<&str> {
        self.friction_dampers
            .iter()
            .filter(|d| d.moving_part.is_some())
            .map(|d| d.name.as_str())
            .collect()
    }

    /// The `elastic` entry of a body.
    pub fn elastic_of(&self, b: BodyRef) -> Option<&Elastic> {
        self.elastic.iter().find(|e| e.body() == Some(b))
    }

    /// A body's `elastic` entry and the modal data the scene runs (`Elastic::data_in`), when
    /// the scene makes it elastic.
    pub fn modes_in(&self, b: BodyRef, scene: &EffectSet) -> Option<(&Elastic, &modal::ModalData)> {
        self.elastic_of(b)
            .filter(|e| e.data.is_some() && scene.has(&Effect::Elastic(b.name().into())))
            .and_then(|e| Some((e, e.data_in(scene)?)))
    }
}
