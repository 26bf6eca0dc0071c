//! Issue 7's table of bad inputs, row by row: each is refused before any file is created
//! (`Error::Settings` naming the option, `Error::Model` naming the file), or stops with a typed
//! error carrying the time (`Error::Integration`). The limits asserted are the ones
//! `RunSpec::validate`, the model checker and `run::Guard` document; the reference model is the
//! repository's own file.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use washdyn::Error;
use washdyn::commands::{
    Backend, RunControl, RunSpec, check_model, resolve_model, run_command_with,
};
use washdyn::spec::Field;
use washdyn_ode::Method;
use washdyn_runtime::run::{Guard, RunError};

fn out_dir(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("washdyn-bad-{tag}-{}", std::process::id()))
}

fn args(tag: &str) -> RunSpec {
    RunSpec {
        model: "reference".into(),
        t_end: Some(2.0),
        out: Some(out_dir(tag)),
        method: Some(Method::Dopri5),
        tol: Some(1e-6),
        step: None,
        rho_inf: None,
        backend: Some(Backend::Generated),
        scene: None,
        sample_rate: 200.0,
        max_steps: None,
        format: washdyn::results::Format::Parquet,
        states: false,
        energy: false,
        start: washdyn_runtime::run::Start::Static,
        ..RunSpec::default()
    }
}

/// Refused before anything is written: [`Error::Settings`] refusing `option` (every refusal
/// names it) and the folder does not exist. Returns the refusals' messages.
fn refused(a: &RunSpec, ctl: &RunControl, option: &str) -> Vec<String> {
    let dir = a.out.clone().unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let msgs = match run_command_with(a, ctl, &mut |_| {}) {
        Ok(o) => panic!("ran (error {:?}), expected {option} refused", o.error),
        Err(Error::Settings(r)) => {
            assert!(
                !r.is_empty() && r.iter().all(|r| r.subject.option() == option),
                "{r:?}"
            );
            r.into_iter().map(|r| r.to_string()).collect()
        }
        Err(e) => panic!("expected {option} refused, got {e:?}"),
    };
    assert!(!dir.exists(), "{} was created", dir.display());
    msgs
}

#[test]
fn rk4_step_out_of_range_or_not_a_number() {
    for (i, h) in [1.0, f64::INFINITY, 0.0, -1.0, f64::NAN, 1e-12]
        .into_iter()
        .enumerate()
    {
        let a = RunSpec {
            method: Some(Method::Rk4),
            step: Some(h),
            ..args(&format!("step{i}"))
        };
        refused(&a, &RunControl::default(), "--step");
    }
}

#[test]
fn step_with_an_adaptive_integrator() {
    let a = RunSpec {
        step: Some(1.0),
        ..args("step-dopri5")
    };
    refused(&a, &RunControl::default(), "--step");
}

/// Chung & Hulbert's family is defined for rho_inf in [0, 1]; other methods have no such
/// parameter, so the flag is refused there rather than ignored.
#[test]
fn rho_inf_out_of_range_or_without_galpha() {
    for (i, r) in [1.5, -0.1, f64::NAN, f64::INFINITY].into_iter().enumerate() {
        let a = RunSpec {
            method: Some(Method::GeneralizedAlpha),
            rho_inf: Some(r),
            ..args(&format!("rho{i}"))
        };
        refused(&a, &RunControl::default(), "--rho-inf");
    }
    let a = RunSpec {
        rho_inf: Some(0.5),
        ..args("rho-dopri5")
    };
    refused(&a, &RunControl::default(), "--rho-inf");
}

#[test]
fn tolerance_out_of_range() {
    for (i, tol) in [f64::INFINITY, 0.0, f64::NAN, -1.0, 0.5, 1e-13]
        .into_iter()
        .enumerate()
    {
        let a = RunSpec {
            tol: Some(tol),
            ..args(&format!("tol{i}"))
        };
        refused(&a, &RunControl::default(), "--tol");
    }
}

#[test]
fn end_time_out_of_range() {
    for (i, t) in [f64::INFINITY, 1e9, 0.0, f64::NAN, -1.0]
        .into_iter()
        .enumerate()
    {
        let a = RunSpec {
            t_end: Some(t),
            ..args(&format!("tend{i}"))
        };
        refused(&a, &RunControl::default(), "--t-end");
    }
}

