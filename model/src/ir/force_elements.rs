//! The force elements of the IR: springs, linear and friction dampers (with a friction
//! damper's moving part), the door gasket and its loss factor, and the tub-cabinet contacts.

use super::{Attach, BodyRef, M6, V3, is_zero};
use serde::{Deserialize, Serialize};

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

/// Massless friction damper (seed paper): axial friction by `law` and a rubber bearing at each
/// end, a rotary spring-damper about the two axes normal to the rod.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionDamper {
    pub name: String,
    pub a: Attach,
    pub b: Attach,
    /// The axial friction law; none named: the paper's arctan.
    #[serde(default, skip_serializing_if = "FrictionLaw::is_arctan")]
    pub law: FrictionLaw,
    /// N: the Coulomb limit of either law.
    pub f_max: f64,
    /// s/m: the arctan law's slope (required by it; the elasto-plastic law ignores it).
    #[serde(default)]
    pub slope: f64,
    /// N/m: the end bushings' axial stiffness in series with the slider (both bushings
    /// together), the elasto-plastic law's presliding stiffness (required by that law).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axial_stiffness: Option<f64>,
    /// The elasto-plastic law's breakaway deflection as a fraction of the sliding one
    /// (Dupont et al. 2002: purely elastic below it), in (0, 1); default `DEFAULT_BREAKAWAY`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub breakaway: Option<f64>,
    /// Rubber bearings, N m/rad (both ends).
    pub bearing_stiffness: f64,
    /// Rubber bearings, N m s/rad (both ends).
    pub bearing_damping: f64,
    /// The damper's moving part as a body of its own, used where a scene names
    /// `damper_mass.<name>` (otherwise the massless element).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moving_part: Option<MovingPart>,
}

/// The axial law of a friction damper.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrictionLaw {
    /// The seed paper's regularised Coulomb law, F = 2 Fmax / pi atan(s v), on a rod rigid
    /// along its axis: a stuck damper is a dashpot of 2 Fmax s / pi.
    #[default]
    Arctan,
    /// The damper as built: the slider in series with the end bushings' axial stiffness, as
    /// the elasto-plastic presliding model of Dupont, Hayward, Armstrong and Altpeter (IEEE TAC
    /// 47(5), 2002) without its micro-viscous term. The bushings' deflection z is the
    /// element's state: F = k z, z' = v (1 - alpha(z, v) z / z_ss), z_ss = Fmax / k. Stuck,
    /// a spring; sliding, the Coulomb force.
    ElastoPlastic,
}

impl FrictionLaw {
    pub fn is_arctan(&self) -> bool {
        *self == FrictionLaw::Arctan
    }
    /// The name in model files and scene effects (`friction_law.<name>`).
    pub fn name(&self) -> &'static str {
        match self {
            FrictionLaw::Arctan => "arctan",
            FrictionLaw::ElastoPlastic => "elasto_plastic",
        }
    }
    pub fn parse(s: &str) -> Option<FrictionLaw> {
        [FrictionLaw::Arctan, FrictionLaw::ElastoPlastic]
            .into_iter()
            .find(|l| l.name() == s)
    }
}

/// The elasto-plastic law's breakaway fraction when a model names none: elastic to 90 % of the
/// sliding deflection, a smooth (C1) transition above (estimate; the ideal slider is 1).
pub const DEFAULT_BREAKAWAY: f64 = 0.9;

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
