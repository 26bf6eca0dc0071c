//! Free parameters (`Model::free`, model/src/codegen/free.rs): the reference machine's spring
//! rates, damper friction and bolt torques are inputs of its generated code, so a variant that changes only
//! them runs on the built code. The reference here is the interpreter on the variant: the same
//! derivation at run time, which knows nothing of stand-ins or parameter arrays.

use washdyn::simulation::{Backend, RunControl, Simulation, Source};
use washdyn::spec::RunSpec;
use washdyn_model::ir::param::{resolve, set};
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::system::{Interpreter, Mechanical};

/// The reference with every free parameter changed: springs 30 % softer, damper friction 50 %
/// higher (a variant a suspension study would run), every bolt loose (torque 0: the loose
/// counterweights of docs/even-orders.md).
fn variant() -> washdyn_model::ir::Model {
    let base = washdyn_models::reference();
    let params: Vec<_> = base
        .free
        .iter()
        .map(|t| resolve(&base, t).unwrap())
        .collect();
    let values: Vec<f64> = params
        .iter()
        .map(|p| {
            let v = washdyn_model::ir::param::get(&base, p);
            if p.text.contains("stiffness") {
                0.7 * v
            } else if p.text.contains("torque") {
                0.0
            } else {
                1.5 * v
            }
        })
        .collect();
    set(&base, &params, &values).unwrap()
}

#[test]
fn the_reference_declares_its_suspension_and_bolts_free() {
    let m = washdyn_models::reference();
    // 3 springs, 4 dampers, 12 bolts.
    assert_eq!(m.free.len(), 19);
    assert_eq!(washdyn_models::reference::FREE.len(), 19);
    // The built-in TOML and the macro's declaration name the same parameters.
    assert_eq!(
        m.free,
        washdyn_models::reference::model().free,
        "models/data/reference.toml and models/src/reference.rs"
    );
}

