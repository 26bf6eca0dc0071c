//! The two back ends agree: generated code (traced from the one derivation at compile time) and
//! the interpreter (the same derivation at run time) give the same M1, h, q'' to round-off for
//! random states and times, the same trajectories, and the generated analytic Jacobians agree
//! with finite differences of the interpreter.

use washdyn_model::ir::Model;
use washdyn_ode::{Options, Rk4};
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::run::{Labels, RunOptions, Start, run};
use washdyn_runtime::system::{FirstOrder, Interpreter, Mechanical};

fn models() -> Vec<(&'static str, Model)> {
    vec![
        ("reference", washdyn_models::reference()),
        ("compact", washdyn_models::compact::model()),
        ("elastic_cabinet", washdyn_models::elastic_cabinet::model()),
    ]
}

struct Rng(u64);
impl Rng {
    /// Uniform in [-0.5, 0.5) (xorshift).
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// Asserts every entry of `b` within 5e-13 of `a`'s largest entry (or equal), naming the
/// entry by `what`; returns the largest relative difference (measured 4.2e-14 on h and q'').
fn agree(a: &[f64], b: &[f64], what: impl Fn(usize) -> String) -> f64 {
    let s = max_abs(a);
    let mut worst: f64 = 0.0;
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        let d = (x - y).abs();
        assert!(d < 5e-13 * s || d == 0.0, "{}: {x} vs {y}", what(i));
        if s > 0.0 {
            worst = worst.max(d / s);
        }
    }
    worst
}

#[test]
fn mass_forces_and_accelerations_agree_for_random_states() {
    let mut worst: f64 = 0.0;
    let mut states = 0;
    for (name, m) in models() {
        for scene in m.scene_names() {
            let eff = m.scene(Some(&scene)).unwrap();
            let mut interp = Interpreter::new(&m, &eff);
            let mut gen_ = washdyn_models::generated(name, &scene).expect("generated scene");
            let lay = interp.layout();
            assert_eq!(lay, gen_.layout());
            assert_eq!(interp.channel_names(), gen_.channel_names());
            let (n, n1) = (lay.n(), lay.n1);
            let mut rng = Rng(0x9E3779B97F4A7C15);
            for _ in 0..200 {
                // Displacements up to 10 mm / 10 mrad, velocities up to 0.5 m/s, any time of
                // the run-up (so any speed and angle).
                let q: Vec<f64> = (0..n).map(|_| 0.02 * rng.next()).collect();
                let qd: Vec<f64> = (0..n).map(|_| rng.next()).collect();
                let t = 200.0 * (rng.next() + 0.5);
                let (mut m1a, mut m1b) = (vec![0.0; n1 * n1], vec![0.0; n1 * n1]);
                let (mut ha, mut hb) = (vec![0.0; n], vec![0.0; n]);
                interp.eval(t, &q, &qd, &mut m1a, &mut ha);
                gen_.eval(t, &q, &qd, &mut m1b, &mut hb);
                let e = agree(&ha, &hb, |i| format!("{name}/{scene} h[{i}]"));
                worst = worst.max(e);
                let e = agree(&m1a, &m1b, |i| format!("{name}/{scene} M1[{i}]"));
                worst = worst.max(e);
                // Element states (a presliding damper's bushing deflection, up to 0.6 mm:
                // elastic, in its transition and sliding) and their rates.
                if lay.nz > 0 {
                    let z: Vec<f64> = (0..lay.nz).map(|_| 6e-4 * rng.next()).collect();
                    let (mut za, mut zb) = (vec![0.0; lay.nz], vec![0.0; lay.nz]);
                    interp.eval_states(t, &q, &qd, &z, &mut m1a, &mut ha, &mut za);
                    gen_.eval_states(t, &q, &qd, &z, &mut m1b, &mut hb, &mut zb);
                    let e = agree(&ha, &hb, |i| format!("{name}/{scene} h[{i}] with states"));
                    worst = worst.max(e);
                    let e = agree(&za, &zb, |i| format!("{name}/{scene} z'[{i}]"));
                    worst = worst.max(e);
                    states += 1;
                }
                // Sensors (a drum rim sensor on `compact` turns with the drive angle).
                let qdd: Vec<f64> = (0..n).map(|_| 10.0 * rng.next()).collect();
                let nc = interp.channel_names().len();
                let (mut ca, mut cb) = (vec![0.0; nc], vec![0.0; nc]);
                interp.sensors(t, &q, &qd, &qdd, &mut ca);
                gen_.sensors(t, &q, &qd, &qdd, &mut cb);
                let e = agree(&ca, &cb, |i| format!("{name}/{scene} channel {i}"));
                worst = worst.max(e);
                // q'': the interpreter's Cholesky at run time vs the generated straight-line one.
                let mut fa = FirstOrder::new(Interpreter::new(&m, &eff));
                let (mut aa, mut ab) = (vec![0.0; n], vec![0.0; n]);
                fa.accelerations(t, &q, &qd, &mut aa);
                assert!(gen_.accelerations(t, &q, &qd, &mut ab));
                let e = agree(&aa, &ab, |i| format!("{name}/{scene} qdd[{i}]"));
                worst = worst.max(e);
            }
        }
    }
    eprintln!("largest relative disagreement of M1, h, sensors and q'': {worst:.2e}");
    assert!(states > 0, "no scene with element states was compared");
}