#[test]
fn sample_rate_out_of_range_or_below_the_analysis_band() {
    for (i, r) in [1e9, f64::INFINITY, f64::NAN, 0.0, -5.0]
        .into_iter()
        .enumerate()
    {
        let a = RunSpec {
            sample_rate: r,
            ..args(&format!("rate{i}"))
        };
        refused(&a, &RunControl::default(), "--sample-rate");
    }
    // With plots, the 300 Hz analysis band needs 600 Hz.
    let ctl = RunControl {
        analysis_band_hz: Some(300.0),
        ..RunControl::default()
    };
    let a = RunSpec {
        sample_rate: 1.0,
        ..args("rate-analysis")
    };
    // 1 Hz passes the range but not the analysis' 2 x 300 Hz.
    let m = refused(&a, &ctl, "--sample-rate");
    assert_eq!(m.len(), 1, "{m:?}");
    assert!(m[0].contains("at least 600 Hz"), "{m:?}");
}

#[test]
fn output_beyond_the_size_limit_names_its_size() {
    // 3600 s x 1e5 Hz + 1 samples x (time, rpm, 3 per sensor of reference.toml) x 8 bytes.
    let src = concat!(env!("CARGO_MANIFEST_DIR"), "/models/data/reference.toml");
    let sensors = std::fs::read_to_string(src)
        .unwrap()
        .matches("[[sensors]]")
        .count();
    let cols = 2 + 3 * sensors;
    let gb = (3600.0 * 1e5 + 1.0) * cols as f64 * 8.0 / 1e9;
    let a = RunSpec {
        t_end: Some(3600.0),
        sample_rate: 1e5,
        ..args("size")
    };
    let m = refused(&a, &RunControl::default(), "--allow-large-output");
    let size = format!("3.600e8 samples x {cols} columns = {gb:.1} GB");
    assert!(m[0].contains(&size), "{m:?} lacks {size}");
    // The flag lifts the limit (the rules alone: the run itself would take hours).
    let cx = washdyn::spec::Context {
        channels: Some(21),
        ..washdyn::spec::Context::bare(Method::Dopri5, 1e-6, 178.375)
    };
    let s = RunSpec {
        allow_large_output: true,
        ..a
    };
    assert!(s.validate(&cx).is_ok());
    let e = RunSpec {
        allow_large_output: false,
        ..s
    }
    .validate(&cx)
    .map_err(Error::Settings)
    .unwrap_err();
    assert_eq!(e.fields(), [Field::AllowLargeOutput], "{e}");
}

#[test]
fn every_violation_is_listed_at_once() {
    let a = RunSpec {
        method: Some(Method::Rk4),
        step: Some(f64::NAN),
        tol: Some(-1.0),
        t_end: Some(0.0),
        ..args("many")
    };
    let e = run_command_with(&a, &RunControl::default(), &mut |_| {})
        .err()
        .unwrap();
    assert_eq!(e.options(), ["--step", "--tol", "--t-end"], "{e}");
    assert_eq!(e.to_string().lines().count(), 3, "{e}");
}

#[test]
fn rk4_step_beyond_the_stability_limit_stops_at_the_start() {
    // 1e-3 s is inside the option's range, but the friction dampers' regularised slope makes
    // the Jacobian's spectral radius about 4e3 1/s, so rk4 is stable only below ~7e-4 s
    // (and 1e-4 s, the default, runs).
    let a = RunSpec {
        method: Some(Method::Rk4),
        step: Some(1e-3),
        ..args("unstable")
    };
    let o = run_command_with(&a, &RunControl::default(), &mut |_| {}).unwrap();
    let e = o.error.expect("must fail");
    assert!(
        matches!(
            e,
            Error::Integration {
                t: 0.0,
                source: RunError::Unstable { h: 1e-3, limit, .. },
            } if limit < 1e-3
        ),
        "{e:?}"
    );
    assert_eq!(o.summary.status, washdyn_runtime::run::RunStatus::Failed);
    assert_eq!(o.summary.steps, 0);
    let ok = RunSpec {
        method: Some(Method::Rk4),
        step: Some(1e-4),
        t_end: Some(0.5),
        ..args("stable")
    };
    let o = run_command_with(&ok, &RunControl::default(), &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "{:?}", o.error);
    std::fs::remove_dir_all(out_dir("unstable")).ok();
    std::fs::remove_dir_all(out_dir("stable")).ok();
}

