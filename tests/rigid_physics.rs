//! Physics of the rigid reference machine on the interpreter path, against expected values from
//! outside the derivation: hand-assembled linear models and closed forms.

use crate::common;

use common::*;
use std::f64::consts::PI;
use washdyn_model::elements::friction_force;
use washdyn_model::ir::{Attach, BodyRef, Model, Spring};
use washdyn_runtime::linearise::Linearisation;
use washdyn_runtime::system::{FirstOrder, Interpreter};

fn full(m: &Model) -> washdyn_model::ir::EffectSet {
    m.scene(Some("full")).unwrap()
}

/// The reference machine without its unbalances: it must hang in equilibrium at q = 0.
fn balanced() -> Model {
    let mut m = washdyn_models::reference();
    m.unbalances.clear();
    m.scenes.clear();
    // The rigid machine: its `full` scene would otherwise switch the elastic bodies on.
    m.elastic.clear();
    m
}

/// M and K = -dh/dq about q = 0 at t = 0, where the balanced machine hangs in equilibrium:
/// the production linearisation (`washdyn modes` takes it about its static equilibrium).
fn linearise(sys: &Interpreter) -> (nalgebra::DMatrix<f64>, nalgebra::DMatrix<f64>) {
    let lin = Linearisation::of(sys, 0.0, &[0.0; 6]).unwrap();
    (lin.m, lin.k)
}

#[test]
fn static_equilibrium_at_rest() {
    // Expected: zero acceleration, because the free lengths in docs/reference-machine.md were
    // chosen so the preloads carry the 55 kg exactly, and all other elements are unloaded at rest.
    let m = balanced();
    let mut sys = FirstOrder::new(Interpreter::new(&m, &full(&m)));
    let q = [0.0; 6];
    let mut qdd = [0.0; 6];
    sys.accelerations(0.0, &q, &q, &mut qdd);
    let worst = qdd.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    eprintln!("accelerations at rest: at most {worst:.1e} m/s^2");
    // Measured 1.3e-14 m/s^2: round-off of the preloads against the weight.
    for (i, a) in qdd.iter().enumerate() {
        assert!(a.abs() < 1e-13, "qdd[{i}] = {a:e}");
    }
}

#[test]
fn rigid_body_modes_match_hand_assembly() {
    // Springs and gasket only (no friction dampers): the linearised model's six frequencies
    // against M and K assembled by hand from the IR (tests/common: potential energy Hessian).
    let mut m = balanced();
    m.friction_dampers.clear();
    let sys = Interpreter::new(&m, &full(&m));
    let (mm, k) = linearise(&sys);
    let asym = (&k - k.transpose()).norm() / k.norm();
    assert!(
        asym < 1e-7,
        "stiffness not symmetric at equilibrium: {asym:e}"
    );
    let mh = mass_hand(&m);
    assert!((&mm - &mh).norm() < 1e-12);
    let kh = stiffness_hand(&m);
    let f_model = frequencies(&mm, &(0.5 * (&k + k.transpose())));
    let f_hand = frequencies(&mh, &kh);
    let worst = f_model
        .iter()
        .zip(&f_hand)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs() / b));
    eprintln!("rigid-body modes: model against hand within {worst:.1e} relative");
    // Measured 4.3e-16: the exact force Jacobians leave the eigensolvers' round-off (4.6e-11
    // with the central differences the modes took before).
    for (a, b) in f_model.iter().zip(&f_hand) {
        assert!(
            (a - b).abs() < 1e-14 * b,
            "model {f_model:?} vs hand {f_hand:?}"
        );
    }
    // docs/reference-machine.md: rigid-body modes between about 1 and 10 Hz (the lowest is the
    // 0.2 m springs' pendulum, 1.06 Hz).
    assert!(f_hand[0] > 1.0 && f_hand[5] < 10.0, "{f_hand:?}");
    eprintln!("rigid-body modes of the suspended tub (Hz): {f_hand:.4?}");
}

