//! A run owns its output folder (`washdyn::run_dir`): it writes into a fresh folder and
//! renames it into place when it ends; a folder holding another run's files is refused unless
//! `--force` replaces it whole; every file carries the run's id, and `fields`, `compare` and
//! `analyse` refuse files whose ids disagree, naming both.

use crate::common;

use std::path::Path;
use washdyn::commands::{RunControl, RunSpec, run_command, run_command_with};
use washdyn::error::compare::CompareError;
use washdyn::error::fields::FieldsError;
use washdyn::run_dir::{file_run_id, summary_run_id};
use washdyn::spec::Field;
use washdyn_runtime::run::RunStatus;

/// The rigid reference's first `t_end` s into `out`.
fn spec(out: &Path, t_end: f64) -> RunSpec {
    RunSpec {
        out: Some(out.to_path_buf()),
        t_end: Some(t_end),
        sample_rate: 200.0,
        ..RunSpec::of("reference")
    }
}

/// Whatever `dir`'s parent holds beside it: a run leaves no folder of its own behind.
fn siblings(dir: &Path) -> Vec<String> {
    let name = dir.file_name().unwrap().to_string_lossy().to_string();
    std::fs::read_dir(dir.parent().unwrap())
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().to_string())
        .filter(|n| n != &name)
        .collect()
}

/// The case: a run with `--states`, then another (another end) into the same folder.
/// Refused before anything runs, naming the first run; with `--force` the folder is the second
/// run's alone (no states.parquet of the first left to be recovered).
#[test]
fn a_folder_of_another_run_is_refused_unless_forced() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d");
    let first = run_command(
        &RunSpec {
            states: true,
            ..spec(&out, 0.3)
        },
        &mut |_| {},
    )
    .unwrap();
    let id = first.summary.run_id.clone().unwrap();
    let e = run_command(&spec(&out, 0.2), &mut |_| {}).unwrap_err();
    assert_eq!(e.fields(), [Field::Force], "{e}");
    assert!(
        e.to_string().contains(&id) && e.to_string().contains("--force"),
        "{e}"
    );
    assert_eq!(
        summary_run_id(&out).unwrap(),
        id,
        "the first run is untouched"
    );
    let second = run_command(
        &RunSpec {
            force: true,
            ..spec(&out, 0.2)
        },
        &mut |_| {},
    )
    .unwrap();
    assert!(!out.join("states.parquet").exists());
    assert_eq!(summary_run_id(&out), second.summary.run_id);
    assert_ne!(second.summary.run_id.as_deref(), Some(id.as_str()));
    assert!(siblings(&out).is_empty(), "{:?}", siblings(&out));
    // An output folder that is a file: exit 4, as any file the command cannot write.
    std::fs::write(dir.path().join("f"), "x").unwrap();
    let o = common::washdyn_in(
        &["run", "reference", "--t-end", "0.1", "--out", "f"],
        dir.path(),
    );
    assert_eq!(
        o.status.code(),
        Some(4),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Every file a run writes carries its id, and summary.json lists them with the start and the
/// sample rate.
#[test]
fn every_file_carries_the_run_id() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d");
    let o = run_command(
        &RunSpec {
            states: true,
            energy: true,
            ..spec(&out, 0.2)
        },
        &mut |_| {},
    )
    .unwrap();
    let id = o.summary.run_id.clone().unwrap();
    for f in ["sensors.parquet", "states.parquet", "energy.parquet"] {
        assert_eq!(
            file_run_id(&out.join(f)).as_deref(),
            Some(id.as_str()),
            "{f}"
        );
        assert!(
            o.summary.files.iter().any(|x| x == f),
            "{:?}",
            o.summary.files
        );
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["run_id"], id.as_str());
    assert_eq!(json["start"], "static");
    assert_eq!(json["sample_rate_hz"], 200.0);
    assert!(json["files"].as_array().unwrap().len() >= 4, "{json}");
}

