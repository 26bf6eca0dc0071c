//! `washdyn sweep`: a grid design of the study over the drum's unbalance and the speed profile.
//! The sweep's options become the study file they stand for, written into its directory and
//! run by the study's runner; what a study refuses before anything runs, the sweep refuses too.

use crate::common;

use std::path::{Path, PathBuf};
use washdyn::Error;
use washdyn::results::{Column, read_table};
use washdyn::simulation::Source;
use washdyn::spec::{Field, RunSpec};
use washdyn::study::sweep::{Grid, out_dir, study_text};
use washdyn::study::{self, Study, StudyError};
use washdyn_ode::Method;
use washdyn_runtime::run::RunStatus;

/// The rigid reference with dopri5 at 200 Hz into `out`, as `washdyn sweep reference --out
/// OUT --integrator dopri5 --tol 1e-5 --sample-rate 200 --t-end T` reads it.
fn spec(out: &Path, t_end: Option<f64>) -> RunSpec {
    RunSpec {
        out: Some(out.to_path_buf()),
        t_end,
        method: Some(Method::Dopri5),
        tol: Some(1e-5),
        sample_rate: 200.0,
        ..RunSpec::of("reference")
    }
}

/// The sweep's study, planned and run on two threads, then collected: what `washdyn sweep`
/// does after its options are checked.
fn sweep(base: &Source, spec: &RunSpec, grid: &Grid) -> (Study, Vec<study::Outcome>) {
    let text = study_text(base, spec, grid).unwrap();
    let out = out_dir(spec, &base.model);
    let s = Study::from_text(&out.join("study.toml"), text).unwrap();
    let plan = study::plan(&s, &out).unwrap();
    let res = study::execute(&s, &plan, 2, &|_| {}).unwrap();
    study::collect(&out).unwrap();
    (s, res)
}

/// Column `name` of the sweep's collected table, in variant order.
fn column(out: &Path, name: &str) -> Vec<f64> {
    match read_table(&out.join("summary.parquet"))
        .unwrap()
        .column(name)
    {
        Some(Column::F64(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    }
}

/// Three positions at 0.6 kg over the first 20 s of the run-up: three variants in design
/// order (front, middle, rear: x from docs/reference-machine.md), one table, and the order-1
/// peak of the door-side tub channel differs between the front and the rear unbalance (the
/// axial position changes the rocking). The study file in the directory completes the sweep
/// again with nothing to run.
#[test]
fn positions_sweep_is_a_grid_study_with_one_table() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sweep");
    let base = Source::load("reference").unwrap();
    let grid = Grid {
        positions: vec!["front".into(), "middle".into(), "rear".into()],
        masses: vec![0.6],
        profiles: vec![],
    };
    let (s, res) = sweep(&base, &spec(&out, Some(20.0)), &grid);
    assert_eq!(s.points, [[0.15, 0.6], [0.0, 0.6], [-0.12, 0.6]]);
    assert!(res.iter().all(|o| o.status == RunStatus::Ok), "{res:?}");
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    let name = base.model.unbalances[0].name.clone();
    assert_eq!(
        column(&out, &format!("unbalances.{name}.position.0")),
        [0.15, 0.0, -0.12]
    );
    let peak = column(&out, "tub1_ax_order1_peak");
    assert!(
        (peak[0] - peak[2]).abs() > 0.05 * peak[0],
        "front {} vs rear {}",
        peak[0],
        peak[2]
    );
    let again = Study::load(&out.join("study.toml")).unwrap();
    assert!(study::plan(&again, &out).unwrap().todo.is_empty());
}

/// Two speed profiles (CSV, time_s and rpm): a variant each, each running to its own
/// profile's end (the table reached the variant's model), its column the profile's index.
#[test]
fn a_profile_is_a_level_of_the_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("slow.csv");
    let b = dir.path().join("fast.csv");
    std::fs::write(&a, "time_s,rpm\n0,0\n0.3,60\n").unwrap();
    std::fs::write(&b, "time_s,rpm\n0,0\n0.5,120\n").unwrap();
    let out = dir.path().join("sweep");
    let base = Source::load("reference").unwrap();
    let grid = Grid {
        profiles: vec![a, b],
        ..Grid::default()
    };
    let (_, res) = sweep(&base, &spec(&out, None), &grid);
    assert!(res.iter().all(|o| o.status == RunStatus::Ok), "{res:?}");
    assert_eq!(column(&out, "speed.profile"), [0.0, 1.0]);
    assert_eq!(column(&out, "t_reached_s"), [0.3, 0.5]);
}

/// No axis at all: the base model alone, its own mass the one level.
#[test]
fn a_sweep_of_nothing_is_the_base_model() {
    let dir = tempfile::tempdir().unwrap();
    let base = Source::load("reference").unwrap();
    let text = study_text(&base, &spec(dir.path(), Some(0.1)), &Grid::default()).unwrap();
    let s = Study::from_text(&dir.path().join("study.toml"), text).unwrap();
    assert_eq!(s.points, [[base.model.unbalances[0].mass]]);
}

