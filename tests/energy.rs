//! `washdyn run --energy`: the balance by category written beside the sensors, from both back
//! ends. What holds it, independent of the split itself: the two back ends (the generated
//! code's M1 for the drive's q'^T M1' q' / 2 against the interpreter's) give the same
//! categories; the residual T - T0 - sum W stays at the integration's error; a dissipated
//! category's energy only grows. The split's own checks (categories against the whole h, modal
//! strain against omega^2 q^2 / 2) are in tests/hard_cases.rs.

use washdyn::commands::{Backend, RunSpec, run_command};
use washdyn::results::{Format, read_parquet_f64};
use washdyn_ode::Method;

fn run(backend: Backend, tag: &str) -> (washdyn_runtime::run::Summary, Vec<String>, Vec<Vec<f64>>) {
    let out = std::env::temp_dir().join(format!("washdyn-energy-{tag}-{}", std::process::id()));
    std::fs::remove_dir_all(&out).ok();
    let args = RunSpec {
        model: "reference".into(),
        t_end: Some(3.0),
        out: Some(out.clone()),
        method: Some(Method::Dopri5),
        tol: Some(1e-7),
        step: None,
        rho_inf: None,
        backend: Some(backend),
        scene: Some("full".into()),
        sample_rate: 100.0,
        max_steps: None,
        format: Format::Parquet,
        states: false,
        energy: true,
        start: washdyn_runtime::run::Start::Static,
        ..RunSpec::default()
    };
    let o = run_command(&args, &mut |_| {}).expect("the run starts");
    assert!(o.error.is_none(), "{:?}", o.error);
    assert!(out.join("energy.png").exists());
    let (names, cols) = read_parquet_f64(&out.join("energy.parquet")).unwrap();
    std::fs::remove_dir_all(&out).ok();
    (o.summary, names, cols)
}

#[test]
fn energy_balance_closes_and_both_back_ends_agree() {
    let (sg, names, gn) = run(Backend::Generated, "gen");
    let (si, names_i, int) = run(Backend::Interpreted, "int");
    assert_eq!(names, names_i);
    assert_eq!(&names[..4], ["time_s", "drum_rpm", "kinetic_J", "drive_J"]);
    assert_eq!(names.last().unwrap(), "residual_J");
    // A row every 10 ms from 0 to 3 s.
    assert_eq!(gn[0].len(), 301);
    assert!((gn[0][300] - 3.0).abs() < 1e-12, "{}", gn[0][300]);
    // Closure at the end, relative to the throughput: measured 3.7e-8 (dopri5 at 1e-7).
    for s in [&sg, &si] {
        let c = s.energy_closure.expect("kept the balance");
        eprintln!("{}: closure {c:.2e}", s.backend);
        assert!(c < 3e-7, "{}: closure {c:.2e}", s.backend);
    }
    // Every category and the kinetic energy agree between the back ends: measured exactly
    // (the two runs take the same steps to the bit, and the balance evaluates the generated
    // code's M1 where the interpreter's own); the bound is round-off of the largest flow.
    let (worst, scale) = crate::common::energy_difference(&gn, &int);
    eprintln!("back ends: {:.1e} of {scale:.3e} J", worst / scale);
    assert!(worst <= 1e-12 * scale, "{worst} of {scale}");
    // A dissipated category's work never rises (its energy taken only grows): the friction
    // law, the dampers and the gasket's damping take energy at every instant.
    for (i, name) in names.iter().enumerate() {
        if name.ends_with("_dissipated_J")
            || name.ends_with("_modal_damping_J")
            || name.ends_with("_feet_J")
        {
            let rise = gn[i].windows(2).fold(0.0f64, |m, w| m.max(w[1] - w[0]));
            assert!(rise <= 1e-12 * scale, "{name} rises by {rise}");
            assert!(*gn[i].last().unwrap() < 0.0, "{name} took nothing");
        }
    }
}
