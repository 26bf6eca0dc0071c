//! The model IR: one plain description of a machine that both front ends (the TOML loader and the
//! `machine!` macro) fill and both back ends (interpreter, code generator) consume.
//!
//! Frame: origin at the centre of the cabinet's base, x along the drum axis towards the door, y to
//! the left seen from the front, z up. SI units throughout. All points and directions are given in
//! this global frame, in the rest (reference) configuration.

pub mod attachments;
pub mod check;
pub mod exact;
pub mod files;
pub mod loads;
pub mod modal;
pub mod toml_file;

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
    #[serde(default)]
    pub sensors: Vec<Sensor>,
    /// Named selections of effects; an empty list means the one scene `full`.
    #[serde(default)]
    pub scenes: Vec<Scene>,
}

pub fn default_gravity() -> V3 {
    [0.0, 0.0, -9.81]
}

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

/// Linear spring, force along its current axis only: F = k (L - L0).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spring {
    pub name: String,
    pub a: Attach,
    pub b: Attach,
    /// N/m
    pub stiffness: f64,
    /// m
    pub free_length: f64,
    /// N/m^2: k2 in F = k (L - L0) + k2 (L - Lr)^2, Lr the length at rest. A characteristic
    /// curve stiffer in one direction (the seed paper's explanation of measured even orders);
    /// it leaves the rest position unchanged.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub quadratic_stiffness: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// Linear viscous damper along its current axis: F = c v (a variant of the friction damper).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearDamper {
    pub name: String,
    pub a: Attach,
    pub b: Attach,
    /// N s/m
    pub damping: f64,
}

/// Massless friction damper (seed paper): axial arctan friction F = 2 Fmax/pi atan(s v) and a
/// rubber bearing at each end, a rotary spring-damper about the two axes normal to the rod.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionDamper {
    pub name: String,
    pub a: Attach,
    pub b: Attach,
    /// N
    pub f_max: f64,
    /// s/m
    pub slope: f64,
    /// Rubber bearings, N m/rad (both ends).
    pub bearing_stiffness: f64,
    /// Rubber bearings, N m s/rad (both ends).
    pub bearing_damping: f64,
    /// The damper's moving part as a body of its own, used where a scene names
    /// `damper_mass.<name>` (otherwise the massless element).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moving_part: Option<MovingPart>,
}

/// A friction damper's moving part (the seed paper's "two independent bodies"): the rod with
/// its piston, a rigid body carried by the rubber bearing at end `a` and sliding with the
/// arctan friction in the housing, which pivots in the rubber bearing at end `b`. Unlike the
/// massless element's bearings, these are elastic in translation too (otherwise the part would
/// have no motion of its own); in the limit of a stiff bearing and a small mass it is the
/// massless element (tests/damper_mass.rs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MovingPart {
    /// kg.
    pub mass: f64,
    /// kg m^2, about its CoG, about the axes normal to the rod (no torsion: the bearings take
    /// none, as in the massless element).
    pub inertia: f64,
    /// N/m, each rubber bearing in every direction (the housing's: across the rod only, the
    /// rod slides in it).
    pub translational_stiffness: f64,
    /// The CoG on the rod, as a fraction of the way from `a` to `b`.
    #[serde(default = "half")]
    pub cog: f64,
}

fn half() -> f64 {
    0.5
}

/// Door gasket: 6-D linear spring-damper between tub and cabinet at `point`, with full K and D
/// in global axes (x, y, z, rx, ry, rz); zero force in the reference position.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gasket {
    pub name: String,
    /// Body whose motion relative to `b` loads the gasket (the tub).
    pub a: BodyRef,
    pub b: BodyRef,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub point: V3,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub stiffness: M6,
    /// Viscous damping, N s/m etc. (default zero); adds to the hysteretic part.
    #[serde(default)]
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub damping: M6,
    /// Hysteretic damping: loss factor eta per direction (x, y, z, rx, ry, rz), or one for all.
    /// Frequency domain: K + i S K S, S = diag(sqrt(eta)); time domain: the equivalent viscous
    /// S K S / max(|Omega|, omega_floor) at the drum speed (`elements::gasket`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub loss_factor: Option<LossFactor>,
}