/// The reference model file with one edit, written to a temp file.
fn variant(tag: &str, from: &str, to: &str) -> PathBuf {
    let src = concat!(env!("CARGO_MANIFEST_DIR"), "/models/data/reference.toml");
    let text = std::fs::read_to_string(src).unwrap();
    assert!(text.contains(from), "reference.toml lacks `{from}`");
    let p = std::env::temp_dir().join(format!("washdyn-bad-{tag}-{}.toml", std::process::id()));
    std::fs::write(&p, absolute_data(&text.replacen(from, to, 1))).unwrap();
    p
}

/// The reference's modal data files are relative to models/data; a copy elsewhere names them
/// absolutely.
fn absolute_data(text: &str) -> String {
    text.replace(
        "\"../fe/",
        &format!("\"{}/models/fe/", env!("CARGO_MANIFEST_DIR")),
    )
}

/// The model file refused by its loader ([`Error::Model`]): a problem at the file whose
/// message (the checker's, with the field) holds `want`; `run` refuses it before writing.
fn model_refused(path: &PathBuf, want: &str) {
    let file = path.to_str().unwrap();
    let at_file = |e: &Error| match e {
        Error::Model(m) => m
            .errors
            .iter()
            .any(|l| l.file == file && l.message.contains(want)),
        _ => false,
    };
    let Err(e) = resolve_model(file) else {
        panic!("{} must be refused", path.display())
    };
    assert!(at_file(&e), "{e:?} lacks `{want}` at {file}");
    let a = RunSpec {
        model: file.into(),
        backend: None,
        ..args("model")
    };
    let dir = a.out.clone().unwrap();
    std::fs::remove_dir_all(&dir).ok();
    match run_command_with(&a, &RunControl::default(), &mut |_| {}) {
        Err(e) => assert!(at_file(&e), "{e:?} lacks `{want}` at {file}"),
        Ok(_) => panic!("{file} ran"),
    }
    assert!(!dir.exists(), "{} was created", dir.display());
    std::fs::remove_file(path).ok();
}

#[test]
fn speed_profile_to_a_million_rpm() {
    let p = variant("rpm", "[178.375, 1400.0]", "[178.375, 1000000.0]");
    model_refused(
        &p,
        "speed: 1000000 rpm at row 3 exceeds the limit of 3000 rpm",
    );
}

#[test]
fn friction_slope_1e12() {
    let p = variant("slope", "slope = 2000.0", "slope = 1e12");
    model_refused(&p, "slope 1000000000000 s/m exceeds 1e6 s/m");
}

#[test]
fn damper_part_with_negative_mass() {
    let p = variant(
        "part",
        "moving_part = { mass = 0.55",
        "moving_part = { mass = -0.55",
    );
    model_refused(
        &p,
        "friction damper `damper_front_left`: moving_part.mass must be positive, got -0.55",
    );
}

#[test]
fn unbalance_of_50_kg() {
    let p = variant("unb", "mass = 0.6\n", "mass = 50.0\n");
    model_refused(&p, "mass 50 kg exceeds 0.1 x the tub mass (55 kg)");
}

#[test]
fn spring_mirrored_below_the_tub() {
    // spring_front: tub end z = 0.62, cabinet end mirrored from 0.82 to 0.42; stretched to
    // 0.2 m > 0.1386875 m free length it pulls the tub down with 4000 x 0.0613125 = 245.25 N
    // (245.3 at 0.1 N: 0.2 - 0.1386875 rounds up in binary).
    let p = variant(
        "mirror",
        "point = [0.12, 0.0, 0.82]",
        "point = [0.12, 0.0, 0.42]",
    );
    model_refused(
        &p,
        "spring `spring_front`: at the reference position it pulls the tub along gravity (245.3 N of its 245.3 N)",
    );
}