/// An interrupted run goes into place as a finished one does.
#[test]
fn an_interrupted_run_goes_into_place() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d");
    let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
    let mut ctl = RunControl::default();
    ctl.guard.interrupt = Some(flag);
    let mut o = run_command_with(&spec(&out, 0.5), &ctl, &mut |_| {}).unwrap();
    o.publish().unwrap();
    assert_eq!(o.summary.status, RunStatus::Interrupted);
    assert_eq!(o.out_dir, out);
    assert!(out.join("summary.json").is_file() && siblings(&out).is_empty());
}

/// Files of two runs in one folder: `fields`, `compare` and `analyse` refuse them, naming
/// both ids.
#[test]
fn files_of_another_run_are_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    for d in [&a, &b] {
        run_command(
            &RunSpec {
                states: true,
                ..spec(d, 0.2)
            },
            &mut |_| {},
        )
        .unwrap();
    }
    let (ia, ib) = (summary_run_id(&a).unwrap(), summary_run_id(&b).unwrap());
    for f in ["states.parquet", "sensors.parquet"] {
        std::fs::copy(a.join(f), b.join(f)).unwrap();
    }
    let names_both = |e: &dyn std::fmt::Display| {
        let m = e.to_string();
        assert!(m.contains(&ia) && m.contains(&ib), "{m}");
    };
    let request = washdyn::fields::Request::DrumEdge {
        stride: 1,
        svg: false,
    };
    let e = washdyn::fields::fields_command(&b, None, &request, dir.path(), None).unwrap_err();
    assert!(matches!(e, FieldsError::OtherRun(_)), "{e}");
    names_both(&e);
    let args = washdyn::compare::CompareArgs {
        runs: [a.clone(), b.clone()],
        labels: ["a".into(), "b".into()],
        out: dir.path().join("cmp"),
        motor_ratio: 11.25,
        svg: false,
        until: None,
    };
    let e = washdyn::compare::compare(&args).unwrap_err();
    assert!(matches!(e, CompareError::OtherRun(_)), "{e}");
    names_both(&e);
    let o = common::washdyn_in(&["analyse", "b/sensors.parquet"], dir.path());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(5), "{err}");
    assert!(err.contains(&ia) && err.contains(&ib), "{err}");
}

/// docs/summary-json.md names every key a run's summary.json holds (issue 50 point 6), read
/// from a run of the binary with its analysis (the `analysis` and `order_peaks` the CLI adds),
/// the energy balance and a model file (`model_files`): the reference at a constant 600 rpm,
/// so that 1 s resolves its orders.
#[test]
fn every_summary_field_is_documented() {
    let dir = tempfile::tempdir().unwrap();
    let src = concat!(env!("CARGO_MANIFEST_DIR"), "/models/data/reference.toml");
    let text = std::fs::read_to_string(src).unwrap();
    let profile = "table = [[0.0, 0.0], [5.0, 93.0], [15.0, 93.0], [178.375, 1400.0]]";
    assert!(text.contains(profile), "reference.toml's profile changed");
    let text = text.replacen(profile, "table = [[0.0, 600.0], [2.0, 600.0]]", 1);
    let fe = format!("\"{}/models/fe/", env!("CARGO_MANIFEST_DIR"));
    std::fs::write(dir.path().join("m.toml"), text.replace("\"../fe/", &fe)).unwrap();
    let o = common::washdyn_in(
        &["run", "m.toml", "--t-end", "1", "--energy", "--out", "d"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(dir.path().join("d/summary.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert!(
        !json["order_peaks"].as_array().unwrap().is_empty(),
        "{json}"
    );
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/summary-json.md"))
        .unwrap();
    let mut keys = Vec::new();
    let mut stack = vec![&json];
    while let Some(v) = stack.pop() {
        match v {
            serde_json::Value::Object(m) => {
                for (k, v) in m {
                    keys.push(k.clone());
                    stack.push(v);
                }
            }
            serde_json::Value::Array(a) => stack.extend(a),
            _ => {}
        }
    }
    let missing: Vec<_> = keys
        .iter()
        .filter(|k| !doc.contains(&format!("`{k}`")))
        .collect();
    assert!(keys.len() > 40, "{keys:?}");
    assert!(missing.is_empty(), "docs/summary-json.md lacks {missing:?}");
}
