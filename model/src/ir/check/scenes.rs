//! The sensors' and scenes' rules: unique sensor names and finite points; unique scene names,
//! known effects (`damper_mass.<name>` with `friction_dampers`), a positive `max_order`.

use super::{Ctx, Names, Path};
use crate::ir::{Effect, EffectNames, FrictionLaw, Model};
use std::collections::HashSet;

/// Sensors: a unique name and a finite point (the drum's sensors: `elastic.rs`).
pub(super) fn sensors<'a>(c: &mut Ctx, names: &mut Names<'a>, m: &'a Model) {
    for (i, s) in m.sensors.iter().enumerate() {
        let p = Path::of(&["sensors"]).idx(i);
        names.add(c, p.clone(), "sensor", &s.name);
        c.vec3(p.key("point"), &format!("sensor `{}`", s.name), &s.point);
    }
}

/// Scenes: a unique name, known effects (`damper_mass.<name>` only with `friction_dampers`), a
/// positive `max_order`.
pub(super) fn scenes(c: &mut Ctx, m: &Model) {
    let names = EffectNames::of(m);
    let mut scene_names = HashSet::new();
    for (i, s) in m.scenes.iter().enumerate() {
        let p = Path::of(&["scenes"]).idx(i);
        if !scene_names.insert(s.name.as_str()) {
            c.err(
                p.clone().key("name"),
                format!("duplicate scene name `{}`", s.name),
            );
        }
        for (j, e) in s.effects.iter().enumerate() {
            if Effect::parse(e, &names).is_none() {
                c.err(
                    p.clone().key("effects").idx(j),
                    format!(
                        "scene `{}`: unknown effect `{e}` (known: gyroscopic, friction_dampers, \
                         gasket_damping, element_geometry, unbalance_inertia, unbalance.<rotor>, \
                         elastic.<body>, centrifugal_stiffening, damper_mass.<friction damper \
                         with a moving_part>, contact, friction_law.<arctan|elasto_plastic>, \
                         characteristic_curves.<elastic body with curves>, counterweights (a \
                         model with counterweights))",
                        s.name
                    ),
                );
            }
        }
        for (j, e) in s.effects.iter().enumerate() {
            let Some(b) = e.strip_prefix("characteristic_curves.") else {
                continue;
            };
            if !s.effects.iter().any(|x| *x == format!("elastic.{b}")) {
                c.err(
                    p.clone().key("effects").idx(j),
                    format!("scene `{}`: `{e}` needs the effect `elastic.{b}`", s.name),
                );
            }
        }
        let bolted = s.effects.iter().position(|e| e == "counterweights");
        let bare = m
            .elastic_of(crate::ir::BodyRef::Tub)
            .is_some_and(|e| e.bare.is_some());
        if let Some(j) = bolted.filter(|_| s.effects.iter().any(|e| e == "elastic.tub") && !bare) {
            c.err(
                p.clone().key("effects").idx(j),
                format!(
                    "scene `{}`: `counterweights` with `elastic.tub` needs the tub's modal data \
                     without the counterweights' bricks: elastic `tub` names none (`bare`, \
                     e.g. fe/tub_bare.modal.toml from `washdyn fe modal`)",
                    s.name
                ),
            );
        }
        let massive = s.effects.iter().position(|e| e.starts_with("damper_mass."));
        if let Some(j) = massive.filter(|_| !s.effects.iter().any(|e| e == "friction_dampers")) {
            c.err(
                p.clone().key("effects").idx(j),
                format!(
                    "scene `{}`: `{}` needs the effect `friction_dampers`",
                    s.name, s.effects[j]
                ),
            );
        }
        law_parameters(c, &p, m, &s.name, &s.effects);
        if let Some(o) = s.max_order {
            c.positive(
                p.clone().key("max_order"),
                &format!("scene `{}`: max_order", s.name),
                o,
            );
        }
        if let Some(v) = s.solver.as_ref().map(|v| v.tol) {
            // The adaptive methods' range: below 1e-2, where an error class covers the run.
            if !(v > 0.0 && v < 1e-2) {
                c.err(
                    p.clone().key("solver").key("tol"),
                    format!(
                        "scene `{}`: solver.tol must be in (0, 1e-2), got {v}",
                        s.name
                    ),
                );
            }
        }
    }
}

/// A scene's `friction_law.<law>`: one at most, and every friction damper has that law's
/// parameters (`slope` for arctan, `axial_stiffness` for elasto-plastic).
fn law_parameters(c: &mut Ctx, p: &Path, m: &Model, scene: &str, effects: &[String]) {
    let laws: Vec<(usize, FrictionLaw)> = effects
        .iter()
        .enumerate()
        .filter_map(|(j, e)| Some((j, FrictionLaw::parse(e.strip_prefix("friction_law.")?)?)))
        .collect();
    if let [_, (j, _), ..] = laws[..] {
        c.err(
            p.clone().key("effects").idx(j),
            format!("scene `{scene}`: names more than one friction_law"),
        );
    }
    let Some(&(j, law)) = laws.first() else {
        return;
    };
    for d in &m.friction_dampers {
        if let Some(missing) = super::force_elements::law_misses(law, d) {
            c.err(
                p.clone().key("effects").idx(j),
                format!(
                    "scene `{scene}`: `friction_law.{}` needs friction damper `{}`'s {missing}",
                    law.name(),
                    d.name
                ),
            );
        }
    }
}