#[test]
fn model_without_springs_fails_check() {
    let src = concat!(env!("CARGO_MANIFEST_DIR"), "/models/data/reference.toml");
    let text = std::fs::read_to_string(src).unwrap();
    let cut = text.find("# Three vertical springs").unwrap();
    // Without the springs and dampers, the free list that names them goes too.
    let free = text.find("free = [").unwrap();
    let free_end = free + text[free..].find("]\n").unwrap() + 2;
    let kept = format!("{}{}", &text[..free], &text[free_end..cut]);
    let p = std::env::temp_dir().join(format!("washdyn-bad-trunc-{}.toml", std::process::id()));
    std::fs::write(&p, absolute_data(&kept)).unwrap();
    let (m, _) = resolve_model(p.to_str().unwrap()).expect("loads: the checker's rules pass");
    let e = check_model(&m).unwrap_err();
    assert!(
        matches!(&e, Error::Scene { problems, .. }
            if problems.iter().any(|p| p.contains("cannot run: static equilibrium: singular stiffness"))),
        "{e:?}"
    );
    // The full model passes and reports its rest position.
    let (r, _) = resolve_model("reference").unwrap();
    let ok = check_model(&r).unwrap();
    assert!(ok.contains("static rest position"), "{ok}");
    std::fs::remove_file(&p).ok();
}

#[test]
fn large_motion_warns_then_stops_with_its_time() {
    // 5 kg (inside the checker's 5.5 kg limit) drives the tub past 30 mm in the hold phase and
    // past 5 x 0.05 rad at the resonance.
    let p = variant("unb5", "mass = 0.6\n", "mass = 5.0\n");
    let a = RunSpec {
        model: p.to_str().unwrap().into(),
        backend: None,
        t_end: Some(40.0),
        ..args("validity")
    };
    let mut o = run_command_with(&a, &RunControl::default(), &mut |_| {}).unwrap();
    // A failed run goes into place like any other.
    o.publish().unwrap();
    let e = o.error.expect("must stop");
    // Guard's defaults: 5 x the 0.05 rad bound.
    assert!(
        matches!(
            e,
            Error::Integration {
                source: RunError::Validity {
                    unit: "rad",
                    bound: 0.05,
                    factor: 5.0,
                    ..
                },
                ..
            }
        ),
        "{e:?}"
    );
    let s = &o.summary;
    assert_eq!(s.status, washdyn_runtime::run::RunStatus::Failed);
    assert!(s.t_reached > 0.0 && s.t_reached < 40.0, "{}", s.t_reached);
    assert!(s.validity.max_rotation_rad > 0.25);
    // The elements' tub ends lie 0.21-0.31 m from the CoG (reference.toml), so 0.25 rad of
    // rotation alone moves them by several cm: past the 30 mm clearance.
    assert!(
        s.validity.max_element_deflection_m > 0.04,
        "{:?}",
        s.validity
    );
    assert!(!s.validity.max_element.is_empty());
    assert!(
        s.warnings.iter().any(|w| w.starts_with("element `")),
        "{:?}",
        s.warnings
    );
    // The door ring (clearance.rs) passes the clearance too; the four dampers keep the CoG's
    // translation below it (measured: door ring 30.2 mm at 23.6 s, rotation 0.05 rad at 20.6 s).
    assert!(
        s.warnings
            .iter()
            .any(|w| w.starts_with("door ring point") && w.contains("0.03 m tub-cabinet")),
        "{:?}",
        s.warnings
    );
    let json = std::fs::read_to_string(out_dir("validity").join("summary.json")).unwrap();
    assert!(
        json.contains("max_rotation_rad") && json.contains("warnings"),
        "{json}"
    );
    // The override runs on past the same time.
    let ctl = RunControl {
        guard: Guard {
            stop_factor: None,
            ..Guard::default()
        },
        ..RunControl::default()
    };
    // Into the same folder: it holds the stopped run, so only with --force.
    let b = RunSpec {
        t_end: Some(s.t_reached + 1.0),
        force: true,
        ..a.clone()
    };
    let o2 = run_command_with(&b, &ctl, &mut |_| {}).unwrap();
    assert!(o2.error.is_none(), "{:?}", o2.error);
    assert!(!o2.summary.warnings.is_empty());
    std::fs::remove_dir_all(out_dir("validity")).ok();
    std::fs::remove_file(&p).ok();
}

