//! The body layer: the bodies of a scene, each with its kind (where its frame is and whether it
//! has modes), its coordinates in q, its own terms in M1 and h, and the markers on it (MBSim's
//! `FlexibleBodyFFR`: a frame of reference, modes in it, frames on nodes). Everything above
//! this file asks a body for a point (`Bodies::marker`) and reads the marker's Jacobian; no one
//! tests a body's name.
//!
//! Layout of q: the floating frame's six rigid coordinates (u, alpha about p0), then the modes
//! of each body in subsystem 1 (floating and spinning bodies: the mass matrix M1 that the drum
//! angle changes), then subsystem 2 (constant M2 = E: modes on a fixed frame, then the rigid
//! parts of their own, mass-normalised: a friction damper's moving part).

use super::kinematics::{MarkerDef, ModalRows, add_rigid_mass, frame_point_jacobian};
use super::part::RigidPart;
use super::{BodyState, Drive, ElasticDrum, Layout, ModalBody, TubDef};
use crate::geom::{V, f};
use crate::ir::{BodyRef, Effect, EffectSet, Model};
use crate::scalar::Scalar;
use std::ops::Range;

/// Where a body's frame of reference is.
#[derive(Clone, Debug, PartialEq)]
pub enum Frame {
    /// Six rigid coordinates from `start`: translation u and small rotation alpha about `p0`
    /// (the tub's rest CoG).
    Floating { start: usize, p0: [f64; 3] },
    /// Turning by `ratio` x the drive angle about `axis` (unit) through `mount`, a marker on
    /// the parent's frame (the drum in its bearing on the tub).
    Spinning {
        parent: BodyRef,
        mount: MarkerDef,
        axis: [f64; 3],
        ratio: f64,
    },
    /// Fixed to the ground (the cabinet on its feet).
    Fixed,
}

/// What a body's own coordinates are beyond its frame's. (A scene has three bodies, built
/// once: the variants' sizes do not matter.)
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)]
pub enum Modes {
    Rigid,
    /// Modes in the body's own frame (floating: the tub; fixed: the cabinet).
    Frame(ModalBody),
    /// A spinning body's modes, turned with it: their inertia terms, their coupling into M1
    /// and their reaction on the parent (equations/drum.rs).
    Spinning(ElasticDrum),
    /// A rigid part's own small motion on a fixed frame (equations/part.rs).
    Part(RigidPart),
}

/// One body of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub id: BodyRef,
    pub frame: Frame,
    pub modes: Modes,
}

impl Body {
    /// The kind, as the issue tracker and the reports name it.
    pub fn kind(&self) -> &'static str {
        match (&self.frame, &self.modes) {
            (Frame::Floating { .. }, Modes::Rigid) => "floating rigid",
            (Frame::Floating { .. }, _) => "floating modal",
            (Frame::Spinning { .. }, Modes::Rigid) => "spinning rigid",
            (Frame::Spinning { .. }, _) => "spinning modal",
            (Frame::Fixed, Modes::Rigid) => "fixed rigid",
            (_, Modes::Part(_)) => "rigid part",
            (Frame::Fixed, _) => "fixed modal",
        }
    }

    /// The body's modes, when the scene makes it elastic.
    pub fn modal(&self) -> Option<&ModalBody> {
        match &self.modes {
            Modes::Rigid | Modes::Part(_) => None,
            Modes::Frame(m) => Some(m),
            Modes::Spinning(d) => Some(&d.modes),
        }
    }

    /// The body's own coordinates in q: its frame's rigid ones and its modes.
    pub fn coordinates(&self) -> Range<usize> {
        let modes = match &self.modes {
            Modes::Part(p) => Some(p.start..p.start + p.n()),
            _ => self.modal().map(|m| m.start..m.start + m.n),
        };
        match (&self.frame, modes) {
            (Frame::Floating { start, .. }, Some(m)) if m.start == start + 6 => *start..m.end,
            (Frame::Floating { start, .. }, None) => *start..start + 6,
            (Frame::Floating { .. }, Some(_)) => unreachable!("a frame's modes follow its DOF"),
            (_, m) => m.unwrap_or(0..0),
        }
    }

    /// The body's own terms in h (and M1): its modes' stiffness and damping (on a fixed frame
    /// also their weight; on a moving frame the weight enters with the frame's motion), and a
    /// spinning body's modal inertia terms with their reaction on the parent.
    pub fn add<T: Scalar>(
        &self,
        b: &BodyState<T>,
        d: &Drive<T>,
        g: V<T>,
        m1: Option<&mut [T]>,
        n1: usize,
        h: &mut [T],
    ) {
        match (&self.frame, &self.modes) {
            (_, Modes::Rigid) => {}
            (Frame::Fixed, Modes::Frame(m)) => m.add(b.q, b.qd, h),
            (_, Modes::Frame(m)) => m.add_elastic(b.q, b.qd, h),
            (_, Modes::Spinning(dr)) => dr.add(b, d, g, m1, n1, h),
            (_, Modes::Part(p)) => p.add(g, h),
        }
    }

    /// Subsystem 2 (the constant M2) holds the bodies on a fixed frame.
    pub fn in_subsystem2(&self) -> bool {
        self.frame == Frame::Fixed
    }
}

