//! What the validity monitor watches beside the tub's rigid motion: the door ring's excursion
//! (the tub's front, where the gasket sits, against the cabinet's opening) and the drum-tub gap
//! at the drum's front edge. Both are set up once from the model and a scene's equations, and
//! evaluated between steps without allocating.
//!
//! Door ring: points on the tub at the gasket's point plus `DOOR_RING_RADIUS` about the drum's
//! axis; each moves with the tub's rigid motion u + alpha x s and, on the elastic tub, with the
//! modes where the tub's modal data has a point there (rigid only elsewhere).
//!
//! Drum-tub gap: the drum rides on the tub's bearing, so the tub's rigid motion moves drum and
//! tub alike and leaves the gap unchanged (to first order). What closes it is elastic: the
//! drum's own deflection at its front edge (drum modes, turning with the drum), the tub's
//! deformation at the bearing carrying the drum (the tub's modes at the mount, moved rigidly to
//! the edge), against the tub's deformation at its ring opposite the edge point. The points are
//! the modal data's node sets DRUM_EDGE_k (drum) and TUB_RING_k (tub), k = 0.., and the
//! clearance is their mean radii's difference; a body without them counts as rigid there.

use washdyn_model::equations::{Equations, MarkerDef, ModalRows, rotate};
use washdyn_model::geom::{V, f};
use washdyn_model::ir::modal::{ModalData, point_at};
use washdyn_model::ir::{BodyRef, Model};

/// Radius of the door ring about the drum axis, m: the tub's front opening where the gasket's
/// bellows is clamped (reference machine: tub radius 0.27 m, ring at 0.25 m).
pub const DOOR_RING_RADIUS: f64 = 0.25;
/// Points on the door ring, 45 degrees apart from +z towards +y (for a drum axis along +x).
pub const DOOR_RING_POINTS: usize = 8;

/// Everything watched beside the tub's rigid motion, with a note per item for the summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Watch {
    /// The first of the floating frame's six rigid coordinates in q (u, alpha): what the
    /// monitor's translation and rotation bounds read.
    pub frame: usize,
    pub door_ring: Option<DoorRing>,
    pub drum_gap: Option<DrumGap>,
    pub notes: Vec<String>,
}

impl Watch {
    /// The door ring and the drum-tub gap of a model in a scene (its equations).
    pub fn new(model: &Model, eq: &Equations) -> Watch {
        let door_ring = DoorRing::new(model, eq);
        let mut notes = vec![door_ring.as_ref().map_or_else(
            || "door ring: not watched (no gasket on the tub or no rotor `drum`)".to_string(),
            |d| d.note.clone(),
        )];
        let drum_gap = match DrumGap::new(model, eq) {
            Ok(g) => {
                notes.push(g.note.clone());
                Some(g)
            }
            Err(why) => {
                notes.push(why);
                None
            }
        };
        Watch {
            frame: eq.bodies.floating().0,
            door_ring,
            drum_gap,
            notes,
        }
    }
}

/// The force elements' ends on the tub, as markers on its frame (rigid motion only): the
/// validity monitor's element deflections (`Guard::elements`).
pub fn element_tub_ends(model: &Model, eq: &Equations) -> Vec<(String, MarkerDef)> {
    let on_tub = |name: &str, ends: [(BodyRef, [f64; 3]); 2]| {
        ends.into_iter()
            .find(|(b, _)| *b == BodyRef::Tub)
            .map(|(b, p)| (name.to_string(), eq.bodies.frame_marker(b, p)))
    };
    let m = model;
    let springs = m.springs.iter().map(|e| (&e.name, &e.a, &e.b));
    let dampers = m.dampers.iter().map(|e| (&e.name, &e.a, &e.b));
    let friction = m.friction_dampers.iter().map(|e| (&e.name, &e.a, &e.b));
    let mut out: Vec<_> = springs
        .chain(dampers)
        .chain(friction)
        .filter_map(|(n, a, b)| on_tub(n, [(a.body, a.point), (b.body, b.point)]))
        .collect();
    out.extend(
        m.gaskets
            .iter()
            .filter_map(|g| on_tub(&g.name, [(g.a, g.point), (g.b, g.point)])),
    );
    out
}

