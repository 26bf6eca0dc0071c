//! A user's own FE deck to modal data (issue 23, must-have 1), through the CLI as a user runs
//! it: the cabinet's mesh written as a user's deck in mm-t-s (the units CalculiX users often
//! write; with its own `*STEP`, which the reader skips), a spec naming its node sets as the
//! points, a point by position and the correction loads, `washdyn fe deck`, then `washdyn
//! check` on the reference machine with the new file as its cabinet.
//!
//! The reference is the committed cabinet data (models/fe/cabinet.modal.toml), solved from the
//! SI deck the FE front end writes itself: the same mesh through another path (our writer and
//! SI, against a deck read back in mm-t-s). Needs ccx: skipped without it, except under CI.

use crate::common;

use std::path::Path;
use std::process::Command;
use washdyn_runtime::ir::modal::{ModalData, read_file};

const MODES: usize = 20;

fn spec(deck: &str, points: &str) -> String {
    format!(
        "name = \"my_cabinet\"\ndeck = \"{deck}\"\nunits = \"mm-t-s\"\nbody = \"cabinet\"\n\
         support = \"on_springs\"\nsolve_modes = {MODES}\nrecovery = false\n\
         keep = {{ max_hz = 1000.0, max_modes = {MODES} }}\n\
         points = [\n{points}]\n\
         correction = [\n\
           {{ point = \"SPRING_1\", direction = [0.0, 0.0, 1.0] }},\n\
           {{ point = \"SPRING_2\", direction = [0.0, 0.0, 1.0] }},\n\
           {{ point = \"SPRING_3\", direction = [0.0, 0.0, 1.0] }},\n\
           {{ point = \"GASKET\", direction = [1.0, 0.0, 0.0] }},\n\
           {{ point = \"GASKET\", direction = [0.0, 1.0, 0.0] }},\n\
           {{ point = \"GASKET\", direction = [0.0, 0.0, 1.0] }},\n]\n"
    )
}

const SETS: [&str; 15] = [
    "SPRING_1", "SPRING_2", "SPRING_3", "MP_CAB1", "MP_CAB2", "GASKET", "DAMPER_1", "DAMPER_2",
    "DAMPER_3", "DAMPER_4", "FOOT_1", "FOOT_2", "FOOT_3", "FOOT_4", "",
];

