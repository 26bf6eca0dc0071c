//! Characteristic curves in the derivation (issue 52 point 2): the reference's elastic scene
//! with a strain-energy polynomial on two cabinet modes (a synthetic one, sized so its force is
//! ~10 % of the modes' linear force at 1 mm of modal displacement).
//!
//! Where the expected numbers come from:
//! - the force is -dV/dq carried through the scene's basis: against central differences of the
//!   polynomial's own energy along each coordinate (an independent path: `Curves::energy`, no
//!   derivative rules);
//! - the structured Jacobian (`force_jacobians`, the curves' Hessian by duals chained through
//!   the basis) against the whole derivation over dual numbers (`force_jacobians_dual`, every
//!   column seeded): the same derivatives by two assemblies, round-off apart;
//! - the energy balance: the curves' power lands in `cabinet modal strain` and equals -dV/dt
//!   by central differences of the energy along q'.

use washdyn_model::equations::{Drive, EnergyWork, Equations, JacobianWork, ModalBody};
use washdyn_model::ir::modal::{Curves, Fit, Term};
use washdyn_model::ir::{Model, Scene};

/// The reference with curves on cabinet modes 0 and 2 and the scene `elastic_curves`
/// (`elastic` plus `characteristic_curves.cabinet`).
fn curved_reference() -> Model {
    let mut m = washdyn_models::built_in("reference").unwrap().unwrap();
    let e = m.elastic.iter_mut().find(|e| e.name == "cabinet").unwrap();
    let d = e.data.as_ref().unwrap();
    let f = |k: usize| d.frequencies[k];
    let w2 = |k: usize| (2.0 * std::f64::consts::PI * f(k)).powi(2);
    // Quadratic force a2 q^2 = 0.1 w^2 q at q = 1e-3: energy coefficient a2 / 3; cubic force
    // likewise: a3 / 4; a coupling term of each degree.
    let (a2, a3) = (0.1 * w2(0) / 1e-3, 0.1 * w2(0) / 1e-6);
    let term = |modes: &[usize], c: f64| Term {
        modes: modes.to_vec(),
        c,
    };
    e.curves = Some("synthetic".into());
    e.curves_data = Some(Curves {
        body: "cabinet".into(),
        source: "synthetic (tests/characteristic_curves.rs)".into(),
        modes: vec![0, 2],
        frequencies: vec![f(0), f(2)],
        cubic: vec![term(&[0, 0, 0], a2 / 3.0), term(&[0, 1, 1], 0.5 * a2)],
        quartic: vec![
            term(&[0, 0, 0, 0], a3 / 4.0),
            term(&[0, 0, 1, 1], -0.3 * a3),
        ],
        fit: Fit {
            loads: vec![],
            residual: 0.0,
            unseen_loads: vec![],
            unseen_residual: 0.0,
            bound: 0.05,
        },
    });
    let elastic = m
        .scenes
        .iter()
        .find(|s| s.name == "elastic")
        .unwrap()
        .clone();
    let mut effects = elastic.effects.clone();
    effects.push("characteristic_curves.cabinet".into());
    m.scenes.push(Scene {
        name: "elastic_curves".into(),
        effects,
        ..elastic
    });
    m
}

/// The cabinet's modal body and its curves' energy at its coordinates, through the scene's
/// basis as the data holds it (the file's chosen modes q_c = T_c q; not `CurveTerms`).
fn cabinet_energy(eq: &Equations) -> (&ModalBody, impl Fn(&[f64]) -> f64 + '_) {
    let cab = eq
        .bodies
        .list
        .iter()
        .filter_map(|b| b.modal())
        .find(|b| b.name == "cabinet")
        .unwrap();
    let c = &cab
        .curves
        .as_ref()
        .expect("the scene switches them on")
        .curves;
    let t = move |r: usize, j: usize| match &cab.data().basis {
        Some(b) => b[c.modes[r] * cab.n + j],
        None => f64::from(u8::from(c.modes[r] == j)),
    };
    let energy = move |qb: &[f64]| {
        let qc: Vec<f64> = (0..c.modes.len())
            .map(|r| (0..cab.n).map(|j| t(r, j) * qb[j]).sum())
            .collect();
        c.energy(&qc)
    };
    (cab, energy)
}

fn state(n: usize) -> (Vec<f64>, Vec<f64>) {
    let q = (0..n)
        .map(|i| 1e-3 * ((i as f64 * 0.37).sin() + 0.2))
        .collect();
    let qd = (0..n)
        .map(|i| 5e-3 * ((i as f64 * 0.91).cos() - 0.1))
        .collect();
    (q, qd)
}

