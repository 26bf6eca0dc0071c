//! The elastic tub with its counterweights bolted on (issue 52): the tub's modal data without
//! the counterweights' bricks (models/fe/tub_bare.modal.toml, `washdyn fe modal`), the three
//! counterweights as rigid bodies on their twelve bolts, against the tub whose bricks share the
//! shell's nodes (models/fe/tub.modal.toml: CalculiX's free-free frequencies of that mesh).
//! Linearisation: M from the derivation, K = -dh/dq by central differences about q = 0, the
//! tub free (no gravity, no suspension), the bolts closed and sticking (linear, 1e9 N/m).

use nalgebra::{DMatrix, Matrix3, Vector3};
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
    crate::common::frequencies(&l.m, &k)
}

/// The patch's least-squares rigid motion at `p` as washdyn's modal points take it
/// (fe/src/modal.rs `rigid_fit`), written out: u(p) = sum_i T_i u_i with
/// T_i = E / N - [d]x A^-1 [r_i]x, r_i = x_i - centroid, d = p - centroid,
/// A = sum (|r_i|^2 E - r_i r_i^T). Row a of the result: per node, the coefficients of its
/// three displacements in u(p)_a.
fn fit_at(x: &[Vector3<f64>], p: Vector3<f64>) -> [Vec<[f64; 3]>; 3] {
    let n = x.len() as f64;
    let c = x.iter().sum::<Vector3<f64>>() / n;
    let skew = |v: Vector3<f64>| v.cross_matrix();
    let mut a = Matrix3::zeros();
    for xi in x {
        let r = xi - c;
        a += Matrix3::identity() * r.norm_squared() - r * r.transpose();
    }
    let ai = a.try_inverse().expect("a patch that fixes a rotation");
    let t: Vec<Matrix3<f64>> = x
        .iter()
        .map(|xi| Matrix3::identity() / n - skew(p - c) * ai * skew(xi - c))
        .collect();
    std::array::from_fn(|r| {
        t.iter()
            .map(|m| [m[(r, 0)], m[(r, 1)], m[(r, 2)]])
            .collect()
    })
}

/// CalculiX's free-free frequencies (Hz, ascending, rigid ones included) of the bare tub's mesh
/// (`tub_bare`, its bolt patches the node sets named after the joints) with each counterweight
/// as washdyn joins it: one *RIGID BODY (its mass and principal inertia as six point masses on
/// its principal axes, m/6 at +-d_a with (m/3)(d_b^2 + d_c^2) = J_a) and, at each bolt, a node
/// of that body tied by SPRING2 elements of stiffness `k` in x, y and z to a node that *EQUATION
/// makes the bolt's patch's rigid fit at the bolt's point (`fit_at`: the marker's translation).
/// The same joint, solved by ccx.
fn ccx_bolted(model: &Model, k: f64, modes: usize) -> Vec<f64> {
    use std::fmt::Write;
    use washdyn_fe::mesh::{Rigid, Section};
    let spec = washdyn_fe::bodies::builtin()
        .into_iter()
        .find(|b| b.name == "tub_bare")
        .unwrap();
    let mut mesh = spec.mesh;
    let (mut springs, mut equations) = (Vec::new(), String::new());
    for (c, w) in model.counterweights.iter().enumerate() {
        let set = format!("COUNTERWEIGHT_{c}");
        for j in model
            .bolted_joints
            .iter()
            .filter(|j| j.counterweight == w.name)
        {
            let patch = mesh.nsets[&j.name.to_uppercase()].clone();
            let (mean, on_body) = (mesh.fresh_node(j.point), mesh.fresh_node(j.point));
            mesh.add_to_set(&set, &[on_body]);
            springs.push((mean, on_body));
            let x: Vec<Vector3<f64>> = patch
                .iter()
                .map(|n| Vector3::from(mesh.nodes[n - 1]))
                .collect();
            for (dof, row) in fit_at(&x, Vector3::from(j.point)).iter().enumerate() {
                let mut terms = vec![format!("{mean},{},1.0", dof + 1)];
                for (n, t) in patch.iter().zip(row) {
                    for (b, c) in t.iter().enumerate().filter(|(_, c)| c.abs() > 1e-14) {
                        terms.push(format!("{n},{},{:.9e}", b + 1, -c));
                    }
                }
                writeln!(equations, "*EQUATION\n{}", terms.len()).unwrap();
                for line in terms.chunks(4) {
                    writeln!(equations, "{}", line.join(",")).unwrap();
                }
            }
        }
        let inertia = |a: usize| w.inertia[a][a];
        let half = |a: usize| {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            (1.5 / w.mass * (inertia(b) + inertia(c) - inertia(a))).sqrt()
        };
        let mut points = Vec::new();
        for a in 0..3 {
            for s in [-1.0, 1.0] {
                let mut p = w.cog;
                p[a] += s * half(a);
                points.push(vec![mesh.fresh_node(p)]);
            }
        }
        let ids: Vec<usize> = points.iter().map(|e| e[0]).collect();
        mesh.add_to_set(&set, &ids);
        let kg = w.mass / 6.0;
        mesh.part(&format!("COUNTERWEIGHT_{c}_MASS"), Section::Mass { kg })
            .elements = points;
        let (ref_node, rot_node) = (mesh.fresh_node(w.cog), mesh.fresh_node(w.cog));
        mesh.rigid.push(Rigid {
            nset: set,
            ref_node,
            rot_node,
        });
    }
    let mut extra = equations;
    for dof in 1..=3 {
        writeln!(extra, "*ELEMENT, TYPE=SPRING2, ELSET=BOLT_SPRING_{dof}").unwrap();
        for (i, (a, b)) in springs.iter().enumerate() {
            writeln!(extra, "{}, {a}, {b}", 900_000 + 100 * dof + i).unwrap();
        }
        writeln!(
            extra,
            "*SPRING, ELSET=BOLT_SPRING_{dof}\n{dof},{dof}\n{k:e}"
        )
        .unwrap();
    }
    let text = mesh.frequency_deck(modes, false).text().to_string();
    let at = text.find("*STEP").expect("a step");
    let deck_text = format!("{}{extra}{}", &text[..at], &text[at..]);
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("bolted.inp");
    std::fs::write(&deck, deck_text).unwrap();
    let run = washdyn_fe::ccx::run(&deck).unwrap_or_else(|e| panic!("{e}"));
    let dat = std::fs::read_to_string(run.dat()).unwrap();
    washdyn_fe::ccx::frequencies(&dat)
}

