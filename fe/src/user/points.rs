//! The points of a user's body: the spec's own (`points`) and, with a model, every point the
//! model attaches to the body (`ir::attachments`, the list the model checker matches against
//! the modal data), so the spec need not repeat the model's positions.

use super::{PointSpec, SpecError, SpecProblem};
use crate::mesh::Mesh;
use std::path::Path;
use washdyn_model::geom::f::{norm, sub};
use washdyn_model::ir::attachments::Attachment;
use washdyn_model::ir::modal::POINT_TOLERANCE;

/// Farthest a model point may lie from the deck's structure and still be read on a patch
/// about the nearest node, m: 1.6 x the farthest built-in patch (the tub's SPRING_3 lug point,
/// 0.094 m from its shell); a point in a hole, such as a gasket's centre (0.20 and 0.25 m from
/// the built-in cabinet's and tub's edges), needs the deck's set of that edge.
pub(super) const FAR: f64 = 0.15;

/// Where an error in the spec stands: `bad(needle, message)` names the spec's file and the line
/// of `needle`.
pub type Bad<'a> = &'a dyn Fn(&str, SpecProblem) -> SpecError;

/// The body's points as (node set, position): the spec's in its order, then each of the
/// model's attachments that no spec point covers, named after the model's item in upper case.
///
/// A spec point named as a model attachment (case-insensitive) is that attachment: read at the
/// model's position unless it gives `at`, which must lie within the checker's
/// `POINT_TOLERANCE` of it, or the spec and the model describe different machines. An
/// attachment within `POINT_TOLERANCE` of an earlier point is covered by it (the checker
/// matches by position). An attachment the spec does not map is read on the deck's node set of
/// its name, or else on a patch of the nodes near it (`bodies::patch`).
pub fn points(
    spec: &[PointSpec],
    model: &[Attachment],
    mesh: &mut Mesh,
    deck: &Path,
    bad: Bad,
) -> Result<Vec<(String, [f64; 3])>, SpecError> {
    let named = |name: &str| model.iter().find(|a| a.name.eq_ignore_ascii_case(name));
    let mut points: Vec<(String, [f64; 3])> = Vec::new();
    for p in spec {
        let line = format!("\"{}\"", p.name);
        let attach = named(&p.name);
        if p.at.is_some_and(|at| !at.iter().all(|v| v.is_finite())) {
            let point = p.name.clone();
            return Err(bad(&line, SpecProblem::PointNotFinite { point }));
        }
        let name = attach.map_or(p.name.clone(), |a| a.name.to_uppercase());
        let at = match (&p.nset, p.at, attach) {
            (Some(set), at, _) => {
                let ids = mesh
                    .nsets
                    .get(&set.to_uppercase())
                    .cloned()
                    .ok_or_else(|| {
                        let problem = SpecProblem::PointSet {
                            point: p.name.clone(),
                            deck: deck.to_path_buf(),
                            set: set.clone(),
                        };
                        bad(&format!("\"{set}\""), problem)
                    })?;
                if set.to_uppercase() != name {
                    mesh.add_to_set(&name, &ids);
                }
                // Read where the spec or the model attaches, or else at the set's centroid.
                at.or(attach.map(|a| a.point))
                    .unwrap_or_else(|| centroid(mesh, &ids))
            }
            (None, Some(at), _) => {
                crate::bodies::patch(mesh, &name, at);
                at
            }
            (None, None, _) => {
                let point = p.name.clone();
                return Err(bad(&line, SpecProblem::PointUnplaced { point }));
            }
        };
        if let Some(a) = attach {
            let off = norm(sub(at, a.point));
            if off > POINT_TOLERANCE {
                let problem = SpecProblem::PointOff {
                    point: p.name.clone(),
                    at,
                    off,
                    model: Box::new(a.clone()),
                };
                return Err(bad(&line, problem));
            }
        }
        points.push((name, at));
    }
    for a in model {
        let near = |(_, q): &(String, [f64; 3])| norm(sub(*q, a.point)) <= POINT_TOLERANCE;
        let name = a.name.to_uppercase();
        if points.iter().any(|(n, _)| *n == name) || points.iter().any(near) {
            continue;
        }
        let off = crate::bodies::set_or_patch(mesh, &name, a.point);
        if off > FAR {
            let model = Box::new(a.clone());
            return Err(bad("model =", SpecProblem::FarFromStructure { model, off }));
        }
        points.push((name, a.point));
    }
    Ok(points)
}