#[test]
fn analytic_jacobians_match_differences_of_the_interpreter() {
    let m = washdyn_models::reference();
    let eff = m.scene(Some("full")).unwrap();
    let mut gen_ = washdyn_models::generated("reference", "full").unwrap();
    let mut fa = FirstOrder::new(Interpreter::new(&m, &eff));
    let n = gen_.layout().n();
    let mut rng = Rng(7);
    for _ in 0..20 {
        let q: Vec<f64> = (0..n).map(|_| 0.02 * rng.next()).collect();
        let qd: Vec<f64> = (0..n).map(|_| 0.01 * rng.next()).collect();
        let t = 200.0 * (rng.next() + 0.5);
        let (mut jq, mut jqd) = (vec![0.0; n * n], vec![0.0; n * n]);
        assert!(gen_.acceleration_jacobians(t, &q, &qd, &mut jq, &mut jqd));
        // Central differences of the interpreter's q'' (step 1e-7, error ~1e-8 relative).
        for (jac, vel) in [(&jq, false), (&jqd, true)] {
            let scale = max_abs(jac);
            for j in 0..n {
                let eps = 1e-7;
                let (mut qp, mut qm) = ((q.clone(), qd.clone()), (q.clone(), qd.clone()));
                if vel {
                    qp.1[j] += eps;
                    qm.1[j] -= eps;
                } else {
                    qp.0[j] += eps;
                    qm.0[j] -= eps;
                }
                let (mut ap, mut am) = (vec![0.0; n], vec![0.0; n]);
                fa.accelerations(t, &qp.0, &qp.1, &mut ap);
                fa.accelerations(t, &qm.0, &qm.1, &mut am);
                for i in 0..n {
                    let fd = (ap[i] - am[i]) / (2.0 * eps);
                    let e = (fd - jac[i * n + j]).abs();
                    assert!(
                        e < 1e-5 * scale + 1e-6 * fd.abs(),
                        "d qdd[{i}]/d{} [{j}]: {fd} vs {}",
                        if vel { "qd" } else { "q" },
                        jac[i * n + j]
                    );
                }
            }
        }
    }
}

/// The sensor signals of a run, with RK4 at a fixed step so both back ends take the same steps.
fn trajectory<S: Mechanical>(sys: S, t_end: f64) -> MemorySink {
    trajectory_with(sys, t_end, 2e-4, 100.0)
}