/// The bolts stiff and isotropic (9.5e10 N/m along and across, closed and sticking: linear),
/// point joints, against CalculiX's model of the same joints (`ccx_bolted`). Both are
/// free-free; every mode to 250 Hz.
#[test]
fn the_stiffly_bolted_tub_rings_like_calculix_with_the_same_joints() {
    if !crate::common::have_ccx() {
        return;
    }
    let mut model = free_tub();
    let k = 9.5e10;
    for j in &mut model.bolted_joints {
        (j.bolt_stiffness, j.member_stiffness) = (0.2 * k, 0.8 * k);
        (j.shear_stiffness, j.bolt_bending_stiffness) = (k, 0.0);
        j.preload = Some(100.0 * j.preload());
        j.torque = None;
        j.interface_diameter = 0.0;
    }
    let ours = frequencies(&model, "bolted");
    let ccx = ccx_bolted(&model, k, 16);
    eprintln!("washdyn {:?}\nccx     {ccx:?}", &ours[..16]);
    // Six rigid-body modes each (ccx's to its solver's round-off).
    assert!(ours[..6].iter().chain(&ccx[..6]).all(|f| *f < 1e-2));
    // Every elastic mode ccx found to 250 Hz, in order: the Ritz basis (100 modes and the bolts'
    // 72 static correction modes) and the joint's lever map are the FE model's. Measured 1.4e-5
    // at worst (ccx prints 7 digits), 103.1 to 249.2 Hz.
    let worst = (6..ccx.len())
        .map(|i| ((ours[i] - ccx[i]) / ccx[i]).abs())
        .fold(0.0f64, f64::max);
    eprintln!("worst {worst:.1e}");
    assert!(ccx[ccx.len() - 1] > 240.0 && worst < 1e-4, "{worst}");
}

/// The tied-tub check with the reference's joints (models/data/reference.toml: 11.4 kN, the
/// clamp 33 mm across), free-free: the tub's first mode and the pair at 185-187 Hz that the
/// tied tub keeps with its concrete rigid (ccx: 111.09, 185.28, 186.14 Hz) come back within
/// 1 %; the modes the bolted tub has besides (the shell between the bolts, which the bricks bond
/// over their whole footprint) and the concrete's own bending (152 Hz) are the idealisation's,
/// reported in docs/even-orders.md. Measured: 110.75 against 111.05 (0.27 %), 185.81 against
/// 185.33 (0.26 %).
#[test]
fn the_bolted_tub_keeps_the_tied_tubs_first_modes() {
    let model = free_tub();
    let tied = frequencies(&model, "tied");
    let bolted = frequencies(&model, "bolted");
    eprintln!("tied   {:?}\nbolted {:?}", &tied[6..12], &bolted[6..14]);
    assert!(tied[..6].iter().chain(&bolted[..6]).all(|f| *f < 1e-2));
    let nearest = |f: f64| {
        bolted[6..]
            .iter()
            .map(|g| (g / f - 1.0).abs())
            .fold(f64::INFINITY, f64::min)
    };
    for f in [tied[6], tied[9]] {
        assert!(nearest(f) < 0.01, "{f} Hz: {}", nearest(f));
    }
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
    let speeds = [100.0, 200.0, 300.0, 500.0, 700.0, 900.0, 1100.0, 1400.0];
    let mut amps = vec![(Vec::new(), Vec::new()); names.len()];
    for rpm in speeds {
        let w = rpm * std::f64::consts::PI / 30.0;
        let a = response(&tied, w, &[1.0]).unwrap().1.remove(0).channels;
        let b = response(&bolted, w, &[1.0]).unwrap().1.remove(0).channels;
        for i in 0..names.len() {
            amps[i].0.push(a[i]);
            amps[i].1.push(b[i]);
        }
    }
    // Each tub channel's difference over the run-up, relative to its largest order-1 amplitude
    // (what an order plot in dB shows).
    let mut worst = (0.0f64, String::new());
    for (i, n) in names
        .iter()
        .enumerate()
        .filter(|(_, n)| n.starts_with("tub"))
    {
        let (a, b) = &amps[i];
        let top = a.iter().map(|z| z.norm()).fold(0.0f64, f64::max);
        for (k, rpm) in speeds.iter().enumerate() {
            let r = (b[k] - a[k]).norm() / top;
            if r > worst.0 {
                worst = (r, format!("{n} at {rpm} rpm"));
            }
        }
    }
    eprintln!("worst {worst:?}");
    // Measured 2.2e-2 (tub2_ay at 1400 rpm): the bolted tub is the softer between its bolts.
    assert!(worst.0 < 0.03, "{worst:?}");
}
