//! Malformed model files give errors that name the file line (and never panic or run).

use std::path::Path;
use washdyn_model::ir::toml_file::{load_str, read_speed_csv};

const REF: &str = washdyn_models::REFERENCE_TOML;

/// The reference file with the first occurrence of `from` replaced.
fn edited(from: &str, to: &str) -> String {
    assert!(
        REF.contains(from),
        "fixture text `{from}` not in the reference file"
    );
    REF.replacen(from, to, 1)
}

fn line_of(src: &str, needle: &str, nth: usize) -> usize {
    src.lines()
        .enumerate()
        .filter(|(_, l)| l.contains(needle))
        .nth(nth)
        .map(|(i, _)| i + 1)
        .expect("needle present")
}

/// Where the reference's relative data files resolve.
fn data_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("models/data")
}

fn errors(src: &str) -> Vec<(usize, String)> {
    let e = load_str(src, "m.toml", &data_dir()).expect_err("must be rejected");
    e.errors
        .iter()
        .map(|l| (l.line, l.message.clone()))
        .collect()
}

#[test]
fn reference_loads() {
    assert!(load_str(REF, "reference.toml", &data_dir()).is_ok());
}

#[test]
fn syntax_error_has_its_line() {
    let src = edited("mass = 55.0", "mass = 55.0.0");
    let e = errors(&src);
    assert_eq!(e[0].0, line_of(&src, "mass = 55.0.0", 0), "{e:?}");
}

#[test]
fn unknown_field_has_its_line() {
    let src = edited("free_length = 0.1386875", "free_lenght = 0.1386875");
    let e = errors(&src);
    assert_eq!(e[0].0, line_of(&src, "free_lenght", 0), "{e:?}");
    assert!(e[0].1.contains("free_lenght"), "{e:?}");
}

#[test]
fn checker_error_points_at_the_field_line() {
    // Second spring's stiffness negative: the error names the spring and sits on its line.
    let src = REF.replacen(
        "name = \"spring_rear_right\"\na = { body = \"tub\", point = [-0.10, -0.15, 0.62] }\nb = { body = \"cabinet\", point = [-0.10, -0.15, 0.82] }\nstiffness = 4000.0",
        "name = \"spring_rear_right\"\na = { body = \"tub\", point = [-0.10, -0.15, 0.62] }\nb = { body = \"cabinet\", point = [-0.10, -0.15, 0.82] }\nstiffness = -4000.0",
        1,
    );
    let e = errors(&src);
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].0, line_of(&src, "stiffness = -4000.0", 0), "{e:?}");
    assert!(
        e[0].1.contains("spring_rear_right") && e[0].1.contains("positive"),
        "{e:?}"
    );
}

#[test]
fn all_checker_errors_are_collected() {
    let src = edited("mass = 55.0", "mass = 0.0").replacen(
        "[15.0, 93.0], [178.375, 1400.0]",
        "[4.0, 93.0], [178.375, 1400.0]",
        1,
    );
    let e = errors(&src);
    // The tub's mass, the speed table, and (from the first) the elastic tub's parts no longer
    // adding up to the rigid tub.
    assert_eq!(e.len(), 3, "{e:?}");
    assert!(
        e.iter()
            .any(|(_, m)| m.contains("but the rigid tub has 0 kg")),
        "{e:?}"
    );
    assert!(
        e.iter()
            .any(|(l, m)| *l == line_of(&src, "mass = 0.0", 0) && m.contains("tub: mass"))
    );
    assert!(
        e.iter()
            .any(|(l, m)| *l == line_of(&src, "table = ", 0) && m.contains("strictly"))
    );
}

#[test]
fn gasket_asymmetry_and_unknown_rotor_are_reported() {
    let src = edited(
        "[0.0, 8000.0, 0.0, 0.0, 0.0, 600.0]",
        "[0.0, 8000.0, 0.0, 0.0, 0.0, 650.0]",
    )
    .replacen("rotor = \"motor\"", "rotor = \"motr\"", 1);
    let e = errors(&src);
    // The error sits on the row of the entry whose mirror differs ([5][1] for the edited [1][5]).
    let row5 = line_of(&src, "[0.0, 600.0, 0.0, 0.0, 0.0, 120.0]", 0);
    assert!(
        e.iter()
            .any(|(l, m)| *l == row5 && m.contains("door_gasket") && m.contains("not symmetric")),
        "{e:?}"
    );
    assert!(
        e.iter().any(|(l, m)| *l == line_of(&src, "rotor = \"motr\"", 0) && m.contains("unknown rotor")),
        "{e:?}"
    );
}