/// As `trajectory`, with the fixed step `h`, sampled at `rate` Hz.
fn trajectory_with<S: Mechanical>(sys: S, t_end: f64, h: f64, rate: f64) -> MemorySink {
    let mut sys = FirstOrder::new(sys);
    let n = sys.layout().dim();
    let opts = Options {
        h0: h,
        ..Options::default()
    };
    let mut solver = Rk4::new(n, opts);
    let mut sink = MemorySink::default();
    let ro = RunOptions {
        t_end,
        sample_rate: rate,
        start: Start::Static,
        ..RunOptions::default()
    };
    run(
        &mut sys,
        &mut solver,
        &ro,
        &Labels::default(),
        (0.0, 0.0),
        &mut sink,
        &mut |_| {},
    )
    .map_err(|e| e.0.to_string())
    .unwrap();
    sink
}

/// Every channel of `b` equals `a`'s within `bound` relative to the channel's largest value (an
/// all-zero channel exactly); returns the largest difference.
fn assert_same_signals(a: &MemorySink, b: &MemorySink, bound: f64) -> f64 {
    assert_eq!(a.values.len(), b.values.len());
    // A NaN would slip through the max below.
    assert!(a.values.iter().chain(&b.values).all(|v| v.is_finite()));
    let mut worst: f64 = 0.0;
    for c in 0..a.channels.len() {
        let (ca, cb) = (a.column(c), b.column(c));
        let scale = max_abs(&ca);
        if scale == 0.0 {
            assert!(max_abs(&cb) == 0.0);
            continue;
        }
        let d = ca
            .iter()
            .zip(&cb)
            .fold(0.0f64, |w, (x, y)| w.max((x - y).abs()))
            / scale;
        worst = worst.max(d);
        assert!(d < bound, "{}: relative difference {d:e}", a.channels[c]);
    }
    worst
}

#[test]
fn whole_run_up_trajectories_agree() {
    // The full reference run-up, 0 -> 1400 rpm in 178.375 s, every effect on.
    let m = washdyn_models::reference();
    let eff = m.scene(Some("full")).unwrap();
    let t_end = 178.375;
    let a = trajectory(Interpreter::new(&m, &eff), t_end);
    let b = trajectory(
        washdyn_models::generated("reference", "full").unwrap(),
        t_end,
    );
    // Measured 0: equal to the last bit (the bound leaves room for another compiler's folding).
    let worst = assert_same_signals(&a, &b, 1e-9);
    eprintln!("largest relative trajectory difference over the run-up: {worst:.2e}");
}

#[test]
fn elastic_run_trajectories_agree() {
    // The reference's elastic scene over its first 50 ms from the static start, RK4 at 20 us,
    // sampled at 2 kHz. The step is below RK4's stability limit there (about 120 us: the
    // basis' kHz coordinates; the dampers as built add none), so the trajectory is the
    // model's own, not a chatter; every value finite (`assert_same_signals`). Both back ends
    // solve M1 through its low-rank structure and carry the dampers' bushing states.
    let m = washdyn_models::reference();
    let eff = m.scene(Some("elastic")).unwrap();
    let a = trajectory_with(Interpreter::new(&m, &eff), 0.05, 2e-5, 2000.0);
    let b = trajectory_with(
        washdyn_models::generated("reference", "elastic").unwrap(),
        0.05,
        2e-5,
        2000.0,
    );
    // Measured 0: the same bits over 2500 steps (the bound leaves room for round-off).
    let worst = assert_same_signals(&a, &b, 1e-10);
    eprintln!("elastic scene: largest relative trajectory difference over 50 ms: {worst:.2e}");
}

