//! The periodic response of a linear time-invariant scene at constant drum speed, in the
//! frequency domain: the same steady state as shooting (`periodic.rs`) when the scene is linear,
//! one complex solve per order instead of 2n + 1 integrations, and the form a harmonic FE
//! solution (CalculiX's `*STEADY STATE DYNAMICS`) is compared in. Set-up code: it may allocate.
//!
//! At constant speed Omega a scene without angle-dependent mass (rigid drum, unbalances as
//! prescribed forces), without friction and with linearised elements is
//! M q'' + C q' + K q = f(t): M = diag(M1, M2), K = -dh/dq and C = -dh/dq' (the one
//! linearisation, `linearise::Linearisation`: the exact force Jacobians), f the drive's loads. Order k of f, F_k = (2 / N) sum_n h(q0, 0, t_n) e^{-i k Omega t_n} over
//! [`MEAN_REVOLUTIONS`] drum revolutions (so the motor's order 11.25 falls on a bin too), gives
//! q(t) = q0 + Re[X_k e^{i k Omega t}] with (K - w^2 M + i w C) X_k = F_k, w = k Omega, and the
//! drum angle phi = Omega t (0 at t = 0). Sensors are linear in q, q', q'' when the scene
//! linearises its elements: a channel's amplitude is the sensor of Re X plus i times the sensor
//! of Im X.

use crate::linearise::Linearisation;
use crate::statics::MEAN_REVOLUTIONS;
use crate::system::{Interpreter, Mechanical};
use nalgebra::{Complex, DMatrix, DVector};
use std::f64::consts::PI;
use washdyn_model::equations::{Drive, Equations};

/// Samples per drum revolution of the load's DFT (orders up to 31 are resolved without
/// aliasing; the prescribed unbalance forces are pure sinusoids of their rotor's order).
const SAMPLES_PER_REV: usize = 64;

/// Why a scene has no frequency-domain steady state.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HarmonicError {
    /// The scene is not linear time-invariant at constant speed; the message names the effect.
    #[error("harmonic response: the scene `{scene}` is not linear time-invariant: {why}")]
    NotLti { scene: String, why: String },
    /// The drum stands still: no order has a frequency.
    #[error("harmonic response: the drum speed must be non-zero")]
    NoSpeed,
    /// An order that is not a multiple of 1 / MEAN_REVOLUTIONS has no DFT bin.
    #[error("harmonic response: order {0} is not a multiple of 1/{MEAN_REVOLUTIONS}")]
    Order(f64),
    /// K - w^2 M + i w C is singular (an undamped resonance at the order's frequency).
    #[error("harmonic response: singular dynamic stiffness at {0:.4} Hz (undamped resonance?)")]
    Singular(f64),
}

/// The linear machine at one drum speed: M, C, K (n x n) about the mean-load rest q0.
#[derive(Clone, Debug)]
pub struct Linear {
    /// Drum speed, rad/s.
    pub omega: f64,
    pub q0: DVector<f64>,
    pub m: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub k: DMatrix<f64>,
}

/// The steady response at one order: the state's and the sensor channels' complex amplitudes
/// (channel(t) = mean + Re[a e^{i order phi}]).
#[derive(Clone, Debug)]
pub struct Harmonic {
    pub order: f64,
    /// Excitation frequency, Hz.
    pub frequency_hz: f64,
    pub force: DVector<Complex<f64>>,
    pub q: DVector<Complex<f64>>,
    /// One per channel, in `Mechanical::channel_names` order.
    pub channels: Vec<Complex<f64>>,
}

/// The structural reasons a scene is not LTI at constant speed; `linearise` also checks
/// numerically that M1 and the Jacobians do not change over the period. Bolted joints
/// (`counterweights`) pass: with their slip held at 0 they are closed, sticking springs, linear
/// while the interface stays closed (the check at the rest refuses one the mean load opens);
/// the response is the small-motion one.
pub fn check_scene(eq: &Equations) -> Result<(), HarmonicError> {
    let why = if !eq.friction_dampers.is_empty() || !eq.damper_joints.is_empty() {
        Some("friction dampers (a nonlinear friction law); use linear dampers")
    } else if !eq.contacts.is_empty() {
        Some("`contact` (a contact force is nonlinear)")
    } else if eq.exact_geometry {
        Some("`element_geometry` (exact element kinematics and second-order sensors)")
    } else if eq.unbalance_inertia {
        Some("`unbalance_inertia` (an unbalance mass makes M1 depend on the drum angle)")
    } else if eq.elastic_drum().is_some() {
        Some("`elastic.drum` (the spinning drum's modes make M1 depend on the drum angle)")
    } else if eq.sensors.iter().any(|s| s.spin.is_some()) {
        Some("a sensor turning with the drum (its point moves with the drum angle)")
    } else {
        None
    };
    match why {
        Some(w) => Err(HarmonicError::NotLti {
            scene: eq.scene.name.clone(),
            why: w.into(),
        }),
        None => Ok(()),
    }
}

