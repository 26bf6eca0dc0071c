//! The elastic bodies' rules: each `elastic` entry and its modal data, and what the model
//! attaches to an elastic body: its points on the body's FE node sets (`attached`), the rotors'
//! mounts on the elastic tub, the tub's mass against its parts, the elastic drum's rotor and
//! stiffening. Also the drum's one use as a body: it carries sensors only.

use super::{Ctx, Path};
use crate::ir::{Attach, BodyRef, DRUM, Model, V3, attachments, modal};

/// Elastic bodies: a known body once each, damping ratios in [0, 1) (the support springs' only
/// where the data has such springs), a Rayleigh beta >= 0, and modal data that is consistent in
/// itself and describes that body.
pub(super) fn elastic(c: &mut Ctx, m: &Model) {
    use modal::ElasticBodyKind as K;
    for (i, e) in m.elastic.iter().enumerate() {
        let p = Path::of(&["elastic"]).idx(i);
        let kind = match e.body() {
            Some(BodyRef::Tub) => Some(K::Tub),
            Some(BodyRef::Drum) => Some(K::Drum),
            Some(BodyRef::Cabinet) => Some(K::Cabinet),
            Some(BodyRef::DamperPart(_) | BodyRef::Counterweight(_)) | None => {
                let other = &e.name;
                c.err(
                    p.clone().key("name"),
                    format!("elastic `{other}`: not a body; one of tub, drum, cabinet"),
                );
                None
            }
        };
        if m.elastic[..i].iter().any(|o| o.name == e.name) {
            c.err(
                p.clone().key("name"),
                format!("elastic `{}`: declared twice", e.name),
            );
        }
        let what = format!("elastic `{}`: damping", e.name);
        c.non_negative(p.clone().key("damping"), &what, e.damping);
        if e.damping >= 1.0 {
            c.err(
                p.clone().key("damping"),
                format!("{what} is a ratio of critical below 1, got {}", e.damping),
            );
        }
        if e.modes == Some(0) {
            c.err(
                p.clone().key("modes"),
                format!("elastic `{}`: modes must be at least 1", e.name),
            );
        }
        if let Some(zs) = e.support_damping {
            let what = format!("elastic `{}`: support_damping", e.name);
            c.non_negative(p.clone().key("support_damping"), &what, zs);
            if zs >= 1.0 {
                c.err(
                    p.clone().key("support_damping"),
                    format!("{what} is a ratio of critical below 1, got {zs}"),
                );
            }
        }
        c.non_negative(
            p.clone().key("stiffness_damping"),
            &format!("elastic `{}`: stiffness_damping (s)", e.name),
            e.stiffness_damping,
        );
        let Some(d) = &e.data else {
            // Not read: `modal::resolve` has reported why.
            continue;
        };
        if e.support_damping.is_some() && d.support_springs.is_empty() {
            c.err(
                p.clone().key("support_damping"),
                format!(
                    "elastic `{}`: support_damping, but {} lists no support_springs",
                    e.name, e.file
                ),
            );
        }
        for problem in modal::problems(d) {
            c.err(
                p.clone().key("file"),
                format!("elastic `{}`: {}: {problem}", e.name, e.file),
            );
        }
        if kind.is_some_and(|k| k != d.body) {
            c.err(
                p.clone().key("file"),
                format!(
                    "elastic `{}`: {}: body: the file describes the {:?}",
                    e.name, e.file, d.body
                ),
            );
        }
        if let Some(b) = &e.bare {
            let bare_kind = e.bare_data.as_ref().map(|d| d.body);
            if kind != Some(K::Tub) || bare_kind.is_some_and(|k| k != K::Tub) {
                c.err(
                    p.clone().key("bare"),
                    format!(
                        "elastic `{}`: bare `{b}`: only the tub's data leave out counterweights",
                        e.name
                    ),
                );
            }
        }
    }
    drum_points(c, m);
    for body in [BodyRef::Cabinet, BodyRef::Tub, BodyRef::Drum] {
        attached(c, m, body);
    }
    rotor_mounts(c, m);
    tub_mass(c, m);
    bare_tub(c, m);
    elastic_drum(c, m);
}

