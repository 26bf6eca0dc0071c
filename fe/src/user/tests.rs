//! The spinning user body's spec: the axis it turns about and the modal data it writes.

use super::*;
use crate::bodies::geometry::polar_bricks;
use crate::mesh::{Material, Mesh, Section};
use std::f64::consts::PI;

/// The drum of tests/user_spinning.rs (back plate and wall about the x axis through
/// z = 0.45 m; coarser round the axis), as a deck in mm-t-s beside its spec.
fn drum_deck(dir: &Path) {
    let steel = Material {
        name: "STEEL".into(),
        e: 210e9,
        nu: 0.3,
        rho: 7850.0,
    };
    let mut m = Mesh::new("user drum");
    let (rs, xs) = ([0.03, 0.07, 0.12, 0.17, 0.176], [0.0, 0.008]);
    let plate = Section::ReducedSolid {
        material: steel.clone(),
    };
    polar_bricks(&mut m, "PLATE", &plate, 0.45, &rs, &xs, (0.0, 2.0 * PI, 12));
    let wall = Section::Solid { material: steel };
    let xs = [0.008, 0.075, 0.145, 0.215];
    polar_bricks(
        &mut m,
        "WALL",
        &wall,
        0.45,
        &rs[3..],
        &xs,
        (0.0, 2.0 * PI, 12),
    );
    let hub: Vec<usize> = (1..=m.nodes.len())
        .filter(|&i| {
            let p = m.nodes[i - 1];
            (p[1].hypot(p[2] - 0.45) - 0.03).abs() < 1e-9
        })
        .collect();
    m.add_to_set("HUB", &hub);
    m.fixed.push(("HUB".into(), 1, 3));
    let mm = inp::in_units(&m, Units::MmTS);
    std::fs::write(dir.join("drum.inp"), mm.deck(10).text()).unwrap();
}

fn spec(axis_point: &str, axis: &str) -> String {
    format!(
        "name = \"drum\"\ndeck = \"drum.inp\"\nunits = \"mm-t-s\"\nbody = \"drum\"\n\
         support = \"clamped\"\nsolve_modes = 10\nrecovery = false\n\
         keep = {{ max_hz = 1000.0, max_modes = 10 }}\n\
         points = [{{ name = \"BEARING\", nset = \"HUB\" }}]\n\n\
         [spin]\naxis_point = {axis_point}\naxis = {axis}\nreference_rpm = 1400.0\n"
    )
}

#[test]
fn a_spin_axis_off_the_drum_is_refused_at_its_line() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    drum_deck(dir);
    let load_with = |axis_point: &str, axis: &str| {
        let p = dir.join("drum.toml");
        std::fs::write(&p, spec(axis_point, axis)).unwrap();
        load(&p)
    };
    // The drum's own axis, in SI as the spec is: taken, the axis as given (made unit).
    let body = load_with("[0.0, 0.0, 0.45]", "[2.0, 0.0, 0.0]").unwrap();
    let s = body.spin.unwrap();
    assert_eq!((s.axis_point, s.axis), ([0.0, 0.0, 0.45], [1.0, 0.0, 0.0]));
    assert!((s.reference_speed - 1400.0 * PI / 30.0).abs() < 1e-12);
    // 5 mm off the drum's axis (3 % of its reach) is taken: the guard is for gross mistakes.
    load_with("[0.0, 0.0, 0.455]", "[1.0, 0.0, 0.0]").unwrap();
    // Gross mistakes, at the line of axis_point: the axis point in the deck's mm, the axis
    // through the origin instead of the drum's centre, the wrong direction.
    for (point, axis, share) in [
        ("[0.0, 0.0, 450.0]", "[1.0, 0.0, 0.0]", "100 %"),
        ("[0.0, 0.0, 0.0]", "[1.0, 0.0, 0.0]", "72 %"),
        ("[0.0, 0.0, 0.45]", "[0.0, 0.0, 1.0]", "26 %"),
    ] {
        let e = load_with(point, axis).unwrap_err();
        assert!(
            e.to_string().contains("drum.toml:12: spin: the axis")
                && e.to_string()
                    .contains(&format!("{share} of the body's reach"))
                && e.to_string().contains("SI units (m)"),
            "{e}"
        );
    }
}

#[test]
fn a_correction_order_other_than_one_or_two_is_refused_at_its_line() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    drum_deck(dir);
    let p = dir.join("drum.toml");
    let text = spec("[0.0, 0.0, 0.45]", "[1.0, 0.0, 0.0]").replace(
        "recovery = false\n",
        "recovery = false\ncorrection_order = 3\n",
    );
    std::fs::write(&p, text).unwrap();
    let e = load(&p).unwrap_err();
    assert!(
        e.to_string()
            .contains("drum.toml:8: correction_order is 1 (the static give) or 2"),
        "{e}"
    );
}

#[test]
fn modal_data_the_checker_would_refuse_is_not_written() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/fe/drum.modal.toml");
    let mut d = washdyn_model::ir::modal::read_file(&p, "drum.modal.toml").unwrap();
    assert!(refused(&d).is_empty(), "{:?}", refused(&d));
    // The axis point in mm, as an unguarded spec once wrote it.
    d.geometric_stiffness.as_mut().unwrap().axis_point = [0.0, 0.0, 450.0];
    let r = refused(&d);
    assert!(
        r.len() == 1 && r[0].starts_with("the modal data's geometric_stiffness.axis_point"),
        "{r:?}"
    );
}