/// The drive at constant speed omega (phi = omega t).
fn drive(omega: f64, t: f64) -> Drive<f64> {
    Drive {
        phi: omega * t,
        omega,
        omega_dot: 0.0,
    }
}

/// Relative difference of two matrices (max entry over the larger max entry).
fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    let s = a.amax().max(b.amax()).max(f64::MIN_POSITIVE);
    (a - b).amax() / s
}

/// The sample times of the load's DFT at speed omega.
fn times(omega: f64) -> Vec<f64> {
    let n = MEAN_REVOLUTIONS as usize * SAMPLES_PER_REV;
    let span = MEAN_REVOLUTIONS * 2.0 * PI / omega;
    (0..n).map(|s| span * s as f64 / n as f64).collect()
}

/// M, C, K and the mean-load rest of `sys`'s scene at drum speed `omega` (rad/s), after checking
/// that the scene is LTI: structurally (`check_scene`), and numerically: M1 and the Jacobians
/// the same at three instants of the period (to 1e-9), the Jacobians the same at the rest
/// and at 0 (affine h).
pub fn linearise(sys: &Interpreter, omega: f64) -> Result<Linear, HarmonicError> {
    let eq = &sys.eq;
    check_scene(eq)?;
    if omega.abs() < 1e-9 {
        return Err(HarmonicError::NoSpeed);
    }
    let (n, n1) = (eq.layout.n(), eq.layout.n1);
    let not_lti = |why: String| HarmonicError::NotLti {
        scene: eq.scene.name.clone(),
        why,
    };
    let ts = times(omega);
    let third = [ts[0], ts[ts.len() / 3], ts[2 * ts.len() / 3]];
    let zero = vec![0.0; n];
    // The linearisation about 0 at the three instants: M1 the same, then K and C.
    let at = |t: f64, q: &[f64]| Linearisation::new(eq, sys.m2(), &drive(omega, t), q);
    let mut lins: Vec<Linearisation> = third.iter().map(|&t| at(t, &zero)).collect();
    let m1 = |l: &Linearisation| l.m.view((0, 0), (n1, n1)).into_owned();
    for l in &lins[1..] {
        let r = rel(&m1(l), &m1(&lins[0]));
        if r > 1e-12 {
            return Err(not_lti(format!(
                "M1 changes over the period (relative {r:.1e})"
            )));
        }
    }
    let (k0, c0) = (lins[0].k.clone(), lins[0].c.clone());
    for l in &lins[1..] {
        let r = rel(&l.k, &k0).max(rel(&l.c, &c0));
        if r > 1e-9 {
            return Err(not_lti(format!(
                "the stiffness or damping changes over the period (relative {r:.1e})"
            )));
        }
    }
    // The mean-load rest: mean over the DFT's samples of h(q0, 0, t) = 0, one Newton step from
    // 0 (exact for an affine h).
    let mut mean = DVector::<f64>::zeros(n);
    let mut m1s = vec![0.0; n1 * n1];
    let mut h = vec![0.0; n];
    for &t in &ts {
        eq.eval(&drive(omega, t), &zero, &zero, &mut m1s, &mut h);
        for i in 0..n {
            mean[i] += h[i] / ts.len() as f64;
        }
    }
    let q0 = k0
        .clone()
        .lu()
        .solve(&mean)
        .ok_or_else(|| not_lti("singular stiffness (a free rigid-body motion?)".into()))?;
    let lin = at(third[0], q0.as_slice());
    let r = rel(&lin.k, &k0).max(rel(&lin.c, &c0));
    if r > 1e-9 {
        return Err(not_lti(format!(
            "the stiffness or damping at the rest differs from that at 0 (relative {r:.1e}): \
             h is not affine"
        )));
    }
    // M1 depends on t only: M is the one checked above.
    let m = lins.swap_remove(0).m;
    let Linearisation { c, k, .. } = lin;
    Ok(Linear { omega, q0, m, c, k })
}