/// Where a scene bolts the counterweights to the elastic tub: the tub's `bare` data hold every
/// tub point and each bolt's point, and with the counterweights they weigh what the tub's
/// `data` weigh (within `TUB_MASS_TOLERANCE`). The scene checker asks for the `bare` file.
fn bare_tub(c: &mut Ctx, m: &Model) {
    let Some(e) = m.elastic_of(BodyRef::Tub) else {
        return;
    };
    let Some(bare) = e.bare_data.as_ref().filter(|_| attachments::bolts_used(m)) else {
        return;
    };
    let mut points = attachments::attachments(m, BodyRef::Tub);
    points.extend(attachments::bolts(m));
    for a in points {
        need_point(c, bare, BodyRef::Tub, a.path, a.what, &a.point);
    }
    let Some(tied) = &e.data else {
        return;
    };
    let weights: f64 = m.counterweights.iter().map(|w| w.mass).sum();
    let total = bare.mass + weights;
    if (total / tied.mass - 1.0).abs() > TUB_MASS_TOLERANCE {
        let i = position_of(m, BodyRef::Tub).unwrap_or(0);
        c.err(
            Path::of(&["elastic"]).idx(i).key("bare"),
            format!(
                "elastic `tub`: bare `{}` ({:.3} kg) and the counterweights ({weights:.3} kg) \
                 weigh {total:.3} kg, the tub's `{}` {:.3} kg: more than {} % apart",
                e.bare.as_deref().unwrap_or(""),
                bare.mass,
                e.file,
                tied.mass,
                TUB_MASS_TOLERANCE * 100.0
            ),
        );
    }
}

/// The drum carries sensors only (anywhere: a rim sensor turns with it; see `BodyRef::Drum`).
fn drum_points(c: &mut Ctx, m: &Model) {
    let drum = m.drum();
    let ends = |a: &Attach, b: &Attach| [(a.body, "a"), (b.body, "b")];
    type End<'a> = (BodyRef, &'a str);
    let mut lists: Vec<(&str, usize, String, [End; 2])> = Vec::new();
    for (i, s) in m.springs.iter().enumerate() {
        lists.push(("springs", i, s.name.clone(), ends(&s.a, &s.b)));
    }
    for (i, s) in m.dampers.iter().enumerate() {
        lists.push(("dampers", i, s.name.clone(), ends(&s.a, &s.b)));
    }
    for (i, s) in m.friction_dampers.iter().enumerate() {
        lists.push(("friction_dampers", i, s.name.clone(), ends(&s.a, &s.b)));
    }
    for (i, g) in m.gaskets.iter().enumerate() {
        lists.push(("gaskets", i, g.name.clone(), [(g.a, "a"), (g.b, "b")]));
    }
    for (list, i, name, e) in lists {
        for (body, key) in e {
            if body == BodyRef::Drum {
                c.err(
                    Path::of(&[list]).idx(i).key(key),
                    format!("{list} `{name}`: force elements attach to the tub or the cabinet; the drum carries sensors only"),
                );
            }
        }
    }
    for (i, s) in m.sensors.iter().enumerate() {
        if s.body == BodyRef::Drum && drum.is_none() {
            c.err(
                Path::of(&["sensors"]).idx(i).key("body"),
                format!(
                    "sensor `{}`: on the drum, but the model has no rotor `drum`",
                    s.name
                ),
            );
        }
    }
}

/// The modal data of an elastic body that some scene switches on (`attachments::used`).
fn modal_of(m: &Model, body: BodyRef) -> Option<&modal::ModalData> {
    m.elastic_of(body)
        .filter(|_| attachments::used(m, body))
        .and_then(|e| e.data.as_ref())
}