/// A tub point watched for its displacement: the body layer's marker there (with the tub's
/// modal rows where its data has a point).
#[derive(Clone, Debug, PartialEq)]
pub struct WatchPoint {
    pub name: String,
    pub at: MarkerDef,
}

impl WatchPoint {
    /// u + alpha x s (+ W q).
    pub fn displacement(&self, q: &[f64]) -> [f64; 3] {
        self.at.displacement(q)
    }
}

/// The door ring's points.
#[derive(Clone, Debug, PartialEq)]
pub struct DoorRing {
    pub points: Vec<WatchPoint>,
    /// What was watched, for the summary.
    pub note: String,
}

impl DoorRing {
    /// Around the first gasket's tub end, about the drum's axis; `None` without a gasket on the
    /// tub or a rotor `drum`.
    pub fn new(model: &Model, eq: &Equations) -> Option<DoorRing> {
        let g = model
            .gaskets
            .iter()
            .find(|g| g.a == BodyRef::Tub || g.b == BodyRef::Tub)?;
        let drum = model.drum()?;
        let (_, b1, b2) = frame(drum.axis);
        let tub = eq.modes(BodyRef::Tub);
        let mut elastic = Vec::new();
        let points = (0..DOOR_RING_POINTS)
            .map(|k| {
                let th = 2.0 * std::f64::consts::PI * k as f64 / DOOR_RING_POINTS as f64;
                let r = f::add(
                    scale(b1, DOOR_RING_RADIUS * th.cos()),
                    scale(b2, DOOR_RING_RADIUS * th.sin()),
                );
                let p = f::add(g.point, r);
                let modal = tub
                    .and_then(|t| point_at(t.data(), p).map(|mp| (t, mp.name.clone())))
                    .map(|(t, name)| {
                        elastic.push(name);
                        t.rows(p)
                    });
                let mut at = eq.bodies.frame_marker(BodyRef::Tub, p);
                at.modal = modal;
                WatchPoint {
                    name: format!("door_ring_{k}"),
                    at,
                }
            })
            .collect();
        let how = match (tub, elastic.len()) {
            (None, _) => "rigid tub".to_string(),
            (Some(_), 0) => "elastic tub, rigid motion only (no modal point on the ring)".into(),
            (Some(_), n) => format!(
                "elastic tub: modes at {n} of them ({}), rigid motion only elsewhere",
                elastic.join(", ")
            ),
        };
        Some(DoorRing {
            points,
            note: format!(
                "door ring: {DOOR_RING_POINTS} points at r {DOOR_RING_RADIUS} m about the drum \
                 axis around gasket `{}` at x {} m; {how}",
                g.name, g.point[0]
            ),
        })
    }

    /// The largest displacement on the ring and its point.
    pub fn excursion(&self, q: &[f64]) -> (f64, usize) {
        let mut best = (0.0, 0);
        for (i, p) in self.points.iter().enumerate() {
            let v = f::norm(p.displacement(q));
            if v > best.0 {
                best = (v, i);
            }
        }
        best
    }
}

/// A drum edge point: rest offset from the drum's mount (drum frame = global at angle 0) and,
/// on the elastic drum, its modal rows (drum frame).
#[derive(Clone, Debug, PartialEq)]
pub struct EdgePoint {
    pub name: String,
    pub x: [f64; 3],
    pub modal: Option<ModalRows>,
}

/// A tub ring point: its angle about the drum axis and its modal rows (elastic tub).
#[derive(Clone, Debug, PartialEq)]
pub struct RingPoint {
    pub name: String,
    pub angle: f64,
    pub modal: ModalRows,
}

