//! The force Jacobians dh/dq and dh/dq' (dual numbers through the one derivation) against
//! central differences of the interpreter's h, an independent path through the same code with
//! a step instead of derivative rules, on the rigid `full`, the `elastic` and the `damper_mass` reference scenes,
//! at a state off rest (every coordinate moved, friction dampers on their slope) and at
//! several drum speeds and angles.

use washdyn_model::equations::{Drive, Equations, JacobianWork};
use washdyn_model::ir::FrictionLaw;
use washdyn_ode::{AnySolver, Method, OdeSystem, Options, PortedJacobian, Solver, Stepper};
use washdyn_runtime::system::{FirstOrder, Interpreter, Mechanical};

/// Largest |dual - difference| over a column, relative to the column's largest entry
/// (with a floor of 1e-6 of the matrix's largest entry, so columns of zeros compare too).
fn worst(eq: &Equations, d: &Drive<f64>, q: &[f64], qd: &[f64], rel: f64) -> (f64, f64) {
    let (n, n1) = (eq.layout.n(), eq.layout.n1);
    let mut w = JacobianWork::new(eq);
    let (mut hq, mut hqd) = (vec![0.0; n * n], vec![0.0; n * n]);
    eq.force_jacobians(d, q, qd, &mut w, &mut hq, &mut hqd);
    let mut m1 = vec![0.0; n1 * n1];
    let mut out = [0.0f64; 2];
    for (slot, (jac, vel)) in [(&hq, false), (&hqd, true)].into_iter().enumerate() {
        let big = jac.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for j in 0..n {
            let x = if vel { qd[j] } else { q[j] };
            let eps = rel * x.abs().max(1e-4);
            // Richardson: (4 D(eps/2) - D(eps)) / 3 cancels the eps^2 term of the central
            // difference D, so a large step keeps h's round-off (modal forces of the stiff
            // correction modes) small against the difference.
            let mut diff = |e: f64| -> Vec<(f64, f64)> {
                let (mut hp, mut hm) = (vec![0.0; n], vec![0.0; n]);
                let (mut a, mut b) = (q.to_vec(), qd.to_vec());
                let x = if vel { &mut b[j] } else { &mut a[j] };
                *x += e;
                eq.eval(d, &a, &b, &mut m1, &mut hp);
                let x = if vel { &mut b[j] } else { &mut a[j] };
                *x -= 2.0 * e;
                eq.eval(d, &a, &b, &mut m1, &mut hm);
                (0..n)
                    .map(|i| ((hp[i] - hm[i]) / (2.0 * e), hp[i].abs().max(hm[i].abs())))
                    .collect::<Vec<_>>()
            };
            let (d1, d2) = (diff(eps), diff(0.5 * eps));
            let col_max = (0..n).fold(1e-6 * big, |m, i| m.max(jac[i * n + j].abs()));
            for i in 0..n {
                let fd = (4.0 * d2[i].0 - d1[i].0) / 3.0;
                // h's own round-off, |h_i| eps_machine, divided by the step: what no
                // difference can resolve (the stiff correction modes' forces are large).
                let noise = 10.0 * f64::EPSILON * d1[i].1.max(d2[i].1) / (0.5 * eps);
                let e = ((jac[i * n + j] - fd).abs() - noise).max(0.0) / col_max;
                out[slot] = out[slot].max(e);
            }
        }
    }
    (out[0], out[1])
}

/// A state off rest: millimetres and milliradians on the rigid coordinates, small modal
/// amplitudes, velocities of 1-10 mm/s (the dampers' friction slope, s v ~ 1).
fn off_rest(n: usize) -> (Vec<f64>, Vec<f64>) {
    let q = (0..n)
        .map(|i| 1e-3 * ((i as f64 * 0.37).sin() + 0.2))
        .collect();
    let qd = (0..n)
        .map(|i| 5e-3 * ((i as f64 * 0.91).cos() - 0.1))
        .collect();
    (q, qd)
}

