//! One simulation set-up (`washdyn::simulation`): `run` and `sweep` build the same simulation
//! from the same settings and refuse the same things; the error class comes only from a study
//! of the same model content, scene, method, tolerance and window; a tolerance beyond every
//! class warns; the exit codes follow the error's variant.

use std::path::PathBuf;
use washdyn::Error;
use washdyn::commands::{Backend, RunControl, RunSpec, run_command, run_simulation};
use washdyn::results::Format;
use washdyn::simulation::{Simulation, Source};
use washdyn::study::sweep::{Grid, study_text};
use washdyn::study::{self, Study};
use washdyn_ode::Method;
use washdyn_runtime::run::{RunError, RunStatus, Start};

fn tmp(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("washdyn-sim-{tag}-{}", std::process::id()))
}

/// `washdyn run reference` with the interpreter (the sweep's back end), 2 s at 200 Hz.
fn args(tag: &str) -> RunSpec {
    RunSpec {
        model: "reference".into(),
        t_end: Some(2.0),
        out: Some(tmp(tag)),
        method: Some(Method::Dopri5),
        tol: Some(1e-6),
        step: None,
        rho_inf: None,
        backend: Some(Backend::Interpreted),
        scene: None,
        sample_rate: 200.0,
        max_steps: None,
        format: Format::Parquet,
        states: false,
        energy: false,
        start: Start::Static,
        ..RunSpec::default()
    }
}

/// The sweep's study of the base model alone (its own mass the one level) for the same
/// specification, as `washdyn sweep` builds it: the specification itself, into another folder.
fn base_sweep(a: &RunSpec, tag: &str) -> Study {
    let base = Source::load(&a.model).unwrap();
    let spec = RunSpec {
        out: Some(tmp(tag)),
        backend: None,
        ..a.clone()
    };
    let text = study_text(&base, &spec, &Grid::default()).unwrap();
    Study::from_text(&tmp(tag).join("study.toml"), text).unwrap()
}

/// The same options give the same simulation in `run` and in `sweep` (a study's variant):
/// scene, back end (generated: the base model fits the built-in's code), method, options
/// (rho_inf and rk4's step included), window, guard (rk4's step for the stability check, the
/// elements' tub ends, the clearance watch), warnings, and labels but the variant's id
/// (`<model>/<id>`).
#[test]
fn run_and_sweep_build_the_same_simulation() {
    for (method, step, rho_inf, tol) in [
        (Method::Dopri5, None, None, 1e-6),
        (Method::GeneralizedAlpha, None, Some(0.5), 1e-5),
        (Method::Rk4, Some(5e-5), None, 1e-6),
        (Method::Auto, None, None, 5e-2),
    ] {
        let a = RunSpec {
            method: Some(method),
            step,
            rho_inf,
            tol: Some(tol),
            backend: None,
            ..args("same")
        };
        let r = run_simulation(&a, &RunControl::default()).unwrap();
        let study = base_sweep(&a, "same");
        let v = &study::variants::variants(&study)[0];
        let s = study::simulation(&study, v).unwrap();
        let dbg = |x: &Simulation| {
            format!(
                "{:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?}",
                x.scene,
                x.backend,
                x.method,
                x.options,
                x.rho_inf,
                x.run,
                x.guard,
                washdyn::error_class::Verdict::of(x),
                (&x.labels.scene, &x.labels.backend)
            )
        };
        assert_eq!(dbg(&r), dbg(&s), "{method}");
        assert_eq!(s.labels.model, format!("{}/{}", r.labels.model, v.id));
        assert_eq!(
            r.guard.fixed_step,
            (method == Method::Rk4).then_some(5e-5),
            "rk4's step goes to the stability check"
        );
        assert!(!r.guard.elements.is_empty());
    }
    assert!(!tmp("same").exists());
}