#[test]
fn interrupt_writes_an_interrupted_summary() {
    let flag = Arc::new(AtomicBool::new(false));
    let ctl = RunControl {
        guard: Guard {
            interrupt: Some(flag.clone()),
            ..Guard::default()
        },
        ..RunControl::default()
    };
    let a = RunSpec {
        t_end: Some(170.0),
        ..args("interrupt")
    };
    // Another thread sets the flag once the run has reported progress (every 100 ms of wall
    // time), so the run is under way however fast the machine.
    let (tx, rx) = std::sync::mpsc::channel::<f64>();
    let setter = std::thread::spawn(move || {
        rx.recv().unwrap();
        flag.store(true, Ordering::Relaxed);
    });
    let mut o = run_command_with(&a, &ctl, &mut |p| {
        let _ = tx.send(p.t);
    })
    .unwrap();
    setter.join().unwrap();
    // An interrupted run goes into place like any other.
    o.publish().unwrap();
    assert_eq!(
        o.summary.status,
        washdyn_runtime::run::RunStatus::Interrupted
    );
    let e = o.error.unwrap();
    assert!(
        matches!(e, Error::Integration { t, source: RunError::Interrupted { .. } } if t == o.summary.t_reached),
        "{e:?}"
    );
    assert!(o.summary.t_reached > 0.0 && o.summary.t_reached < 170.0);
    let json = std::fs::read_to_string(out_dir("interrupt").join("summary.json")).unwrap();
    assert!(json.contains("\"interrupted\""), "{json}");
    std::fs::remove_dir_all(out_dir("interrupt")).ok();
}

#[test]
fn a_run_without_progress_stops() {
    // A budget no run can meet (the remaining time projected to take more than 1 ms of wall
    // time, measured over 0.05 s windows) exercises the rule without a slow model.
    let ctl = RunControl {
        guard: Guard {
            stall_window_s: 0.05,
            ..Guard::default()
        },
        ..RunControl::default()
    };
    let a = RunSpec {
        t_end: Some(170.0),
        max_projected_wall: 1e-3,
        ..args("stall")
    };
    let o = run_command_with(&a, &ctl, &mut |_| {}).unwrap();
    let e = o.error.expect("must stop");
    assert!(
        matches!(
            e,
            Error::Integration {
                source: RunError::Stalled { budget_s: 1e-3, .. },
                ..
            }
        ),
        "{e:?}"
    );
    // What to do about it (issue 50): a faster method, or more time.
    let m = e.to_string();
    for part in [
        "beyond the 0.001 s budget: a faster method may finish it",
        "the scene's default: leave out --integrator; on a stiff scene `--integrator galpha`",
        "or give it the time with `--max-projected-wall <s>` (`inf`: never stop)",
    ] {
        assert!(m.contains(part), "`{part}` in: {m}");
    }
    assert_eq!(o.summary.status, washdyn_runtime::run::RunStatus::Failed);
    std::fs::remove_dir_all(out_dir("stall")).ok();
}

/// `--max-projected-wall` (the guard's budget) takes seconds > 0 or `inf`: the settings' rule
/// refuses the rest before anything runs (`run` and `sweep` share it), and clap what is no
/// number at all.
#[test]
fn the_progress_budget_is_refused_unless_positive() {
    for bad in [0.0, -3.0, f64::NAN] {
        let a = RunSpec {
            max_projected_wall: bad,
            ..args("budget")
        };
        let m = refused(&a, &RunControl::default(), "--max-projected-wall");
        let want = format!("--max-projected-wall must be > 0 s (inf: never stop), got {bad}");
        assert_eq!(m, [want]);
    }
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
        .args(["run", "reference", "--max-projected-wall=soon"])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{e}");
    assert!(
        e.contains("invalid value 'soon' for '--max-projected-wall"),
        "{e}"
    );
}

/// A sweep refuses what `run` refuses of its settings, every field at once and before
/// anything is written (the sweep's study file is not made), and `--jobs` 0.
#[test]
fn sweep_settings_are_validated() {
    let base = washdyn::simulation::Source::load("reference").unwrap();
    let grid = washdyn::study::sweep::Grid::default();
    let bad = RunSpec {
        tol: Some(f64::INFINITY),
        t_end: Some(0.0),
        sample_rate: 1e9,
        out: Some(out_dir("sweep")),
        ..RunSpec::of("reference")
    };
    let e = washdyn::study::sweep::study_text(&base, &bad, &grid).unwrap_err();
    assert_eq!(
        e.fields(),
        [Field::Tol, Field::TEnd, Field::SampleRate],
        "{e}"
    );
    let ok = RunSpec {
        out: Some(out_dir("sweep")),
        ..RunSpec::of("reference")
    };
    assert!(washdyn::study::sweep::study_text(&base, &ok, &grid).is_ok());
    let e = washdyn::study::check_jobs(0).unwrap_err();
    assert_eq!(e.options(), ["--jobs"], "{e}");
    assert!(!out_dir("sweep").exists());
}

