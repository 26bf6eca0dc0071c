//! `washdyn sweep`: variants over the unbalance position run in parallel, one folder each and a
//! comparison table.

use washdyn::sweep::{SweepRun, SweepSpec, run_sweep, variants};
use washdyn_runtime::ode::Method;

#[test]
fn positions_sweep_writes_folders_and_table() {
    let base = washdyn_models::reference();
    let spec = SweepSpec {
        positions: vec!["front".into(), "middle".into(), "rear".into()],
        masses: vec![0.6],
        profiles: vec![],
    };
    let vars = variants(&base, &spec).unwrap();
    assert_eq!(vars.len(), 3);
    assert_eq!(vars[2].model.unbalances[0].position[0], -0.12);
    let out = std::env::temp_dir().join(format!("washdyn-sweep-{}", std::process::id()));
    let cfg = SweepRun {
        out: out.clone(),
        t_end: Some(8.0),
        method: Method::Dopri5,
        tol: 1e-5,
        scene: None,
        sample_rate: 200.0,
        jobs: 2,
    };
    let res = run_sweep(vars, &cfg, &|_| {}).unwrap();
    assert!(res.iter().all(|r| r.summary.status == "ok"));
    for v in ["front_0.6kg", "middle_0.6kg", "rear_0.6kg"] {
        assert!(out.join(v).join("sensors.csv").exists(), "{v}");
    }
    let table = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(table.lines().count(), 4, "{table}");
    // The unbalance's axial position changes the rocking: the front x-acceleration at the door
    // differs between front and rear.
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
    assert!(e.contains("unknown position `back`"), "{e}");
}