/// A gasket's loss factor: one value for every direction, or one per direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum LossFactor {
    Uniform(f64),
    /// (x, y, z, rx, ry, rz); the checker requires 6 values.
    PerDirection(Vec<f64>),
}

impl LossFactor {
    /// eta per direction (a wrong count reads as zeros beyond it: the checker refuses it).
    pub fn per_direction(&self) -> [f64; 6] {
        match self {
            LossFactor::Uniform(e) => [*e; 6],
            LossFactor::PerDirection(v) => {
                std::array::from_fn(|i| v.get(i).copied().unwrap_or(0.0))
            }
        }
    }
}

impl Gasket {
    /// S K S with S = diag(sqrt(eta)): the imaginary part of the complex stiffness K + i S K S,
    /// and Omega times the time domain's equivalent viscous damping. Zero without a loss factor.
    /// With one eta for all directions it is eta K; per direction it keeps K's couplings and
    /// gives each direction i the loss factor eta_i (x^T S K S x = eta_i K_ii x_i^2 for a motion
    /// along i alone).
    pub fn hysteretic_damping(&self) -> M6 {
        let eta = self
            .loss_factor
            .as_ref()
            .map_or([0.0; 6], LossFactor::per_direction);
        let s = eta.map(|e| e.max(0.0).sqrt());
        std::array::from_fn(|i| std::array::from_fn(|j| s[i] * self.stiffness[i][j] * s[j]))
    }
}

/// A stiff penalty contact where the tub can reach the cabinet (`elements::contact`): point on
/// `a` against a plane moving with `b`, normal force k delta^p (1 + 3/2 alpha delta') past the
/// clearance `gap` along `normal`, never pulling.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Contact {
    pub name: String,
    /// The body whose point touches (the tub).
    pub a: BodyRef,
    /// The body whose surface it touches (the cabinet).
    pub b: BodyRef,
    /// The touching point on `a`, m.
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub point: V3,
    /// The point of `b` whose motion the surface follows (on the elastic cabinet a node set
    /// near the surface); default `point`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub b_point: Option<V3>,
    /// Direction from the point towards the surface (normalised by the derivation).
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub normal: V3,
    /// Clearance at rest along `normal`, m.
    pub gap: f64,
    /// k, N/m^exponent.
    pub stiffness: f64,
    /// p: 1.5 (Hertz) by default; above 1 so the force is C1 at first touch.
    #[serde(default = "hertz")]
    pub exponent: f64,
    /// Hunt-Crossley damping alpha, s/m: e = 1 - alpha v0 for an impact at v0 (to first order;
    /// alpha = (1 - e^2) / (2 v0) after Lankarani and Nikravesh).
    pub alpha: f64,
}

fn hertz() -> f64 {
    1.5
}

impl Contact {
    /// The point on `b`.
    pub fn b_point(&self) -> V3 {
        self.b_point.unwrap_or(self.point)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SensorKind {
    Acceleration,
    Displacement,
}

/// A measurement point: three channels (x, y, z) in global axes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sensor {
    pub name: String,
    pub body: BodyRef,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub point: V3,
    pub kind: SensorKind,
}

impl Sensor {
    /// CSV column names of the three channels.
    pub fn channels(&self) -> [String; 3] {
        let p = match self.kind {
            SensorKind::Acceleration => "a",
            SensorKind::Displacement => "u",
        };
        ["x", "y", "z"].map(|c| format!("{}_{}{}", self.name, p, c))
    }
}

/// A named selection of effects to simulate; what is not listed is left out.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    pub effects: Vec<String>,
    /// Highest drum order of interest: the scene keeps each elastic body's modes up to
    /// `MODE_MARGIN` x this order x the highest drum speed (and at most the entry's `modes`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_order: Option<f64>,
}