/// SIGINT, SIGTERM and SIGHUP to the real binary (Ctrl-C; a batch system's time limit or a
/// closed session): the ctrlc handler sets the flag, the run stops between steps,
/// summary.json says "interrupted", the sensor file written so far is a complete parquet file
/// (its footer written: read back here) and the exit code is a failure.
#[cfg(unix)]
#[test]
fn a_stop_signal_to_the_binary_writes_an_interrupted_summary_and_a_readable_file() {
    use std::process::{Command, Stdio};
    for signal in ["INT", "TERM", "HUP"] {
        let dir = out_dir(&format!("sig{signal}"));
        std::fs::remove_dir_all(&dir).ok();
        let child = Command::new(env!("CARGO_BIN_EXE_washdyn"))
            .args([
                "run",
                "reference",
                "--no-plots",
                "--backend",
                "interpreted",
                "--out",
            ])
            .arg(&dir)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // The run's own folder (`<out>.tmp-<id>`, renamed into place when the run ends)
        // appears once the settings passed and the run starts (the 178 s run-up takes
        // seconds); stop it shortly after.
        let start = std::time::Instant::now();
        let tmp = format!("{}.tmp-", dir.file_name().unwrap().to_string_lossy());
        let parent = dir.parent().unwrap();
        while !std::fs::read_dir(parent)
            .unwrap()
            .flatten()
            .any(|e| e.file_name().to_string_lossy().starts_with(&tmp))
        {
            assert!(start.elapsed().as_secs() < 60, "no run folder after 60 s");
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
        let killed = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "SIG{signal}: {stderr}");
        assert!(
            stderr.contains("interrupted at t = "),
            "SIG{signal}: {stderr}"
        );
        let json = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        assert!(json.contains("\"status\": \"interrupted\""), "{json}");
        let (names, cols) =
            washdyn::analysis::results::read_parquet_f64(&dir.join("sensors.parquet"))
                .unwrap_or_else(|e| panic!("SIG{signal}: the sensor file: {e}"));
        assert_eq!(names[0], "time_s");
        assert!(!cols[0].is_empty(), "SIG{signal}: no sample kept");
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// The FE and Campbell commands refuse bad arguments before writing anything, as refused data
/// (exit code 5: `Error::Fe`, `Error::Campbell`; docs/commands.md); a model they cannot resolve
/// is a refused model (3, tests/exit_codes.rs).
#[test]
fn fe_and_campbell_arguments_are_refused_before_anything_is_written() {
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(5), "{args:?}: {err}");
        err
    };
    let dir = out_dir("fe");
    let d = dir.to_str().unwrap();
    let e = run(&[
        "fe",
        "modal",
        "--only",
        "tub,drumm",
        "--out",
        d,
        "--work",
        d,
    ]);
    assert!(
        e.contains("--only: no built-in body `drumm`; the bodies are tub, drum, cabinet"),
        "{e}"
    );
    let e = run(&["campbell", "no/such.modal.toml", "--out", d]);
    assert!(e.contains("no/such.modal.toml: cannot read"), "{e}");
    let modal = concat!(env!("CARGO_MANIFEST_DIR"), "/models/fe/drum.modal.toml");
    let e = run(&["campbell", modal, "--max-rpm", "5000", "--out", d]);
    assert!(
        e.contains("--max-rpm must be in (0, 3000], got 5000"),
        "{e}"
    );
    // A body that does not spin has no Campbell diagram.
    let cab = concat!(env!("CARGO_MANIFEST_DIR"), "/models/fe/cabinet.modal.toml");
    let e = run(&["campbell", cab, "--out", d]);
    assert!(e.contains("not a spinning body"), "{e}");
    assert!(!dir.exists(), "something was written to {}", dir.display());
}