fn washdyn(args: &[&str], dir: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_washdyn"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

#[test]
fn a_users_mm_t_s_cabinet_deck_gives_the_committed_modes_and_runs_in_the_machine() {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cab = washdyn_fe::bodies::builtin()
        .into_iter()
        .find(|b| b.name == "cabinet")
        .unwrap();
    let mm = washdyn_fe::inp::in_units(&cab.mesh, washdyn_fe::inp::Units::MmTS);
    std::fs::write(dir.path().join("my_cabinet.inp"), mm.deck(60).text()).unwrap();
    // The deck's node sets, read where the model attaches (the positions the built-in body
    // is read at).
    let mut points: String = SETS[..14]
        .iter()
        .map(|s| {
            let p = cab.points.iter().find(|(n, _)| n == s).unwrap().1;
            format!(
                "  {{ name = \"{s}\", nset = \"{s}\", at = [{:?}, {:?}, {:?}] }},\n",
                p[0], p[1], p[2]
            )
        })
        .collect();
    // A sensor of the user's own, by position (on the left side panel at y = 0.30 m).
    points.push_str("  { name = \"MY_SENSOR\", at = [0.0, 0.30, 0.60] },\n");

    // Errors in the spec name the file, line and set; nothing is solved.
    let bad = spec(
        "my_cabinet.inp",
        &points.replace("nset = \"MP_CAB2\"", "nset = \"NO_SUCH\""),
    );
    std::fs::write(dir.path().join("bad.toml"), bad).unwrap();
    let out = washdyn(&["fe", "deck", "bad.toml"], dir.path());
    let err = String::from_utf8_lossy(&out.stderr);
    // Refused data: exit code 5 (README, "Commands").
    assert_eq!(out.status.code(), Some(5), "{err}");
    assert!(
        err.contains("bad.toml:14") && err.contains("no node set `NO_SUCH`"),
        "{err}"
    );
    let bad = spec("missing.inp", &points);
    std::fs::write(dir.path().join("bad.toml"), bad).unwrap();
    let err = String::from_utf8_lossy(&washdyn(&["fe", "deck", "bad.toml"], dir.path()).stderr)
        .to_string();
    assert!(
        err.contains("missing.inp") && err.contains("cannot read"),
        "{err}"
    );

    if !common::required_tool(
        washdyn_fe::ccx::available(),
        "CalculiX",
        "apt-get install calculix-ccx",
    ) {
        return;
    }
    std::fs::write(
        dir.path().join("my_cabinet.toml"),
        spec("my_cabinet.inp", &points),
    )
    .unwrap();
    let out = washdyn(
        &[
            "fe",
            "deck",
            "my_cabinet.toml",
            "--out",
            "data",
            "--work",
            "work",
        ],
        dir.path(),
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    println!("{text}");
    let ours = read_file(&dir.path().join("data/my_cabinet.modal.toml"), "ours").unwrap();
    let committed: ModalData =
        read_file(&root.join("models/fe/cabinet.modal.toml"), "committed").unwrap();
    assert_eq!((ours.eigenmodes(), ours.modes()), (MODES, MODES + 6));
    // The same mesh and solver: the eigenfrequencies agree to ccx's precision (measured below).
    let worst = (0..MODES)
        .map(|k| (ours.frequencies[k] / committed.frequencies[k] - 1.0).abs())
        .fold(0.0f64, f64::max);
    // The mode shapes at the points, up to each mode's sign (one sign over all points),
    // relative to the mode's largest point translation: the same node sets.
    let pairs: Vec<_> = SETS[..14]
        .iter()
        .map(|name| {
            let a = ours.points.iter().find(|p| p.name == *name).unwrap();
            let b = committed.points.iter().find(|p| p.name == *name).unwrap();
            (a, b)
        })
        .collect();
    let (mut worst_w, mut at) = (0.0f64, String::new());
    for k in 0..MODES {
        let (mut dot, mut big) = (0.0, 0.0f64);
        for (a, b) in &pairs {
            for i in 0..3 {
                dot += a.w[i][k] * b.w[i][k];
                big = big.max(b.w[i][k].abs());
            }
        }
        let s = dot.signum();
        for (a, b) in &pairs {
            for i in 0..3 {
                let e = (s * a.w[i][k] - b.w[i][k]).abs() / big;
                if e > worst_w {
                    worst_w = e;
                    at = format!(
                        "{} mode {k} axis {i}: {} vs {}",
                        a.name, a.w[i][k], b.w[i][k]
                    );
                }
            }
        }
    }
    println!(
        "frequencies to {:.1} Hz: worst {worst:.1e} off the committed data; point shapes {worst_w:.1e}",
        ours.frequencies[MODES - 1]
    );
    // Measured 0 and 7.6e-12 on the machine that solved the committed data; a solve on
    // another machine differs by about 1e-9 in the frequencies and 1e-6 in small shape
    // components (issue 23), which these bounds allow.
    assert!(worst < 1e-8, "{worst}");
    assert!(worst_w < 1e-5, "{worst_w} at {at}");
    assert!(ours.points.iter().any(|p| p.name == "MY_SENSOR"));

    // The machine takes it: the reference model with this file as its cabinet passes `check`.
    let model = std::fs::read_to_string(root.join("models/data/reference.toml"))
        .unwrap()
        .replace("../fe/cabinet.modal.toml", "data/my_cabinet.modal.toml")
        .replace("../fe/", &format!("{}/models/fe/", root.display()));
    std::fs::write(dir.path().join("machine.toml"), model).unwrap();
    let out = washdyn(&["check", "machine.toml"], dir.path());
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}