/// For `scene`: the largest difference of the generated h for `v` from the interpreter's on
/// `v`, and the smallest difference of the unchanged model's folded h from it, both relative to
/// the largest force, over five states; M1 checked equal on the way.
fn h_against_interpreter(v: &washdyn_model::ir::Model, scene: &str) -> (f64, f64) {
    let eff = v.scene(Some(scene)).unwrap();
    let mut interp = Interpreter::new(v, &eff);
    let mut built = washdyn_models::generated_for("reference", scene, v)
        .expect("scene exists")
        .expect("only free parameters changed");
    let mut folded = washdyn_models::generated("reference", scene).unwrap();
    let lay = interp.layout();
    let (n, n1) = (lay.n(), lay.n1);
    let (mut worst, mut moved) = (0.0f64, f64::INFINITY);
    for k in 0..5 {
        let t = 20.0 + 37.0 * k as f64;
        let q: Vec<f64> = (0..n)
            .map(|i| 2e-3 * (0.3 + (i + k) as f64).sin())
            .collect();
        let qd: Vec<f64> = (0..n)
            .map(|i| 2e-2 * (1.1 + (i * k) as f64).cos())
            .collect();
        let mut m_i = vec![0.0; n1 * n1];
        let mut h_i = vec![0.0; n];
        let mut m_g = m_i.clone();
        let mut h_g = h_i.clone();
        let mut m_b = m_i.clone();
        let mut h_b = h_i.clone();
        interp.eval(t, &q, &qd, &mut m_i, &mut h_i);
        built.eval(t, &q, &qd, &mut m_g, &mut h_g);
        folded.eval(t, &q, &qd, &mut m_b, &mut h_b);
        let scale = h_i.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let diff = |a: &[f64], b: &[f64]| {
            a.iter()
                .zip(b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
                / scale
        };
        worst = worst.max(diff(&h_i, &h_g));
        moved = moved.min(diff(&h_i, &h_b));
        // M1 holds no free parameter: the generated M1 is the built model's (above 12
        // coordinates from its fitted harmonics, hence round-off, not equality).
        let m_scale = m_i.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let dm = m_i
            .iter()
            .zip(&m_g)
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(dm <= 5e-13 * m_scale, "{scene}: M1 {dm:e}");
    }
    (worst, moved)
}

/// M1 and h of the generated code for the variant equal the interpreter's on the variant to
/// round-off, in every scene, and differ from the unchanged model's (the parameters are read).
#[test]
fn generated_code_follows_its_free_parameters_in_every_scene() {
    let v = variant();
    let (mut worst, mut moved) = (0.0f64, f64::INFINITY);
    for scene in v.scene_names() {
        let (d, m) = h_against_interpreter(&v, &scene);
        // Measured: 0 (the same arithmetic; backend_agreement's bound for folded code).
        assert!(d < 5e-13, "{scene}: h {d:e}");
        // The unchanged model's forces are not the variant's (measured at least 8.1e-6 of
        // the largest force: in the elastic scenes the modal forces dominate h, in
        // `counterweights` the bolts' at these 2 mm deflections).
        assert!(m > 1e-6, "{scene}: {m:e}");
        (worst, moved) = (worst.max(d), moved.min(m));
    }
    println!("h: generated vs interpreter {worst:e}, variant vs unchanged {moved:e}");
}

/// The loose bolts alone (every torque 0, the rest as built): the run docs/even-orders.md's
/// cabinet channels need. The torque reaches the generated forces of the scenes with
/// counterweights as a parameter (the preload is the declared torque times its newtons per N m
/// at run time, not a product folded while setting up), so the loose joints' kinks are the
/// interpreter's to round-off, and far from the tight joints' forces.
#[test]
fn loose_bolts_run_on_the_built_code() {
    let base = washdyn_models::reference();
    let torques: Vec<_> = base
        .free
        .iter()
        .filter(|t| t.ends_with("torque.moment"))
        .map(|t| resolve(&base, t).unwrap())
        .collect();
    assert_eq!(torques.len(), 12);
    let loose = set(&base, &torques, &[0.0; 12]).unwrap();
    for scene in ["counterweights", "cabinet_counterweights"] {
        assert_eq!(
            washdyn_models::fits("reference", scene, &loose),
            Some(Ok(()))
        );
        let (d, m) = h_against_interpreter(&loose, scene);
        println!("{scene}: generated vs interpreter {d:e}, loose vs tight {m:e}");
        // Measured: 0, and the loose bolts 1.9e-2 (`counterweights`) and 1.1e-2
        // (`cabinet_counterweights`) of the largest force away from the tight ones.
        assert!(d < 5e-13, "{scene}: h {d:e}");
        assert!(m > 1e-3, "{scene}: the torque is not read: {m:e}");
    }
}

/// A study's variant through `Simulation`: the generated back end runs it, with the same
/// sensor signals as the interpreter; a change of a number that is not free is refused with
/// its path.
#[test]
fn a_variant_runs_on_the_built_code_or_is_refused_by_name() {
    let base = Source::load("reference").unwrap();
    let spec = |backend| RunSpec {
        backend: Some(backend),
        scene: Some("full".into()),
        t_end: Some(3.0),
        sample_rate: 500.0,
        ..RunSpec::default()
    };
    let run = |src: Source, backend| {
        let sim = Simulation::new(src, &spec(backend), &RunControl::default()).unwrap();
        let mut sink = MemorySink::default();
        let (summary, err) = sim.integrate(&mut sink, &mut |_| {});
        assert!(err.is_none(), "{err:?}");
        assert_eq!(summary.status, washdyn_runtime::run::RunStatus::Ok);
        sink
    };
    let g = run(base.variant(variant()), Backend::Generated);
    let i = run(base.variant(variant()), Backend::Interpreted);
    let b = run(
        base.variant(washdyn_models::reference()),
        Backend::Generated,
    );
    let width = g.channels.len();
    let col = |s: &MemorySink, k: usize| s.values.chunks(width).map(|r| r[k]).collect::<Vec<f64>>();
    assert_eq!(g.time, i.time);
    let (mut worst, mut moved) = (0.0f64, 0.0f64);
    for k in 0..width {
        let (x, y, z) = (col(&g, k), col(&i, k), col(&b, k));
        let scale = y.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-30);
        for ((a, c), d) in x.iter().zip(&y).zip(&z) {
            worst = worst.max((a - c).abs() / scale);
            moved = moved.max((c - d).abs() / scale);
        }
    }
    println!("sensors: generated vs interpreter {worst:e}, variant vs unchanged {moved:e}");
    // Measured: 0 (the same arithmetic, the same steps); the variant moved the signals by 1.1
    // of their largest value (3 s of the run-up from rest).
    assert!(
        worst < 1e-9,
        "generated vs interpreter on the variant: {worst:e}"
    );
    assert!(moved > 0.1, "the variant changed nothing: {moved:e}");

    let mut heavier = variant();
    heavier.tub.mass *= 1.1;
    let Err(e) = Simulation::new(
        base.variant(heavier),
        &spec(Backend::Generated),
        &RunControl::default(),
    ) else {
        panic!("tub mass is not free, yet the generated code took the variant");
    };
    let e = e.to_string();
    assert!(e.contains("`tub.mass`") && e.contains("interpreter"), "{e}");
}

/// The fit check a study chooses each variant's back end by (`washdyn_models::fits`) says what
/// building the system says, without building it: a free-only variant fits, a change elsewhere
/// is refused with the same message, a scene without generated code or an unknown model is
/// `None`.
#[test]
fn the_fit_check_agrees_with_the_build() {
    let v = variant();
    let mut heavier = variant();
    heavier.tub.mass *= 1.1;
    for scene in washdyn_models::reference::SCENES {
        assert_eq!(washdyn_models::fits("reference", scene, &v), Some(Ok(())));
        let built = washdyn_models::generated_for("reference", scene, &heavier).unwrap();
        let Err(by_build) = built else {
            panic!("{scene}: the build took a heavier tub")
        };
        assert_eq!(
            washdyn_models::fits("reference", scene, &heavier),
            Some(Err(by_build))
        );
    }
    assert_eq!(washdyn_models::fits("reference", "no_such_scene", &v), None);
    assert_eq!(washdyn_models::fits("no_such_model", "full", &v), None);
}

/// The committed study of docs/even-orders.md (docs/even-orders/loose_bolts.toml) is one
/// variant, every bolt's torque 0, and a study runs it on the generated code.
#[test]
fn the_loose_bolts_study_runs_generated() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/even-orders/loose_bolts.toml");
    let study = washdyn::study::Study::load(&path).unwrap();
    let variants = washdyn::study::variants::variants(&study);
    assert_eq!(variants.len(), 1);
    let model = variants[0].model(&study).unwrap();
    assert!(model.bolted_joints.iter().all(|j| j.preload() == 0.0));
    assert_eq!(model.bolted_joints.len(), 12);
    assert_eq!(
        washdyn::study::run::backend_for(&study, &variants[0]),
        Backend::Generated
    );
}
