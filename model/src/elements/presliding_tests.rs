//! The elasto-plastic law against its closed forms: a damper stroked harmonically between two
//! fixed points, its state integrated along the stroke (classical RK4 on a fine grid, the
//! element's own `state_rate` and `wrenches`), the loop's area against the branches' closed
//! form, the presliding stiffness, the Coulomb limit and rate independence.

use super::*;
use crate::ir::{Attach, BodyRef, FrictionLaw};

const K: f64 = 2.5e5;
const F_MAX: f64 = 75.0;
const Z_SS: f64 = F_MAX / K;

fn damper(breakaway: f64) -> FrictionDamper {
    let d = ir::FrictionDamper {
        name: "d".into(),
        a: Attach {
            body: BodyRef::Tub,
            point: [0.0, 0.0, 0.3],
        },
        b: Attach {
            body: BodyRef::Cabinet,
            point: [0.0, 0.0, 0.0],
        },
        law: FrictionLaw::ElastoPlastic,
        f_max: F_MAX,
        slope: 0.0,
        axial_stiffness: Some(K),
        breakaway: Some(breakaway),
        bearing_stiffness: 0.0,
        bearing_damping: 0.0,
        moving_part: None,
    };
    let (a, b) = (d.a.point, d.b.point);
    FrictionDamper::new(
        &d,
        FrictionLaw::ElastoPlastic,
        0,
        MarkerDef::fixed(BodyRef::Tub, a),
        MarkerDef::fixed(BodyRef::Cabinet, b),
    )
}

/// The damper's ends: a at rest, b moved by x along the rod's axis (-z: b below a, so a
/// positive x extends the rod) at velocity v.
fn ends(e: &FrictionDamper, x: f64, v: f64) -> (Marker<f64>, Marker<f64>) {
    let mk = |p: [f64; 3], dz: f64, vz: f64| Marker::<f64> {
        pos: V::c([p[0], p[1], p[2] + dz]),
        vel: V::c([0.0, 0.0, vz]),
        rot: V::zero(),
        angvel: V::zero(),
    };
    (mk(e.a.point, 0.0, 0.0), mk(e.b.point, -x, -v))
}

/// The force resisting extension (on a, along the rod towards b) at stroke x, state z.
fn force(e: &FrictionDamper, x: f64, z: f64, exact: bool) -> f64 {
    let (a, b) = ends(e, x, 0.0);
    let d = Drive {
        phi: 0.0,
        omega: 0.0,
        omega_dot: 0.0,
    };
    let (wa, _) = e.wrenches(&a, &b, exact, &d, &[z]);
    -wa.force.0[2]
}

/// `cycles` of x = X sin(w t) from z = 0 in RK4 steps of 1/4000 cycle: the last cycle's
/// (x, F) samples at every step, and the state left.
fn stroke(e: &FrictionDamper, amp: f64, w: f64, cycles: usize) -> Vec<(f64, f64)> {
    let per = 4000;
    let h = 2.0 * PI / w / per as f64;
    let rate = |t: f64, z: f64| {
        let (a, b) = ends(e, amp * (w * t).sin(), amp * w * (w * t).cos());
        e.state_rate(&a, &b, false, &[z])
    };
    let (mut t, mut z) = (0.0, 0.0);
    let mut out = Vec::new();
    for k in 0..cycles * per {
        let k1 = rate(t, z);
        let k2 = rate(t + h / 2.0, z + h / 2.0 * k1);
        let k3 = rate(t + h / 2.0, z + h / 2.0 * k2);
        let k4 = rate(t + h, z + h * k3);
        z += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        t += h;
        if k + 1 >= (cycles - 1) * per {
            let x = amp * (w * t).sin();
            out.push((x, force(e, x, z, false)));
        }
    }
    out
}

/// The loop's area, closed by the trapezoidal rule over the samples.
fn area(l: &[(f64, f64)]) -> f64 {
    l.windows(2)
        .map(|p| 0.5 * (p[0].1 + p[1].1) * (p[1].0 - p[0].0))
        .sum()
}

/// The energy one cycle of a steady stroke of amplitude X dissipates, in closed form from the
/// law's branches (derived for this test): elastic up to z_ba, then z_ss - z = d exp(-s / d) over
/// stroke s past it, d = z_ss - z_ba. With z_r the deflection at reversal and L = 2 X - z_ba - z_r
/// the loading branch's exponential part, z_r = z_ss - d exp(-L / d) and
/// E = 2 k ((z_ba^2 - z_r^2) / 2 + z_ss L - d^2 (1 - exp(-L / d))); zero for X <= z_ba.
fn loop_energy(breakaway: f64, x: f64) -> f64 {
    let (z_ba, d) = (breakaway * Z_SS, (1.0 - breakaway) * Z_SS);
    if x <= z_ba {
        return 0.0;
    }
    // z_r by fixed point: the map's slope is exp(-L / d) < 1.
    let mut zr = z_ba;
    for _ in 0..500 {
        zr = Z_SS - d * (-(2.0 * x - z_ba - zr) / d).exp();
    }
    let l = 2.0 * x - z_ba - zr;
    2.0 * K * ((z_ba * z_ba - zr * zr) / 2.0 + Z_SS * l - d * d * (1.0 - (-l / d).exp()))
}