/// Refusals at their option before anything is written: an unknown position, a position or
/// mass given twice or not finite, an unreadable profile, and what a study does not take.
#[test]
fn bad_levels_and_options_are_refused_at_their_option() {
    let dir = tempfile::tempdir().unwrap();
    let base = Source::load("reference").unwrap();
    let s = spec(dir.path(), Some(1.0));
    let refused = |grid: Grid, spec: &RunSpec| study_text(&base, spec, &grid).unwrap_err();
    let positions = |p: &[&str]| Grid {
        positions: p.iter().map(|s| s.to_string()).collect(),
        ..Grid::default()
    };
    let masses = |m: &[f64]| Grid {
        masses: m.to_vec(),
        ..Grid::default()
    };
    for g in [positions(&["back"]), positions(&["front", "0.15"])] {
        assert_eq!(refused(g, &s).options(), ["--positions"]);
    }
    for g in [masses(&[0.3, 0.3]), masses(&[f64::NAN])] {
        assert_eq!(refused(g, &s).options(), ["--masses"]);
    }
    let missing = Grid {
        profiles: vec![dir.path().join("none.csv")],
        ..Grid::default()
    };
    assert_eq!(refused(missing, &s).options(), ["--profiles"]);
    for (field, spec) in [
        (
            Field::Backend,
            RunSpec {
                backend: Some(washdyn::spec::Backend::Interpreted),
                ..s.clone()
            },
        ),
        (
            Field::Format,
            RunSpec {
                format: washdyn::results::Format::Csv,
                ..s.clone()
            },
        ),
        (
            Field::Energy,
            RunSpec {
                energy: true,
                ..s.clone()
            },
        ),
        (
            Field::States,
            RunSpec {
                states: true,
                ..s.clone()
            },
        ),
    ] {
        assert_eq!(refused(masses(&[0.3]), &spec).fields(), [field]);
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

/// A mass the model checker refuses (-1 kg) refuses the whole sweep before anything runs,
/// naming the variant, the parameter and its value, as a study does (it used to run the
/// others and record that one as failed); the binary exits 3 and writes nothing.
#[test]
fn a_bad_mass_refuses_the_sweep_before_anything_runs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sweep");
    let base = Source::load("reference").unwrap();
    let text = study_text(
        &base,
        &spec(&out, Some(0.5)),
        &Grid {
            masses: vec![0.3, -1.0],
            ..Grid::default()
        },
    )
    .unwrap();
    let s = Study::from_text(&out.join("study.toml"), text).unwrap();
    let e = study::plan(&s, &out).unwrap_err();
    let Error::Study(StudyError::Variants(bad)) = &e else {
        panic!("{e}");
    };
    let name = &base.model.unbalances[0].name;
    assert_eq!(bad.len(), 1, "{e}");
    assert_eq!(bad[0].id, "0001");
    assert_eq!(bad[0].values, [(format!("unbalances.{name}.mass"), -1.0)]);
    assert!(!out.exists());
    let o = common::washdyn_in(
        &[
            "sweep",
            "reference",
            "--masses",
            "0.3,-1",
            "--out",
            "o",
            "--t-end",
            "0.5",
        ],
        dir.path(),
    );
    assert_eq!(
        o.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!dir.path().join("o").exists());
}

/// Named positions are the built-in drums'; another model takes positions in m.
#[test]
fn named_positions_only_for_the_built_in_drums() {
    let dir = tempfile::tempdir().unwrap();
    let mut base = Source::load("reference").unwrap();
    base.model.name = "other".into();
    let s = spec(dir.path(), Some(1.0));
    let front = Grid {
        positions: vec!["front".into()],
        ..Grid::default()
    };
    let e = study_text(&base, &s, &front).unwrap_err();
    assert_eq!(e.options(), ["--positions"], "{e}");
    let free = Grid {
        positions: vec!["0.1".into()],
        ..Grid::default()
    };
    let text = study_text(&base, &s, &free).unwrap();
    assert!(
        text.contains("position.0") && text.contains("levels = [0.1]"),
        "{text}"
    );
}

/// A sweep of a model file names it absolutely in its study file, so the sweep's directory
/// is a study that runs again from anywhere.
#[test]
fn a_model_file_is_named_absolutely() {
    let dir = tempfile::tempdir().unwrap();
    let model: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/data/reference.toml");
    let base = Source::load(model.to_str().unwrap()).unwrap();
    let s = RunSpec {
        model: model.display().to_string(),
        ..spec(dir.path(), Some(0.1))
    };
    let text = study_text(&base, &s, &Grid::default()).unwrap();
    assert!(
        text.contains(&format!("model = \"{}\"", model.display())),
        "{text}"
    );
    let elsewhere = tempfile::tempdir().unwrap();
    let study = Study::from_text(&elsewhere.path().join("study.toml"), text).unwrap();
    assert_eq!(study.source.model.name, base.model.name);
}
