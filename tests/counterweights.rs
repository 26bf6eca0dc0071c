//! The counterweights as rigid bodies on their bolted joints (scene `counterweights`, issue 52)
//! against what no one here wrote into them:
//! - each counterweight's six frequencies on its bolts, the tub held: the closed form of a rigid
//!   body on point springs (k_b + k_m along each bolt while the interface is closed, k_t + the
//!   bolt's bending stiffness across it, and the clamped interface's tilt and twist on the
//!   rotation), M = diag(m, m, m, J);
//! - the rest position: each counterweight's sag under its weight is that body's static
//!   solution, and the tub rests where it rests with the counterweights inside it (the mass
//!   split: the bare tub and its counterweights are the tub);
//! - the model file's refusals, by file, line and field.

use nalgebra::{DMatrix, Matrix3, SymmetricEigen, Vector3};
use washdyn::commands::resolve_model;
use washdyn_model::equations::{BodyState, Equations, Modes};
use washdyn_model::ir::{BodyRef, Model};
use washdyn_runtime::statics::static_equilibrium;
use washdyn_runtime::system::Interpreter;

fn reference() -> Model {
    resolve_model("reference").unwrap().0
}

/// The 6 x 6 stiffness of counterweight `i` on its closed bolts about its CoG, coordinates
/// (x, theta): a bolt at p sees u = x + theta x (p - c), and pushes back with
/// S = k_n n n^T + k_t (I - n n^T).
fn bolt_stiffness(m: &Model, i: usize) -> DMatrix<f64> {
    let w = &m.counterweights[i];
    let c = Vector3::from(w.cog);
    let mut k = DMatrix::zeros(6, 6);
    for j in m.bolted_joints.iter().filter(|j| j.counterweight == w.name) {
        let n = Vector3::from(j.axis).normalize();
        let s = (j.bolt_stiffness + j.member_stiffness) * n * n.transpose()
            + (j.shear_stiffness + j.bolt_bending_stiffness)
                * (Matrix3::identity() - n * n.transpose());
        // u = G [x; theta], G = [I, -[r]x] at the lever r = p - c.
        let g = crate::common::t_point(Vector3::from(j.point) - c);
        k += g.transpose() * DMatrix::from_fn(3, 3, |a, b| s[(a, b)]) * g;
        // The clamped interface, a disc of diameter D: tilt k_m D^2 / 16 about the tangents,
        // twist k_t D^2 / 8 about the axis, on the relative rotation theta.
        let d2 = j.interface_diameter.powi(2);
        let r = j.member_stiffness * d2 / 16.0 * (Matrix3::identity() - n * n.transpose())
            + j.shear_stiffness * d2 / 8.0 * n * n.transpose();
        for a in 0..3 {
            for b in 0..3 {
                k[(3 + a, 3 + b)] += r[(a, b)];
            }
        }
    }
    k
}

fn mass(m: &Model, i: usize) -> DMatrix<f64> {
    let w = &m.counterweights[i];
    let mut mm = DMatrix::zeros(6, 6);
    for a in 0..3 {
        mm[(a, a)] = w.mass;
        for b in 0..3 {
            mm[(3 + a, 3 + b)] = w.inertia[a][b];
        }
    }
    mm
}

/// omega^2 of K x = omega^2 M x, ascending.
fn generalised(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let l = m.clone().cholesky().unwrap().l();
    let li = l.try_inverse().unwrap();
    let a = &li * k * li.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let mut v = SymmetricEigen::new(a).eigenvalues.as_slice().to_vec();
    v.sort_by(f64::total_cmp);
    v
}