/// Four equal vertical springs attached at CoG height, symmetric about the CoG.
fn symmetric_spring_only(k: f64, len: f64) -> Model {
    let mut m = balanced();
    m.friction_dampers.clear();
    m.gaskets.clear();
    m.dampers.clear();
    let mass = m.tub.mass;
    let preload = mass * 9.81 / 4.0;
    m.springs = [(0.2, 0.15), (0.2, -0.15), (-0.2, 0.15), (-0.2, -0.15)]
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| Spring {
            name: format!("s{i}"),
            a: Attach {
                body: BodyRef::Tub,
                point: [x, y, 0.45],
            },
            b: Attach {
                body: BodyRef::Cabinet,
                point: [x, y, 0.45 + len],
            },
            stiffness: k,
            free_length: len - preload / k,
            quadratic_stiffness: 0.0,
        })
        .collect();
    m
}

#[test]
fn symmetric_variant_bounce_and_pendulum_closed_form() {
    let (k, len) = (4000.0, 0.2);
    let m = symmetric_spring_only(k, len);
    let sys = Interpreter::new(&m, &full(&m));
    let (mm, kk) = linearise(&sys);
    let f = frequencies(&mm, &(0.5 * (&kk + kk.transpose())));
    // Closed forms: bounce sqrt(sum k / m) / 2 pi; pendulum sqrt(g / L) / 2 pi (L: spring length
    // at rest, lateral stiffness P / L per spring, sum P = m g).
    let bounce = (4.0 * k / m.tub.mass).sqrt() / (2.0 * PI);
    let pendulum = (9.81 / len).sqrt() / (2.0 * PI);
    let close = |x: f64| f.iter().filter(|&&v| (v - x).abs() < 1e-6 * x).count();
    assert_eq!(close(pendulum), 2, "pendulum {pendulum} in {f:?}");
    assert_eq!(close(bounce), 1, "bounce {bounce} in {f:?}");
}

#[test]
fn friction_force_has_only_odd_harmonics_and_coulomb_limit() {
    // For v = V sin(w t) the arctan law is odd and half-wave antisymmetric: only odd harmonics.
    // As s V -> infinity it tends to a square wave of height Fmax, whose nth harmonic is
    // 4 Fmax / (n pi) (Fourier series of the square wave).
    let harmonics = |f_max: f64, slope: f64, n_max: usize| {
        let n = 1 << 16;
        (1..=n_max)
            .map(|h| {
                let (mut re, mut im) = (0.0, 0.0);
                for k in 0..n {
                    let th = 2.0 * PI * (k as f64 + 0.5) / n as f64;
                    let f = friction_force(f_max, slope, 0.01 * th.sin());
                    re += f * (h as f64 * th).cos();
                    im += f * (h as f64 * th).sin();
                }
                2.0 * (re * re + im * im).sqrt() / n as f64
            })
            .collect::<Vec<f64>>()
    };
    let a = harmonics(100.0, 2000.0, 8);
    let even = (2..=8)
        .step_by(2)
        .fold(0.0f64, |m, h| m.max(a[h - 1] / a[0]));
    eprintln!("even harmonics: at most {even:.1e} of the first");
    // Measured 1.5e-16: round-off of the 65536-term sums.
    for h in (2..=8).step_by(2) {
        assert!(a[h - 1] < 2e-15 * a[0], "even harmonic {h}: {:e}", a[h - 1]);
    }
    assert!(a[2] > 1e-3 * a[0], "odd harmonics present");
    let c = harmonics(100.0, 1e9, 7);
    let coulomb = [1, 3, 5, 7].iter().fold(0.0f64, |m, &h| {
        let expect = 4.0 * 100.0 / (h as f64 * PI);
        m.max((c[h - 1] - expect).abs() / expect)
    });
    eprintln!("Coulomb limit: harmonics within {coulomb:.1e} of 4 Fmax / (n pi)");
    // Measured 6.8e-7: the arctan law's 1 / (s V) rounding of the square wave's corners.
    for h in [1, 3, 5, 7] {
        let expect = 4.0 * 100.0 / (h as f64 * PI);
        assert!(
            (c[h - 1] - expect).abs() < 1e-5 * expect,
            "n={h}: {} vs {expect}",
            c[h - 1]
        );
    }
}

#[test]
fn shipped_reference_model_passes_checker() {
    let m = washdyn_models::reference();
    assert_eq!(m.name, "reference");
    assert_eq!(m.rotors[1].ratio, 11.25);
}