/// A periodic start needs constant speed: on the reference run-up (standing at t = 0) it is
/// refused before anything is written.
#[test]
fn periodic_start_without_constant_speed() {
    let a = RunSpec {
        start: washdyn_runtime::run::Start::Periodic,
        ..args("periodic")
    };
    let m = refused(&a, &RunControl::default(), "--start");
    assert!(m[0].contains("the drum stands still at the start"), "{m:?}");
}

/// Times computed as sums of steps print rounded to 12 significant digits in messages (issue
/// 50): the run's errors, the integrators' and the settings' refusals.
#[test]
fn computed_times_print_rounded_in_messages() {
    let t = 0.013000000000000001;
    assert_eq!(
        RunError::Interrupted { t }.to_string(),
        "interrupted at t = 0.013 s"
    );
    let e = RunError::Ode(washdyn_ode::OdeError::StepSizeUnderflow { t, h: 1e-14 });
    assert_eq!(
        e.to_string(),
        "integration failed: step size underflow at t = 0.013 s (h = 1e-14 s)"
    );
    let e = RunError::Setup {
        t: 0.1 + 0.2,
        reason: "no static equilibrium".into(),
    };
    assert_eq!(e.to_string(), "no static equilibrium (at t = 0.3 s)");
    // The end of the run a start must precede: t_end as computed (0.1 + 0.2).
    let a = RunSpec {
        t_end: Some(0.1 + 0.2),
        t_start: 0.5,
        ..args("rounded")
    };
    let m = refused(&a, &RunControl::default(), "--t-start");
    assert!(
        m[0].contains("before the end of the run (0.3 s), got 0.5"),
        "{m:?}"
    );
}

/// Negative numbers reach the settings' rules instead of being taken for options (issue 50):
/// `--t-end -1` is refused by the rule with exit code 2, nothing written.
#[test]
fn negative_numbers_reach_the_rules() {
    let dir = out_dir("hyphen");
    std::fs::remove_dir_all(&dir).ok();
    for (option, value, says) in [
        (
            "--t-end",
            "-1",
            "--t-end must be > 0 and at most 3600 s, got -1",
        ),
        (
            "--tol",
            "-1e-6",
            "--tol must be in [1e-12, 1e-1], got -0.000001",
        ),
        (
            "--sample-rate",
            "-2000",
            "--sample-rate must be in [1e0, 1e5] Hz, got -2000",
        ),
        (
            "--max-projected-wall",
            "-5",
            "--max-projected-wall must be > 0 s (inf: never stop), got -5",
        ),
    ] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
            .args(["run", "reference", option, value, "--no-plots", "--out"])
            .arg(&dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{option} {value}: {err}");
        assert!(err.contains(says), "{option} {value}: {err}");
        assert!(!dir.exists(), "{option} {value}");
    }
}

/// An unknown scene is refused listing the model's scenes, each once (issue 50: the reference
/// declares `full`, which the message named a second time).
#[test]
fn an_unknown_scene_lists_each_scene_once() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
        .args(["modes", "reference", "--scene", "nope"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains(
            "unknown scene `nope`; this model has: full, presliding, rigid_low_speed, \
             damper_mass, counterweights, contact, elastic, elastic_fine, elastic_rigid_tub, \
             panel_curves, cabinet_counterweights\n"
        ),
        "{err}"
    );
    // A model that declares no `full` still has it, first.
    let (m, _) = resolve_model("compact").unwrap();
    let e = m.scene(Some("nope")).unwrap_err();
    let names = m.every_scene();
    assert_eq!(names.iter().filter(|n| **n == "full").count(), 1, "{e}");
    assert!(e.ends_with(&names.join(", ")), "{e}");
}

/// A run whose stderr is no terminal (a pipe, a Slurm log) says how far it is: a `progress:`
/// line every interval (`WASHDYN_PROGRESS_INTERVAL_S` shortens the 10 s) with the simulated
/// time and the end projected from the speed profile's remaining work.
#[test]
fn a_run_piped_prints_progress_lines() {
    let dir = out_dir("progress");
    std::fs::remove_dir_all(&dir).ok();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
        .args(["run", "reference", "--no-plots", "--out"])
        .arg(&dir)
        .env("WASHDYN_PROGRESS_INTERVAL_S", "0.2")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("progress: t = ") && l.contains("projected end"))
        .collect();
    assert!(lines.len() >= 2, "{stderr}");
    assert!(
        lines.iter().any(|l| l.contains("projected end in ")),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