#[test]
fn force_jacobians_match_central_differences_on_full_elastic_and_damper_mass() {
    let model = washdyn_models::built_in("reference").unwrap().unwrap();
    for scene in ["full", "elastic", "damper_mass"] {
        let s = model.scene(Some(scene)).unwrap();
        let eq = Equations::new(&model, &s);
        let n = eq.layout.n();
        let (q, qd) = off_rest(n);
        for (phi, omega, omega_dot) in [(0.3, 10.0, 2.0), (2.1, 146.6, 0.0)] {
            let d = Drive {
                phi,
                omega,
                omega_dot,
            };
            let (kq, kqd) = worst(&eq, &d, &q, &qd, 1e-3);
            eprintln!("{scene} omega {omega}: dh/dq {kq:.2e}, dh/dq' {kqd:.2e}");
            // Richardson-extrapolated central differences, step 1e-3 relative: beyond h's
            // round-off the two agree to 7.1e-10 (elastic, dh/dq') or better.
            assert!(kq < 1e-8, "{scene}: dh/dq differs by {kq:e}");
            assert!(kqd < 1e-8, "{scene}: dh/dq' differs by {kqd:e}");
        }
    }
}

/// The structured route (each element's local Jacobian through its markers' maps, the body
/// terms over dual numbers without the elements) against the whole derivation over dual
/// numbers, every column seeded: the same derivatives by two assemblies, on every scene of the
/// reference machine (linearised and exact element geometry, rigid and elastic bodies).
#[test]
fn structured_jacobians_equal_the_whole_derivation_over_dual_numbers_on_every_scene() {
    let model = washdyn_models::built_in("reference").unwrap().unwrap();
    for scene in model.scene_names() {
        let s = model.scene(Some(&scene)).unwrap();
        let eq = Equations::new(&model, &s);
        let n = eq.layout.n();
        let (q, qd) = off_rest(n);
        let d = Drive {
            phi: 2.1,
            omega: 146.6,
            omega_dot: 3.0,
        };
        let mut w = JacobianWork::new(&eq);
        let (mut sq, mut sqd) = (vec![0.0; n * n], vec![0.0; n * n]);
        let (mut dq, mut dqd) = (vec![0.0; n * n], vec![0.0; n * n]);
        eq.force_jacobians(&d, &q, &qd, &mut w, &mut sq, &mut sqd);
        eq.force_jacobians_dual(&d, &q, &qd, &mut w, &mut dq, &mut dqd);
        for (name, a, b) in [("dh/dq", &sq, &dq), ("dh/dq'", &sqd, &dqd)] {
            let big = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let err = a
                .iter()
                .zip(b.iter())
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            eprintln!("{scene} (n = {n}) {name}: {:.2e} of {big:.2e}", err / big);
            // Same derivatives, other summation order: round-off only (measured 4.5e-16 of
            // the largest entry, elastic dh/dq).
            assert!(err <= 1e-15 * big, "{scene} {name}: {err:e} of {big:e}");
        }
        // The ported form (`washdyn_ode::ported`): T^T E T + diag(0, d) is the same matrix.
        let Some(r) = eq.ported_ports() else {
            eprintln!("{scene}: no ported form");
            continue;
        };
        let n1 = eq.layout.n1;
        let mut j = PortedJacobian::new(n1, r, n - n1, 0);
        let (jq, jv) = (&mut j.eq, &mut j.ev);
        let (dq_, dv_) = (&mut j.dq, &mut j.dv);
        eq.force_jacobians_ported(&d, (&q, &qd, &[]), &mut w, jq, jv, dq_, dv_, &mut j.b2);
        let mut m = vec![0.0; n * n];
        j.expand(&mut m, &mut dq, &mut dqd);
        for (name, a, b) in [("dh/dq", &dq, &sq), ("dh/dq'", &dqd, &sqd)] {
            let big = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let err = a
                .iter()
                .zip(b.iter())
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            eprintln!(
                "{scene} (n1 = {n1}, r = {r}) ported {name}: {:.2e} of {big:.2e}",
                err / big
            );
            // Another summation order again (measured 1.2e-15 of the largest entry, elastic
            // dh/dq').
            assert!(
                err <= 5e-15 * big,
                "{scene} ported {name}: {err:e} of {big:e}"
            );
        }
    }
}

/// The first-order form with its ported form withheld: the implicit methods then factorise
/// the dense n x n mass form (the route before `OdeSystem::ported_jacobians`).
struct NoPorted<S: Mechanical>(FirstOrder<S>);

