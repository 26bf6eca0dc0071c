//! Where a model attaches to each body: the points that must be modal points of the body's
//! data when it is elastic. The checker matches each against the data (`check::need_point`,
//! within `modal::POINT_TOLERANCE`), and the FE front end makes the body's points from the same
//! list (`washdyn fe deck` with a `model`, the built-in bodies), so the two never hold different lists.
//! It reads only the model, never its modal data: the data is what the list helps make.

use super::check::Path;
use super::{Attach, BodyRef, DRUM, Model, Scene, V3};

/// One point where the model attaches to a body.
#[derive(Clone, Debug, PartialEq)]
pub struct Attachment {
    /// Where the model states the point (for errors located in its file).
    pub path: Path,
    /// What attaches there, as errors name it: "springs `spring_front`", "sensor `tub1`".
    pub what: String,
    /// The model item's name (`<rotor>_mount` for a rotor's mount): the name the FE front end
    /// gives the point's node set.
    pub name: String,
    pub point: V3,
}

/// An element's name and its two ends (body, point, key).
type Ends<'a> = (&'a str, [(BodyRef, V3, &'a str); 2]);

/// Some scene makes `body` elastic (no declared scene: the implicit `full` has them all). A
/// body no scene uses constrains nothing: a variant may move an unbalance off the drum's node
/// sets and stay rigid.
pub fn used(m: &Model, body: BodyRef) -> bool {
    let effect = format!("elastic.{}", body.name());
    m.scenes.is_empty() || m.scenes.iter().any(|s| s.effects.contains(&effect))
}

/// Contacts count only in scenes that have both `contact` and the body elastic: a rigid
/// contact scene may put its points anywhere on a body other scenes make elastic.
fn contacts_used(m: &Model, body: BodyRef) -> bool {
    let effect = format!("elastic.{}", body.name());
    let both = |s: &Scene| s.effects.iter().any(|e| e == "contact") && s.effects.contains(&effect);
    (m.scenes.is_empty() && m.elastic_of(body).is_some()) || m.scenes.iter().any(both)
}

/// Some scene bolts the counterweights to the elastic tub (`counterweights` with
/// `elastic.tub`, which uses the tub's `bare` data).
pub fn bolts_used(m: &Model) -> bool {
    let both = |s: &Scene| {
        s.effects.iter().any(|e| e == "counterweights")
            && s.effects.iter().any(|e| e == "elastic.tub")
    };
    m.scenes.iter().any(both)
}

/// The bolted joints' points on the tub, which its `bare` data must hold where some scene
/// bolts the counterweights to the elastic tub (`bolts_used`); the FE front end names each
/// point's node set after its joint.
pub fn bolts(m: &Model) -> Vec<Attachment> {
    if !bolts_used(m) {
        return Vec::new();
    }
    m.bolted_joints
        .iter()
        .enumerate()
        .map(|(i, j)| Attachment {
            path: Path::of(&["bolted_joints"]).idx(i).key("point"),
            what: format!("bolted joint `{}`", j.name),
            name: j.name.clone(),
            point: j.point,
        })
        .collect()
}

/// Every point `body` must hold as a modal point where some scene makes it elastic, in the
/// model's order: on the tub and the cabinet the force elements' ends, gaskets, sensors and
/// (contact scenes) contacts, on the tub the rotors' mounts; on the drum its off-axis sensors
/// (a sensor on the axis moves with the mount) and the drum's unbalances.
pub fn attachments(m: &Model, body: BodyRef) -> Vec<Attachment> {
    let mut out = Vec::new();
    if !used(m, body) {
        return out;
    }
    let mut at = |path: Path, what: String, name: &str, point: V3| {
        out.push(Attachment {
            path,
            what,
            name: name.to_string(),
            point,
        })
    };
    if matches!(body, BodyRef::Tub | BodyRef::Cabinet) {
        let ends = |a: &Attach, b: &Attach| [(a.body, a.point, "a"), (b.body, b.point, "b")];
        let lists: [(&str, Vec<Ends>); 3] = [
            (
                "springs",
                m.springs
                    .iter()
                    .map(|s| (s.name.as_str(), ends(&s.a, &s.b)))
                    .collect(),
            ),
            (
                "dampers",
                m.dampers
                    .iter()
                    .map(|s| (s.name.as_str(), ends(&s.a, &s.b)))
                    .collect(),
            ),
            (
                "friction_dampers",
                m.friction_dampers
                    .iter()
                    .map(|s| (s.name.as_str(), ends(&s.a, &s.b)))
                    .collect(),
            ),
        ];
        for (list, items) in lists {
            for (i, (name, e)) in items.iter().enumerate() {
                for (b, point, key) in e {
                    if *b == body {
                        let path = Path::of(&[list]).idx(i).key(key).key("point");
                        at(path, format!("{list} `{name}`"), name, *point);
                    }
                }
            }
        }
        for (i, g) in m.gaskets.iter().enumerate() {
            if g.a == body || g.b == body {
                let path = Path::of(&["gaskets"]).idx(i).key("point");
                at(path, format!("gasket `{}`", g.name), &g.name, g.point);
            }
        }
        for (i, s) in m.sensors.iter().enumerate() {
            if s.body == body {
                let path = Path::of(&["sensors"]).idx(i).key("point");
                at(path, format!("sensor `{}`", s.name), &s.name, s.point);
            }
        }
        if contacts_used(m, body) {
            for (i, k) in m.contacts.iter().enumerate() {
                let p = Path::of(&["contacts"]).idx(i);
                let what = format!("contact `{}`", k.name);
                if k.a == body {
                    at(p.clone().key("point"), what.clone(), &k.name, k.point);
                }
                if k.b == body {
                    let key = if k.b_point.is_some() {
                        "b_point"
                    } else {
                        "point"
                    };
                    at(p.key(key), what, &k.name, k.b_point());
                }
            }
        }
    }
    if body == BodyRef::Tub {
        for (i, r) in m.rotors.iter().enumerate() {
            let key = if r.mount.is_some() {
                "mount"
            } else {
                "axis_point"
            };
            at(
                Path::of(&["rotors"]).idx(i).key(key),
                format!("rotor `{}`: mount", r.name),
                &format!("{}_mount", r.name),
                r.mount_point(),
            );
        }
    }
    if body == BodyRef::Drum
        && let Some(r) = m.drum()
    {
        // Off the axis the point turns with the drum, so the drum's modes are read there.
        for (i, s) in m.sensors.iter().enumerate() {
            if s.body == body && crate::geom::f::off_line(s.point, r.axis_point, r.axis) > 1e-3 {
                at(
                    Path::of(&["sensors"]).idx(i).key("point"),
                    format!("sensor `{}` (off the drum's axis)", s.name),
                    &s.name,
                    s.point,
                );
            }
        }
        for (j, u) in m.unbalances.iter().enumerate() {
            if u.rotor == DRUM {
                at(
                    Path::of(&["unbalances"]).idx(j).key("position"),
                    format!("unbalance `{}`", u.name),
                    &u.name,
                    u.position,
                );
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference machine's points per body, by name (its model file,
    /// models/data/reference.toml): the scenes that make the bodies elastic have no contacts,
    /// and the drum's one sensor sits on its axis.
    #[test]
    fn the_reference_machine_attaches_where_its_file_says() {
        let m = crate::ir::toml_file::reference_for_tests();
        let names = |b| -> Vec<String> { attachments(&m, b).into_iter().map(|a| a.name).collect() };
        let springs = ["spring_rear_left", "spring_rear_right", "spring_front"];
        let dampers = [
            "damper_front_left",
            "damper_front_right",
            "damper_rear_left",
            "damper_rear_right",
        ];
        let mut tub: Vec<&str> = [&springs[..], &dampers[..], &["door_gasket"]].concat();
        tub.extend([
            "tub1",
            "tub2",
            "tub3",
            "tub4",
            "tub5",
            "drum_mount",
            "motor_mount",
        ]);
        assert_eq!(names(BodyRef::Tub), tub);
        let mut cab: Vec<&str> = [&springs[..], &dampers[..], &["door_gasket"]].concat();
        cab.extend(["cabinet1", "cabinet2"]);
        assert_eq!(names(BodyRef::Cabinet), cab);
        assert_eq!(names(BodyRef::Drum), ["test_mass"]);
        let drum_mount = attachments(&m, BodyRef::Tub).remove(13);
        assert_eq!(drum_mount.point, [-0.25, 0.0, 0.45]);
        assert_eq!(drum_mount.path.to_string(), "rotors[0].mount");
    }

    /// Without its modal data (files that do not exist yet, as when the FE front end makes
    /// them) the model loads, checked, with the same points.
    #[test]
    fn the_points_need_no_modal_data() {
        let src = include_str!("../../../models/data/reference.toml").replace("../fe/", "none/");
        let files = crate::ir::files::DataFiles::Embedded(&[]);
        assert!(crate::ir::toml_file::load_with(&src, "r.toml", files).is_err());
        let m = crate::ir::toml_file::load_unresolved(&src, "r.toml", files).unwrap();
        assert!(m.elastic.iter().all(|e| e.data.is_none()));
        let full = crate::ir::toml_file::reference_for_tests();
        for b in BodyRef::ALL {
            assert_eq!(attachments(&m, b), attachments(&full, b));
        }
    }

    /// A scene with `contact` and the elastic cabinet puts the contacts' surface points on it;
    /// a model whose scenes leave the body rigid asks nothing of it.
    #[test]
    fn scenes_decide_what_a_body_must_hold() {
        let mut m = crate::ir::toml_file::reference_for_tests();
        let n = attachments(&m, BodyRef::Cabinet).len();
        m.scenes[0].effects.push("elastic.cabinet".into());
        m.scenes[0].effects.push("contact".into());
        let with = attachments(&m, BodyRef::Cabinet);
        assert_eq!(with.len(), n + 8);
        assert_eq!(with[n].point, [0.3, 0.0, 0.45]);
        m.scenes
            .retain(|s| !s.effects.iter().any(|e| e.starts_with("elastic.")));
        assert!(attachments(&m, BodyRef::Cabinet).is_empty());
    }
}
