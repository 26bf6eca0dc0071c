//! The deck reader against the decks the writer writes, in both unit systems, and its refusals.
use super::*;
use crate::bodies::builtin;
use crate::mesh::{Material, Section};

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

fn same_section(a: &Section, b: &Section) -> bool {
    let mat = |a: &Material, b: &Material| {
        a.name == b.name && close(a.e, b.e) && close(a.nu, b.nu) && close(a.rho, b.rho)
    };
    match (a, b) {
        (
            Section::Shell {
                thickness: t,
                material: m,
            },
            Section::Shell {
                thickness: u,
                material: n,
            },
        ) => close(*t, *u) && mat(m, n),
        (Section::Solid { material: m }, Section::Solid { material: n })
        | (Section::ReducedSolid { material: m }, Section::ReducedSolid { material: n }) => {
            mat(m, n)
        }
        (
            Section::Beam {
                width: w,
                height: h,
                normal: d,
                material: m,
            },
            Section::Beam {
                width: v,
                height: g,
                normal: e,
                material: n,
            },
        ) => close(*w, *v) && close(*h, *g) && (0..3).all(|i| close(d[i], e[i])) && mat(m, n),
        (Section::Mass { kg: a }, Section::Mass { kg: b }) => close(*a, *b),
        (Section::Ground { dof: a, k: c }, Section::Ground { dof: b, k: d }) => {
            a == b && close(*c, *d)
        }
        _ => false,
    }
}

/// The mesh read back equals the one written: nodes (to the printed 13 digits), parts
/// with their sections and elements, node sets, rigid parts and the boundary.
fn assert_same(read: &Mesh, built: &Mesh) {
    assert_eq!(read.nodes.len(), built.nodes.len());
    for (p, q) in read.nodes.iter().zip(&built.nodes) {
        for i in 0..3 {
            assert!(
                (p[i] - q[i]).abs() <= 1e-12 * (1.0 + q[i].abs()),
                "{p:?} {q:?}"
            );
        }
    }
    assert_eq!(read.parts.len(), built.parts.len());
    for (a, b) in read.parts.iter().zip(&built.parts) {
        assert_eq!(a.name, b.name);
        assert!(
            same_section(&a.section, &b.section),
            "{:?} vs {:?}",
            a.section,
            b.section
        );
        assert_eq!(a.elements, b.elements, "part {}", a.name);
    }
    assert_eq!(read.nsets, built.nsets);
    assert_eq!(read.rigid, built.rigid);
    assert_eq!(read.fixed, built.fixed);
}

/// Every built-in body's deck, as the writer writes it (and models/fe/ keeps it), reads back
/// to the mesh it was written from.
#[test]
fn builtin_decks_read_back_to_their_meshes() {
    let dir = tempfile::tempdir().unwrap();
    for b in builtin() {
        let path = dir.path().join(format!("{}.inp", b.name));
        std::fs::write(&path, b.mesh.deck(b.solve_modes).text()).unwrap();
        let read = read(&path, Units::Si).unwrap_or_else(|e| panic!("{e}"));
        assert_same(&read, &b.mesh);
    }
}

/// The same mesh written in mm-t-s (coordinates and sizes in mm, E in MPa, density in
/// t/mm^3, masses in t, springs in N/mm) reads to the SI mesh.
#[test]
fn an_mm_t_s_deck_reads_to_the_si_mesh() {
    let dir = tempfile::tempdir().unwrap();
    for b in builtin() {
        let mm = in_units(&b.mesh, Units::MmTS);
        let path = dir.path().join(format!("{}_mm.inp", b.name));
        std::fs::write(&path, mm.deck(b.solve_modes).text()).unwrap();
        let read = read(&path, Units::MmTS).unwrap_or_else(|e| panic!("{e}"));
        assert_same(&read, &b.mesh);
    }
}

/// mm-t-s by the textbook's numbers, not by `in_units`: steel 210 000 MPa and 7.85e-9
/// t/mm^3, a node at 1000 mm, 1e-3 t, 1 N/mm, a 0.7 mm shell, a 10 x 20 mm bar.
#[test]
fn mm_t_s_numbers_read_as_si() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mm.inp");
    let text = "*NODE\n1, 0, 0, 0\n2, 500, 0, 0\n3, 1000, 0, 0\n\
        4, 0, 1000, 0\n5, 1000, 1000, 0\n6, 0, 500, 0\n7, 1000, 500, 0\n8, 500, 1000, 0\n\
        *ELEMENT, TYPE=B32, ELSET=ROD\n1, 1, 2, 3\n\
        *ELEMENT, TYPE=S8R, ELSET=SHEET\n2, 1, 3, 5, 4, 2, 7, 8, 6\n\
        *ELEMENT, TYPE=MASS, ELSET=PM\n3, 5\n*ELEMENT, TYPE=SPRING1, ELSET=FOOT\n4, 1\n\
        *MATERIAL, NAME=STEEL\n*ELASTIC\n210000, 0.3\n*DENSITY\n7.85e-9\n\
        *BEAM SECTION, ELSET=ROD, MATERIAL=STEEL, SECTION=RECT\n10, 20\n0, 0, 1\n\
        *SHELL SECTION, ELSET=SHEET, MATERIAL=STEEL\n0.7\n*MASS, ELSET=PM\n1e-3,\n\
        *SPRING, ELSET=FOOT\n3\n1.0,\n";
    std::fs::write(&path, text).unwrap();
    let m = read(&path, Units::MmTS).unwrap();
    assert_eq!(m.nodes[2], [1.0, 0.0, 0.0]);
    let steel = Material {
        name: "STEEL".into(),
        e: 2.1e11,
        nu: 0.3,
        rho: 7850.0,
    };
    let want = [
        Section::Beam {
            width: 0.01,
            height: 0.02,
            normal: [0.0, 0.0, 1.0],
            material: steel.clone(),
        },
        Section::Shell {
            thickness: 7e-4,
            material: steel,
        },
        Section::Mass { kg: 1.0 },
        Section::Ground { dof: 3, k: 1000.0 },
    ];
    for (part, w) in m.parts.iter().zip(&want) {
        assert!(
            same_section(&part.section, w),
            "{:?} vs {w:?}",
            part.section
        );
    }
}

