//! Tests of `washdyn fields`: refused requests, the run's model file, the drum-edge table and
//! plot.

use super::*;

/// Bad requests are refused with a message before anything is written.
#[test]
fn bad_requests_are_refused() {
    let st = States {
        t: vec![0.0, 1.0, 2.0],
        phi: vec![0.0, 0.5, 1.0],
        q: vec![vec![0.0; 3]],
    };
    let e = st.at(2.5).unwrap_err();
    assert!(matches!(e, FieldsError::Outside { t: 2.5, .. }), "{e}");
    assert!(
        e.to_string()
            .contains("outside the stored states (0 to 2 s)"),
        "{e}"
    );
    let e = st.instants(&Times::Range(1.0, 0.0, 0.1)).unwrap_err();
    assert!(matches!(e, FieldsError::Range { .. }), "{e}");
    assert!(
        e.to_string().contains("need from <= to and step > 0"),
        "{e}"
    );
    let e = st.instants(&Times::Revolution(0.0)).unwrap_err();
    assert!(matches!(e, FieldsError::Revolution { t: 0.0 }), "{e}");
    assert!(e.to_string().contains("ends before one revolution"), "{e}");
    // Every instant is checked, not just the first: NaN (which compares false) included.
    let e = st
        .instants(&Times::List(vec![0.5, f64::NAN, 9.0]))
        .unwrap_err();
    match &e {
        FieldsError::Instants { option, outside } => {
            assert_eq!(*option, "--times");
            assert!(
                matches!(outside[..], [FieldsError::Outside { t: a, .. }, FieldsError::Outside { t: 9.0, .. }] if a.is_nan()),
                "{e}"
            );
        }
        _ => panic!("not the instants outside: {e}"),
    }
    let e = e.to_string();
    assert!(
        e.starts_with("--times: t = NaN s is outside") && e.contains("t = 9 s"),
        "{e}"
    );
    let e = st
        .instants(&Times::Range(0.0, 1.0, f64::MIN_POSITIVE))
        .unwrap_err();
    assert!(matches!(e, FieldsError::RangeTooLong { .. }), "{e}");
    assert!(e.to_string().contains("more than 10000"), "{e}");
    assert!(matches!(
        st.instants(&Times::Revolution(f64::NAN)),
        Err(FieldsError::Outside { .. })
    ));
    // A run directory without a summary, and one whose model has no field files.
    let dir = tempfile::tempdir().unwrap();
    let req = Request::Fields(Times::List(vec![0.0]));
    let e = fields_command(dir.path(), None, &req, dir.path(), None)
        .err()
        .unwrap();
    assert!(matches!(e, FieldsError::NoSummary { .. }), "{e}");
    assert!(e.to_string().contains("summary.json"), "{e}");
    std::fs::write(
        dir.path().join("summary.json"),
        r#"{"model": "reference", "scene": "full"}"#,
    )
    .unwrap();
    let e = fields_command(dir.path(), None, &req, dir.path(), None)
        .err()
        .unwrap();
    assert!(matches!(e, FieldsError::NoFieldFiles { .. }), "{e}");
    assert!(e.to_string().contains("no field files"), "{e}");
    assert!(!dir.path().join("fields").exists());
    // Not a field file.
    std::fs::write(dir.path().join("tub.field.bin"), b"garbage").unwrap();
    let e = washdyn_fe::field::Field::read(&dir.path().join("tub.field.bin")).unwrap_err();
    assert!(
        matches!(
            e,
            washdyn_fe::Error::Results(washdyn_fe::error::ResultsError::NotAField { .. })
        ),
        "{e}"
    );
    assert!(e.to_string().contains("not a washdyn field file"), "{e}");
}

/// A run on a model file: `fields` without --model takes the file summary.json names, and
/// refuses it, naming it, once its content changed.
#[test]
fn the_run_s_model_file_is_used_and_a_changed_one_refused() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.toml");
    std::fs::write(&model, washdyn_models::REFERENCE_TOML).unwrap();
    let hashed = FileHash::of(&model).unwrap();
    let summary = serde_json::json!({
        "model": "reference", "scene": "full", "model_files": [hashed],
    });
    std::fs::write(dir.path().join("summary.json"), summary.to_string()).unwrap();
    let req = Request::Fields(Times::List(vec![0.0]));
    // The file as run: loaded (its `../fe/` data is not beside it here: named absolute).
    let e = fields_command(dir.path(), None, &req, dir.path(), None)
        .err()
        .unwrap();
    assert!(
        matches!(&e, FieldsError::Model(m) if matches!(**m, crate::Error::Model(_))),
        "{e}"
    );
    let e = e.to_string();
    assert!(e.contains(&format!("{}:", model.display())), "{e}");
    assert!(e.contains("tub.modal.toml: cannot read"), "{e}");
    std::fs::write(&model, "name = \"other\"").unwrap();
    let e = fields_command(dir.path(), None, &req, dir.path(), None)
        .err()
        .unwrap();
    assert!(matches!(e, FieldsError::ModelChanged { .. }), "{e}");
    let e = e.to_string();
    assert!(
        e.starts_with(&format!("{}: changed since the run", hashed.path)),
        "{e}"
    );
    assert!(e.contains("--model"), "{e}");
}

#[test]
fn drum_edge_table_and_plot() {
    let rows: Vec<EdgeRow> = (0..50)
        .map(|i| {
            let rpm = 30.0 * i as f64;
            EdgeRow {
                t: i as f64,
                rpm,
                max_m: 1e-8 * rpm * rpm,
                node: 7,
                peak: Some((1e2 * rpm * rpm, 9)),
            }
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let files = write_drum_edge(&rows, dir.path(), true).unwrap();
    assert_eq!(files.len(), 3);
    let csv = std::fs::read_to_string(&files[0]).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "time_s,drum_rpm,front_edge_max_m,node,peak_von_mises_Pa,peak_node"
    );
    assert_eq!(lines.len(), 51);
    assert_eq!(lines[2], "1,30,0.000009,7,90000,9");
    assert!(std::fs::metadata(&files[1]).unwrap().len() > 10_000);
}