/// The drum-tub gap at the drum's front edge.
#[derive(Clone, Debug, PartialEq)]
pub struct DrumGap {
    /// Radial clearance at rest, m.
    pub clearance: f64,
    /// Unit drum axis and two unit vectors normal to it (angles: atan2(. b2, . b1)).
    pub axis: [f64; 3],
    pub b1: [f64; 3],
    pub b2: [f64; 3],
    /// Drum angle / drive angle.
    pub ratio: f64,
    pub edge: Vec<EdgePoint>,
    /// The tub's modes at the drum's mount (elastic tub).
    pub mount: Option<ModalRows>,
    /// Sorted by angle; empty on the rigid tub or without TUB_RING points.
    pub ring: Vec<RingPoint>,
    /// What was watched, for the summary.
    pub note: String,
}

/// The modal data's points named `PREFIX_k`, k = 0.. (in order, stopping at the first gap).
fn named_points<'a>(
    d: &'a ModalData,
    prefix: &str,
) -> Vec<&'a washdyn_model::ir::modal::ModalPoint> {
    (0..)
        .map_while(|k| d.point(&format!("{prefix}_{k}")))
        .collect()
}

impl DrumGap {
    /// From the drum's DRUM_EDGE_k and the tub's TUB_RING_k; `None` without a rotor `drum` or
    /// without drum edge points in the model's drum data (the note says why).
    pub fn new(model: &Model, eq: &Equations) -> Result<DrumGap, String> {
        let drum = model
            .drum()
            .ok_or("drum-tub gap: not watched (no rotor `drum`)")?;
        let data = |b: BodyRef| model.elastic_of(b).and_then(|e| e.data.as_ref());
        let edge_pts = data(BodyRef::Drum).map_or(Vec::new(), |d| named_points(d, "DRUM_EDGE"));
        if edge_pts.is_empty() {
            return Err(
                "drum-tub gap: not watched (the drum's modal data has no DRUM_EDGE_k \
                        points)"
                    .into(),
            );
        }
        let (axis, b1, b2) = frame(drum.axis);
        let mount_p = drum.mount_point();
        let tub = eq.modes(BodyRef::Tub);
        let edrum = eq.elastic_drum();
        let edge: Vec<EdgePoint> = edge_pts
            .iter()
            .map(|p| EdgePoint {
                name: p.name.clone(),
                x: f::sub(p.position, mount_p),
                modal: edrum.map(|d| d.modes.rows(p.position)),
            })
            .collect();
        let ring_pts = data(BodyRef::Tub).map_or(Vec::new(), |d| named_points(d, "TUB_RING"));
        let radius = |p: [f64; 3]| f::norm(reject(f::sub(p, drum.axis_point), axis));
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let r_drum = mean(
            &edge_pts
                .iter()
                .map(|p| radius(p.position))
                .collect::<Vec<_>>(),
        );
        let clearance = if ring_pts.is_empty() {
            None
        } else {
            let r_tub = mean(
                &ring_pts
                    .iter()
                    .map(|p| radius(p.position))
                    .collect::<Vec<_>>(),
            );
            Some(r_tub - r_drum)
        };
        let angle = |p: [f64; 3]| {
            let r = f::sub(p, drum.axis_point);
            dot(r, b2).atan2(dot(r, b1))
        };
        let mut ring: Vec<RingPoint> = match tub {
            Some(t) => ring_pts
                .iter()
                .map(|p| RingPoint {
                    name: p.name.clone(),
                    angle: angle(p.position),
                    modal: t.rows(p.position),
                })
                .collect(),
            None => Vec::new(),
        };
        ring.sort_by(|a, b| a.angle.total_cmp(&b.angle));
        let Some(clearance) = clearance else {
            return Err(format!(
                "drum-tub gap: not watched (the tub's modal data has no TUB_RING_k points to \
                 measure the clearance from the drum's {} DRUM_EDGE_k at r {r_drum:.3} m)",
                edge.len()
            ));
        };
        let drum_how = if edrum.is_some() {
            "elastic drum"
        } else {
            "rigid drum"
        };
        let tub_how = match tub {
            Some(_) => "elastic tub (modes at the bearing and at the ring)",
            None => "rigid tub",
        };
        Ok(DrumGap {
            clearance,
            axis,
            b1,
            b2,
            ratio: drum.ratio,
            mount: tub.map(|t| t.rows(mount_p)),
            ring,
            note: format!(
                "drum-tub gap: {} DRUM_EDGE_k (r {r_drum:.3} m) against {} TUB_RING_k, \
                 clearance {clearance:.4} m; {drum_how}, {tub_how}{}",
                edge.len(),
                ring_pts.len(),
                if edrum.is_none() && tub.is_none() {
                    ": the gap cannot change"
                } else {
                    ""
                }
            ),
            edge,
        })
    }

