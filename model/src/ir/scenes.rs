//! Scenes and effects: a scene's named selection of effects, the effects a scene can switch,
//! the resolved set (`EffectSet`), and the model's scenes (`Model::scene`, `full`).

use super::{BodyRef, FrictionLaw, Model};
use serde::{Deserialize, Serialize};

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
    /// The integration a run of this scene takes when it names none (`Model::scene_solver`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<SceneSolver>,
}

/// A scene's default integrator and relative tolerance, chosen by the accuracy study for what
/// the scene holds (docs/accuracy.md): the elastic machine's kHz coordinates want an implicit
/// method, the rigid one an explicit one. In a file: `solver = { method = "galpha", tol =
/// 1e-4 }`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSolver {
    pub method: Integrator,
    pub tol: f64,
}

/// The integrators by name, as a model file names them (the runtime maps each to its method;
/// the model knows no integrator's code).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Integrator {
    Rk4,
    Dopri5,
    Sdirk4,
    Rodas4,
    Galpha,
    Imex,
    Auto,
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
    /// The tub's counterweights as rigid bodies on their bolted joints (`counterweights`,
    /// `bolted_joints`), their mass out of the tub's. Not in `full`: the alternative to the
    /// counterweights inside the tub, not an added effect.
    Counterweights,
    /// Every friction damper of the scene on this law, whatever its `law` says
    /// (`friction_law.arctan`: the paper's machine beside the one as built).
    FrictionLaw(FrictionLaw),
    /// The named elastic body's characteristic curves (its `curves` file): the nonlinear
    /// restoring force on its chosen modes. Needs `elastic.<body>`.
    CharacteristicCurves(String),
}

/// The names effects refer to: rotors, elastic bodies, those of them with characteristic
/// curves, friction dampers with a moving part.
#[derive(Clone, Debug, Default)]
pub struct EffectNames<'a> {
    pub rotors: Vec<&'a str>,
    pub elastic: Vec<&'a str>,
    pub curved: Vec<&'a str>,
    pub massive: Vec<&'a str>,
    /// The model has counterweights (`counterweights`).
    pub bolted: bool,
}

impl<'a> EffectNames<'a> {
    pub fn of(m: &'a Model) -> Self {
        EffectNames {
            rotors: m.rotors.iter().map(|r| r.name.as_str()).collect(),
            elastic: m.elastic.iter().map(|e| e.name.as_str()).collect(),
            curved: m
                .elastic
                .iter()
                .filter(|e| e.curves.is_some())
                .map(|e| e.name.as_str())
                .collect(),
            massive: m.massive_dampers(),
            bolted: !m.counterweights.is_empty(),
        }
    }
}

impl Effect {
    /// Parse an effect name against the names it may refer to.
    pub fn parse(s: &str, names: &EffectNames) -> Option<Effect> {
        let EffectNames {
            rotors,
            elastic,
            curved,
            massive,
            bolted,
        } = names;
        match s {
            "gyroscopic" => Some(Effect::Gyroscopic),
            "friction_dampers" => Some(Effect::FrictionDampers),
            "gasket_damping" => Some(Effect::GasketDamping),
            "element_geometry" => Some(Effect::ElementGeometry),
            "unbalance_inertia" => Some(Effect::UnbalanceInertia),
            "centrifugal_stiffening" => Some(Effect::CentrifugalStiffening),
            "contact" => Some(Effect::Contact),
            "counterweights" if *bolted => Some(Effect::Counterweights),
            _ => {
                if let Some(b) = s.strip_prefix("elastic.") {
                    return elastic.contains(&b).then(|| Effect::Elastic(b.to_string()));
                }
                if let Some(b) = s.strip_prefix("characteristic_curves.") {
                    return curved
                        .contains(&b)
                        .then(|| Effect::CharacteristicCurves(b.to_string()));
                }
                if let Some(l) = s.strip_prefix("friction_law.") {
                    return FrictionLaw::parse(l).map(Effect::FrictionLaw);
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
            Effect::Counterweights => "counterweights".into(),
            Effect::FrictionLaw(l) => format!("friction_law.{}", l.name()),
            Effect::CharacteristicCurves(b) => format!("characteristic_curves.{b}"),
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

    /// The law a friction damper runs on in this scene: the scene's `friction_law.<law>`, or
    /// the damper's own.
    pub fn friction_law(&self, own: FrictionLaw) -> FrictionLaw {
        self.effects
            .iter()
            .find_map(|e| match e {
                Effect::FrictionLaw(l) => Some(*l),
                _ => None,
            })
            .unwrap_or(own)
    }
}

impl Model {
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
            if e.curves.is_some() {
                v.push(Effect::CharacteristicCurves(e.name.clone()));
            }
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

    /// Every scene [`Model::scene`] resolves, each once: `full` first unless declared (it
    /// always exists), then the declared ones in their order.
    pub fn every_scene(&self) -> Vec<&str> {
        let mut names: Vec<&str> = self.scenes.iter().map(|s| s.name.as_str()).collect();
        if !names.contains(&"full") {
            names.insert(0, "full");
        }
        names
    }

    /// The default integration of the scene `name` resolves to (`scene`'s rule), if it
    /// declares one.
    pub fn scene_solver(&self, name: Option<&str>) -> Option<SceneSolver> {
        let name = self.scene_name(name);
        self.scenes.iter().find(|s| s.name == name)?.solver
    }

    /// The scene `name` stands for: itself, or the first declared scene, or `full`.
    fn scene_name<'a>(&'a self, name: Option<&'a str>) -> &'a str {
        name.unwrap_or_else(|| self.scenes.first().map_or("full", |s| s.name.as_str()))
    }

    /// Resolve a scene by name (`None`: the first declared scene, or `full`). `full` always
    /// exists and holds every effect. Unknown effects were rejected by the checker; here they are
    /// an error too, so an unchecked model cannot silently drop one.
    pub fn scene(&self, name: Option<&str>) -> Result<EffectSet, String> {
        let name = self.scene_name(name);
        if name == "full" && !self.scenes.iter().any(|s| s.name == "full") {
            return Ok(EffectSet {
                name: "full".into(),
                effects: self.all_effects(),
                mode_cutoff: None,
            });
        }
        let scene = self.scenes.iter().find(|s| s.name == name).ok_or_else(|| {
            format!(
                "unknown scene `{name}`; this model has: {}",
                self.every_scene().join(", ")
            )
        })?;
        let names = EffectNames::of(self);
        let mut effects = Vec::new();
        for e in &scene.effects {
            let eff = Effect::parse(e, &names)
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