fn drive() -> Drive<f64> {
    Drive {
        phi: 2.1,
        omega: 146.6,
        omega_dot: 3.0,
    }
}

/// h with and without the curves differ by -T_c^T dV/dq_c, which central differences of V
/// along each coordinate give independently.
#[test]
fn the_curves_force_is_minus_the_energy_gradient_through_the_basis() {
    let m = curved_reference();
    let with = Equations::new(&m, &m.scene(Some("elastic_curves")).unwrap());
    let without = Equations::new(&m, &m.scene(Some("elastic")).unwrap());
    let n = with.layout.n();
    assert_eq!(n, without.layout.n());
    let (q, qd) = state(n);
    let n1 = with.layout.n1;
    let (mut m1, mut h1, mut h0) = (vec![0.0; n1 * n1], vec![0.0; n], vec![0.0; n]);
    with.eval(&drive(), &q, &qd, &mut m1, &mut h1);
    without.eval(&drive(), &q, &qd, &mut m1, &mut h0);
    let (cab, energy) = cabinet_energy(&with);
    let qb = &q[cab.start..cab.start + cab.n];
    let (mut worst, mut big) = (0.0f64, 0.0f64);
    for j in 0..cab.n {
        let e = 1e-7;
        let (mut p, mut mm) = (qb.to_vec(), qb.to_vec());
        p[j] += e;
        mm[j] -= e;
        let grad = (energy(&p) - energy(&mm)) / (2.0 * e);
        let diff = h1[cab.start + j] - h0[cab.start + j];
        worst = worst.max((diff + grad).abs());
        big = big.max(grad.abs());
    }
    for i in (0..n).filter(|i| !(cab.start..cab.start + cab.n).contains(i)) {
        assert_eq!(h1[i], h0[i], "coordinate {i} outside the cabinet");
    }
    eprintln!(
        "curves' force against -dV/dq: {:.2e} of {big:.2e}",
        worst / big
    );
    // Central differences of a quartic at step 1e-7 on q ~ 1e-3: truncation ~ (e / q)^2 ~ 1e-8
    // relative, round-off ~ 1e-16 V / e (measured 5.8e-9).
    assert!(big > 0.0 && worst <= 1e-7 * big, "{worst:e} of {big:e}");
}

/// Structured against whole-derivation Jacobians with the curves on; the ported form declines.
#[test]
fn structured_jacobians_with_curves_equal_the_whole_derivation_over_duals() {
    let m = curved_reference();
    let eq = Equations::new(&m, &m.scene(Some("elastic_curves")).unwrap());
    assert_eq!(eq.ported_ports(), None, "curves couple subsystem 2's modes");
    let n = eq.layout.n();
    let (q, qd) = state(n);
    let mut w = JacobianWork::new(&eq);
    let (mut sq, mut sqd) = (vec![0.0; n * n], vec![0.0; n * n]);
    let (mut dq, mut dqd) = (vec![0.0; n * n], vec![0.0; n * n]);
    eq.force_jacobians(&drive(), &q, &qd, &mut w, &mut sq, &mut sqd);
    eq.force_jacobians_dual(&drive(), &q, &qd, &mut w, &mut dq, &mut dqd);
    for (name, a, b) in [("dh/dq", &sq, &dq), ("dh/dq'", &sqd, &dqd)] {
        let big = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = a
            .iter()
            .zip(b.iter())
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        eprintln!("{name}: {:.2e} of {big:.2e}", err / big);
        // Round-off of two summation orders (measured 3.0e-16 of the largest entry).
        assert!(err <= 5e-15 * big, "{name}: {err:e} of {big:e}");
    }
}