/// Generalized-alpha is `galpha` with its rho_inf in `run`'s summary and in the sweep's study
/// record (`study.json`), which every variant runs by.
#[test]
fn sweep_labels_generalized_alpha_like_run() {
    let a = RunSpec {
        method: Some(Method::GeneralizedAlpha),
        rho_inf: Some(0.5),
        tol: Some(1e-5),
        t_end: Some(0.1),
        backend: None,
        ..args("galpha")
    };
    let o = run_command(&a, &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "{:?}", o.error);
    let s = base_sweep(&a, "galpha-sweep");
    let plan = study::plan(&s, &tmp("galpha-sweep")).unwrap();
    let res = study::execute(&s, &plan, 1, &|_| {}).unwrap();
    assert_eq!(res[0].status, RunStatus::Ok, "{res:?}");
    let record = study::dataset::Record::read(&tmp("galpha-sweep")).unwrap();
    assert_eq!(record.run.method, o.summary.integrator);
    assert_eq!(record.run.method, "galpha");
    assert_eq!(record.run.rho_inf, o.summary.rho_inf);
    assert_eq!(record.run.rho_inf, Some(0.5));
    std::fs::remove_dir_all(tmp("galpha")).ok();
    std::fs::remove_dir_all(tmp("galpha-sweep")).ok();
}

/// rk4 with a step beyond its stability limit: the sweep's variant stops at t = 0 like
/// `run` (the limit 2.78 / spectral radius at the start: about 7e-4 s on the reference,
/// tests/bad_input.rs), with the same message (the same limit), no step taken, and its row
/// says failed.
#[test]
fn sweep_refuses_rk4_beyond_its_stability_limit_like_run() {
    let a = RunSpec {
        method: Some(Method::Rk4),
        step: Some(1e-3),
        backend: None,
        ..args("rk4")
    };
    let o = run_command(&a, &mut |_| {}).unwrap();
    assert!(
        matches!(
            &o.error,
            Some(Error::Integration {
                t: 0.0,
                source: RunError::Unstable { h: 1e-3, .. },
            })
        ),
        "expected rk4's stability limit at t = 0, got {:?}",
        o.error
    );
    let s = base_sweep(&a, "rk4-sweep");
    let plan = study::plan(&s, &tmp("rk4-sweep")).unwrap();
    let res = study::execute(&s, &plan, 1, &|_| {}).unwrap();
    assert_eq!(res[0].status, RunStatus::Failed);
    assert_eq!(res[0].steps, 0);
    assert_eq!(res[0].error, o.summary.error);
    let c = study::collect(&tmp("rk4-sweep")).unwrap();
    assert_eq!(c.rows, 1);
    let table = std::fs::read_to_string(tmp("rk4-sweep").join("summary.csv")).unwrap();
    assert!(
        table.lines().nth(1).unwrap().contains(",failed,"),
        "{table}"
    );
    std::fs::remove_dir_all(tmp("rk4")).ok();
    std::fs::remove_dir_all(tmp("rk4-sweep")).ok();
}

/// A sweep of a model file runs its variants from that file (its data files with it): the
/// study's record names the file and holds the content hash `run`'s error class reads, and
/// an edit of the file makes it another study.
#[test]
fn sweep_variants_record_the_model_files() {
    let model = reference_file("files", None);
    let a = RunSpec {
        model: model.to_str().unwrap().into(),
        backend: None,
        t_end: Some(0.2),
        ..args("files")
    };
    let s = base_sweep(&a, "files-sweep");
    let plan = study::plan(&s, &tmp("files-sweep")).unwrap();
    let res = study::execute(&s, &plan, 1, &|_| {}).unwrap();
    assert_eq!(res[0].status, RunStatus::Ok, "{res:?}");
    let record = study::dataset::Record::read(&tmp("files-sweep")).unwrap();
    assert_eq!(record.model, model.to_str().unwrap());
    let r = run_simulation(&a, &RunControl::default()).unwrap();
    assert_eq!(
        record.model_content,
        washdyn::error_class::content_hash(r.model(), &r.scene)
    );
    // The same file with another spring rate: the same study text, another study.
    reference_file("files", Some(("stiffness = 4000.0", "stiffness = 4100.0")));
    let e = study::plan(&base_sweep(&a, "files-sweep"), &tmp("files-sweep")).unwrap_err();
    assert!(
        matches!(&e, Error::Study(study::StudyError::Directory { .. }))
            && e.to_string().contains("model_content"),
        "{e}"
    );
    std::fs::remove_dir_all(tmp("files")).ok();
    std::fs::remove_dir_all(tmp("files-sweep")).ok();
    std::fs::remove_file(model).ok();
}