/// Below the breakaway deflection the damper is the bushings' spring: F = k x on the whole
/// cycle and no loop.
#[test]
fn presliding_is_the_bushings_spring() {
    let e = damper(0.5);
    let l = stroke(&e, 0.4 * Z_SS, 30.0, 2);
    let worst = l.iter().fold(0.0f64, |m, &(x, f)| m.max((f - K * x).abs()));
    // Measured: 2.8e-11 N of 75 N.
    assert!(worst < 3e-10, "F - k x up to {worst:e} N");
    assert!(area(&l).abs() < 1e-12, "loop area {:e} J", area(&l));
}

/// The loop's area is the closed form's at amplitudes from just past breakaway to 100 sliding
/// deflections, for a round and a sharp transition.
#[test]
fn loop_area_is_the_closed_form() {
    for b in [0.5, 0.9] {
        for m in [0.8, 1.5, 4.0, 30.0, 100.0] {
            let x = m * Z_SS;
            let e = damper(b);
            // Near breakaway the loop settles slowly (by exp(-L / d) a half cycle): 20 cycles.
            let got = area(&stroke(&e, x, 30.0, 20));
            let want = loop_energy(b, x);
            // Measured: 5.6e-7 at most (the trapezoidal rule's on 4000 samples).
            assert!(
                (got - want).abs() <= 5e-6 * want + 1e-12,
                "b {b}, X {m} z_ss: {got:e} J against {want:e} J"
            );
        }
    }
}

/// At large amplitude the loop is Coulomb's rectangle, 4 Fmax X per cycle; as the transition
/// sharpens it is the ideal slider's, 4 Fmax (X - z_ss).
#[test]
fn coulomb_and_ideal_slider_limits() {
    let x = 200.0 * Z_SS;
    let e = damper(0.5);
    let got = area(&stroke(&e, x, 30.0, 3));
    let coulomb = 4.0 * F_MAX * x;
    // Measured: 0.53 % below (the presliding stroke's share, about z_ss / X).
    assert!(
        (coulomb - got) / coulomb < 0.01,
        "{got} J against {coulomb} J"
    );
    let x = 5.0 * Z_SS;
    let sharp = damper(0.999);
    let got = area(&stroke(&sharp, x, 30.0, 3));
    let ideal = 4.0 * F_MAX * (x - Z_SS);
    // Measured: 3.9e-4.
    assert!(
        (got - ideal).abs() < 2e-3 * ideal,
        "{got} J against {ideal} J"
    );
}

/// The loop does not depend on the rate: the same at 1 and 300 rad/s.
#[test]
fn rate_independent() {
    let e = damper(0.9);
    let slow = stroke(&e, 3.0 * Z_SS, 1.0, 3);
    let fast = stroke(&e, 3.0 * Z_SS, 300.0, 3);
    let worst = slow
        .iter()
        .zip(&fast)
        .fold(0.0f64, |m, (s, f)| m.max((s.1 - f.1).abs()));
    // Measured: 1.7e-9 N (the same steps in stroke; round-off in the rates' scaling by w).
    assert!(worst < 2e-8, "forces differ by {worst:e} N");
}

/// The force is k z along the rod in either kinematics, and the state's rate is the stroke
/// rate while loading elastically, zero while sliding, the stroke rate on reversal.
#[test]
fn force_and_rate_at_the_branches() {
    let e = damper(0.5);
    for exact in [false, true] {
        assert!((force(&e, 0.0, 0.2 * Z_SS, exact) - 0.2 * F_MAX).abs() < 1e-12);
    }
    let rate = |z: f64, v: f64| {
        let (a, b) = ends(&e, 0.0, v);
        e.state_rate(&a, &b, true, &[z])
    };
    assert_eq!(rate(0.3 * Z_SS, 0.1), 0.1);
    assert!(rate(Z_SS, 0.1).abs() < 1e-15);
    assert_eq!(rate(Z_SS, -0.1), -0.1);
    assert_eq!(rate(-Z_SS, 0.1), 0.1);
    // Halfway through the transition: alpha z / z_ss = 1/2.
    assert!((rate(0.75 * Z_SS, 0.1) - 0.05).abs() < 1e-15);
}