/// The energy balance with the curves on: the categories add up to q'^T h (their contract),
/// and against the scene without curves only `cabinet modal strain` changes, by the curves'
/// power -dV/dt, which central differences of the polynomial's energy along q' give
/// independently.
#[test]
fn the_curves_power_is_the_cabinets_modal_strain() {
    let m = curved_reference();
    let powers = |scene: &str| {
        let eq = Equations::new(&m, &m.scene(Some(scene)).unwrap());
        let n = eq.layout.n();
        let (q, qd) = state(n);
        let n1 = eq.layout.n1;
        let (mut m1, mut h) = (vec![0.0; n1 * n1], vec![0.0; n]);
        let z = vec![1e-5; eq.layout.nz];
        eq.eval_states(&drive(), &q, &qd, &z, &mut m1, &mut h);
        let total: f64 = qd.iter().zip(&h).map(|(v, f)| v * f).sum();
        let mut w = EnergyWork::new(&eq);
        let mut out = Vec::new();
        eq.powers(&drive(), &q, &qd, &z, &mut w, &mut out);
        let sum: f64 = out.iter().sum();
        assert!(
            (sum - total).abs() <= 1e-12 * total.abs(),
            "{scene}: {sum} {total}"
        );
        let names: Vec<String> = eq.energy_categories().into_iter().map(|c| c.name).collect();
        (names, out, eq, q, qd)
    };
    let (names, with, eq, q, qd) = powers("elastic_curves");
    let (names0, without, ..) = powers("elastic");
    assert_eq!(names, names0);
    let (cab, energy) = cabinet_energy(&eq);
    let r = cab.start..cab.start + cab.n;
    let energy_at = |e: f64| {
        let qb: Vec<f64> = r.clone().map(|i| q[i] + e * qd[i]).collect();
        energy(&qb)
    };
    let power = -(energy_at(1e-4) - energy_at(-1e-4)) / 2e-4;
    for (k, name) in names.iter().enumerate() {
        let diff = with[k] - without[k];
        if name == "cabinet modal strain" {
            eprintln!("{name}: {diff:.6e} against -dV/dt {power:.6e}");
            assert!((diff - power).abs() <= 1e-6 * power.abs(), "{diff} {power}");
        } else {
            assert!(
                diff.abs() <= 1e-12 * with[k].abs().max(1.0),
                "{name}: {diff}"
            );
        }
    }
}

/// One mode with a quadratic term, q'' + 2 zeta w q' + w^2 q + a2 q^2 = F cos(W t), its force
/// from `Curves::force_into` (V = a2 q^3 / 3), integrated by washdyn's dopri5 to the steady
/// state. Closed form (regular perturbation, small a2 A / w^2): q = A cos(W t - theta) with
/// A = F / |D(W)|, D(s) = w^2 - s^2 + 2 i zeta w s, and a second harmonic of amplitude
/// a2 A^2 / (2 |D(2 W)|) (from a2 A^2 / 2 cos(2 W t - 2 theta)), and a mean -a2 A^2 / (2 w^2);
/// the next corrections are of relative order (a2 A / w^2) (A2 + |mean|) / A, ~1e-4 here
/// (a2 A / w^2 = 0.003). Measured: the second harmonic within 6.8e-5 of the closed form, the
/// mean within 1.3e-4.
#[test]
fn a_quadratic_curve_gives_the_closed_form_second_harmonic() {
    use std::f64::consts::PI;
    use washdyn_ode::{AnySolver, Method, OdeSystem, Options, Solver, Stepper};
    let (w, zeta, big_w) = (2.0 * PI * 10.0, 0.05, 2.0 * PI * 4.6);
    let amp = 1e-3;
    let d = |s: f64| ((w * w - s * s).powi(2) + (2.0 * zeta * w * s).powi(2)).sqrt();
    let force = amp * d(big_w);
    let a2 = 0.003 * w * w / amp;
    let curves = Curves {
        body: "cabinet".into(),
        source: "closed form".into(),
        modes: vec![0],
        frequencies: vec![10.0],
        cubic: vec![Term {
            modes: vec![0, 0, 0],
            c: a2 / 3.0,
        }],
        quartic: vec![],
        fit: Fit {
            loads: vec![],
            residual: 0.0,
            unseen_loads: vec![],
            unseen_residual: 0.0,
            bound: 0.05,
        },
    };
    struct Osc<'a>(&'a Curves, [f64; 4]);
    impl OdeSystem for Osc<'_> {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
            let [w, zeta, big_w, force] = self.1;
            let mut f = [0.0];
            self.0.force_into(&y[..1], &mut f);
            dy[0] = y[1];
            dy[1] = force * (big_w * t).cos() - w * w * y[0] - 2.0 * zeta * w * y[1] - f[0];
        }
    }
    let mut sys = Osc(&curves, [w, zeta, big_w, force]);
    let opts = Options {
        rtol: 1e-10,
        atol: 1e-14,
        ..Options::default()
    };
    let mut s = AnySolver::new(Method::Dopri5, 2, opts);
    s.init(&mut sys, 0.0, &[0.0, 0.0]).unwrap();
    // 40 periods of W after 6 s (19 decay times 1 / (zeta w)), sampled 64 times a period.
    let period = 2.0 * PI / big_w;
    let (t0, samples) = (6.0, 40 * 64);
    let (mut c1, mut s2c, mut s2s, mut mean) = (0.0, 0.0, 0.0, 0.0);
    let mut y = [0.0; 2];
    for k in 0..samples {
        let t = t0 + k as f64 * period / 64.0;
        while s.t() < t {
            s.step(&mut sys, t).unwrap();
        }
        s.interpolate(t, &mut y);
        c1 += y[0] * (big_w * t).cos();
        s2c += y[0] * (2.0 * big_w * t).cos();
        s2s += y[0] * (2.0 * big_w * t).sin();
        mean += y[0];
    }
    let nf = samples as f64;
    let second = 2.0 * (s2c * s2c + s2s * s2s).sqrt() / nf;
    let expect = a2 * amp * amp / (2.0 * d(2.0 * big_w));
    let mean_expect = -a2 * amp * amp / (2.0 * w * w);
    eprintln!(
        "second harmonic {second:.6e} against {expect:.6e} ({:.2e} relative); mean {:.4e} \
         against {mean_expect:.4e}; first harmonic (in phase part) {:.3e}",
        (second - expect).abs() / expect,
        mean / nf,
        2.0 * c1 / nf
    );
    assert!(
        (second - expect).abs() <= 1e-3 * expect,
        "{second} {expect}"
    );
    assert!((mean / nf - mean_expect).abs() <= 1e-3 * mean_expect.abs());
}