    /// The largest closure of the gap (radial motion of a drum edge point towards the tub ring
    /// opposite it, m) at drive angle `phi` and state q, and its edge point.
    pub fn closure(&self, phi: f64, q: &[f64]) -> (f64, usize) {
        let th = phi * self.ratio;
        let (c, s) = (th.cos(), th.sin());
        let e = V::<f64>(self.axis);
        let mut best = (f64::NEG_INFINITY, 0);
        for (i, p) in self.edge.iter().enumerate() {
            // Where the edge point is now (relative to the mount) and its outward direction.
            let r = rotate(e, c, s, V(p.x));
            let er = r.reject(e);
            let er = er.scale(1.0 / er.norm());
            let mut d = V::<f64>::zero();
            if let Some(rows) = &p.modal {
                d = d + rotate(e, c, s, rows.motion(q).0);
            }
            if let Some(rows) = &self.mount {
                let (w, ph) = rows.motion(q);
                d = d + w + ph.cross(r);
            }
            d = d - self.ring_motion(er.dot(V(self.b2)).atan2(er.dot(V(self.b1))), q);
            let v = d.dot(er);
            if v > best.0 {
                best = (v, i);
            }
        }
        best
    }

    /// The tub ring's elastic displacement at an angle: linear between its two neighbouring
    /// points (cyclic); zero without ring points.
    fn ring_motion(&self, angle: f64, q: &[f64]) -> V<f64> {
        let n = self.ring.len();
        if n == 0 {
            return V::zero();
        }
        let tau = 2.0 * std::f64::consts::PI;
        // The last point at or before `angle` (cyclic), and the next.
        let j = match self.ring.iter().rposition(|p| p.angle <= angle) {
            Some(j) => j,
            None => n - 1,
        };
        let k = (j + 1) % n;
        let (a0, mut a1) = (self.ring[j].angle, self.ring[k].angle);
        let mut x = angle;
        if a1 <= a0 {
            a1 += tau;
        }
        if x < a0 {
            x += tau;
        }
        let lam = if n == 1 { 0.0 } else { (x - a0) / (a1 - a0) };
        let (d0, d1) = (
            self.ring[j].modal.motion(q).0,
            self.ring[k].modal.motion(q).0,
        );
        d0.scale(1.0 - lam) + d1.scale(lam)
    }
}

fn scale(a: [f64; 3], k: f64) -> [f64; 3] {
    a.map(|x| x * k)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn reject(a: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    f::sub(a, scale(n, dot(a, n)))
}

/// Unit axis e and two unit vectors normal to it: b1 along +z's part normal to e (+y when e is
/// vertical), b2 = b1 x e; angles count from b1 towards b2 (for e = +x: from +z towards +y, as
/// the FE models number their ring node sets).
fn frame(axis: [f64; 3]) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let e = f::unit(axis);
    let mut b = reject([0.0, 0.0, 1.0], e);
    if f::norm(b) < 1e-6 {
        b = reject([0.0, 1.0, 0.0], e);
    }
    let b1 = f::unit(b);
    (e, b1, f::cross(b1, e))
}