/// The bodies of a scene, in the order of `BodyRef::ALL`; the drum is present when the model
/// has its rotor.
#[derive(Clone, Debug, PartialEq)]
pub struct Bodies {
    pub list: Vec<Body>,
    pub layout: Layout,
}

impl Bodies {
    /// The checked model's bodies for a scene: the tub floating, the drum spinning on it, the
    /// cabinet fixed, each with the modes the scene keeps; then the moving part of each
    /// friction damper the scene gives its mass (`damper_mass.<name>`), then the
    /// counterweights where the scene has `counterweights`.
    pub fn new(model: &Model, scene: &EffectSet) -> Bodies {
        let g = model.gravity;
        let modes = |b: BodyRef, start: &mut usize| {
            model.modes_in(b, scene).map(|(e, d)| {
                let loads = model.element_loads(b, scene);
                let curves = scene.has(&Effect::CharacteristicCurves(b.name().into()));
                let m = ModalBody::new(e, d, *start, g, (scene.mode_cutoff, curves), &loads);
                *start += m.n;
                m
            })
        };
        let mut n1 = 6;
        let tub_modes = modes(BodyRef::Tub, &mut n1);
        let drum_modes = modes(BodyRef::Drum, &mut n1);
        let mut n = n1;
        let cabinet_modes = modes(BodyRef::Cabinet, &mut n);
        let parts: Vec<_> = model
            .friction_dampers
            .iter()
            .enumerate()
            .filter(|(_, d)| {
                scene.has(&Effect::FrictionDampers)
                    && scene.has(&Effect::DamperMass(d.name.clone()))
            })
            .map(|(i, d)| {
                let mp = d
                    .moving_part
                    .as_ref()
                    .expect("checked: damper_mass has its part");
                let p = RigidPart::new(mp, d.a.point, d.b.point, n);
                n += p.n();
                (BodyRef::DamperPart(i), p)
            })
            .collect();
        let weights: Vec<_> = model
            .counterweights
            .iter()
            .enumerate()
            .filter(|_| scene.has(&Effect::Counterweights))
            .map(|(i, w)| {
                let p = RigidPart::counterweight(w, n);
                n += p.n();
                (BodyRef::Counterweight(i), p)
            })
            .collect();
        let layout = Layout {
            n1,
            n2: n - n1,
            nz: 0,
        };
        let frame_modes = |m: Option<ModalBody>| m.map_or(Modes::Rigid, Modes::Frame);
        let mut bodies = Bodies {
            list: vec![Body {
                id: BodyRef::Tub,
                frame: Frame::Floating {
                    start: 0,
                    p0: model.tub.cog,
                },
                modes: frame_modes(tub_modes),
            }],
            layout,
        };
        if let Some(r) = model.drum() {
            let mount = bodies.marker(BodyRef::Tub, r.mount_point());
            let axis = f::unit(r.axis);
            let modes = match drum_modes {
                Some(m) => Modes::Spinning(ElasticDrum::new(
                    m,
                    axis,
                    r.ratio,
                    mount.clone(),
                    n1,
                    scene.has(&Effect::CentrifugalStiffening),
                )),
                None => Modes::Rigid,
            };
            bodies.list.push(Body {
                id: BodyRef::Drum,
                frame: Frame::Spinning {
                    parent: BodyRef::Tub,
                    mount,
                    axis,
                    ratio: r.ratio,
                },
                modes,
            });
        }
        bodies.list.push(Body {
            id: BodyRef::Cabinet,
            frame: Frame::Fixed,
            modes: frame_modes(cabinet_modes),
        });
        for (id, p) in parts.into_iter().chain(weights) {
            bodies.list.push(Body {
                id,
                frame: Frame::Fixed,
                modes: Modes::Part(p),
            });
        }
        bodies
    }