/// models/data/reference.toml as a file elsewhere (its data files named absolutely), with
/// one edit.
fn reference_file(tag: &str, edit: Option<(&str, &str)>) -> PathBuf {
    let src = concat!(env!("CARGO_MANIFEST_DIR"), "/models/data/reference.toml");
    let mut text = std::fs::read_to_string(src).unwrap().replace(
        "\"../fe/",
        &format!("\"{}/models/fe/", env!("CARGO_MANIFEST_DIR")),
    );
    if let Some((from, to)) = edit {
        assert!(text.contains(from), "reference.toml lacks `{from}`");
        text = text.replacen(from, to, 1);
    }
    let p = tmp(tag).with_extension("toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// The class `run` would report for this model and settings (no run needed: the class depends
/// on the set-up only, and a failed run reports none).
fn class(model: &str, spec: &RunSpec) -> Option<String> {
    let sim = Simulation::new(Source::load(model).unwrap(), spec, &RunControl::default());
    washdyn::error_class::error_class(&sim.unwrap())
}

/// The committed study (docs/accuracy.json) measured the reference's `full` scene over the
/// whole run-up, 0 .. 178.375 s: dopri5 at --tol 1e-6 reached 2.7e-3 (class 1e-2), at 1e-7
/// 2.3e-4 (1e-3). The built-in reference with those settings, and a model file of the same
/// content, get that class; a file named `reference` with one number changed, another window
/// (0.05 s, or 150 s), another scene, or a tolerance the study did not measure get none.
#[test]
fn error_class_only_for_the_studied_model_content_and_window() {
    let full = RunSpec {
        scene: Some("full".into()),
        ..RunSpec::default()
    };
    let c = class("reference", &full).expect("the study's own setting");
    assert!(
        c.starts_with("1e-2 (docs/accuracy.md: dopri5 at 1e-6"),
        "{c}"
    );
    let tighter = RunSpec {
        tol: Some(1e-7),
        ..full.clone()
    };
    assert!(class("reference", &tighter).unwrap().starts_with("1e-3 "));
    // The same content from a file: the same class (the backend does not enter).
    let same = reference_file("same-content", None);
    assert_eq!(class(same.to_str().unwrap(), &full), Some(c.clone()));
    // A file named `reference` whose friction slope differs: none.
    let changed = reference_file("changed", Some(("slope = 2000.0", "slope = 2001.0")));
    let m = Source::load(changed.to_str().unwrap()).unwrap();
    assert_eq!(m.model.name, "reference");
    assert_eq!(class(changed.to_str().unwrap(), &full), None);
    // Other windows: a 0.05 s run, a 150 s run-up.
    for t in [0.05, 150.0] {
        let short = RunSpec {
            t_end: Some(t),
            ..full.clone()
        };
        assert_eq!(class("reference", &short), None, "t_end {t}");
    }
    // The study's elastic window starts at 150 s, so no run from 0 matches it; and a scene it
    // did not study, or two decades off its tolerances.
    for s in [
        RunSpec {
            scene: Some("rigid_low_speed".into()),
            ..full.clone()
        },
        RunSpec {
            tol: Some(1e-12),
            ..full.clone()
        },
    ] {
        assert_eq!(class("reference", &s), None, "{s:?}");
    }
    std::fs::remove_file(same).ok();
    std::fs::remove_file(changed).ok();
}

/// End to end: the whole run-up with `run`'s defaults writes the class into summary.json.
#[test]
fn the_studied_run_up_reports_its_class() {
    let a = RunSpec {
        backend: Some(Backend::Generated),
        t_end: None,
        ..args("class")
    };
    let o = run_command(&a, &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "{:?}", o.error);
    let c = o.summary.error_class.clone().expect("class");
    assert!(c.starts_with("1e-2 "), "{c}");
    let json = std::fs::read_to_string(tmp("class").join("summary.json")).unwrap();
    assert!(json.contains("\"error_class\": \"1e-2 "), "{json}");
    std::fs::remove_dir_all(tmp("class")).ok();
}

/// The binary's stderr, exit code and out folder for `args`.
fn washdyn(args: &[&str]) -> (Option<i32>, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// 1e-2 is the study's loosest class (src/accuracy/mod.rs, CLASSES): a tolerance at or beyond
/// it warns on stderr and in summary.json's `warnings`; the default's does not.
#[test]
fn a_tolerance_looser_than_every_class_warns() {
    let dir = tmp("loose");
    let d = dir.to_str().unwrap();
    for (tol, warns) in [("5e-2", true), ("1e-2", true), ("1e-3", false)] {
        let (code, err) = washdyn(&[
            "run",
            "reference",
            "--t-end",
            "0.2",
            "--tol",
            tol,
            "--no-plots",
            "--force",
            "--out",
            d,
        ]);
        assert_eq!(code, Some(0), "{err}");
        let line = format!("warning: --tol {tol} is not tighter than the loosest error class");
        assert_eq!(err.contains(&line), warns, "--tol {tol}: {err}");
        let json = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        let in_summary = v["warnings"].as_array().unwrap().iter().any(|w| {
            w.as_str()
                .unwrap()
                .starts_with(&format!("--tol {tol} is not tighter"))
        });
        assert_eq!(in_summary, warns, "--tol {tol}: {json}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// One exit code per kind of error (src/cli/mod.rs, EXIT_CODES; README): a refused setting 2, a model
/// that is neither built in nor a file 3, a run that stopped (rk4 beyond its limit) 1.
#[test]
fn exit_codes_follow_the_error() {
    let dir = tmp("codes");
    let d = dir.to_str().unwrap();
    let (code, err) = washdyn(&["run", "reference", "--tol", "0.5", "--out", d]);
    assert_eq!(code, Some(2), "{err}");
    assert!(!dir.exists());
    let (code, err) = washdyn(&["run", "no_such_model", "--out", d]);
    assert_eq!(code, Some(3), "{err}");
    let (code, err) = washdyn(&[
        "run",
        "reference",
        "--integrator",
        "rk4",
        "--step",
        "1e-3",
        "--no-plots",
        "--out",
        d,
    ]);
    assert_eq!(code, Some(1), "{err}");
    let (code, err) = washdyn(&["sweep", "reference", "--jobs", "0", "--out", d]);
    assert_eq!(code, Some(2), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A run that names no method takes its scene's default (`solver` in the model file): the
/// damper bodies' galpha, dopri5 elsewhere (every built-in scene names one). The scene's
/// tolerance goes with its method only: a run naming another method gets 1e-6; a scene
/// without a `solver`, dopri5 at 1e-6.
#[test]
fn runs_take_their_scenes_default_solver() {
    let solver_for = |model: &washdyn_model::ir::Model, scene: Option<&str>, method, tol| {
        RunSpec {
            scene: scene.map(String::from),
            method,
            tol,
            ..RunSpec::default()
        }
        .solver(model)
    };
    use washdyn_model::ir::{Integrator, SceneSolver};
    let mut model = washdyn_models::built_in("reference").unwrap().unwrap();
    let (galpha, dopri) = (Method::GeneralizedAlpha, Method::Dopri5);
    for name in model.scene_names() {
        let stiff = ["damper_mass", "counterweights"].contains(&name.as_str());
        let want = if stiff { galpha } else { dopri };
        assert_eq!(
            solver_for(&model, Some(&name), None, None),
            (want, 1e-6),
            "{name}"
        );
    }
    assert_eq!(
        solver_for(&model, None, None, None),
        (dopri, 1e-6),
        "the first scene"
    );
    let elastic = model
        .scenes
        .iter_mut()
        .find(|s| s.name == "elastic")
        .unwrap();
    elastic.solver = Some(SceneSolver {
        method: Integrator::Galpha,
        tol: 1e-4,
    });
    let s = Some("elastic");
    assert_eq!(solver_for(&model, s, None, None), (galpha, 1e-4));
    assert_eq!(solver_for(&model, s, Some(galpha), None), (galpha, 1e-4));
    assert_eq!(solver_for(&model, s, Some(dopri), None), (dopri, 1e-6));
    assert_eq!(solver_for(&model, s, None, Some(1e-5)), (galpha, 1e-5));
    model.scenes.iter_mut().for_each(|s| s.solver = None);
    assert_eq!(
        solver_for(&model, s, None, None),
        (dopri, 1e-6),
        "no solver named"
    );
}

/// A run shorter than the analysis' 1 s block (issue 50) is analysed in one block of all its
/// samples, down to 0.25 s, and skipped below, each saying so on stderr and in summary.json's
/// `analysis`, with exit 0 and status ok; an analysis that fails (its folder taken by a file)
/// fails the run's status with the exit code; `--no-plots` leaves `analysis` out.
#[test]
fn short_runs_are_analysed_in_one_block_or_skipped_and_say_so() {
    let dir = tmp("short");
    let d = dir.to_str().unwrap();
    let summary = || -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
    };
    let run = |t_end: &str, more: &[&str]| {
        let mut a = vec![
            "run",
            "reference",
            "--t-end",
            t_end,
            "--sample-rate",
            "1000",
        ];
        // Each run replaces the one before (a run owns its folder).
        a.extend(["--force", "--out", d]);
        a.extend(more);
        washdyn(&a)
    };
    std::fs::remove_dir_all(&dir).ok();
    let (code, err) = run("0.5", &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains(
            "note: the run's 501 samples (0.501 s) are fewer than the analysis' 1 s block: \
             analysed in one block of them (frequency resolution 1.996 Hz)"
        ),
        "{err}"
    );
    let s = summary();
    assert_eq!(s["status"], "ok", "{s}");
    assert_eq!(s["analysis"]["status"], "done", "{s}");
    assert_eq!(s["analysis"]["block_length_s"], 0.501, "{s}");
    assert!(dir.join("analysis").join("orders.parquet").is_file());

    std::fs::remove_dir_all(&dir).ok();
    let (code, err) = run("0.1", &[]);
    assert_eq!(code, Some(0), "{err}");
    let note = "no analysis: the signal spans 0.101 s at 1000 Hz, shorter than the shortest \
                analysis block (0.25 s)";
    assert!(err.contains(&format!("note: {note}")), "{err}");
    let s = summary();
    assert_eq!(s["status"], "ok", "{s}");
    assert_eq!(s["analysis"]["status"], "skipped", "{s}");
    assert!(
        s["analysis"]["note"].as_str().unwrap().starts_with(note),
        "{s}"
    );
    assert!(!dir.join("analysis").exists());

    // (A failed analysis fails the run's status too, src/cli/run.rs; a run now owns a fresh
    // folder, so no file left in the way can make it fail from here.)
    let (code, err) = run("0.1", &["--no-plots"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("note:"), "{err}");
    assert!(summary().get("analysis").is_none());
    std::fs::remove_dir_all(&dir).ok();
}
