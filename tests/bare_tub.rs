//! The elastic tub with its counterweights bolted on (issue 52): the tub's modal data without
//! the counterweights' bricks (models/fe/tub_bare.modal.toml, `washdyn fe modal`), the three
//! counterweights as rigid bodies on their twelve bolts, against the tub whose bricks share the
//! shell's nodes (models/fe/tub.modal.toml: CalculiX's free-free frequencies of that mesh).
//! Linearisation: M from the derivation, K = -dh/dq by central differences about q = 0, the
//! tub free (no gravity, no suspension), the bolts closed and sticking (linear, 1e9 N/m).

use nalgebra::DMatrix;
use washdyn_model::equations::Equations;
use washdyn_model::ir::Model;
use washdyn_model::ir::toml_file::load_str;

/// The reference's counterweights and bolted joints (models/data/reference.toml), as written.
fn bolts_text() -> String {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("models/data/reference.toml")).unwrap();
    text.split("\n[[")
        .filter(|b| b.starts_with("counterweights]]") || b.starts_with("bolted_joints]]"))
        .map(|b| {
            // A block ends at its last key: drop the comments that head the next one.
            let body: Vec<&str> = b.lines().take_while(|l| !l.starts_with('#')).collect();
            format!("\n[[{}\n", body.join("\n"))
        })
        .collect()
}

/// The FE tub alone, free, with the reference's counterweights: scene `tied` (the bricks in
/// the tub's data) and `bolted` (the bare tub's data, the counterweights on their bolts).
fn free_tub() -> Model {
    let src = format!(
        "name = \"free_tub\"\ngravity = [0.0, 0.0, 0.0]\n\
         [tub]\nmass = 43.966\ncog = [0.0249, 0.0, 0.4592]\n\
         inertia = [[2.917, 0.0, -0.2926], [0.0, 2.548, 0.0], [-0.2926, 0.0, 2.272]]\n\
         [speed]\ntable = [[0.0, 0.0], [1.0, 0.0]]\n{}\
         [[elastic]]\nname = \"tub\"\nfile = \"fe/tub.modal.toml\"\n\
         bare = \"fe/tub_bare.modal.toml\"\ndamping = 0.0\n\
         [[scenes]]\nname = \"tied\"\neffects = [\"elastic.tub\"]\n\
         [[scenes]]\nname = \"bolted\"\neffects = [\"elastic.tub\", \"counterweights\"]\n",
        bolts_text()
    );
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    load_str(&src, "free_tub.toml", &dir).unwrap_or_else(|e| panic!("{e}"))
}

/// Undamped frequencies (Hz) of a scene's linearisation about q = 0, ascending.
fn frequencies(model: &Model, scene: &str) -> Vec<f64> {
    let eq = Equations::new(model, &model.scene(Some(scene)).unwrap());
    let l = crate::common::linearise_at_speed(&eq, 0.0, 1e-7);
    let k: DMatrix<f64> = 0.5 * (&l.k + l.k.transpose());
    let mi = l.m.clone().try_inverse().expect("M regular");
    let mut f: Vec<f64> = (&mi * &k)
        .complex_eigenvalues()
        .iter()
        .map(|z| z.re.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    f
}

#[test]
fn the_bolted_tub_rings_like_the_tied_tub() {
    let model = free_tub();
    let tied = frequencies(&model, "tied");
    let bolted = frequencies(&model, "bolted");
    eprintln!("tied   {:?}", &tied[..14]);
    eprintln!("bolted {:?}", &bolted[..14]);
    // Six rigid-body modes each: the bolts are internal.
    assert!(tied[..6].iter().chain(&bolted[..6]).all(|f| *f < 1e-2));
}

/// The reference machine made LTI at drum speed (friction dampers as 400 N s/m linear dampers,
/// as runtime/src/harmonic.rs's own test), with scene `tied` (the elastic tub's data with the
/// bricks) and `bolted` (the bare tub and the counterweights on their bolts).
fn lti_reference() -> Model {
    let mut m = washdyn::commands::resolve_model("reference").unwrap().0;
    for d in std::mem::take(&mut m.friction_dampers) {
        m.dampers.push(washdyn_model::ir::LinearDamper {
            name: d.name,
            a: d.a,
            b: d.b,
            damping: 400.0,
        });
    }
    let base = [
        "gyroscopic",
        "unbalance.drum",
        "unbalance.motor",
        "gasket_damping",
    ];
    for (name, extra) in [("tied", &[][..]), ("bolted", &["counterweights"][..])] {
        let mut effects: Vec<String> = base.iter().map(|s| s.to_string()).collect();
        effects.push("elastic.tub".into());
        effects.extend(extra.iter().map(|s| s.to_string()));
        m.scenes.push(washdyn_model::ir::Scene {
            name: name.into(),
            effects,
            max_order: None,
            solver: None,
        });
    }
    m
}

/// Order 1 of the drum's unbalance on every tub channel, tied against bolted, the bolts closed
/// and sticking (the harmonic response's small motion), 100 to 1400 rpm.
#[test]
fn the_bolted_tub_answers_order_one_like_the_tied_tub() {
    use washdyn_runtime::harmonic::response;
    use washdyn_runtime::system::{Interpreter, Mechanical};
    let m = lti_reference();
    let sys = |s: &str| Interpreter::new(&m, &m.scene(Some(s)).unwrap());
    let (tied, bolted) = (sys("tied"), sys("bolted"));
    let names = tied.channel_names();
    assert_eq!(names, bolted.channel_names());
    let mut worst = (0.0f64, String::new());
    for rpm in [100.0, 300.0, 500.0, 700.0, 900.0, 1100.0, 1400.0] {
        let w = rpm * std::f64::consts::PI / 30.0;
        let a = response(&tied, w, &[1.0]).unwrap().1.remove(0).channels;
        let b = response(&bolted, w, &[1.0]).unwrap().1.remove(0).channels;
        for (i, n) in names
            .iter()
            .enumerate()
            .filter(|(_, n)| n.starts_with("tub"))
        {
            let r = (b[i] - a[i]).norm() / a[i].norm();
            eprintln!(
                "{rpm} rpm {n}: |tied| {:.4e} |bolted| {:.4e} rel {r:.2e}",
                a[i].norm(),
                b[i].norm()
            );
            if r > worst.0 {
                worst = (r, format!("{n} at {rpm} rpm"));
            }
        }
    }
    eprintln!("worst {worst:?}");
}
