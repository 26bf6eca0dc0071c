//! The hysteretic door gasket: the energy a harmonic gasket motion at drum order 1 dissipates
//! per cycle is pi eta k X^2 (the loss factor's definition, Nashif, Jones & Henderson,
//! "Vibration Damping", 1985, eq. 3.8: eta = W / (2 pi U), U = k X^2 / 2), independent of the
//! frequency; the floor below which the reference frequency stops tracking the drum; the IR's
//! rules; and the traced graph (the generator's input) against the interpreter.

use std::f64::consts::PI;
use washdyn_model::elements::{Element, Gasket, OMEGA_FLOOR};
use washdyn_model::equations::{Drive, Equations, Marker, MarkerDef};
use washdyn_model::geom::V;
use washdyn_model::ir::toml_file::load_str;
use washdyn_model::ir::{BodyRef, LossFactor, Model};

/// The reference's gasket stiffness (docs/reference-machine.md), with the loss factors below.
fn reference_gasket(eta: LossFactor, viscous: [[f64; 6]; 6]) -> washdyn_model::ir::Gasket {
    let mut g = washdyn_models::reference().gaskets[0].clone();
    g.loss_factor = Some(eta);
    g.damping = viscous;
    g
}

/// Energy dissipated over one period of the relative motion x(t) = Re(X e^{i w t}) (6-vector,
/// complex amplitude as (re, im)) at drive speed `omega_drive`: -int w_a . x' dt, by the
/// trapezoidal rule over a period, exact for the trigonometric polynomials of degree 2 here.
fn dissipated(g: &Gasket, x: &[(f64, f64); 6], w: f64, omega_drive: f64) -> f64 {
    let n = 64;
    let period = 2.0 * PI / w;
    let d = Drive {
        phi: 0.0,
        omega: omega_drive,
        omega_dot: 0.0,
    };
    let p = g.a.point;
    let mut energy = 0.0;
    for k in 0..n {
        let t = period * k as f64 / n as f64;
        let (c, s) = ((w * t).cos(), (w * t).sin());
        let pos: [f64; 6] = std::array::from_fn(|i| x[i].0 * c - x[i].1 * s);
        let vel: [f64; 6] = std::array::from_fn(|i| -w * (x[i].0 * s + x[i].1 * c));
        let a = Marker {
            pos: V([p[0] + pos[0], p[1] + pos[1], p[2] + pos[2]]),
            vel: V([vel[0], vel[1], vel[2]]),
            rot: V([pos[3], pos[4], pos[5]]),
            angvel: V([vel[3], vel[4], vel[5]]),
        };
        let b = Marker {
            pos: V(p),
            vel: V([0.0; 3]),
            rot: V([0.0; 3]),
            angvel: V([0.0; 3]),
        };
        let (wa, _) = g.wrenches(&a, &b, true, &d, &[]);
        let power = wa.force.dot(a.vel) + wa.moment.dot(a.angvel);
        energy -= power * period / n as f64;
    }
    energy
}

fn element(g: &washdyn_model::ir::Gasket) -> Gasket {
    let p0 = [0.0, 0.0, 0.45];
    Gasket::new(
        g,
        MarkerDef::floating(BodyRef::Tub, g.point, 0, p0),
        MarkerDef::fixed(BodyRef::Cabinet, g.point),
        true,
    )
}

#[test]
fn energy_per_cycle_at_order_one_is_pi_eta_k_x2_at_any_speed() {
    let eta = [0.1, 0.2, 0.25, 0.15, 0.3, 0.35];
    let ir = reference_gasket(LossFactor::PerDirection(eta.to_vec()), [[0.0; 6]; 6]);
    let g = element(&ir);
    let mut worst: f64 = 0.0;
    // 4.5 Hz (the rocking modes) and 23 Hz (top speed): the viscous 0.01 s K gave loss factors
    // 0.28 and 1.46 there; the hysteretic law gives eta at both.
    for f in [4.5, 23.0] {
        let w = 2.0 * PI * f;
        for i in 0..6 {
            let amp = if i < 3 { 5e-3 } else { 0.02 };
            let mut x = [(0.0, 0.0); 6];
            x[i] = (amp, 0.0);
            let e = dissipated(&g, &x, w, w);
            let expect = PI * eta[i] * ir.stiffness[i][i] * amp * amp;
            worst = worst.max((e / expect - 1.0).abs());
        }
        // A motion along all six directions with phases: pi Re(X^H S K S X).
        let x: [(f64, f64); 6] =
            std::array::from_fn(|i| (1e-3 * (i + 1) as f64, 2e-3 - 4e-4 * i as f64));
        let h = ir.hysteretic_damping();
        let mut expect = 0.0;
        for i in 0..6 {
            for j in 0..6 {
                expect += PI * h[i][j] * (x[i].0 * x[j].0 + x[i].1 * x[j].1);
            }
        }
        let e = dissipated(&g, &x, w, w);
        worst = worst.max((e / expect - 1.0).abs());
    }
    eprintln!("energy per cycle against pi eta k X^2: worst relative error {worst:e}");
    // Measured 4.2e-15 (round-off of 64-term sums).
    assert!(worst < 4e-14, "relative error {worst:e}");
}

