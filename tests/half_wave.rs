//! Half-wave symmetry (seed paper: the friction law's odd Fourier series excites only odd
//! orders): with the friction damper as the only nonlinearity, a harmonic unbalance force gives
//! a response without even orders; an asymmetric characteristic curve brings them back.

use std::f64::consts::PI;
use washdyn_model::ir::{Model, Scene};
use washdyn_ode::{Dopri5, Options};
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::run::{Labels, RunOptions, Start, run};
use washdyn_runtime::system::{FirstOrder, Interpreter};

const RPM: f64 = 300.0;

/// The rigid reference machine at constant drum speed, drum unbalance only, with the given
/// effects on top of friction dampers, gasket damping and gyroscopic terms.
fn variant(extra: &[&str]) -> Model {
    let mut m = washdyn_models::reference();
    m.unbalances.retain(|u| u.rotor == "drum");
    m.speed.table = vec![[0.0, RPM], [1e4, RPM]];
    let mut effects: Vec<String> = [
        "gyroscopic",
        "unbalance.drum",
        "friction_dampers",
        "gasket_damping",
    ]
    .iter()
    .chain(extra)
    .map(|s| s.to_string())
    .collect();
    effects.dedup();
    m.scenes = vec![Scene {
        name: "s".into(),
        effects,
        max_order: None,
        solver: None,
    }];
    m
}

/// Amplitudes of drum orders 1..=8 of every channel in steady state: DFT over 10 whole drum
/// revolutions after 30 s of settling, 256 samples per revolution (dense output).
fn orders(m: &Model) -> Vec<(String, Vec<f64>)> {
    let scene = m.scene(Some("s")).unwrap();
    let mut sys = FirstOrder::new(Interpreter::new(m, &scene));
    let f = RPM / 60.0;
    let per = 256.0;
    let opts = Options {
        rtol: 1e-10,
        atol: 1e-13,
        ..Options::default()
    };
    let mut solver = Dopri5::new(12, opts);
    let revs = 10.0;
    let t_settle = (60.0 * f).ceil() / f;
    let ro = RunOptions {
        t_start: 0.0,
        t_end: t_settle + revs / f,
        sample_rate: per * f,
        start: Start::Static,
    };
    let mut sink = MemorySink::default();
    run(
        &mut sys,
        &mut solver,
        &ro,
        &Labels::default(),
        (1e-10, 1e-13),
        &mut sink,
        &mut |_| {},
    )
    .map_err(|e| e.0.to_string())
    .unwrap();
    let n = (revs * per) as usize;
    let start = sink.time.len() - 1 - n;
    (0..sink.channels.len())
        .filter(|&c| sink.channels[c].starts_with("tub"))
        .map(|c| {
            let x = &sink.column(c)[start..start + n];
            let amps = (1..=8)
                .map(|k| {
                    let (mut re, mut im) = (0.0, 0.0);
                    for (i, v) in x.iter().enumerate() {
                        let th = 2.0 * PI * (k as f64) * revs * i as f64 / n as f64;
                        re += v * th.cos();
                        im += v * th.sin();
                    }
                    2.0 * (re * re + im * im).sqrt() / n as f64
                })
                .collect();
            (sink.channels[c].clone(), amps)
        })
        .collect()
}

/// Largest even-order amplitude over largest odd-order amplitude, over all tub channels.
fn even_over_odd(o: &[(String, Vec<f64>)]) -> f64 {
    let mut even: f64 = 0.0;
    let mut odd: f64 = 0.0;
    for (_, a) in o {
        for (k, v) in a.iter().enumerate() {
            if (k + 1) % 2 == 0 {
                even = even.max(*v);
            } else {
                odd = odd.max(*v);
            }
        }
    }
    even / odd
}

#[test]
fn friction_alone_excites_only_odd_orders() {
    let o = orders(&variant(&[]));
    let r = even_over_odd(&o);
    let third = o.iter().map(|(_, a)| a[2] / a[0]).fold(0.0f64, f64::max);
    eprintln!("friction-only variant: even/odd = {r:.2e}, largest 3rd/1st order = {third:.2e}");
    assert!(
        third > 1e-3,
        "the friction damper must excite odd higher orders"
    );
    // Measured 1.1e-5 (1.6e-6 with the earlier two dampers at x = 0): what the 60 s of
    // settling leave of the transient; the asymmetric variant below stays above 1e-3.
    assert!(r < 1e-4, "even orders {r:e} of the odd ones");
}

#[test]
fn asymmetric_characteristic_brings_even_orders() {
    // Springs 30 % stiffer at 10 mm extension than at 10 mm compression: k2 = 0.3 k / 0.02 m.
    let mut m = variant(&[]);
    for s in &mut m.springs {
        s.quadratic_stiffness = 0.3 * s.stiffness / 0.02;
    }
    let r = even_over_odd(&orders(&m));
    eprintln!("asymmetric springs: even/odd = {r:.2e}");
    // Measured 1.3e-3.
    assert!(r > 1e-3, "even orders only {r:e} of the odd ones");
}

#[test]
fn even_orders_of_the_full_model_and_their_sources() {
    // How large the even orders are with the full kinematics, and which effect brings them.
    // Measured (300 rpm, rigid): 0.030 (element geometry), 0.012 (unbalance inertia), 0.032
    // (both; 0.108, 0.021, 0.114 before issue 19's dampers and gasket). Each effect
    // alone must lift them at least 1e3 times above the friction-only level (< 1e-5), and they
    // stay below the odd orders.
    for (label, extra) in [
        ("+ element geometry", &["element_geometry"][..]),
        ("+ unbalance inertia", &["unbalance_inertia"][..]),
        (
            "full (both)",
            &["element_geometry", "unbalance_inertia"][..],
        ),
    ] {
        let o = orders(&variant(extra));
        let r = even_over_odd(&o);
        let (ch, a) = o.iter().max_by(|x, y| x.1[1].total_cmp(&y.1[1])).unwrap();
        eprintln!(
            "{label}: even/odd = {r:.2e}; largest 2nd order on {ch}: {:.3e} (1st {:.3e})",
            a[1], a[0]
        );
        assert!(r > 1e-2 && r < 0.5, "{label}: even/odd = {r:e}");
    }
}