/// Margin on the highest excitation frequency up to which a scene keeps modes (see
/// `Scene::max_order`). A mode at 1.5 x the excitation still answers with 1 / (1 - 1/1.5^2) =
/// 1.8 x its static share; the ones above contribute at most their static share, which is
/// what the margin buys (measured in docs/accuracy.md: modal truncation).
pub const MODE_MARGIN: f64 = 1.5;

/// The effects a scene can switch. Everything else (rigid tub, gravity, springs, gasket
/// stiffness, linear dampers) is always simulated.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Effect {
    /// Spin angular momentum of the rotors: gyroscopic moments and spin-up reaction.
    Gyroscopic,
    /// The unbalances carried by the named rotor.
    Unbalance(String),
    /// The friction dampers (axial friction and rubber bearings).
    FrictionDampers,
    /// The named friction damper with its moving part as a body of its own (its
    /// `moving_part`), instead of the massless element. Not in the scene `full`: it is the
    /// alternative element, not an added effect.
    DamperMass(String),
    /// The gasket's damping matrix.
    GasketDamping,
    /// Force elements with their exact kinematics (current axis, rod tilt) and the tilting of
    /// applied loads with the tub. Off: all linearised about the rest position, so a scene's only
    /// nonlinearity can be the friction law (half-wave symmetry checks).
    ElementGeometry,
    /// Unbalances as masses: angle-dependent M1, Coriolis, and the centrifugal load turning with
    /// the tub. Off: prescribed rotating forces only.
    UnbalanceInertia,
    /// The named body's modes (an `elastic` entry): `elastic.cabinet`. Off: the body is rigid
    /// (the cabinet fixed).
    Elastic(String),
    /// The elastic drum's stress stiffening from its centrifugal prestress, Omega^2 K_G (spin
    /// softening is always in; it is kinematics).
    CentrifugalStiffening,
    /// The tub-cabinet contacts (`contacts`): penalty forces where the tub reaches the cabinet.
    /// Off: no contact code or state; the validity monitor still watches the clearances.
    Contact,
}

impl Effect {
    /// Parse an effect name; `rotors` are the model's rotor names, `elastic` its elastic
    /// bodies, `massive` its friction dampers with a moving part.
    pub fn parse(s: &str, rotors: &[&str], elastic: &[&str], massive: &[&str]) -> Option<Effect> {
        match s {
            "gyroscopic" => Some(Effect::Gyroscopic),
            "friction_dampers" => Some(Effect::FrictionDampers),
            "gasket_damping" => Some(Effect::GasketDamping),
            "element_geometry" => Some(Effect::ElementGeometry),
            "unbalance_inertia" => Some(Effect::UnbalanceInertia),
            "centrifugal_stiffening" => Some(Effect::CentrifugalStiffening),
            "contact" => Some(Effect::Contact),
            _ => {
                if let Some(b) = s.strip_prefix("elastic.") {
                    return elastic.contains(&b).then(|| Effect::Elastic(b.to_string()));
                }
                if let Some(d) = s.strip_prefix("damper_mass.") {
                    return massive
                        .contains(&d)
                        .then(|| Effect::DamperMass(d.to_string()));
                }
                let r = s.strip_prefix("unbalance.")?;
                rotors
                    .contains(&r)
                    .then(|| Effect::Unbalance(r.to_string()))
            }
        }
    }

    pub fn name(&self) -> String {
        match self {
            Effect::Gyroscopic => "gyroscopic".into(),
            Effect::FrictionDampers => "friction_dampers".into(),
            Effect::GasketDamping => "gasket_damping".into(),
            Effect::ElementGeometry => "element_geometry".into(),
            Effect::UnbalanceInertia => "unbalance_inertia".into(),
            Effect::Unbalance(r) => format!("unbalance.{r}"),
            Effect::Elastic(b) => format!("elastic.{b}"),
            Effect::DamperMass(d) => format!("damper_mass.{d}"),
            Effect::CentrifugalStiffening => "centrifugal_stiffening".into(),
            Effect::Contact => "contact".into(),
        }
    }
}