#[test]
fn below_the_floor_the_reference_frequency_stays_at_the_floor() {
    // At standstill and at half the floor the equivalent viscous damping is S K S / OMEGA_FLOOR:
    // a motion at frequency w dissipates pi eta k X^2 w / OMEGA_FLOOR.
    let ir = reference_gasket(LossFactor::Uniform(0.2), [[0.0; 6]; 6]);
    let g = element(&ir);
    let x = {
        let mut x = [(0.0, 0.0); 6];
        x[2] = (4e-3, 0.0);
        x
    };
    let k = ir.stiffness[2][2];
    for (drive, w) in [
        (0.0, 2.0 * PI * 1.06),
        (0.5 * OMEGA_FLOOR, 0.5 * OMEGA_FLOOR),
    ] {
        let e = dissipated(&g, &x, w, drive);
        let expect = PI * 0.2 * k * 16e-6 * w / OMEGA_FLOOR;
        assert!((e / expect - 1.0).abs() < 1e-12, "{e} vs {expect}");
    }
    // Negative drum speed (a reversing drum): |Omega|.
    let w = 2.0 * PI * 10.0;
    let e = dissipated(&g, &x, w, -w);
    let expect = PI * 0.2 * k * 16e-6;
    assert!((e / expect - 1.0).abs() < 1e-12, "{e} vs {expect}");
}

#[test]
fn viscous_and_hysteretic_damping_add() {
    // D = 0.002 s K (the issue's viscous alternative) plus eta = 0.2: pi (w 0.002 + 0.2) k X^2.
    let k = washdyn_models::reference().gaskets[0].stiffness;
    let d = k.map(|r| r.map(|v| 0.002 * v));
    let ir = reference_gasket(LossFactor::Uniform(0.2), d);
    let g = element(&ir);
    let mut x = [(0.0, 0.0); 6];
    x[1] = (3e-3, 0.0);
    let w = 2.0 * PI * 12.0;
    let e = dissipated(&g, &x, w, w);
    let expect = PI * (w * 0.002 + 0.2) * k[1][1] * 9e-6;
    assert!((e / expect - 1.0).abs() < 1e-12, "{e} vs {expect}");
}

const BASE: &str = r#"
name = "g"
gravity = [0.0, 0.0, -9.81]
[tub]
mass = 55.0
cog = [0.0, 0.0, 0.45]
inertia = [[3.43, 0.0, -0.233], [0.0, 3.01, 0.0], [-0.233, 0.0, 2.62]]
[[rotors]]
name = "drum"
axis_point = [0.0, 0.0, 0.45]
polar_inertia = 0.215
[[unbalances]]
name = "u"
rotor = "drum"
mass = 0.6
position = [0.15, 0.0, 0.69]
[speed]
table = [[0.0, 0.0], [10.0, 1400.0]]
[[springs]]
name = "s"
a = { body = "tub", point = [0.0, 0.0, 0.62] }
b = { body = "cabinet", point = [0.0, 0.0, 0.82] }
stiffness = 12000.0
free_length = 0.155
[[gaskets]]
name = "door"
a = "tub"
b = "cabinet"
point = [0.30, 0.0, 0.45]
stiffness = [
  [3000.0, 0.0, 0.0, 0.0, 0.0, 0.0],
  [0.0, 8000.0, 0.0, 0.0, 0.0, 600.0],
  [0.0, 0.0, 8000.0, 0.0, -600.0, 0.0],
  [0.0, 0.0, 0.0, 150.0, 0.0, 0.0],
  [0.0, 0.0, -600.0, 0.0, 120.0, 0.0],
  [0.0, 600.0, 0.0, 0.0, 0.0, 120.0],
]
"#;

