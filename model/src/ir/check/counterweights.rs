//! The counterweights' and their bolted joints' rules: mass properties as the tub's; each joint
//! on a known counterweight with a non-zero axis, exactly one of preload and torque, the preload
//! not negative (zero: a loose bolt), positive stiffnesses; each counterweight held by at least
//! three bolts not on one line (fewer leave it a free rotation); and less mass than the tub.

use super::{Ctx, Names, Path, bodies::inertia, norm};
use crate::geom::f;
use crate::ir::{BoltedJoint, Model, V3};

pub(super) fn counterweights<'a>(c: &mut Ctx, names: &mut Names<'a>, m: &'a Model) {
    let mut total = 0.0;
    for (i, w) in m.counterweights.iter().enumerate() {
        let p = Path::of(&["counterweights"]).idx(i);
        names.add(c, p.clone(), "counterweight", &w.name);
        let who = format!("counterweight `{}`", w.name);
        c.positive(p.clone().key("mass"), &format!("{who}: mass"), w.mass);
        c.vec3(p.clone().key("cog"), &format!("{who}: cog"), &w.cog);
        inertia(c, p.clone().key("inertia"), &who, &w.inertia);
        total += w.mass;
        let bolts: Vec<V3> = m
            .bolted_joints
            .iter()
            .filter(|j| j.counterweight == w.name)
            .map(|j| j.point)
            .collect();
        if !spans_a_plane(&bolts) {
            c.err(
                p.key("name"),
                format!(
                    "{who}: held by {} bolted joint(s) {}; it needs three or more not on one \
                     line, or it turns freely about them",
                    bolts.len(),
                    if bolts.len() >= 3 { "on one line" } else { "" }
                ),
            );
        }
    }
    // A tub without mass is its own error (`bodies::tub`).
    if m.tub.mass > 0.0 && total >= m.tub.mass {
        c.err(
            Path::of(&["counterweights"]),
            format!(
                "the counterweights' {total} kg are the tub's {} kg or more: the tub's mass \
                 includes them",
                m.tub.mass
            ),
        );
    }
    for (i, j) in m.bolted_joints.iter().enumerate() {
        let p = Path::of(&["bolted_joints"]).idx(i);
        names.add(c, p.clone(), "bolted joint", &j.name);
        joint(c, p, m, j);
    }
}

/// At least three points, not all on one line.
fn spans_a_plane(pts: &[V3]) -> bool {
    let Some(&a) = pts.first() else { return false };
    pts.iter().any(|&b| {
        pts.iter().any(|&c| {
            let (u, v) = (f::sub(b, a), f::sub(c, a));
            f::norm(f::cross(u, v)) > 1e-6 * (1.0 + f::norm(u) * f::norm(v))
        })
    })
}

fn joint(c: &mut Ctx, p: Path, m: &Model, j: &BoltedJoint) {
    let who = format!("bolted joint `{}`", j.name);
    if !m.counterweights.iter().any(|w| w.name == j.counterweight) {
        c.err(
            p.clone().key("counterweight"),
            format!("{who}: no counterweight `{}`", j.counterweight),
        );
    }
    c.vec3(p.clone().key("point"), &who, &j.point);
    if c.finite(&p.clone().key("axis"), &who, &j.axis) && norm(&j.axis) < 1e-12 {
        c.err(
            p.clone().key("axis"),
            format!("{who}: axis is the zero vector"),
        );
    }
    match (j.preload, j.torque) {
        (Some(f), None) => c.non_negative(p.clone().key("preload"), &format!("{who}: preload"), f),
        (None, Some(t)) => {
            let q = p.clone().key("torque");
            let w = format!("{who}: torque");
            c.non_negative(q.clone().key("moment"), &format!("{w}.moment"), t.moment);
            for (k, v) in [
                ("pitch", t.pitch),
                ("pitch_diameter", t.pitch_diameter),
                ("head_diameter", t.head_diameter),
            ] {
                c.positive(q.clone().key(k), &format!("{w}.{k}"), v);
            }
            for (k, v) in [
                ("thread_friction", t.thread_friction),
                ("head_friction", t.head_friction),
            ] {
                c.non_negative(q.clone().key(k), &format!("{w}.{k}"), v);
            }
        }
        _ => c.err(
            p.clone().key("preload"),
            format!("{who}: give the preload (N) or the tightening torque, one of them"),
        ),
    }
    for (k, v) in [
        ("bolt_stiffness", j.bolt_stiffness),
        ("member_stiffness", j.member_stiffness),
        ("shear_stiffness", j.shear_stiffness),
    ] {
        c.positive(p.clone().key(k), &format!("{who}: {k}"), v);
    }
    c.non_negative(
        p.clone().key("friction"),
        &format!("{who}: friction"),
        j.friction,
    );
    c.non_negative(
        p.clone().key("bolt_bending_stiffness"),
        &format!("{who}: bolt_bending_stiffness"),
        j.bolt_bending_stiffness,
    );
    c.non_negative(
        p.clone().key("interface_diameter"),
        &format!("{who}: interface_diameter"),
        j.interface_diameter,
    );
    c.non_negative(p.key("damping"), &format!("{who}: damping"), j.damping);
}