/// The scene `contact` in contact: states with the tub moved up to 40 mm and 40 mrad put the
/// door ring past its 20 mm clearance at some of its 8 points. The back ends agree on h and
/// q'' (as above), and the generated analytic Jacobians, traced through the contact's clamp
/// (`f64::max`) and Hertz's power, match central differences of the interpreter.
#[test]
fn contact_scene_agrees_in_contact() {
    use washdyn_model::elements::Element;
    use washdyn_model::equations::BodyState;
    let m = washdyn_models::reference();
    let eff = m.scene(Some("contact")).unwrap();
    let mut interp = Interpreter::new(&m, &eff);
    let mut gen_ = washdyn_models::generated("reference", "contact").unwrap();
    let mut fa = FirstOrder::new(Interpreter::new(&m, &eff));
    let lay = gen_.layout();
    let (n, n1) = (lay.n(), lay.n1);
    let mut rng = Rng(11);
    let mut touching = 0;
    for _ in 0..40 {
        let q: Vec<f64> = (0..n).map(|_| 0.08 * rng.next()).collect();
        let qd: Vec<f64> = (0..n).map(|_| 0.5 * rng.next()).collect();
        let t = 200.0 * (rng.next() + 0.5);
        let st = BodyState::new(&q, &qd);
        let force: f64 = interp
            .eq
            .contacts
            .iter()
            .map(|p| {
                let (ma, mb) = p.e.markers();
                let (a, b) = (ma.state(&st), mb.state(&st));
                let d = |u: [f64; 3], v: [f64; 3]| (0..3).map(|i| p.e.n[i] * (u[i] - v[i])).sum();
                let delta: f64 = d(a.pos.0, b.pos.0);
                p.e.law(delta - p.e.offset - p.e.gap, d(a.vel.0, b.vel.0))
            })
            .sum();
        touching += usize::from(force > 0.0);
        let (mut m1a, mut m1b) = (vec![0.0; n1 * n1], vec![0.0; n1 * n1]);
        let (mut ha, mut hb) = (vec![0.0; n], vec![0.0; n]);
        interp.eval(t, &q, &qd, &mut m1a, &mut ha);
        gen_.eval(t, &q, &qd, &mut m1b, &mut hb);
        agree(&ha, &hb, |i| format!("contact h[{i}]"));
        let (mut aa, mut ab) = (vec![0.0; n], vec![0.0; n]);
        fa.accelerations(t, &q, &qd, &mut aa);
        assert!(gen_.accelerations(t, &q, &qd, &mut ab));
        agree(&aa, &ab, |i| format!("contact qdd[{i}]"));
        let (mut jq, mut jqd) = (vec![0.0; n * n], vec![0.0; n * n]);
        assert!(gen_.acceleration_jacobians(t, &q, &qd, &mut jq, &mut jqd));
        for (jac, vel) in [(&jq, false), (&jqd, true)] {
            let scale = max_abs(jac);
            for j in 0..n {
                let eps = 1e-7;
                let (mut qp, mut qm) = ((q.clone(), qd.clone()), (q.clone(), qd.clone()));
                let (p, mm) = if vel {
                    (&mut qp.1, &mut qm.1)
                } else {
                    (&mut qp.0, &mut qm.0)
                };
                p[j] += eps;
                mm[j] -= eps;
                let (mut ap, mut am) = (vec![0.0; n], vec![0.0; n]);
                fa.accelerations(t, &qp.0, &qp.1, &mut ap);
                fa.accelerations(t, &qm.0, &qm.1, &mut am);
                for i in 0..n {
                    let fd = (ap[i] - am[i]) / (2.0 * eps);
                    let e = (fd - jac[i * n + j]).abs();
                    assert!(
                        e < 1e-5 * scale + 1e-6 * fd.abs(),
                        "contact: d qdd[{i}]/d{}[{j}]: {fd} vs {}",
                        if vel { "qd" } else { "q" },
                        jac[i * n + j]
                    );
                }
            }
        }
    }
    eprintln!("contact scene: {touching} of 40 random states in contact");
    // [36 of 40]
    assert!(touching >= 10, "{touching} of 40 states touch");
}
