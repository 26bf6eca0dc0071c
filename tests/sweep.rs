//! `washdyn sweep`: variants over the unbalance position run in parallel, one folder each and a
//! comparison table.

use washdyn::Error;
use washdyn::results::Format;
use washdyn::simulation::{RunControl, Source};
use washdyn::spec::RunSpec;
use washdyn::sweep::{SweepRun, SweepSpec, run_sweep, variants};
use washdyn_ode::Method;

#[test]
fn positions_sweep_writes_folders_and_table() {
    let source = Source::load("reference").unwrap();
    let base = source.model.clone();
    let spec = SweepSpec {
        positions: vec!["front".into(), "middle".into(), "rear".into()],
        masses: vec![0.6],
        profiles: vec![],
    };
    let vars = variants(&base, &spec).unwrap();
    assert_eq!(vars.len(), 3);
    assert_eq!(
        vars[2].model.as_ref().unwrap().unbalances[0].position[0],
        -0.12
    );
    let out = std::env::temp_dir().join(format!("washdyn-sweep-{}", std::process::id()));
    let cfg = SweepRun {
        spec: RunSpec {
            out: Some(out.clone()),
            t_end: Some(20.0),
            method: Some(Method::Dopri5),
            tol: Some(1e-5),
            sample_rate: 200.0,
            format: Format::Parquet,
            ..RunSpec::of("reference")
        },
        control: RunControl::default(),
        jobs: 2,
    };
    let res = run_sweep(&source, vars, &cfg, &|_| {}).unwrap();
    assert!(
        res.iter()
            .all(|r| r.summary.status == washdyn_runtime::run::RunStatus::Ok)
    );
    for v in ["front_0.6kg", "middle_0.6kg", "rear_0.6kg"] {
        assert!(out.join(v).join("sensors.parquet").exists(), "{v}");
    }
    let table = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(table.lines().count(), 4, "{table}");
    // The peaks are order 1's run-up envelope. The unbalance's axial position changes the
    // rocking: the front x-acceleration at the door differs between front and rear.
    let peak = |i: usize| res[i].peaks.iter().find(|p| p.0 == "tub1_ax").unwrap().1;
    assert!(
        (peak(0) - peak(2)).abs() > 0.05 * peak(0),
        "{} vs {}",
        peak(0),
        peak(2)
    );
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn unknown_position_is_an_error() {
    let spec = SweepSpec {
        positions: vec!["back".into()],
        ..SweepSpec::default()
    };
    let e = variants(&washdyn_models::reference(), &spec).unwrap_err();
    assert_eq!(e.options(), ["--positions"], "{e}");
}

#[test]
fn equal_variants_get_distinct_folders_and_a_bad_variant_its_own_row() {
    let source = Source::load("reference").unwrap();
    let base = source.model.clone();
    let spec = SweepSpec {
        positions: vec![],
        // 0.3 twice: two folders; -1 kg fails the checker but must not sink the others.
        masses: vec![0.3, 0.3, -1.0],
        profiles: vec![],
    };
    let vars = variants(&base, &spec).unwrap();
    let names: Vec<&str> = vars.iter().map(|v| v.name.as_str()).collect();
    assert_eq!(names, ["0.3kg", "0.3kg_2", "-1kg"]);
    let out = std::env::temp_dir().join(format!("washdyn-sweep-dup-{}", std::process::id()));
    let cfg = SweepRun {
        spec: RunSpec {
            out: Some(out.clone()),
            t_end: Some(2.0),
            method: Some(Method::Dopri5),
            tol: Some(1e-5),
            sample_rate: 200.0,
            format: Format::Csv,
            ..RunSpec::of("reference")
        },
        control: RunControl::default(),
        jobs: 2,
    };
    let res = run_sweep(&source, vars, &cfg, &|_| {}).unwrap();
    assert_eq!(res[0].summary.status, washdyn_runtime::run::RunStatus::Ok);
    assert_eq!(res[1].summary.status, washdyn_runtime::run::RunStatus::Ok);
    assert!(out.join("0.3kg").join("sensors.csv").exists());
    assert!(out.join("0.3kg_2").join("sensors.csv").exists());
    assert_eq!(
        res[2].summary.status,
        washdyn_runtime::run::RunStatus::Failed
    );
    // The checker's finding at the unbalance's mass (the field it names).
    assert!(
        matches!(&res[2].error, Some(Error::Check { errors, .. })
            if errors.iter().any(|e| e.path.to_string().contains("mass"))),
        "{:?}",
        res[2].error
    );
    let table = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(table.lines().count(), 4, "{table}");
    assert!(
        table.lines().nth(3).unwrap().starts_with("-1kg,failed"),
        "{table}"
    );
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn named_positions_only_for_the_built_in_drums() {
    let mut m = washdyn_models::reference();
    m.name = "other".into();
    // Free positions are for the rigid drum: the elastic scene needs its node sets.
    m.scenes.retain(|s| !s.name.starts_with("elastic"));
    let spec = SweepSpec {
        positions: vec!["front".into()],
        ..SweepSpec::default()
    };
    let e = variants(&m, &spec).unwrap_err();
    assert_eq!(e.options(), ["--positions"], "{e}");
    let spec = SweepSpec {
        positions: vec!["0.1".into()],
        ..SweepSpec::default()
    };
    let v = variants(&m, &spec).unwrap();
    assert_eq!(v[0].model.as_ref().unwrap().unbalances[0].position[0], 0.1);
}