/// A model file's `curves` entry: resolved relative to the model like its modal file, the
/// effect `characteristic_curves.cabinet` known once the entry has curves and refused without
/// `elastic.cabinet`; a curves file fitted on other modes refused at the entry's `curves`,
/// naming the curves file and its field, before anything runs.
#[test]
fn a_model_files_curves_are_resolved_and_refused_by_file_and_field() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let text = std::fs::read_to_string(root.join("models/data/reference.toml")).unwrap();
    let fe = root.join("models/fe").display().to_string() + "/";
    let entry = "curves = \"../fe/cabinet.curves.toml\"\n";
    assert!(text.contains(entry), "the reference's cabinet entry moved");
    let text = text
        .replace(entry, "curves = \"cab.curves.toml\"\n")
        .replace("../fe/", &fe);
    let scene = |effects: &str| format!("\n[[scenes]]\nname = \"curved\"\neffects = [{effects}]\n");
    let model = |extra: &str| {
        std::fs::write(d.join("m.toml"), format!("{text}{extra}")).unwrap();
    };
    let curves = |f0: f64| {
        let toml = format!(
            "body = \"cabinet\"\nsource = \"test\"\nmodes = [0]\nfrequencies = [{f0}]\n\
             cubic = [{{ modes = [0, 0, 0], c = 1e6 }}]\n\
             [fit]\nloads = [1e-3]\nresidual = 0.01\nunseen_loads = [2e-3]\n\
             unseen_residual = 0.02\nbound = 0.05\n"
        );
        std::fs::write(d.join("cab.curves.toml"), toml).unwrap();
    };
    let check = || {
        let o = washdyn_in_dir(&["check", "m.toml"], d);
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    curves(26.40195992);
    model(&scene(
        "\"elastic.cabinet\", \"characteristic_curves.cabinet\"",
    ));
    let (code, err) = check();
    assert_eq!(code, Some(0), "{err}");
    model(&scene("\"characteristic_curves.cabinet\""));
    let (code, err) = check();
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("`characteristic_curves.cabinet` needs the effect `elastic.cabinet`"),
        "{err}"
    );
    curves(26.5);
    model(&scene(
        "\"elastic.cabinet\", \"characteristic_curves.cabinet\"",
    ));
    let (code, err) = check();
    assert_eq!(code, Some(3), "{err}");
    // At the model file's line of the `curves` key (`m.toml:343:10: elastic `cabinet`: ...`).
    let line = text
        .lines()
        .position(|l| l.starts_with("curves = "))
        .unwrap()
        + 1;
    assert!(
        err.contains(&format!("m.toml:{line}:")) && err.contains("elastic `cabinet`: "),
        "{err}"
    );
    assert!(
        err.contains("cab.curves.toml")
            && err.contains("frequencies[0]: 26.5 Hz, mode 0 of the modal data is 26.40195992 Hz"),
        "{err}"
    );
}

fn washdyn_in_dir(args: &[&str], dir: &std::path::Path) -> std::process::Output {
    crate::common::washdyn_in(args, dir)
}