impl<S: Mechanical> OdeSystem for NoPorted<S> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.0.rhs(t, y, dy)
    }
    fn jacobian(&mut self, t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        self.0.jacobian(t, y, jac)
    }
    fn mass_jacobians(
        &mut self,
        t: f64,
        y: &[f64],
        m: &mut [f64],
        hq: &mut [f64],
        hqd: &mut [f64],
    ) -> bool {
        self.0.mass_jacobians(t, y, m, hq, hqd)
    }
    fn second_order(&self) -> Option<usize> {
        self.0.second_order()
    }
    fn atol_scales(&self, s: &mut [f64]) {
        self.0.atol_scales(s)
    }
}

/// The first-order form with its mass form withheld: the implicit methods then iterate on
/// I - c J with J = [[0, I], [M^-1 dh/dq, M^-1 dh/dq']] (M^-1 by Cholesky solves), the route
/// before `OdeSystem::mass_jacobians`.
struct NoMassForm<S: Mechanical>(FirstOrder<S>);

impl<S: Mechanical> OdeSystem for NoMassForm<S> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.0.rhs(t, y, dy)
    }
    fn jacobian(&mut self, t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        self.0.jacobian(t, y, jac)
    }
    fn second_order(&self) -> Option<usize> {
        self.0.second_order()
    }
    fn atol_scales(&self, s: &mut [f64]) {
        self.0.atol_scales(s)
    }
}

/// sdirk4, rodas4 and generalized-alpha on the elastic scene, iterating on the ported form
/// (generalized-alpha on M - beta' h gamma dh/dq' - beta' h^2 beta dh/dq), on the dense
/// mass form (d^2 M - c d dh/dq' - c^2 dh/dq) and on the first-order Jacobian: the same steps
/// to the Newton tolerance (the methods' iteration matrices are the same up to the factor M
/// and the elimination of the cabinet's modes).
#[test]
fn implicit_methods_take_the_same_steps_with_and_without_the_mass_form() {
    let model = washdyn_models::built_in("reference").unwrap().unwrap();
    // On the paper's friction law, whose dampers carry no state: the ported and mass forms
    // cover y = [q; q'] alone (a scene with element states iterates on its whole Jacobian).
    let mut s = model.scene(Some("elastic")).unwrap();
    s.effects
        .retain(|e| !matches!(e, washdyn_model::ir::Effect::FrictionLaw(_)));
    assert_eq!(s.friction_law(FrictionLaw::Arctan), FrictionLaw::Arctan);
    let n = Equations::new(&model, &s).layout.n();
    // From rest at t = 60 s (60 rpm/s up from the profile's start; the tub drops under its
    // weight and the unbalance), 20 ms.
    let (t0, t1) = (60.0, 60.02);
    let y0 = vec![0.0; 2 * n];
    let opts = Options {
        rtol: 1e-6,
        atol: 1e-9,
        ..Options::default()
    };
    // The end state and the accepted steps of `method` on `sys` over [t0, t1].
    let integrate = |sys: &mut dyn OdeSystem, method: Method| -> (Vec<f64>, u64) {
        let mut solver = AnySolver::new(method, 2 * n, opts);
        solver.init(sys, t0, &y0).unwrap();
        while solver.t() < t1 {
            solver.step(sys, t1).unwrap();
        }
        (solver.y().to_vec(), solver.stats().steps)
    };
    // Each step's Newton (sdirk4) or linear solve (rodas4) differs by round-off of another
    // factorisation, carried over 529-1400 steps; a round-off flip of one step's acceptance
    // is allowed. Measured: the same step counts (sdirk4 1400, rodas4 1159, galpha 529); the
    // ported form against the dense mass form 3.3e-11 (sdirk4), 3.7e-12 (rodas4), 2.6e-15
    // (galpha); against the first-order Jacobian 6.3e-11 (sdirk4), 1.8e-11 (rodas4), 1.5e-15
    // (galpha) (on the 324-coordinate data: 2.7e-11, 1.5e-12, 1.4e-15 and 6.9e-12, 2.4e-12,
    // 1.4e-15).
    let agree =
        |method: Method, what: &str, (ya, na): &(Vec<f64>, u64), (yb, nb): &(Vec<f64>, u64)| {
            let scale = yb.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let diff = ya
                .iter()
                .zip(yb)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            eprintln!(
                "{method}: ported {na} / {what} {nb} steps, difference {:.1e} of {scale:.1e}",
                diff / scale
            );
            assert!(
                na.abs_diff(*nb) <= 2,
                "{method} ({what}): {na} against {nb} steps"
            );
            assert!(
                diff <= 2e-10 * scale,
                "{method} ({what}): {diff:e} of {scale:e}"
            );
        };
    for method in [Method::Sdirk4, Method::Rodas4, Method::GeneralizedAlpha] {
        let mut a = FirstOrder::new(Interpreter::new(&model, &s));
        assert!(a.ported_shape().is_some(), "elastic is ported");
        let ported = integrate(&mut a, method);
        let first_order = integrate(
            &mut NoMassForm(FirstOrder::new(Interpreter::new(&model, &s))),
            method,
        );
        let dense = integrate(
            &mut NoPorted(FirstOrder::new(Interpreter::new(&model, &s))),
            method,
        );
        agree(method, "dense mass form", &ported, &dense);
        agree(method, "first-order Jacobian", &ported, &first_order);
    }
}