/// Each counterweight's block of -dh/dq at rest (its coordinates are mass-normalised, so the
/// block's eigenvalues are omega^2, the tub held) against the closed form. Measured: largest
/// relative difference 1.8e-15 (bound 1e-10).
#[test]
fn each_counterweight_rings_on_its_bolts_as_a_rigid_body_on_springs() {
    let model = reference();
    let (eq, hq, _) = crate::common::at_rest(&model, "counterweights");
    let mut seen = 0;
    let mut worst = 0.0f64;
    for body in &eq.bodies.list {
        let (BodyRef::Counterweight(i), Modes::Part(_)) = (body.id, &body.modes) else {
            continue;
        };
        seen += 1;
        let r = body.coordinates();
        assert_eq!(r.len(), 6, "three translations and three rotations");
        let k = -hq.view((r.start, r.start), (6, 6)).into_owned();
        let k = (&k + k.transpose()) * 0.5;
        let mut got = SymmetricEigen::new(k).eigenvalues.as_slice().to_vec();
        got.sort_by(f64::total_cmp);
        let want = generalised(&bolt_stiffness(&model, i), &mass(&model, i));
        for (g, w) in got.iter().zip(&want) {
            worst = worst.max((g - w).abs() / w);
        }
        let hz: Vec<String> = want
            .iter()
            .map(|w2| format!("{:.0}", w2.sqrt() / (2.0 * std::f64::consts::PI)))
            .collect();
        eprintln!("{}: {} Hz", model.counterweights[i].name, hz.join(", "));
    }
    eprintln!("largest relative difference of omega^2: {worst:.1e}");
    assert_eq!(seen, 3, "the reference's three counterweights");
    assert!(worst < 1e-10, "{worst:e}");
}

