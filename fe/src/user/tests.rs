//! The spinning user body's spec: the axis it turns about and the modal data it writes.

use super::*;
use crate::bodies::geometry::polar_bricks;
use crate::mesh::{Material, Mesh, Section};
use std::f64::consts::PI;

/// The drum of tests/user_spinning.rs (back plate and wall about the x axis through
/// z = 0.45 m; coarser round the axis), as a deck in mm-t-s beside its spec (and in SI, for
/// a deck declared in the wrong units), with a one-node set TIP.
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
    m.add_to_set("TIP", &hub[..1]);
    m.fixed.push(("HUB".into(), 1, 3));
    let mm = inp::in_units(&m, Units::MmTS);
    std::fs::write(dir.join("drum.inp"), mm.deck(10).text()).unwrap();
    std::fs::write(dir.join("drum_si.inp"), m.deck(10).text()).unwrap();
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

/// What `load` refuses before any solve, each at its line: `problem` of the spec `text` (the
/// drum's spec edited) in `dir`.
fn refused_spec(dir: &Path, text: &str) -> SpecError {
    let p = dir.join("drum.toml");
    std::fs::write(&p, text).unwrap();
    match load(&p) {
        Err(Error::Spec(e)) => e,
        other => panic!("{:?}", other.map(|b| b.name)),
    }
}

#[test]
fn a_deck_in_other_units_than_declared_is_refused_naming_the_units_it_fits() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    drum_deck(dir);
    let good = spec("[0.0, 0.0, 0.45]", "[1.0, 0.0, 0.0]");
    // The mm-t-s deck declared SI: a drum of grams 450 m from the origin.
    let e = refused_spec(dir, &good.replace("units = \"mm-t-s\"", "units = \"SI\""));
    let SpecProblem::Units { read, fits } = &e.problem else {
        panic!("{e}")
    };
    assert_eq!((e.line, read.units), (Some(3), Units::Si));
    assert!(read.mass < 0.1 && read.cog > 400.0, "{e}");
    assert_eq!(fits.len(), 1);
    assert!((fits[0].mass / read.mass - 1e3).abs() < 1e-9 && fits[0].units == Units::MmTS);
    let m = e.to_string();
    assert!(
        m.contains("drum.toml:3: units = \"SI\": read in these units the deck weighs")
            && m.contains("if the deck is in mm-t-s, write units = \"mm-t-s\""),
        "{m}"
    );
    // The SI deck declared mm-t-s (issue 50: refused after 278 s of ccx, naming the mass only).
    let e = refused_spec(dir, &good.replace("drum.inp", "drum_si.inp"));
    let SpecProblem::Units { read, fits } = &e.problem else {
        panic!("{e}")
    };
    assert!(
        read.mass > 1e3 && fits.len() == 1 && fits[0].units == Units::Si,
        "{e}"
    );
    assert!(e.to_string().contains("write units = \"SI\""), "{e}");
}

#[test]
fn spec_mistakes_the_modal_data_would_refuse_are_refused_before_ccx() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    drum_deck(dir);
    let good = spec("[0.0, 0.0, 0.45]", "[1.0, 0.0, 0.0]");
    let line = |text: &str, needle: &str, n: usize| {
        text.lines()
            .enumerate()
            .filter(|(_, l)| l.contains(needle))
            .nth(n)
            .map(|(i, _)| i + 1)
    };
    let points = "points = [{ name = \"BEARING\", nset = \"HUB\" }]\n";
    let with = |more: &str| good.replace(points, &format!("{points}{more}"));
    // A point in the deck's mm (1000x off the mesh).
    let text = good.replace(
        points,
        "points = [{ name = \"BEARING\", nset = \"HUB\" },\n  \
         { name = \"RIM\", at = [100.0, 0.0, 626.0] }]\n",
    );
    let e = refused_spec(dir, &text);
    assert!(
        matches!(&e.problem, SpecProblem::PointOffMesh { point, .. } if point == "RIM"),
        "{e}"
    );
    assert_eq!(e.line, line(&text, "RIM", 0));
    assert!(
        e.to_string().contains("outside the deck's nodes")
            && e.to_string().contains("SI units (m)")
    );
    // A name twice: at the second.
    let text = good.replace(
        points,
        "points = [{ name = \"BEARING\", nset = \"HUB\" },\n  \
         { name = \"BEARING\", at = [0.0, 0.0, 0.275] }]\n",
    );
    let e = refused_spec(dir, &text);
    assert!(matches!(&e.problem, SpecProblem::DuplicatePoint { point } if point == "BEARING"));
    assert_eq!(e.line, line(&text, "BEARING", 1));
    assert!(e.to_string().contains("named twice"), "{e}");
    // Correction directions: none, and not a unit vector (the remedy gives it).
    for (d, words) in [
        ("[0.0, 0.0, 0.0]", "is no direction"),
        ("[0.0, 0.0, 2.0]", "write the unit vector, [0.0, 0.0, 1.0]"),
    ] {
        let text = with(&format!(
            "correction = [\n  {{ point = \"BEARING\", direction = [1.0, 0.0, 0.0] }},\n  \
             {{ point = \"BEARING\", direction = {d} }},\n]\n"
        ));
        let e = refused_spec(dir, &text);
        assert!(
            matches!(
                &e.problem,
                SpecProblem::CorrectionDirection { index: 1, .. }
            ),
            "{e}"
        );
        assert_eq!(e.line, line(&text, "direction", 1));
        assert!(e.to_string().contains(words), "{e}");
    }
    // A moment at a one-node set.
    let text = good.replace(
        points,
        "points = [{ name = \"BEARING\", nset = \"HUB\" }, { name = \"TIP\", nset = \"TIP\" }]\n\
         correction = [{ point = \"TIP\", direction = [1.0, 0.0, 0.0], kind = \"moment\" }]\n",
    );
    let e = refused_spec(dir, &text);
    assert!(
        matches!(&e.problem, SpecProblem::MomentOnFewNodes { nodes: 1, .. }),
        "{e}"
    );
    // The spin beyond the machine's speed, and its axis point along the axis 20 m away.
    let e = refused_spec(dir, &good.replace("1400.0", "5000.0"));
    assert!(
        matches!(e.problem, SpecProblem::SpinSpeed { .. }) && e.line == Some(14),
        "{e}"
    );
    let e = refused_spec(dir, &spec("[20.0, 0.0, 0.45]", "[1.0, 0.0, 0.0]"));
    assert!(
        matches!(e.problem, SpecProblem::SpinAxisPoint { .. }) && e.line == Some(12),
        "{e}"
    );
}