fn centroid(mesh: &Mesh, ids: &[usize]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &id in ids {
        for i in 0..3 {
            c[i] += mesh.nodes[id - 1][i] / ids.len() as f64;
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bodies::{cabinet::Cabinet, reference_model};
    use washdyn_model::ir::BodyRef;
    use washdyn_model::ir::attachments::attachments;

    fn spec(name: &str, nset: Option<&str>, at: Option<[f64; 3]>) -> PointSpec {
        PointSpec {
            name: name.into(),
            nset: nset.map(String::from),
            at,
        }
    }

    /// The reference cabinet from the model, the spec mapping only what a patch cannot stand
    /// for (the gasket's edge about the door opening, the dampers' brackets), and the cases the
    /// spec and the model disagree on.
    #[test]
    fn the_model_gives_the_points_the_spec_leaves_out() {
        let model = attachments(&reference_model(), BodyRef::Cabinet);
        let mesh = Cabinet::default().mesh();
        // The needle as the line: where `load` puts the line the needle is found on.
        let bad = |needle: &str, problem| SpecError {
            file: format!("spec.toml[{needle}]").into(),
            line: None,
            problem,
        };
        let deck = Path::new("deck.inp");
        let mut maps = vec![spec("door_gasket", Some("GASKET"), None)];
        for (k, d) in ["front_left", "front_right", "rear_left", "rear_right"]
            .iter()
            .enumerate()
        {
            let set = format!("DAMPER_{}", k + 1);
            maps.push(spec(&format!("damper_{d}"), Some(&set), None));
        }
        let mut m = mesh.clone();
        let got = points(&maps, &model, &mut m, deck, &bad).unwrap();
        let names: Vec<&str> = got.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "DOOR_GASKET",
                "DAMPER_FRONT_LEFT",
                "DAMPER_FRONT_RIGHT",
                "DAMPER_REAR_LEFT",
                "DAMPER_REAR_RIGHT",
                "SPRING_REAR_LEFT",
                "SPRING_REAR_RIGHT",
                "SPRING_FRONT",
                "CABINET1",
                "CABINET2"
            ]
        );
        // Each at the model's position, the mapped sets copied, the others patched.
        for ((_, p), a) in got[5..].iter().zip([0, 1, 2, 8, 9].map(|i| &model[i])) {
            assert_eq!(*p, a.point);
        }
        assert_eq!(got[0].1, [0.30, 0.0, 0.45]);
        assert_eq!(m.nsets["DOOR_GASKET"], m.nsets["GASKET"]);
        assert_eq!(m.nsets["SPRING_FRONT"].len(), {
            let mut p = mesh.clone();
            crate::bodies::patch(&mut p, "P", [0.12, 0.0, 0.82]);
            p.nsets["P"].len()
        });

        // A spec point of another name within 5 mm covers the model's point (the checker
        // matches by position): no second set there.
        let mut with = maps.clone();
        with.push(spec("S3", None, Some([0.12, 0.0, 0.824])));
        let got = points(&with, &model, &mut mesh.clone(), deck, &bad).unwrap();
        assert!(!got.iter().any(|(n, _)| n == "SPRING_FRONT"));

        // A spec point of the model's name 1 cm off its position is refused, at its line.
        let mut off = maps.clone();
        off.push(spec("spring_front", None, Some([0.12, 0.01, 0.82])));
        let err = points(&off, &model, &mut mesh.clone(), deck, &bad).unwrap_err();
        assert!(
            matches!(&err.problem, SpecProblem::PointOff { point, .. } if point == "spring_front")
        );
        let err = err.to_string();
        assert!(
            err.starts_with("spec.toml[\"spring_front\"]: point `spring_front`")
                && err.contains("10.0 mm from where the model puts it (springs `spring_front`")
                && err.contains("springs[2].b.point"),
            "{err}"
        );

        // Left to a patch, the gasket's point (the door opening's centre) is 0.20 m from the
        // nearest node: refused, naming the set to map.
        let err = points(&maps[1..], &model, &mut mesh.clone(), deck, &bad).unwrap_err();
        assert!(matches!(&err.problem, SpecProblem::FarFromStructure { .. }));
        let err = err.to_string();
        assert!(
            err.contains("gasket `door_gasket`") && err.contains("0.202 m"),
            "{err}"
        );
    }
}
