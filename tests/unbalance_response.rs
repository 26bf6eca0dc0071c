//! Unbalance response of a linear variant of the reference machine at constant drum speed
//! against the linear frequency response (K - W^2 M + i W (D + G(W)))^-1 F, with K, D, M, G and
//! F assembled by hand from the IR (tests/common), not from the derivation under test.

use crate::common;

use common::*;
use nalgebra::{Complex, DMatrix, DVector, Vector3};
use std::f64::consts::PI;
use washdyn_model::ir::{Attach, LinearDamper, Model};
use washdyn_ode::{Dopri5, Options, Solver, Stepper};
use washdyn_runtime::system::{FirstOrder, Interpreter};

type C = Complex<f64>;

/// Linear dampers (150 N s/m) in place of the friction dampers, and a 1 g unbalance at the front
/// of the drum: small enough that the response is linear to better than 1e-5. `inertia`: the
/// unbalance as a mass (angle-dependent M1) or as a prescribed rotating force.
fn linear_variant(rpm: f64, inertia: bool) -> Model {
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
    // Balance the unbalance's mean weight so the machine still hangs in equilibrium at q = 0:
    // the tub gives up its mass and moves its CoG so the combined CoG stays where the springs
    // carry it. Otherwise the static sag (~1e-6 m) changes K by ~q/L, which the resonance
    // amplifies to ~1e-4 of the response.
    let (mu, mt) = (m.unbalances[0].mass, m.tub.mass);
    let rotor = m.rotors.iter().find(|r| r.name == "drum").unwrap();
    let e = v3(rotor.axis).normalize();
    let a = v3(rotor.axis_point);
    let mean = a + e * e.dot(&(v3(m.unbalances[0].position) - a));
    let cog = (v3(m.tub.cog) * mt - mean * mu) / (mt - mu);
    m.tub.mass = mt - mu;
    m.tub.cog = [cog.x, cog.y, cog.z];
    m.speed.table = vec![[0.0, rpm], [1.0e4, rpm]];
    // The rigid machine (the hand-assembled model has the tub's 6 DOF).
    m.elastic.clear();
    let mut effects: Vec<String> = m.all_effects().iter().map(|e| e.name()).collect();
    if !inertia {
        effects.retain(|e| e != "unbalance_inertia");
    }
    m.scenes = vec![washdyn_model::ir::Scene {
        name: "linear".into(),
        effects,
        max_order: None,
        solver: None,
    }];
    m
}

/// Hand-assembled complex amplitude of the steady state at drum speed w. With `inertia` the
/// unbalance's mass averaged over a turn joins M (its 2 W fluctuation cannot enter an LTI model).
fn frf(m: &Model, w: f64, inertia: bool) -> DVector<C> {
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
    let mu_m = if inertia { mu } else { 0.0 };
    for k in 0..3 {
        mm[(k, k)] += mu_m;
    }
    let c = lever;
    let r2 = rho_r.norm_squared();
    let avg_ss = c * c.transpose() + 0.5 * r2 * (nalgebra::Matrix3::identity() - e * e.transpose());
    let inertia = (c.norm_squared() + r2) * nalgebra::Matrix3::identity() - avg_ss;
    let sk = skew(c);
    for i in 0..3 {
        for j in 0..3 {
            mm[(3 + i, 3 + j)] += mu_m * inertia[(i, j)];
            mm[(i, 3 + j)] -= mu_m * sk[(i, j)];
            mm[(3 + i, j)] += mu_m * sk[(i, j)];
        }
    }
    // Load stiffness of the unbalance's mean weight W at lever c, as for the spring preloads:
    // Hessian of -W.r with the finite rotation, (c.W) I - sym(W c^T). A prescribed rotating
    // force (no inertia) depends on time only and has none.
    let mut k = stiffness_hand(m);
    let wv = g * mu_m;
    let load = c.dot(&wv) * nalgebra::Matrix3::identity()
        - 0.5 * (wv * c.transpose() + c * wv.transpose());
    for i in 0..3 {
        for j in 0..3 {
            k[(3 + i, 3 + j)] += load[(i, j)];
        }
    }
    let d = damping_hand(m, w);
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
    // The slowest mode decays by more than e^-20 in this time.
    let settle = 80.0;
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

/// Relative error of the simulated first harmonic against the FRF at three speeds: below, near
/// and above the first rigid-body resonance.
fn errors(inertia: bool) -> Vec<(String, f64)> {
    let probe = linear_variant(60.0, inertia);
    let f = frequencies(&mass_hand(&probe), &stiffness_hand(&probe));
    [("below", 0.5 * f[0]), ("near", f[0]), ("above", 3.0 * f[5])]
        .into_iter()
        .map(|(label, hz)| {
            let w = 2.0 * PI * hz;
            let m = linear_variant(hz * 60.0, inertia);
            let expect = frf(&m, w, inertia);
            let got = simulated(&m, w);
            let err = (&got - &expect).norm() / expect.norm();
            eprintln!(
                "inertia {inertia}, {label} ({hz:.3} Hz): |q| = {:.3e}, relative error {err:.2e}",
                expect.norm()
            );
            (label.to_string(), err)
        })
        .collect()
}

#[test]
fn unbalance_response_matches_linear_frequency_response() {
    // The unbalance as a prescribed rotating force: the model is then exactly linear
    // time-invariant apart from the springs' and dampers' geometry (second order at 1e-4 m).
    // Measured (issue 19's machine: four dampers, hysteretic gasket): 2.3e-6 below, 4.0e-6
    // near, 2.8e-8 above the first resonance (the prescribed force lacks the weight's own load
    // stiffness that the hand K's equilibrium has: ~1e-6, amplified near resonance). Bounds:
    // about 4x the measured errors, so a regression of the linear path shows.
    for ((label, err), bound) in errors(false).into_iter().zip([1e-5, 2e-5, 1e-7]) {
        assert!(err < bound, "{label}: relative error {err:e} >= {bound:e}");
    }
}

#[test]
fn unbalance_inertia_adds_only_a_small_parametric_term() {
    // With the 1 g unbalance as a mass, M1 fluctuates at 2 W; fed by the W response it adds a
    // first harmonic of relative order m r^2 / I ~ 1e-5 (x the resonance's amplification),
    // which no LTI frequency response holds. Measured here: 1.8e-7, 3.7e-6, 3.4e-5.
    // Bounds: 2 to 6x the measured errors (the parametric term is the test's subject, its size
    // the claim).
    for ((label, err), bound) in errors(true).into_iter().zip([1e-6, 2e-5, 1e-4]) {
        assert!(err < bound, "{label}: relative error {err:e} >= {bound:e}");
    }
}