impl Linear {
    /// The complex amplitude of order `order` of h(q0, 0, t) over the DFT's samples.
    pub fn force(
        &self,
        eq: &Equations,
        order: f64,
    ) -> Result<DVector<Complex<f64>>, HarmonicError> {
        let bin = order * MEAN_REVOLUTIONS;
        if (bin - bin.round()).abs() > 1e-9 || bin < 0.5 {
            return Err(HarmonicError::Order(order));
        }
        let (n, n1) = (eq.layout.n(), eq.layout.n1);
        let ts = times(self.omega);
        let mut m1 = vec![0.0; n1 * n1];
        let mut h = vec![0.0; n];
        let zero = vec![0.0; n];
        let mut f = DVector::<Complex<f64>>::zeros(n);
        let scale = 2.0 / ts.len() as f64;
        for &t in &ts {
            eq.eval(
                &drive(self.omega, t),
                self.q0.as_slice(),
                &zero,
                &mut m1,
                &mut h,
            );
            let e = Complex::from_polar(scale, -order * self.omega * t);
            for i in 0..n {
                f[i] += e * h[i];
            }
        }
        Ok(f)
    }

    /// X = (K - w^2 M + i w C)^-1 F at w = order x omega.
    pub fn solve(
        &self,
        order: f64,
        f: &DVector<Complex<f64>>,
    ) -> Result<DVector<Complex<f64>>, HarmonicError> {
        let w = order * self.omega;
        let n = self.k.nrows();
        let a = DMatrix::<Complex<f64>>::from_fn(n, n, |i, j| {
            Complex::new(self.k[(i, j)] - w * w * self.m[(i, j)], w * self.c[(i, j)])
        });
        a.lu()
            .solve(f)
            .ok_or(HarmonicError::Singular(w / (2.0 * PI)))
    }

    /// Undamped eigenfrequencies (Hz, ascending) of M q'' + K q = 0, from the symmetric parts
    /// (M is positive definite; K symmetric at an equilibrium).
    pub fn eigenfrequencies(&self) -> Vec<f64> {
        let n = self.m.nrows();
        let ms = (&self.m + self.m.transpose()) * 0.5;
        let ks = (&self.k + self.k.transpose()) * 0.5;
        let Some(l) = ms.cholesky() else {
            return vec![f64::NAN; n];
        };
        let li = l.l().try_inverse().expect("Cholesky factor is invertible");
        let a = &li * ks * li.transpose();
        let a = (&a + a.transpose()) * 0.5;
        let mut f: Vec<f64> = a
            .symmetric_eigenvalues()
            .iter()
            .map(|l| l.max(0.0).sqrt() / (2.0 * PI))
            .collect();
        f.sort_by(f64::total_cmp);
        f
    }
}

/// Sensor channels of a complex state amplitude X at frequency w (rad/s): each sensor of the
/// real part plus i times the sensor of the imaginary part (sensors are linear and homogeneous
/// in q, q', q'' when the scene linearises its elements).
pub fn channels(eq: &Equations, x: &DVector<Complex<f64>>, w: f64) -> Vec<Complex<f64>> {
    let n = x.len();
    let part = |f: fn(&Complex<f64>) -> f64, s: Complex<f64>| -> Vec<f64> {
        x.iter().map(|v| f(&(v * s))).collect::<Vec<_>>()
    };
    let re = |c: &Complex<f64>| c.re;
    let im = |c: &Complex<f64>| c.im;
    let (one, iw, acc) = (
        Complex::new(1.0, 0.0),
        Complex::new(0.0, w),
        Complex::new(-w * w, 0.0),
    );
    let zero = vec![0.0; n];
    // No sensor turns with the drum (`check_scene`): the drive does not enter.
    let d = drive(w, 0.0);
    let mut out = Vec::with_capacity(eq.n_channels());
    for s in 0..eq.sensors.len() {
        let base = eq.sensor(s, &d, &zero, &zero, &zero);
        let r = eq.sensor(s, &d, &part(re, one), &part(re, iw), &part(re, acc));
        let i = eq.sensor(s, &d, &part(im, one), &part(im, iw), &part(im, acc));
        for a in 0..3 {
            out.push(Complex::new(r[a] - base[a], i[a] - base[a]));
        }
    }
    out
}

