//! The `machine!` front end fills the same IR as the TOML front end.

use washdyn_model::ir::check::check;
use washdyn_models::{compact, reference};

/// Equal models, or a panic naming the differing top-level fields and list items (a model
/// with modal data prints megabytes).
fn assert_same(a: &washdyn_model::ir::Model, b: &washdyn_model::ir::Model) {
    let (va, vb) = (
        serde_json::to_value(a).unwrap(),
        serde_json::to_value(b).unwrap(),
    );
    let mut diffs = Vec::new();
    for (k, x) in va.as_object().unwrap() {
        let y = &vb[k];
        if x == y {
            continue;
        }
        match (x.as_array(), y.as_array()) {
            (Some(xs), Some(ys)) if xs.len() == ys.len() => {
                for (i, (p, q)) in xs.iter().zip(ys).enumerate() {
                    if p != q {
                        let fields: Vec<&String> = p
                            .as_object()
                            .map(|o| o.keys().filter(|f| p[*f] != q[*f]).collect())
                            .unwrap_or_default();
                        diffs.push(format!("{k}[{i}]: {fields:?}"));
                    }
                }
            }
            _ => diffs.push(k.clone()),
        }
    }
    assert!(diffs.is_empty(), "models differ in {diffs:?}");
}

#[test]
fn declared_reference_equals_the_toml_file() {
    // Data files are relative to each front end's base: compare which file, not the path.
    let files = |mut m: washdyn_model::ir::Model| {
        let name = |f: &str| f.rsplit('/').next().unwrap_or_default().to_string();
        for e in &mut m.elastic {
            e.file = name(&e.file);
            e.bare = e.bare.as_deref().map(name);
            e.curves = e.curves.as_deref().map(name);
        }
        m
    };
    assert_eq!(
        files(reference::model()),
        files(washdyn_models::reference())
    );
}

#[test]
fn compact_differs_from_the_reference_exactly_where_declared() {
    let c = compact::model();
    check(&c).expect("the compact machine passes the checker");

    // Undo the declared changes; what remains must be the reference file.
    let mut undone = c.clone();
    assert_eq!(undone.name, "compact");
    undone.name = "reference".into();

    let drum = undone.rotors.iter_mut().find(|r| r.name == "drum").unwrap();
    assert_eq!(drum.polar_inertia, 0.155);
    drum.polar_inertia = 0.232;

    let test_mass = undone
        .unbalances
        .iter_mut()
        .find(|u| u.name == "test_mass")
        .unwrap();
    assert_eq!(test_mass.position, [0.15, 0.0, 0.66]);
    test_mass.position = [0.15, 0.0, 0.69];

    for (name, preload, l0_ref) in [
        ("spring_rear_left", 147.15, 0.1632125),
        ("spring_rear_right", 147.15, 0.1632125),
        ("spring_front", 245.25, 0.1386875),
    ] {
        let s = undone.springs.iter_mut().find(|s| s.name == name).unwrap();
        assert_eq!(s.stiffness, 5000.0);
        // Free length keeps the tub's rest position: 0.2 m between the attachment points.
        assert!(
            (s.free_length - (0.2 - preload / 5000.0)).abs() < 1e-12,
            "{name}"
        );
        s.stiffness = 4000.0;
        s.free_length = l0_ref;
    }

    let rim = undone
        .sensors
        .iter()
        .position(|s| s.name == "drum_rim")
        .unwrap();
    assert_eq!(undone.sensors[rim].point, [0.17, 0.0, 0.69]);
    undone.sensors.remove(rim);

    let reference = washdyn_models::reference();
    for name in [
        "elastic",
        "elastic_fine",
        "elastic_rigid_tub",
        "panel_curves",
        "cabinet_counterweights",
    ] {
        let scene = undone.scenes.iter_mut().find(|s| s.name == name).unwrap();
        assert!(
            !scene
                .effects
                .iter()
                .any(|e| e == "elastic.tub" || e == "elastic.drum")
        );
        *scene = reference
            .scenes
            .iter()
            .find(|s| s.name == name)
            .unwrap()
            .clone();
    }

    // The base's data files resolve relative to the base file (`../fe`) there, to the crate
    // (`fe`) here.
    for e in &mut undone.elastic {
        e.file = format!("../{}", e.file);
        e.bare = e.bare.as_ref().map(|b| format!("../{b}"));
        e.curves = e.curves.as_ref().map(|c| format!("../{c}"));
    }
    assert_same(&undone, &reference);
}

#[test]
fn compact_spring_preloads_carry_the_tub() {
    // Static balance at the reference position: sum of k (L - L0) = m g with L = 0.2 m.
    let c = compact::model();
    let total: f64 = c
        .springs
        .iter()
        .map(|s| s.stiffness * (0.2 - s.free_length))
        .sum();
    assert!((total - c.tub.mass * 9.81).abs() < 1e-9, "{total}");
}