/// Every point the model attaches to an elastic body (`attachments::attachments`, which says
/// where each counts) is one of its modal points (an FE node set), within
/// `modal::POINT_TOLERANCE`.
fn attached(c: &mut Ctx, m: &Model, body: BodyRef) {
    let Some(data) = m.elastic_of(body).and_then(|e| e.data.as_ref()) else {
        return;
    };
    for a in attachments::attachments(m, body) {
        need_point(c, data, body, a.path, a.what, &a.point);
    }
}

/// The index of a body's `elastic` entry (for error paths).
fn position_of(m: &Model, body: BodyRef) -> Option<usize> {
    m.elastic.iter().position(|e| e.body() == Some(body))
}

/// A point on an elastic body must be one of its modal points; the message names the nearest.
fn need_point(c: &mut Ctx, d: &modal::ModalData, body: BodyRef, path: Path, what: String, p: &V3) {
    let body = body.name();
    let dist = |a: V3, b: V3| crate::geom::f::norm(crate::geom::f::sub(a, b));
    if modal::point_at(d, *p).is_none() {
        let near = d
            .points
            .iter()
            .min_by(|a, b| dist(a.position, *p).total_cmp(&dist(b.position, *p)));
        c.err(
            path,
            format!(
                "{what}: the elastic {body} has no FE node set at {p:?}{}",
                near.map_or(String::new(), |q| format!(
                    " (nearest: {} at {:?})",
                    q.name, q.position
                ))
            ),
        );
    }
}

/// On the elastic tub every rotor sits at a tub node set (its mount), on its own axis.
fn rotor_mounts(c: &mut Ctx, m: &Model) {
    if modal_of(m, BodyRef::Tub).is_none() {
        return;
    }
    for (i, r) in m.rotors.iter().enumerate() {
        let p = Path::of(&["rotors"]).idx(i);
        let key = if r.mount.is_some() {
            "mount"
        } else {
            "axis_point"
        };
        let mp = r.mount_point();
        if crate::geom::f::off_line(mp, r.axis_point, r.axis) > 1e-3 {
            c.err(
                p.key(key),
                format!(
                    "rotor `{}`: mount {mp:?} is not on the rotor's axis (more than 1 mm off)",
                    r.name
                ),
            );
        }
        if !(r.mass.is_finite() && r.mass >= 0.0) {
            c.err(
                Path::of(&["rotors"]).idx(i).key("mass"),
                format!("rotor `{}`: mass must be >= 0, got {}", r.name, r.mass),
            );
        }
    }
}

/// Relative tolerance between the rigid tub's mass and the elastic tub's parts: the two
/// descriptions are one machine (rigid and elastic scenes side by side); 2 % is the agreement
/// the FE models were built to.
pub const TUB_MASS_TOLERANCE: f64 = 0.02;

/// The elastic tub carries the drum (its FE mass) and the other rotors' masses: together they
/// must be the rigid tub's mass, or one of the two descriptions is missing a part. The drum's
/// FE mass counts whenever the model has the drum's modal data, whether or not a scene makes
/// the drum elastic: the equations put it on the elastic tub either way (`Equations::new`).
fn tub_mass(c: &mut Ctx, m: &Model) {
    let Some(tub) = modal_of(m, BodyRef::Tub) else {
        return;
    };
    let drum_data = m.elastic_of(BodyRef::Drum).and_then(|e| e.data.as_ref());
    let drum = drum_data.map_or(0.0, |d| d.mass);
    let rotors: f64 = m
        .rotors
        .iter()
        .filter(|r| r.name != DRUM || drum_data.is_none())
        .map(|r| r.mass)
        .sum();
    let total = tub.mass + drum + rotors;
    if (total - m.tub.mass).abs() > TUB_MASS_TOLERANCE * m.tub.mass {
        let i = position_of(m, BodyRef::Tub).unwrap_or(0);
        c.err(
            Path::of(&["elastic"]).idx(i),
            format!(
                "elastic `tub`: FE tub {:.3} kg + drum {drum:.3} kg + rotors {rotors:.3} kg = \
                 {total:.3} kg, but the rigid tub has {} kg (more than {} % apart): add the \
                 drum's elastic entry or the rotors' `mass`, or correct `tub.mass`",
                tub.mass,
                m.tub.mass,
                TUB_MASS_TOLERANCE * 100.0
            ),
        );
    }
}