/// The ported form with element states (`elastic` on the dampers as built: four bushing
/// deflections z) against central differences of the interpreter's h and z' at a state off
/// rest: dh/dq, dh/dq', dz'/dq, dz'/dq' through the ports, and dh/dz, dz'/dz in E_v's state
/// columns (`states.rs`), expanded to the dense (n + nz)^2 matrices.
#[test]
fn ported_jacobians_with_element_states_match_central_differences() {
    let model = washdyn_models::built_in("reference").unwrap().unwrap();
    let s = model.scene(Some("elastic")).unwrap();
    assert_eq!(
        s.friction_law(FrictionLaw::Arctan),
        FrictionLaw::ElastoPlastic
    );
    let eq = Equations::new(&model, &s);
    let (n, n1, nz) = (eq.layout.n(), eq.layout.n1, eq.layout.nz);
    assert_eq!(nz, 4, "one deflection per damper");
    let (q, qd) = off_rest(n);
    // z_ss = Fmax / k = 3e-4 m, breakaway at 2.7e-4: two dampers on the elasto-plastic
    // transition, two elastic; none at a kink of the law.
    let z = [2.85e-4, -1.0e-4, -2.9e-4, 0.5e-4];
    let d = Drive {
        phi: 2.1,
        omega: 146.6,
        omega_dot: 3.0,
    };
    let r = eq.ported_ports().expect("elastic is ported");
    let mut j = PortedJacobian::new(n1, r, n - n1, nz);
    let mut w = JacobianWork::new(&eq);
    let (jq, jv) = (&mut j.eq, &mut j.ev);
    eq.force_jacobians_ported(
        &d,
        (&q, &qd, &z),
        &mut w,
        jq,
        jv,
        &mut j.dq,
        &mut j.dv,
        &mut j.b2,
    );
    let m = n + nz;
    let (mut mm, mut aq, mut av) = (vec![0.0; m * m], vec![0.0; m * m], vec![0.0; m * m]);
    j.expand(&mut mm, &mut aq, &mut av);
    // [h; z'] at y = [q; q'; z].
    let f = |y: &[f64]| -> Vec<f64> {
        let mut out = vec![0.0; m];
        let (h, zd) = out.split_at_mut(n);
        eq.forces(&d, &y[..n], &y[n..2 * n], &y[2 * n..], h);
        eq.state_rates(&y[..n], &y[n..2 * n], &y[2 * n..], zd);
        out
    };
    let y: Vec<f64> = q.iter().chain(&qd).chain(&z).copied().collect();
    // Column c of y (q, q' or z) against its matrix: q in A_q, q' and z in A_v.
    let mut worst = [0.0f64; 3];
    for c in 0..2 * n + nz {
        let (jac, col, kind) = match c {
            c if c < n => (&aq, c, 0),
            c if c < 2 * n => (&av, c - n, 1),
            c => (&av, c - n, 2),
        };
        let e = 1e-6 * y[c].abs().max(if kind == 2 { 1e-4 } else { 1e-3 });
        let (mut yp, mut ym) = (y.clone(), y.clone());
        yp[c] += e;
        ym[c] -= e;
        let (fp, fm) = (f(&yp), f(&ym));
        let big = (0..m).fold(1e-9, |a: f64, i| a.max(jac[i * m + col].abs()));
        for i in 0..m {
            let fd = (fp[i] - fm[i]) / (2.0 * e);
            // h's round-off over the step (the correction modes' large forces).
            let noise = 10.0 * f64::EPSILON * fp[i].abs().max(fm[i].abs()) / e;
            let err = ((jac[i * m + col] - fd).abs() - noise).max(0.0) / big;
            worst[kind] = worst[kind].max(err);
        }
    }
    eprintln!(
        "ported with states: columns of q {:.1e}, q' {:.1e}, z {:.1e}",
        worst[0], worst[1], worst[2]
    );
    // The z columns of A_q are zero by convention (z enters through A_v).
    for i in 0..m {
        for c in n..m {
            assert_eq!(aq[i * m + c], 0.0, "A_q's state column {c}, row {i}");
        }
    }
    // Central differences with a relative step of 1e-6, beyond h's round-off. Measured: q
    // 5.9e-9, q' 3.4e-7 (the states' rows, the law's rate near its breakaway ramp), z 1.1e-12.
    for (k, name) in ["q", "q'", "z"].iter().enumerate() {
        assert!(worst[k] < 1e-6, "columns of {name}: {:e}", worst[k]);
    }
}