/// At the static start, each counterweight hangs on its bolts by its weight: the relative
/// displacement at every bolt is the rigid body's static solution K^-1 [m g; 0] carried to the
/// bolt. The tub rests as in `full` (its counterweights inside it): the mass split moves
/// nothing to first order. Measured: bolt displacements within 4.3e-5 of the closed form (bound
/// 1e-2: the bolts' axes turn with the tub's 8e-5 rad rest tilt, the closed form's stay), the
/// tub's rest translation within 8.3e-5 of `full`'s (bound 1e-3) and its tilt within 2.2e-3
/// (bound 1e-2: the counterweights' own rotations are first order about their CoGs, so their
/// weight's pendulum moment about the tub's CoG, a second-order term that cancels the bare
/// tub's inside one rigid body, is kept only in part; without the unbalance's weight both rest
/// at the same place to 1e-16).
#[test]
fn the_rest_position_hangs_each_counterweight_on_its_bolts() {
    let model = reference();
    let rest = |scene: &str| {
        let s = model.scene(Some(scene)).unwrap();
        let mut sys = Interpreter::new(&model, &s);
        let q = static_equilibrium(&mut sys, 0.0).unwrap();
        (Equations::new(&model, &s), q)
    };
    let (eq, q) = rest("counterweights");
    let (_, q_full) = rest("full");
    // Translations and rotations each against their own size.
    let off = |r: std::ops::Range<usize>| {
        let size = q_full[r.clone()].iter().fold(0.0f64, |a, v| a.max(v.abs()));
        r.fold(0.0f64, |a, k| a.max((q[k] - q_full[k]).abs())) / size
    };
    let (moved, turned) = (off(0..3), off(3..6));
    let qd = vec![0.0; q.len()];
    let st = BodyState::new(&q, &qd);
    let g = Vector3::from(model.gravity);
    let mut worst = 0.0f64;
    for (i, w) in model.counterweights.iter().enumerate() {
        let x = bolt_stiffness(&model, i)
            .lu()
            .solve(&DMatrix::from_iterator(
                6,
                1,
                (g * w.mass).iter().copied().chain([0.0; 3]),
            ))
            .unwrap();
        let (xt, th) = (
            Vector3::new(x[0], x[1], x[2]),
            Vector3::new(x[3], x[4], x[5]),
        );
        for j in model
            .bolted_joints
            .iter()
            .filter(|j| j.counterweight == w.name)
        {
            let p = Vector3::from(j.point);
            let want = xt + th.cross(&(p - Vector3::from(w.cog)));
            let on = |b| eq.bodies.marker(b, j.point).state(&st).pos.0;
            let (a, b) = (on(BodyRef::Tub), on(BodyRef::Counterweight(i)));
            let got = Vector3::new(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
            worst = worst.max((got - want).norm() / want.norm());
        }
    }
    eprintln!(
        "bolt sag against the closed form: {worst:.1e}; the tub's rest against full: \
         translation {moved:.1e}, rotation {turned:.1e}"
    );
    assert!(worst < 1e-2, "{worst:e}");
    assert!(moved < 1e-3, "{moved:e}");
    assert!(turned < 1e-2, "{turned:e}");
}

/// A model file's counterweights and bolts refused at file, line and field: a negative preload,
/// a counterweight on two bolts, a bolt on an unknown counterweight, a bolt off the elastic
/// tub's wall, and the effect with an elastic tub that has no data without the bricks.
#[test]
fn a_model_files_bolts_are_refused_by_file_and_field() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let fe = root.join("models/fe").display().to_string() + "/";
    let text = std::fs::read_to_string(root.join("models/data/reference.toml"))
        .unwrap()
        .replace("../fe/", &fe);
    let check = |t: &str| {
        std::fs::write(d.join("m.toml"), t).unwrap();
        let o = crate::common::washdyn_in(&["check", "m.toml"], d);
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let (code, err) = check(&text);
    assert_eq!(code, Some(0), "{err}");
    let torque = "torque = { moment = 15.0, pitch = 1.25e-3, pitch_diameter = 7.188e-3, \
                  thread_friction = 0.12, head_friction = 0.12, head_diameter = 10.3e-3 }";
    assert!(text.contains(torque), "the reference's bolts moved");
    let first = text.find(torque).unwrap();
    let line = text[..first].lines().count() + 1;
    let bad = format!(
        "{}preload = -100.0{}",
        &text[..first],
        &text[first + torque.len()..]
    );
    let (code, err) = check(&bad);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains(&format!("m.toml:{line}:"))
            && err.contains("bolted joint `bolt_top_1`: preload must not be negative, got -100"),
        "{err}"
    );
    let bad = text.replacen(
        "counterweight = \"counterweight_top\"",
        "counterweight = \"counterweight_bottom\"",
        2,
    );
    let (code, err) = check(&bad);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("counterweight `counterweight_top`: held by 2 bolted joint(s)"),
        "{err}"
    );
    let bad = text.replacen(
        "counterweight = \"counterweight_top\"",
        "counterweight = \"counterweight_tpo\"",
        1,
    );
    let (_, err) = check(&bad);
    assert!(
        err.contains("bolted joint `bolt_top_1`: no counterweight `counterweight_tpo`"),
        "{err}"
    );
    // The elastic tub with its counterweights bolted on: its `bare` data hold each bolt's
    // point; a bolt moved off the tub's wall (10 cm inwards) has no node set there, and
    // without `bare` the scene has no data to bolt them to.
    let both = format!(
        "{text}\n[[scenes]]\nname = \"both\"\neffects = [\"elastic.tub\", \"counterweights\"]\n"
    );
    let (code, err) = check(&both);
    assert_eq!(code, Some(0), "{err}");
    let wall = "point = [-0.04000, -0.23383, 0.58500]";
    let at = both.find(wall).unwrap();
    let line = both[..at].lines().count() + 1;
    let (code, err) = check(&both.replacen(wall, "point = [-0.04000, -0.18383, 0.50000]", 1));
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains(&format!("m.toml:{line}:"))
            && err.contains("bolted joint `bolt_top_1`: the elastic tub has no FE node set"),
        "{err}"
    );
    let bare = "bare = \"";
    let no_bare = both.replacen(bare, "# bare = \"", 1);
    let (code, err) = check(&no_bare);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains(
            "scene `both`: `counterweights` with `elastic.tub` needs the tub's modal data"
        ),
        "{err}"
    );
}