#[test]
fn unknown_body_and_scene_effect() {
    let src = edited(
        "body = \"tub\", point = [0.18, 0.18, 0.20]",
        "body = \"tubb\", point = [0.18, 0.18, 0.20]",
    );
    let e = errors(&src);
    assert_eq!(e[0].0, line_of(&src, "tubb", 0), "{e:?}");
    let src = edited("\"gasket_damping\"", "\"gasket_dampin\"");
    let e = errors(&src);
    assert!(e[0].1.contains("unknown effect `gasket_dampin`"), "{e:?}");
    assert_eq!(e[0].0, line_of(&src, "gasket_dampin\"", 0), "{e:?}");
}

#[test]
fn speed_csv_errors_have_lines() {
    let dir = std::env::temp_dir().join(format!("washdyn-csv-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("profile.csv");
    std::fs::write(&p, "time_s,rpm\n0,0\n5,93\n7,abc\n").unwrap();
    let e = read_speed_csv(&p).unwrap_err();
    assert_eq!(e.line, 4, "{e}");
    std::fs::write(&p, "time_s,rpm\n0,0\n5,93\n10,400\n").unwrap();
    assert_eq!(
        read_speed_csv(&p).unwrap(),
        vec![[0.0, 0.0], [5.0, 93.0], [10.0, 400.0]]
    );
    // A comment and a blank line before the header (an exported file's preamble): the header is
    // the first row that is not a comment, and errors still name the physical line.
    let q = dir.join("bench.csv");
    std::fs::write(
        &q,
        "# from the test bench\n\n\"time_s\",rpm\n0,0\n5,93\n7,x\n",
    )
    .unwrap();
    assert_eq!(read_speed_csv(&q).unwrap_err().line, 6);
    std::fs::write(&q, "# from the test bench\n\ntime_s,rpm\n0,0\n5,93\n").unwrap();
    assert_eq!(read_speed_csv(&q).unwrap(), vec![[0.0, 0.0], [5.0, 93.0]]);
    // A model that takes its profile from that file.
    let src = REF
        .replacen(
            "table = [[0.0, 0.0], [5.0, 93.0], [15.0, 93.0], [178.375, 1400.0]]",
            "csv = \"profile.csv\"",
            1,
        )
        .replace(
            "\"../fe/",
            &format!("\"{}/models/fe/", env!("CARGO_MANIFEST_DIR")),
        );
    let m = load_str(&src, "m.toml", &dir).unwrap();
    assert_eq!(m.speed.table.len(), 3);
    std::fs::remove_dir_all(&dir).ok();
}

/// Modal data files go through the one resolver and the one checker: a file of the wrong size
/// is reported at the model's `file = ..` line, naming the modal file and its field; a file
/// that is not TOML names its own line.
#[test]
fn modal_data_errors_name_the_model_line_the_file_and_the_field() {
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("macros/tests");
    let with = |file: &str| {
        format!("{REF}\n[[elastic]]\nname = \"cabinet\"\nfile = \"{file}\"\ndamping = 0.02\n")
    };
    let src = with("ui-data/cabinet_bad.modal.toml");
    let e = load_str(&src, "m.toml", &fixtures).expect_err("must be rejected");
    let line = line_of(&src, "file = \"ui-data/cabinet_bad", 0);
    assert!(
        e.errors.iter().any(|l| l.line == line
            && l.message
                .contains("ui-data/cabinet_bad.modal.toml: elementary.g[z][z]: expected 4")),
        "{e}"
    );
    let src = with("ui-data/cabinet_malformed.modal.toml");
    let e = load_str(&src, "m.toml", &fixtures).expect_err("must be rejected");
    assert!(
        e.errors
            .iter()
            .any(|l| l.line == line_of(&src, "cabinet_malformed", 0)
                && l.message.contains("cabinet_malformed.modal.toml:4:")),
        "{e}"
    );
    let src = with("no/such.modal.toml");
    let e = load_str(&src, "m.toml", &fixtures).expect_err("must be rejected");
    assert!(
        e.to_string().contains("no/such.modal.toml: cannot read"),
        "{e}"
    );
}

/// Each `[[elastic]]` rule refuses with a message at the entry's line: an unknown body, one
/// declared twice, a damping ratio outside [0, 1), zero modes or more than the file has, and a
/// cabinet marker that is not at one of its FE node sets.
#[test]
fn elastic_entries_are_checked_at_their_lines() {
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/data");
    let entry = |name: &str, extra: &str| {
        format!("\n[[elastic]]\nname = \"{name}\"\nfile = \"../fe/cabinet.modal.toml\"\n{extra}")
    };
    let refused = |src: &str, want: &str, at: &str| {
        let e = load_str(src, "m.toml", &base).expect_err("must be rejected");
        let line = line_of(src, at, 0);
        assert!(
            e.errors
                .iter()
                .any(|l| l.line == line && l.message.contains(want)),
            "{want} at line {line}: {e}"
        );
    };
    let src = format!("{REF}{}", entry("cabinett", ""));
    refused(
        &src,
        "elastic `cabinett`: not a body; one of tub, drum, cabinet",
        "\"cabinett\"",
    );
    let src = format!("{REF}{}{}", entry("cabinet", ""), entry("cabinet", ""));
    let e = load_str(&src, "m.toml", &base).expect_err("must be rejected");
    assert!(
        e.to_string().contains("elastic `cabinet`: declared twice"),
        "{e}"
    );
    let src = format!("{REF}{}", entry("cabinet", "damping = 1.5\n"));
    refused(
        &src,
        "damping is a ratio of critical below 1, got 1.5",
        "damping = 1.5",
    );
    let src = format!("{REF}{}", entry("cabinet", "modes = 0\n"));
    refused(&src, "modes must be at least 1", "modes = 0");
    let src = format!("{REF}{}", entry("cabinet", "modes = 500\n"));
    // The file by its absolute path.
    let file = base.join("../fe/cabinet.modal.toml");
    let eigen = washdyn_model::ir::modal::read_file(&file, "cabinet")
        .unwrap()
        .eigenmodes();
    let want = format!("asks for 500 modes, `{}` has {eigen}", file.display());
    refused(&src, &want, "modes = 500");
    // The rear left spring moved 10 cm off its node set on the cabinet's top.
    let src = edited(
        "b = { body = \"cabinet\", point = [-0.10, 0.15, 0.82] }",
        "b = { body = \"cabinet\", point = [-0.20, 0.15, 0.82] }",
    ) + &entry("cabinet", "");
    refused(
        &src,
        "the elastic cabinet has no FE node set at [-0.2, 0.15, 0.82] (nearest: SPRING_1",
        "point = [-0.20, 0.15, 0.82]",
    );
}

/// The elastic machine's rules, each at its line: a rotor mounted off its axis, a force element
/// on the drum, a drum sensor off the axis, a scene's non-positive `max_order` and a default
/// tolerance no error class covers.
#[test]
fn elastic_machine_rules_have_lines() {
    let src = edited("mount = [-0.25, 0.0, 0.45]", "mount = [-0.25, 0.0, 0.30]")
        .replacen(
            "b = { body = \"cabinet\", point = [0.12, 0.0, 0.82] }",
            "b = { body = \"drum\", point = [0.12, 0.0, 0.82] }",
            1,
        )
        .replacen(
            "body = \"drum\"\npoint = [0.17, 0.0, 0.45]",
            "body = \"drum\"\npoint = [0.17, 0.1, 0.45]",
            1,
        )
        .replacen("max_order = 12.0", "max_order = -1.0", 1)
        .replacen("tol = 1e-6 }", "tol = 0.5 }", 1);
    let e = errors(&src);
    let has = |needle: &str, line: usize| {
        assert!(
            e.iter().any(|(l, m)| *l == line && m.contains(needle)),
            "`{needle}` at line {line}: {e:?}"
        )
    };
    has(
        "is not on the rotor's axis",
        line_of(&src, "mount = [-0.25, 0.0, 0.30]", 0),
    );
    has(
        "the drum carries sensors only",
        line_of(&src, "b = { body = \"drum\"", 0),
    );
    has(
        "(off the drum's axis): the elastic drum has no FE node set at [0.17, 0.1, 0.45]",
        line_of(&src, "point = [0.17, 0.1, 0.45]", 0),
    );
    has(
        "max_order must be positive, got -1",
        line_of(&src, "max_order = -1.0", 0),
    );
    has(
        "solver.tol must be in (0, 1e-2), got 0.5",
        line_of(&src, "tol = 0.5 }", 0),
    );
}