/// Largest |a - b| relative to b's largest entry.
fn rel_max(a: &nalgebra::DMatrix<f64>, b: &nalgebra::DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax().max(f64::MIN_POSITIVE)
}

/// The production linearisation (`washdyn_runtime::linearise`: the exact force Jacobians, what
/// `washdyn modes` and the harmonic steady state stand on) against the tests' one difference
/// path (`common::differences`, step 1e-6), where the two are taken: `washdyn modes`' rigid
/// machine about its static equilibrium (unbalances off, friction released), and the elastic
/// machine at 1000 rpm about q = 0 (friction released: the arctan law's slope at v = 0 is no
/// place for a difference). The difference's own error bounds the agreement: truncation
/// eps^2 h''' / 6 ~ 1e-12 / L^2 of K for the elements' geometry (lengths L ~ 0.1 m) and
/// round-off 1e-16 |h| / eps against the stiff correction modes' forces.
#[test]
fn linearisation_matches_the_tests_central_differences() {
    use crate::common;
    use washdyn_runtime::linearise::Linearisation;
    let mut model = washdyn_models::built_in("reference").unwrap().unwrap();
    model.unbalances.clear();
    for d in &mut model.friction_dampers {
        d.f_max = 0.0;
    }
    let mut rigid = model.clone();
    rigid.elastic.clear();
    let mut sys = Interpreter::new(&rigid, &rigid.scene(None).unwrap());
    let lin = Linearisation::at_rest(&mut sys, 0.0).unwrap();
    let dif = common::differences(&sys.eq, &lin.drive, lin.q0.as_slice(), 1e-6);
    let (ek, em) = (rel_max(&lin.k, &dif.k), rel_max(&lin.m, &dif.m));
    let sym = |k: &nalgebra::DMatrix<f64>| 0.5 * (k + k.transpose());
    let fa = common::frequencies(&lin.m, &sym(&lin.k));
    let fb = common::frequencies(&dif.m, &sym(&dif.k));
    let ef = fa
        .iter()
        .zip(&fb)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs() / b));
    eprintln!("modes' machine: K {ek:.1e}, M {em:.1e}, frequencies {ef:.1e}\n  {fa:?}\n  {fb:?}");
    // Measured: K 3.3e-11, frequencies 2.4e-11 (what `washdyn modes` moved by when it left
    // these differences for the exact Jacobians); the elastic machine K 2.0e-14, C 4.4e-11.
    assert_eq!(em, 0.0, "M1 is the same evaluation");
    assert!(ek < 1e-9, "K: {ek:e}");
    assert!(ef < 1e-9, "frequencies: {ef:e}");

    let s = model.scene(Some("elastic")).unwrap();
    let sys = Interpreter::new(&model, &s);
    let n = sys.layout().n();
    let d = Drive {
        phi: 0.0,
        omega: 1000.0 * std::f64::consts::PI / 30.0,
        omega_dot: 0.0,
    };
    let lin = Linearisation::new(&sys.eq, sys.m2(), &d, &vec![0.0; n]);
    let dif = common::differences(&sys.eq, &d, &vec![0.0; n], 1e-6);
    let (ek, ec) = (rel_max(&lin.k, &dif.k), rel_max(&lin.c, &dif.c));
    eprintln!("elastic machine at 1000 rpm: K {ek:.1e}, C {ec:.1e}");
    assert!(ek < 1e-9, "K: {ek:e}");
    assert!(ec < 1e-9, "C: {ec:e}");
}
