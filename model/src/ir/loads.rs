//! What a scene's elements can load a body with: the load cases whose static response a modal
//! truncation keeps (`ModalData::truncate`). Eigenmodes cut at a frequency lose the local give
//! of the body under its point loads (a tub wall under a spring, a damper bracket): a truncated
//! tub with only its bearing's correction modes differs from all its modes by 5 % on the
//! accelerations at top speed (docs/modal-data.md); folding the dropped modes' static response to
//! every attachment's loads keeps that give exactly.

use super::modal::{LoadCase, LoadKind, ModalData, point_at};
use super::{BodyRef, Effect, EffectSet, Model, V3};

/// One load an element applies: at `point` (global, at rest) a force or moment along
/// `direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElementLoad {
    pub point: V3,
    pub kind: LoadKind,
    pub direction: V3,
}

impl ElementLoad {
    /// The load case at `d`'s modal point here (`None`: the body has no node set here).
    pub fn case(&self, d: &ModalData) -> Option<LoadCase> {
        point_at(d, self.point).map(|p| LoadCase {
            point: p.name.clone(),
            direction: self.direction,
            kind: self.kind,
        })
    }
}

const AXES: [V3; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn force(point: V3, direction: V3) -> ElementLoad {
    ElementLoad {
        point,
        kind: LoadKind::Force,
        direction,
    }
}

/// Three forces at `point`.
fn forces(point: V3) -> impl Iterator<Item = ElementLoad> {
    AXES.into_iter().map(move |d| force(point, d))
}

/// Three moments at `point`.
fn moments(point: V3) -> impl Iterator<Item = ElementLoad> {
    AXES.into_iter().map(move |direction| ElementLoad {
        point,
        kind: LoadKind::Moment,
        direction,
    })
}

/// The unit vector from `a` to `b` (an element's axis at rest).
fn axis(a: V3, b: V3) -> V3 {
    let d = crate::geom::f::sub(b, a);
    crate::geom::f::scale(d, 1.0 / crate::geom::f::norm(d))
}

impl Model {
    /// The loads the scene's elements apply to `body`, each direction they act in: a spring's
    /// or linear damper's force along its axis; a massless friction damper's along its rod
    /// (its rubber bearings' moments are four orders smaller), a damper with its own mass's
    /// bearing forces in every direction; the gasket's forces and moments; a contact's forces;
    /// on the tub every rotor's mount (the drum's bearing: forces and moments; others: forces);
    /// on the drum its unbalances' forces.
    pub fn element_loads(&self, body: BodyRef, scene: &EffectSet) -> Vec<ElementLoad> {
        let mut v = Vec::new();
        let ends = |a: &super::Attach, b: &super::Attach| {
            [a, b]
                .into_iter()
                .filter(|e| e.body == body)
                .map(|e| e.point)
                .collect::<Vec<_>>()
        };
        for s in &self.springs {
            let d = axis(s.a.point, s.b.point);
            v.extend(ends(&s.a, &s.b).into_iter().map(|p| force(p, d)));
        }
        for s in &self.dampers {
            let d = axis(s.a.point, s.b.point);
            v.extend(ends(&s.a, &s.b).into_iter().map(|p| force(p, d)));
        }
        if scene.has(&Effect::FrictionDampers) {
            for s in &self.friction_dampers {
                let massive =
                    s.moving_part.is_some() && scene.has(&Effect::DamperMass(s.name.clone()));
                for p in ends(&s.a, &s.b) {
                    if massive {
                        v.extend(forces(p));
                    } else {
                        v.push(force(p, axis(s.a.point, s.b.point)));
                    }
                }
            }
        }
        for g in self.gaskets.iter().filter(|g| g.a == body || g.b == body) {
            v.extend(forces(g.point).chain(moments(g.point)));
        }
        if scene.has(&Effect::Contact) {
            for c in &self.contacts {
                if c.a == body {
                    v.extend(forces(c.point));
                }
                if c.b == body {
                    v.extend(forces(c.b_point()));
                }
            }
        }
        if body == BodyRef::Tub {
            for r in &self.rotors {
                v.extend(forces(r.mount_point()));
                if r.name == super::DRUM {
                    v.extend(moments(r.mount_point()));
                }
            }
            if scene.has(&Effect::Counterweights) {
                for j in &self.bolted_joints {
                    v.extend(forces(j.point));
                    // The clamp's tilt and twist.
                    if j.interface_diameter > 0.0 {
                        v.extend(moments(j.point));
                    }
                }
            }
        }
        if body == BodyRef::Drum {
            for u in self.unbalances.iter().filter(|u| u.rotor == super::DRUM) {
                v.extend(forces(u.position));
            }
        }
        v
    }
}