/// The steady response of `sys`'s scene at drum speed `omega` (rad/s) at each of `orders`.
pub fn response(
    sys: &Interpreter,
    omega: f64,
    orders: &[f64],
) -> Result<(Linear, Vec<Harmonic>), HarmonicError> {
    let lin = linearise(sys, omega)?;
    let mut out = Vec::new();
    for &k in orders {
        let f = lin.force(&sys.eq, k)?;
        let q = lin.solve(k, &f)?;
        let w = k * omega;
        out.push(Harmonic {
            order: k,
            frequency_hz: w / (2.0 * PI),
            channels: channels(&sys.eq, &q, w),
            force: f,
            q,
        });
    }
    Ok((lin, out))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::periodic::periodic_state;
    use crate::system::FirstOrder;
    use washdyn_model::ir::{LinearDamper, Model};
    use washdyn_ode::{Dopri5, Options, Solver, Stepper};

    /// The rigid reference machine at constant `rpm`, friction dampers replaced by linear ones
    /// (the rubber bearings left out), with gravity and preloads: an LTI scene whose rest is not 0.
    fn lti_rigid(rpm: f64, effects: &[&str]) -> Interpreter {
        let src = include_str!("../../models/data/reference.toml");
        let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/data");
        let mut m: Model =
            washdyn_model::ir::toml_file::load_str(src, "reference.toml", &data).unwrap();
        m.speed.table = vec![[0.0, rpm], [1000.0, rpm]];
        for d in std::mem::take(&mut m.friction_dampers) {
            m.dampers.push(LinearDamper {
                name: d.name,
                a: d.a,
                b: d.b,
                damping: 400.0,
            });
        }
        m.scenes.push(washdyn_model::ir::Scene {
            name: "lti".into(),
            effects: effects.iter().map(|s| s.to_string()).collect(),
            max_order: None,
            solver: None,
        });
        let scene = m.scene(Some("lti")).unwrap();
        Interpreter::new(&m, &scene)
    }

    /// Against the independent path: the periodic steady state by shooting (dopri5 at rtol
    /// 1e-11 over 4 revolutions), sampled over one period and transformed by a DFT, every
    /// channel's order-1 and order-11.25 (motor) amplitude and phase. Gyroscopic moments make
    /// C unsymmetric; gravity and the springs' preloads put the rest away from 0.
    #[test]
    fn harmonic_response_is_the_shooting_steady_state() {
        let effects = [
            "unbalance.drum",
            "unbalance.motor",
            "gasket_damping",
            "gyroscopic",
        ];
        for rpm in [400.0, 1130.0] {
            let sys = lti_rigid(rpm, &effects);
            let omega = rpm * PI / 30.0;
            let orders = [1.0, 11.25];
            let (lin, harm) = response(&sys, omega, &orders).unwrap();
            let n = lin.k.nrows();
            let mut fo = FirstOrder::new(sys);
            let y0 = periodic_state(&mut fo, 0.0).unwrap();
            let ts = times(omega);
            let mut s = Dopri5::new(
                2 * n,
                Options {
                    rtol: 1e-11,
                    atol: 1e-14,
                    ..Options::default()
                },
            );
            s.init(&mut fo, 0.0, &y0).unwrap();
            let nc = fo.sys.eq.n_channels();
            let mut dft = vec![vec![Complex::new(0.0, 0.0); nc]; orders.len()];
            let (mut qdd, mut ch) = (vec![0.0; n], vec![0.0; nc]);
            for &t in &ts {
                while s.t() < t {
                    s.step(&mut fo, t).unwrap();
                }
                let y = s.y().to_vec();
                fo.accelerations(t, &y[..n], &y[n..], &mut qdd);
                fo.sys.sensors(t, &y[..n], &y[n..], &qdd, &mut ch);
                for (o, k) in orders.iter().enumerate() {
                    let e = Complex::from_polar(2.0 / ts.len() as f64, -k * omega * t);
                    for c in 0..nc {
                        dft[o][c] += e * ch[c];
                    }
                }
            }
            for (o, h) in harm.iter().enumerate() {
                let top = h.channels.iter().fold(0.0f64, |m, a| m.max(a.norm()));
                let err = h
                    .channels
                    .iter()
                    .zip(&dft[o])
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).norm()))
                    / top;
                println!(
                    "{rpm} rpm, order {}: largest channel {top:.4e}, worst complex difference \
                     to shooting {err:.2e} of it",
                    h.order
                );
                // Measured: 1.1e-13, 1.2e-14 (order 1); 6.9e-12, 1.9e-12 (order 11.25).
                assert!(err < 3e-11, "order {}: {err:.2e}", h.order);
            }
        }
    }

    /// Scenes that are not LTI at constant speed are refused by name.
    #[test]
    fn nonlinear_scenes_are_refused() {
        let sys = lti_rigid(600.0, &["unbalance.drum", "unbalance_inertia"]);
        let e = response(&sys, 60.0, &[1.0]).unwrap_err();
        assert!(e.to_string().contains("unbalance_inertia"), "{e}");
        let sys = lti_rigid(600.0, &["unbalance.drum", "element_geometry"]);
        let e = response(&sys, 60.0, &[1.0]).unwrap_err();
        assert!(e.to_string().contains("element_geometry"), "{e}");
        let sys = lti_rigid(600.0, &["unbalance.drum"]);
        assert_eq!(
            response(&sys, 0.0, &[1.0]).unwrap_err(),
            HarmonicError::NoSpeed
        );
        assert!(matches!(
            response(&sys, 60.0, &[0.3]).unwrap_err(),
            HarmonicError::Order(_)
        ));
    }
}
