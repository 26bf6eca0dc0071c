//! The bodies of the IR and what they carry: the rigid tub, the cabinet, the elastic bodies'
//! entries, the body an element attaches to (`BodyRef`, `Attach`), the rotors and their
//! unbalances.

use super::{Effect, EffectSet, M3, V3, is_zero, modal};
use serde::{Deserialize, Serialize};

/// The tub assembly with everything rigidly attached to it and the non-spinning mass of the rotors.
/// Its CoG at rest is the reference point of the tub's 6 DOF.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tub {
    /// kg
    pub mass: f64,
    /// Centre of gravity at rest, m.
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub cog: V3,
    /// Inertia tensor about the CoG in global axes, kg m^2.
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub inertia: M3,
}

/// The cabinet. Without modes it is the fixed ground frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cabinet {}

/// An elastic body: its modal data file and how much of it to use.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Elastic {
    /// The body: `tub`, `drum` or `cabinet`.
    pub name: String,
    /// Modal data file (`washdyn fe write`), relative to the model file (TOML) or to the
    /// crate (`machine!`).
    pub file: String,
    /// Keep the first `modes` modes of the file; all when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modes: Option<usize>,
    /// Modal damping ratio of every mode (the FE model gives none; reference: 2 % of critical).
    #[serde(default = "two_percent")]
    pub damping: f64,
    /// Damping ratio of the strain energy stored in the modal data's `support_springs` (the
    /// cabinet's feet), by modal strain energy: mode k gets `damping` + (`support_damping` -
    /// `damping`) e_k, e_k its share of strain energy in those springs (1 for a mode that only
    /// rides on them, 0 for a panel mode). None: every mode has `damping`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub support_damping: Option<f64>,
    /// Stiffness-proportional (Rayleigh beta) damping, s: zeta_k += beta omega_k / 2, exact for
    /// K-orthogonal modes (CalculiX's `*MODAL DAMPING, RAYLEIGH` with alpha = 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub stiffness_damping: f64,
    /// Characteristic curves of the body (`<body>.curves.toml`, `washdyn fe curves`), relative
    /// like `file`: a nonlinear restoring force on chosen modes that a scene switches on with
    /// `characteristic_curves.<body>`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curves: Option<String>,
    /// The curves' content, read by `modal::resolve` and checked against the modal data file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curves_data: Option<modal::Curves>,
    /// The tub's modal data without its counterweights' bricks (`tub_bare.modal.toml`), relative
    /// like `file`: what a scene with `counterweights` bolts them to. Its node sets hold the
    /// tub's points and one at each bolted joint's point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bare: Option<String>,
    /// The `bare` file's content, read by `modal::resolve` like `data`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bare_data: Option<modal::ModalData>,
    /// The file's content, read by `modal::resolve` (both front ends), truncated to `modes`.
    /// Serialised so a `machine!` model's embedded IR carries it; `resolve` always replaces it
    /// from the file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub data: Option<modal::ModalData>,
}

impl Elastic {
    /// The body this entry describes (the checker refuses other names).
    pub fn body(&self) -> Option<BodyRef> {
        BodyRef::from_name(&self.name)
    }

    /// The data a scene runs: with `counterweights` the tub's `bare` data stand in for its
    /// `data` (the counterweights are then bodies of their own).
    pub fn data_in(&self, scene: &EffectSet) -> Option<&modal::ModalData> {
        match &self.bare_data {
            Some(b) if scene.has(&Effect::Counterweights) => Some(b),
            _ => self.data.as_ref(),
        }
    }
}

fn two_percent() -> f64 {
    0.02
}

/// A body a force element or sensor can attach to. `drum`: sensors only. A drum point turns
/// with the drum (its rest position at drum angle 0) and reads its small motion: the tub's
/// motion at the drum's mount carried to the turning point, plus the elastic drum's own modes
/// there (a modal point of the drum's data off the axis), as the field recovery moves it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BodyRef {
    Tub,
    Cabinet,
    Drum,
    /// The moving part of the friction damper with this index (a scene's `damper_mass.<name>`):
    /// the body layer makes it; a model cannot attach to it.
    #[serde(skip)]
    DamperPart(usize),
    /// The counterweight with this index (a scene's `counterweights`): the body layer makes
    /// it; only its bolted joints attach to it.
    #[serde(skip)]
    Counterweight(usize),
}

impl BodyRef {
    /// Every body, in the order the state lays out their coordinates.
    pub const ALL: [BodyRef; 3] = [BodyRef::Tub, BodyRef::Drum, BodyRef::Cabinet];

    /// The body's name in a model (`elastic` entries, markers, effects): the one place the
    /// names live.
    pub fn name(self) -> &'static str {
        match self {
            BodyRef::Tub => "tub",
            BodyRef::Cabinet => "cabinet",
            BodyRef::Drum => "drum",
            BodyRef::DamperPart(_) => "damper part",
            BodyRef::Counterweight(_) => "counterweight",
        }
    }

    pub fn from_name(name: &str) -> Option<BodyRef> {
        BodyRef::ALL.into_iter().find(|b| b.name() == name)
    }

    /// The rotor that turns this body (the drum's), by its name in the model.
    pub fn rotor(self) -> Option<&'static str> {
        (self == BodyRef::Drum).then_some(DRUM)
    }
}

/// The rotor that carries the drum and defines the drive angle (ratio 1 by convention).
pub const DRUM: &str = "drum";
/// The motor's rotor (belt ratio to the drum).
pub const MOTOR: &str = "motor";

/// A point fixed on a body, given in global coordinates at rest.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Attach {
    pub body: BodyRef,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub point: V3,
}

/// A rotor without DOF of its own: it turns about `axis` through `axis_point` (fixed in the tub)
/// at `ratio` times the drum speed. On the rigid tub its mass and transverse inertia belong to
/// the tub and only its spin angular momentum (polar inertia) acts. On the elastic tub it sits
/// on the tub's node set at `mount` (a point on its axis) and moves with it: the drum with its
/// FE model's mass and inertia, any other rotor as a point mass `mass` at `axis_point`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rotor {
    pub name: String,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub axis_point: V3,
    /// Unit vector (normalised by the derivation); positive spin by the right-hand rule.
    #[serde(default = "default_axis")]
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub axis: V3,
    /// Speed ratio to the drum (drum 1, motor 11.25).
    #[serde(default = "one")]
    pub ratio: f64,
    /// kg m^2 about the spin axis.
    pub polar_inertia: f64,
    /// kg; used where the tub is elastic (the rigid tub's mass includes it). The drum's comes
    /// from its modal data.
    #[serde(default)]
    pub mass: f64,
    /// The tub point (an FE node set on its axis) that carries the rotor; default `axis_point`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub mount: Option<V3>,
}

impl Rotor {
    /// Where the rotor sits on the tub.
    pub fn mount_point(&self) -> V3 {
        self.mount.unwrap_or(self.axis_point)
    }
}

fn default_axis() -> V3 {
    [1.0, 0.0, 0.0]
}
fn one() -> f64 {
    1.0
}

/// A point mass on a rotor; `position` is where it is at rotor angle 0 (global, at rest).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Unbalance {
    pub name: String,
    pub rotor: String,
    /// kg
    pub mass: f64,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub position: V3,
}