/// A resolved scene: which effects are on.
#[derive(Clone, Debug, PartialEq)]
pub struct EffectSet {
    pub name: String,
    pub effects: Vec<Effect>,
    /// Keep elastic modes up to this frequency (Hz), from the scene's `max_order`.
    pub mode_cutoff: Option<f64>,
}

impl EffectSet {
    pub fn has(&self, e: &Effect) -> bool {
        self.effects.contains(e)
    }
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

    /// A body's modal data when the scene makes it elastic.
    pub fn modes_in(&self, b: BodyRef, scene: &EffectSet) -> Option<&Elastic> {
        self.elastic_of(b)
            .filter(|e| e.data.is_some() && scene.has(&Effect::Elastic(b.name().into())))
    }

    /// Every effect this model can switch: the scene `full`.
    pub fn all_effects(&self) -> Vec<Effect> {
        let mut v = vec![
            Effect::Gyroscopic,
            Effect::ElementGeometry,
            Effect::UnbalanceInertia,
        ];
        for r in &self.rotors {
            if self.unbalances.iter().any(|u| u.rotor == r.name) {
                v.push(Effect::Unbalance(r.name.clone()));
            }
        }
        if !self.friction_dampers.is_empty() {
            v.push(Effect::FrictionDampers);
        }
        if !self.gaskets.is_empty() {
            v.push(Effect::GasketDamping);
        }
        if !self.contacts.is_empty() {
            v.push(Effect::Contact);
        }
        for e in &self.elastic {
            v.push(Effect::Elastic(e.name.clone()));
            if e.body() == Some(BodyRef::Drum) {
                v.push(Effect::CentrifugalStiffening);
            }
        }
        v
    }

    /// Names of the scenes: the declared ones, or `full` when none is declared.
    pub fn scene_names(&self) -> Vec<String> {
        if self.scenes.is_empty() {
            vec!["full".to_string()]
        } else {
            self.scenes.iter().map(|s| s.name.clone()).collect()
        }
    }

    /// Resolve a scene by name (`None`: the first declared scene, or `full`). `full` always
    /// exists and holds every effect. Unknown effects were rejected by the checker; here they are
    /// an error too, so an unchecked model cannot silently drop one.
    pub fn scene(&self, name: Option<&str>) -> Result<EffectSet, String> {
        let name = name.unwrap_or_else(|| self.scenes.first().map_or("full", |s| s.name.as_str()));
        if name == "full" && !self.scenes.iter().any(|s| s.name == "full") {
            return Ok(EffectSet {
                name: "full".into(),
                effects: self.all_effects(),
                mode_cutoff: None,
            });
        }
        let scene = self.scenes.iter().find(|s| s.name == name).ok_or_else(|| {
            format!(
                "unknown scene `{name}`; this model has: full{}",
                self.scenes
                    .iter()
                    .map(|s| format!(", {}", s.name))
                    .collect::<String>()
            )
        })?;
        let rotors: Vec<&str> = self.rotors.iter().map(|r| r.name.as_str()).collect();
        let elastic: Vec<&str> = self.elastic.iter().map(|e| e.name.as_str()).collect();
        let massive = self.massive_dampers();
        let mut effects = Vec::new();
        for e in &scene.effects {
            let eff = Effect::parse(e, &rotors, &elastic, &massive)
                .ok_or_else(|| format!("scene `{name}`: unknown effect `{e}`"))?;
            if !effects.contains(&eff) {
                effects.push(eff);
            }
        }
        let top_rpm = self
            .speed
            .table
            .iter()
            .map(|r| r[1].abs())
            .fold(0.0, f64::max);
        Ok(EffectSet {
            name: name.to_string(),
            effects,
            mode_cutoff: scene.max_order.map(|o| MODE_MARGIN * o * top_rpm / 60.0),
        })
    }
}