fn load(extra: &str) -> Result<Model, String> {
    load_str(
        &format!("{BASE}{extra}\n"),
        "g.toml",
        std::path::Path::new("."),
    )
    .map_err(|e| e.to_string())
}

#[test]
fn toml_takes_one_loss_factor_or_six_and_the_checker_refuses_the_rest() {
    // `damping` is optional (zero); one number or six.
    let m = load("loss_factor = 0.2").unwrap();
    assert_eq!(m.gaskets[0].loss_factor, Some(LossFactor::Uniform(0.2)));
    assert_eq!(m.gaskets[0].damping, [[0.0; 6]; 6]);
    let m = load("loss_factor = [0.1, 0.2, 0.2, 0.3, 0.3, 0.3]").unwrap();
    let h = m.gaskets[0].hysteretic_damping();
    // S K S: the diagonal is eta_i K_ii, the coupling K[y][rz] = 600 gets sqrt(0.2 * 0.3).
    assert!((h[0][0] - 300.0).abs() < 1e-12 && (h[3][3] - 45.0).abs() < 1e-12);
    assert!((h[1][5] - 600.0 * (0.2f64 * 0.3).sqrt()).abs() < 1e-12);
    let e = load("loss_factor = [0.1, 0.2, 0.2, 0.3, 0.3]").unwrap_err();
    assert!(e.contains("loss_factor needs one number or 6"), "{e}");
    let e = load("loss_factor = -0.1").unwrap_err();
    assert!(e.contains("loss_factor must not be negative"), "{e}");
    let e = load("loss_factor = [0.1, 0.2, nan, 0.3, 0.3, 0.3]").unwrap_err();
    assert!(e.contains("loss_factor: non-finite"), "{e}");
}

#[test]
fn traced_graph_agrees_with_the_interpreter_across_the_floor() {
    // The generator traces the one derivation; the branch-free max(|Omega|, floor) must give
    // the interpreter's h at standstill, below the floor and above it. Drive speeds: the
    // profile reaches the floor (60 rpm) at t = 0.43 s.
    use washdyn_model::codegen::trace_equations;
    use washdyn_runtime::system::{Interpreter, Mechanical};
    let m = load("loss_factor = [0.1, 0.2, 0.2, 0.3, 0.3, 0.3]\n[[scenes]]\nname = \"s\"\neffects = [\"unbalance.drum\", \"gasket_damping\", \"element_geometry\", \"unbalance_inertia\", \"gyroscopic\"]").unwrap();
    let eff = m.scene(Some("s")).unwrap();
    let eq = Equations::new(&m, &eff);
    assert!(eq.gaskets[0].e.hysteretic.is_some());
    let t = trace_equations(&eq);
    let mut interp = Interpreter::new(&m, &eff);
    let n = t.n;
    let mut worst: f64 = 0.0;
    for (k, time) in [0.0, 0.2, 0.43, 1.0, 9.0].into_iter().enumerate() {
        let q: Vec<f64> = (0..n).map(|i| 1e-3 * ((i + k) as f64).sin()).collect();
        let qd: Vec<f64> = (0..n).map(|i| 0.05 * ((i * 3 + k) as f64).cos()).collect();
        let d = interp.speed.drive(time);
        let mut inputs = q.clone();
        inputs.extend(&qd);
        inputs.extend([d.phi, d.omega, d.omega_dot]);
        let mut m1 = vec![0.0; t.n1 * t.n1];
        let mut h = vec![0.0; n];
        interp.eval(time, &q, &qd, &mut m1, &mut h);
        let (g, _, sh) = &t.mh;
        let gh = g.eval(&inputs, sh);
        let scale = h.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for i in 0..n {
            worst = worst.max((gh[i] - h[i]).abs() / scale);
        }
    }
    eprintln!("traced graph against the interpreter: worst relative difference in h {worst:e}");
    // Measured 0 (the same operations in the same order); the back ends' bound
    // (tests/backend_agreement.rs).
    assert!(worst < 1e-12, "{worst:e}");
    // Without `gasket_damping` the gasket has neither part.
    let m2 = load("loss_factor = 0.2\n[[scenes]]\nname = \"s\"\neffects = []").unwrap();
    let eq2 = Equations::new(&m2, &m2.scene(Some("s")).unwrap());
    assert!(eq2.gaskets[0].e.hysteretic.is_none() && eq2.gaskets[0].e.damping.is_none());
}
