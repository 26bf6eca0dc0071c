//! Unbalance response of a linear variant of the reference machine at constant drum speed
//! against the linear frequency response (K - W^2 M + i W (D + G(W)))^-1 F, with K, D, M, G and
//! F assembled by hand from the IR (tests/common), not from the derivation under test.

mod common;

use common::*;
use nalgebra::{Complex, DMatrix, DVector, Vector3};
use std::f64::consts::PI;
use washdyn_runtime::ir::{Attach, LinearDamper, Model};
use washdyn_runtime::ode::{Dopri5, Options, Solver};
use washdyn_runtime::system::{FirstOrder, Interpreter};

type C = Complex<f64>;

/// Linear dampers (150 N s/m) in place of the friction dampers, and a 1 g unbalance at the front
/// of the drum: small enough that the response is linear to better than 1e-5.
fn linear_variant(rpm: f64) -> Model {
    let mut m = washdyn_models::reference();
    m.dampers = m
        .friction_dampers
        .iter()
        .map(|d| LinearDamper {
            name: d.name.clone(),
            a: Attach { ..d.a },
            b: Attach { ..d.b },
            damping: 150.0,
        })
        .collect();
    m.friction_dampers.clear();
    m.unbalances.retain(|u| u.rotor == "drum");
    m.unbalances[0].mass = 1e-3;
    m.speed.table = vec![[0.0, rpm], [1.0e4, rpm]];
    m.scenes.clear();
    m
}

/// Hand-assembled complex amplitude of the steady state at drum speed w.
fn frf(m: &Model, w: f64) -> DVector<C> {
    let u = &m.unbalances[0];
    let rotor = m.rotors.iter().find(|r| r.name == "drum").unwrap();
    let p0 = v3(m.tub.cog);
    let e = v3(rotor.axis).normalize();
    let a = v3(rotor.axis_point);
    let rho = v3(u.position) - a;
    let rho_ax = e * e.dot(&rho);
    let rho_r = rho - rho_ax;
    // rho(t) = Re[(rho_r - i e x rho_r) e^{i w t}].
    let hat: Vec<C> = (0..3)
        .map(|k| C::new(rho_r[k], -e.cross(&rho_r)[k]))
        .collect();
    let lever = a + rho_ax - p0;
    let g = Vector3::new(m.gravity[0], m.gravity[1], m.gravity[2]);
    let mu = u.mass;
    // Forces on the tub: centrifugal m w^2 rho(t) at the unbalance, and the moment of its weight
    // about p0 turning with it, rho(t) x m g.
    let mut f = DVector::<C>::zeros(6);
    for k in 0..3 {
        f[k] = hat[k] * (mu * w * w);
    }
    let cross = |l: [C; 3], r: [C; 3]| {
        [
            l[1] * r[2] - l[2] * r[1],
            l[2] * r[0] - l[0] * r[2],
            l[0] * r[1] - l[1] * r[0],
        ]
    };
    let lv = [C::from(lever.x), C::from(lever.y), C::from(lever.z)];
    let fv = [f[0], f[1], f[2]];
    let hv = [hat[0], hat[1], hat[2]];
    let gv = [C::from(mu * g.x), C::from(mu * g.y), C::from(mu * g.z)];
    let mom = cross(lv, fv);
    let wmom = cross(hv, gv);
    for k in 0..3 {
        f[3 + k] = mom[k] + wmom[k];
    }
    // Mass: tub plus the unbalance's mean contribution (point mass averaged over a turn).
    let mut mm = mass_hand(m);
    for k in 0..3 {
        mm[(k, k)] += mu;
    }
    let c = lever;
    let r2 = rho_r.norm_squared();
    let avg_ss = c * c.transpose() + 0.5 * r2 * (nalgebra::Matrix3::identity() - e * e.transpose());
    let inertia = (c.norm_squared() + r2) * nalgebra::Matrix3::identity() - avg_ss;
    let sk = skew(c);
    for i in 0..3 {
        for j in 0..3 {
            mm[(3 + i, 3 + j)] += mu * inertia[(i, j)];
            mm[(i, 3 + j)] -= mu * sk[(i, j)];
            mm[(3 + i, j)] += mu * sk[(i, j)];
        }
    }
    let k = stiffness_hand(m);
    let d = damping_hand(m);
    // Gyroscopic: d/dt (Jp W e) in tub axes gives Jp W (alpha' x e) = -Jp W e~ alpha'.
    let mut gm = DMatrix::zeros(6, 6);
    for r in &m.rotors {
        let er = v3(r.axis).normalize();
        let s = -r.polar_inertia * r.ratio * w * skew(er);
        for i in 0..3 {
            for j in 0..3 {
                gm[(3 + i, 3 + j)] += s[(i, j)];
            }
        }
    }
    let a = k.map(C::from) - (mm * (w * w)).map(C::from) + (d + gm).map(|x| C::new(0.0, w * x));
    a.lu().solve(&f).expect("regular")
}

/// Steady-state first harmonic of the simulated tub motion at drum speed w.
fn simulated(m: &Model, w: f64) -> DVector<C> {
    let scene = m.scene(None).unwrap();
    let mut sys = FirstOrder::new(Interpreter::new(m, &scene));
    let opts = Options {
        rtol: 1e-11,
        atol: 1e-15,
        ..Options::default()
    };
    let mut s = Dopri5::new(12, opts);
    let period = 2.0 * PI / w;
    let settle = 25.0;
    let t0 = (settle / period).ceil() * period;
    let n_per = 8usize;
    let n_samples = 64 * n_per;
    s.init(&mut sys, 0.0, &[0.0; 12]).unwrap();
    let mut acc = DVector::<C>::zeros(6);
    let mut y = [0.0; 12];
    let mut k = 0;
    let t1 = t0 + n_per as f64 * period;
    while s.t() < t1 {
        s.step(&mut sys, t1).unwrap();
        while k < n_samples {
            let t = t0 + k as f64 * (t1 - t0) / n_samples as f64;
            if t > s.t() {
                break;
            }
            if t >= s.t_prev() {
                s.interpolate(t, &mut y);
                let ph = C::new(0.0, -w * t).exp();
                for i in 0..6 {
                    acc[i] += ph * y[i];
                }
                k += 1;
            } else {
                break;
            }
        }
    }
    assert_eq!(k, n_samples);
    acc * C::from(2.0 / n_samples as f64)
}

#[test]
fn unbalance_response_matches_linear_frequency_response() {
    let probe = linear_variant(60.0);
    let f = frequencies(&mass_hand(&probe), &stiffness_hand(&probe));
    // Below, near and above the first rigid-body resonance.
    for (label, hz) in [("below", 0.5 * f[0]), ("near", f[0]), ("above", 3.0 * f[5])] {
        let w = 2.0 * PI * hz;
        let m = linear_variant(hz * 60.0);
        let expect = frf(&m, w);
        let got = simulated(&m, w);
        let err = (&got - &expect).norm() / expect.norm();
        eprintln!(
            "{label} ({hz:.3} Hz): |q| = {:.3e}, relative error {err:.2e}",
            expect.norm()
        );
        assert!(err < 1e-4, "{label}: {got:?} vs {expect:?}");
    }
}