    /// The body `id`, when the scene has it (the drum needs its rotor).
    pub fn get(&self, id: BodyRef) -> Option<&Body> {
        self.list.iter().find(|b| b.id == id)
    }

    /// The modes of body `id`, when the scene makes it elastic.
    pub fn modes(&self, id: BodyRef) -> Option<&ModalBody> {
        self.get(id).and_then(Body::modal)
    }

    /// The spinning elastic body's terms (the drum's), when there is one.
    pub fn spinning(&self) -> Option<&ElasticDrum> {
        self.list.iter().find_map(|b| match &b.modes {
            Modes::Spinning(d) => Some(d),
            _ => None,
        })
    }

    /// The floating frame: its first rigid coordinate and its reference point.
    pub fn floating(&self) -> (usize, [f64; 3]) {
        self.list
            .iter()
            .find_map(|b| match b.frame {
                Frame::Floating { start, p0 } => Some((start, p0)),
                _ => None,
            })
            .expect("the tub floats")
    }

    /// The floating frame's translation and rotation in q (or q'').
    pub fn rigid_motion<'a>(&self, x: &'a [f64]) -> (&'a [f64], &'a [f64]) {
        let (c, _) = self.floating();
        (&x[c..c + 3], &x[c + 3..c + 6])
    }

    /// A marker at `point` (global, at rest) on body `id`: the frame it rides on with its
    /// lever, and the modal rows there. A point on a spinning body rides on the parent's
    /// material frame at the mount, carried rigidly to the point (its own modes turn with it
    /// and are the spinning body's business: `Spin`, `ElasticDrum`).
    pub fn marker(&self, id: BodyRef, point: [f64; 3]) -> MarkerDef {
        let b = self.get(id).expect("checked: the marker's body exists");
        match &b.frame {
            Frame::Spinning { mount, .. } => self.carried(id, mount, point),
            _ => {
                let mut m = self.frame_marker(id, point);
                m.modal = match &b.modes {
                    Modes::Frame(mb) => Some(mb.rows(point)),
                    Modes::Part(p) => Some(p.rows(point)),
                    _ => None,
                };
                m
            }
        }
    }

    /// A point rigidly attached at `point` to the marker `at` (a part carried at a mount): the
    /// frame's lever at the point, the mount's modal rows moved there (W + Phi x r).
    pub fn carried(&self, id: BodyRef, at: &MarkerDef, point: [f64; 3]) -> MarkerDef {
        let mut m = self.frame_marker(at.body, point);
        m.body = id;
        m.modal = at.modal.as_ref().map(|r| r.moved(f::sub(point, at.point)));
        m
    }

    /// The frame part of a marker (no modal rows): on a spinning body, its parent's frame.
    pub fn frame_marker(&self, id: BodyRef, point: [f64; 3]) -> MarkerDef {
        let b = self.get(id).expect("checked: the marker's body exists");
        match &b.frame {
            Frame::Floating { start, p0 } => MarkerDef::floating(id, point, *start, *p0),
            Frame::Spinning { parent, .. } => {
                let mut m = self.frame_marker(*parent, point);
                m.body = id;
                m
            }
            Frame::Fixed => MarkerDef::fixed(id, point),
        }
    }

    /// The tub's weight and the constant part of M1 (row-major n1 x n1): the floating body's
    /// rigid mass (or the FE tub with its modes' frame blocks and the rigid parts it carries:
    /// the drum's FE mass at the drum's mount, other rotors as point masses at their axis
    /// point, each moving with the tub's modes at its mount), and E on a spinning body's
    /// modes. The carried parts come back with their mass: their weight acts at their CoG.
    pub fn constant_mass(&self, model: &Model) -> (TubDef, Vec<f64>, Vec<(MarkerDef, f64)>) {
        let n1 = self.layout.n1;
        let (start, p0) = self.floating();
        let mut m1 = vec![0.0; n1 * n1];
        let mut carried = Vec::new();
        let jac = |s: [f64; 3], rows: Option<&ModalRows>| frame_point_jacobian(start, s, rows, n1);
        let tub = match self.modes(BodyRef::Tub) {
            None => {
                let bolted = self
                    .list
                    .iter()
                    .any(|b| matches!(b.id, BodyRef::Counterweight(_)));
                let t = if bolted {
                    model.bare_tub()
                } else {
                    model.tub.clone()
                };
                let jac = jac(f::sub(t.cog, p0), None);
                add_rigid_mass(&mut m1, n1, t.mass, t.inertia, &jac);
                TubDef {
                    mass: t.mass,
                    p0,
                    inertia: t.inertia,
                    cog_offset: f::sub(t.cog, p0),
                    modal_weight: None,
                }
            }
            Some(t) => {
                let d = t.data();
                add_rigid_mass(
                    &mut m1,
                    n1,
                    d.mass,
                    d.inertia,
                    &jac(f::sub(d.cog, p0), None),
                );
                t.add_frame_mass(&mut m1, n1, p0);
                for r in &model.rotors {
                    let mount = self.marker(BodyRef::Tub, r.mount_point());
                    let fe = model
                        .elastic_of(BodyRef::Drum)
                        .and_then(|e| e.data.as_ref())
                        .filter(|_| model.drum().is_some_and(|dr| dr.name == r.name));
                    let (mass, cog, inertia) = match fe {
                        Some(d) => (d.mass, d.cog, d.inertia),
                        None => (r.mass, r.axis_point, [[0.0; 3]; 3]),
                    };
                    if mass == 0.0 {
                        continue;
                    }
                    let at = self.carried(BodyRef::Tub, &mount, cog);
                    let jac = jac(at.s, at.modal.as_ref());
                    add_rigid_mass(&mut m1, n1, mass, inertia, &jac);
                    carried.push((at, mass));
                }
                TubDef {
                    mass: d.mass,
                    p0,
                    inertia: d.inertia,
                    cog_offset: f::sub(d.cog, p0),
                    modal_weight: Some((t.start, t.weight_sums())),
                }
            }
        };
        if let Some(d) = self.spinning() {
            let b = &d.modes;
            for k in 0..b.n {
                m1[(b.start + k) * n1 + b.start + k] += 1.0;
            }
        }
        (tub, m1, carried)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference() -> Model {
        crate::ir::toml_file::reference_for_tests()
    }

    /// The reference machine's bodies: the tub floats (0..6), the drum spins on it, the
    /// cabinet is fixed; in the scene `elastic` each has its modes, and the bodies' own
    /// coordinates tile q in the order of the layout.
    #[test]
    fn kinds_and_coordinates() {
        let m = reference();
        let b = Bodies::new(&m, &m.scene(Some("full")).unwrap());
        let kinds: Vec<_> = b.list.iter().map(|b| (b.id, b.kind())).collect();
        assert_eq!(
            kinds,
            [
                (BodyRef::Tub, "floating rigid"),
                (BodyRef::Drum, "spinning rigid"),
                (BodyRef::Cabinet, "fixed rigid")
            ]
        );
        assert_eq!(b.get(BodyRef::Tub).unwrap().coordinates(), 0..6);
        assert_eq!(
            b.layout,
            Layout {
                n1: 6,
                n2: 0,
                nz: 0
            }
        );
        // A drum point rides on the tub's frame at its own lever from p0.
        let p = [0.3, 0.1, 0.2];
        let d = b.marker(BodyRef::Drum, p);
        assert_eq!((d.body, d.frame), (BodyRef::Drum, Some(0)));
        assert_eq!(d.s, f::sub(p, b.floating().1));
        assert!(b.marker(BodyRef::Cabinet, p).frame.is_none());

        let b = Bodies::new(&m, &m.scene(Some("elastic")).unwrap());
        let kinds: Vec<_> = b.list.iter().map(|b| b.kind()).collect();
        assert_eq!(kinds, ["floating modal", "spinning modal", "fixed modal"]);
        let mut next = 0;
        for body in &b.list {
            let c = body.coordinates();
            assert_eq!(c.start, next, "{:?}", body.id);
            next = c.end;
            assert_eq!(body.in_subsystem2(), c.start >= b.layout.n1);
        }
        assert_eq!(next, b.layout.n());
    }
}