fn deck_error(text: &str) -> InpError {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("user.inp");
    std::fs::write(&path, text).unwrap();
    read(&path, Units::Si).unwrap_err()
}

const NODES: &str = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 2, 0, 0\n";
const STEEL: &str = "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850\n";

/// What the pipeline cannot take is refused with the file and line, and what it is.
#[test]
fn unsupported_or_broken_decks_name_file_and_line() {
    let beam = format!(
        "{NODES}*ELEMENT, TYPE=B32, ELSET=ROD\n1, 1, 2, 3\n{STEEL}\
         *BEAM SECTION, ELSET=ROD, MATERIAL=STEEL, SECTION=RECT\n0.01, 0.02\n0, 0, 1\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let ok = dir.path().join("ok.inp");
    std::fs::write(&ok, &beam).unwrap();
    let m = read(&ok, Units::Si).unwrap();
    assert_eq!(
        (m.nodes.len(), m.parts[0].elements[0].clone()),
        (3, vec![1, 2, 3])
    );
    let cases: [(String, usize, &str); 8] = [
        (
            format!("{NODES}*ELEMENT, TYPE=C3D10, ELSET=T\n1, 1, 2, 3\n"),
            5,
            "element type C3D10 is not supported",
        ),
        (
            format!("{beam}*EQUATION\n2\n1, 1, 1.0, 2, 1, -1.0\n"),
            15,
            "*EQUATION is not supported",
        ),
        (
            format!(
                "{NODES}*ELEMENT, TYPE=B32, ELSET=ROD\n1, 1, 2, 9\n{STEEL}\
             *BEAM SECTION, ELSET=ROD, MATERIAL=STEEL, SECTION=RECT\n0.01, 0.02\n0, 0, 1\n"
            ),
            6,
            "node 9 is not defined",
        ),
        (
            format!("{NODES}*ELEMENT, TYPE=B32, ELSET=ROD\n1, 1, 2, 3\n"),
            6,
            "element 1 (B32) has no section",
        ),
        (
            format!(
                "{NODES}*ELEMENT, TYPE=B32, ELSET=ROD\n1, 1, 2, 3\n\
             *MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n\
             *BEAM SECTION, ELSET=ROD, MATERIAL=STEEL, SECTION=RECT\n0.01, 0.02\n0, 0, 1\n"
            ),
            10,
            "material `STEEL` has no *DENSITY",
        ),
        (
            format!("{NODES}*INCLUDE, INPUT=missing.inp\n"),
            0,
            "cannot read",
        ),
        (
            format!(
                "{NODES}*ELEMENT, TYPE=B32, ELSET=ROD\n1, 1, 2, 3\n{STEEL}\
             *BEAM SECTION, ELSET=ROD, MATERIAL=STEEL, SECTION=RECT\n0.01, -0.02\n0, 0, 1\n"
            ),
            13,
            "height must be positive",
        ),
        (format!("{NODES}4, nan, 0, 0\n"), 5, "coordinate is NaN"),
    ];
    // The refusals as their variants (what a caller matches), in the order of `cases`.
    let kinds: [fn(&InpProblem) -> bool; 8] = [
        |p| matches!(p, InpProblem::UnsupportedElement { kind, .. } if kind == "C3D10"),
        |p| matches!(p, InpProblem::UnsupportedKeyword { keyword } if keyword == "*EQUATION"),
        |p| matches!(p, InpProblem::NoNode { id: 9 }),
        |p| matches!(p, InpProblem::NoSection { id: 1, .. }),
        |p| {
            matches!(
                p,
                InpProblem::MaterialLacks {
                    card: "*DENSITY",
                    ..
                }
            )
        },
        |p| matches!(p, InpProblem::Read(_)),
        |p| matches!(p, InpProblem::NotPositive { what: "height", .. }),
        |p| matches!(p, InpProblem::NotFinite { value, .. } if value.is_nan()),
    ];
    for ((text, line, want), kind) in cases.into_iter().zip(kinds) {
        let e = deck_error(&text);
        assert!(kind(&e.problem), "{e:?}");
        assert!(
            e.problem.to_string().contains(want),
            "want `{want}`, got: {e}"
        );
        assert_eq!(e.line, line, "{e}");
        if line > 0 {
            assert!(e.file.ends_with("user.inp"), "{e}");
        } else {
            assert!(e.file.ends_with("missing.inp"), "{e}");
        }
    }
}