/// The elastic drum spins with the rotor `drum` and carries its unbalances at its node sets;
/// stiffening needs the geometric stiffness in its modal data.
fn elastic_drum(c: &mut Ctx, m: &Model) {
    let Some(i) = position_of(m, BodyRef::Drum) else {
        return;
    };
    if m.drum().is_none() {
        c.err(
            Path::of(&["elastic"]).idx(i).key("name"),
            "elastic `drum`: the model has no rotor `drum` to spin it".to_string(),
        );
    }
    let Some(d) = modal_of(m, BodyRef::Drum) else {
        return;
    };
    // The stress stiffening was computed for a spin about one axis: the model's rotor must
    // turn the drum about the same line (a unit axis; the point within the points' tolerance).
    if let (Some(k), Some(r)) = (&d.geometric_stiffness, m.drum()) {
        let (e, f) = (crate::geom::f::unit(r.axis), crate::geom::f::unit(k.axis));
        let dist = crate::geom::f::off_line(k.axis_point, r.axis_point, r.axis);
        let parallel = (crate::geom::f::norm(crate::geom::f::cross(e, f)) <= 1e-6)
            && crate::geom::f::dot(e, f) > 0.0;
        if !(parallel && dist <= crate::ir::modal::POINT_TOLERANCE) {
            c.err(
                Path::of(&["elastic"]).idx(i).key("file"),
                format!(
                    "{}: geometric_stiffness spins about {:?} through {:?}, the rotor `drum` \
                     about {:?} through {:?} ({:.3} m apart): the data was made for another axis",
                    m.elastic[i].file, k.axis, k.axis_point, r.axis, r.axis_point, dist
                ),
            );
        }
    }
    if d.geometric_stiffness.is_none() {
        for (j, s) in m.scenes.iter().enumerate() {
            if s.effects.iter().any(|e| e == "centrifugal_stiffening") {
                c.err(
                    Path::of(&["scenes"]).idx(j).key("effects"),
                    format!(
                        "scene `{}`: centrifugal_stiffening, but {} has no geometric_stiffness",
                        s.name, m.elastic[i].file
                    ),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::ir::BodyRef;
    use crate::ir::toml_file::reference_for_tests;

    /// Drum modal data made for another spin axis (a user's spec with the axis point off, or
    /// another model's drum) is refused; the reference's own passes.
    #[test]
    fn drum_data_for_another_axis_is_refused() {
        let ok = reference_for_tests();
        assert!(crate::ir::check::check(&ok).is_ok());
        for (shift, axis) in [
            ([0.0, 0.0, 0.05], [1.0, 0.0, 0.0]),
            ([0.0; 3], [0.0, 1.0, 0.0]),
        ] {
            let mut m = ok.clone();
            let e = m
                .elastic
                .iter_mut()
                .find(|e| e.body() == Some(BodyRef::Drum))
                .unwrap();
            let k = e
                .data
                .as_mut()
                .unwrap()
                .geometric_stiffness
                .as_mut()
                .unwrap();
            k.axis_point = crate::geom::f::add(k.axis_point, shift);
            k.axis = axis;
            let err = crate::ir::check::check(&m).unwrap_err();
            assert!(
                format!("{err:?}").contains("made for another axis"),
                "{err:?}"
            );
        }
    }
}
