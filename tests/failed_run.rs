//! A failing integration stops with a typed error carrying the time, and keeps what it wrote:
//! the sensor file up to the failure and a summary that says why.

use washdyn::Error;
use washdyn::commands::{Backend, RunSpec, run_command};
use washdyn::results::{Format, read_parquet_f64};
use washdyn_ode::{Method, OdeError};
use washdyn_runtime::run::RunError;

#[test]
fn spent_step_budget_fails_with_time_and_keeps_output() {
    // A budget of 5000 steps runs out a few seconds into the run-up. (An unstable explicit step
    // does not do: the arctan friction force is bounded, so the instability saturates into a
    // wrong but finite chatter.)
    let out = std::env::temp_dir().join(format!("washdyn-fail-{}", std::process::id()));
    let args = RunSpec {
        model: "reference".into(),
        t_end: Some(30.0),
        out: Some(out.clone()),
        method: Some(Method::Dopri5),
        tol: Some(1e-6),
        step: None,
        rho_inf: None,
        backend: Some(Backend::Interpreted),
        scene: None,
        sample_rate: 100.0,
        max_steps: Some(5000),
        format: Format::Parquet,
        states: false,
        energy: false,
        start: washdyn_runtime::run::Start::Static,
        ..RunSpec::default()
    };
    let o = run_command(&args, &mut |_| {}).expect("the run starts");
    let err = o.error.expect("the run must fail");
    // The budget given above, spent: the integrator's typed error, with the time it reached.
    let Error::Integration {
        t,
        source: RunError::Ode(OdeError::StepBudget { steps: 5000, .. }),
    } = err
    else {
        panic!("expected the spent step budget, got {err:?}")
    };
    let s = &o.summary;
    assert_eq!(t, s.t_reached);
    assert_eq!(s.status, washdyn_runtime::run::RunStatus::Failed);
    // dopri5 at 1e-6 on `full` is a setting the study measured; a failed run claims no class.
    assert_eq!(s.error_class, None);
    assert!(s.t_reached > 0.0 && s.t_reached < 30.0, "{}", s.t_reached);
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"failed\"") && summary.contains("budget"),
        "{summary}"
    );
    // The Parquet file is complete (footer written on the failure path) and holds every sample
    // up to the failure, all finite, and nothing after it.
    let (names, cols) = read_parquet_f64(&out.join("sensors.parquet")).unwrap();
    assert_eq!(names[0], "time_s");
    assert_eq!(cols[0].len() as u64, s.samples);
    assert!(cols[0].len() > 10);
    assert!(cols.iter().flatten().all(|v| v.is_finite()));
    let last_t = *cols[0].last().unwrap();
    assert!(
        last_t <= s.t_reached && last_t > s.t_reached - 0.02,
        "{last_t} vs {}",
        s.t_reached
    );
    eprintln!("failed at t = {} s: {err}", s.t_reached);
    std::fs::remove_dir_all(&out).ok();
}
