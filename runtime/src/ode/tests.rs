//! Cross-method tests on the problems in `problems/`. Every expected value comes from a closed
//! form, a published reference, or theory (convergence orders); none from our own output.
//! Run with `--nocapture` to see the accuracy and work each test reached.

use super::problems::{
    Blowup, Exponential, Harmonic, Hires, StiffDecay, VanDerPol, VanDerPolClassic,
};
use super::{AnySolver, Dopri5, Method, OdeError, OdeSystem, Options, Rk4, Sdirk4, Solver, Stats};

/// Steps `solver` from (t0, y0) to exactly t_end.
fn integrate<S: OdeSystem, V: Solver<S>>(
    solver: &mut V,
    sys: &mut S,
    t0: f64,
    y0: &[f64],
    t_end: f64,
) -> Result<Stats, OdeError> {
    solver.init(sys, t0, y0)?;
    while solver.t() < t_end {
        solver.step(sys, t_end)?;
    }
    assert_eq!(solver.t(), t_end);
    Ok(solver.stats())
}

fn tols(rtol: f64, atol: f64) -> Options {
    Options {
        rtol,
        atol,
        ..Options::default()
    }
}

/// Options that pin an adaptive method to the fixed step h: h0 = h_max = h and a tolerance so
/// loose that no step is rejected. Used to measure the order of the underlying formula.
fn pinned(h: f64) -> Options {
    Options {
        rtol: 1.0,
        atol: 1.0,
        h0: h,
        h_max: h,
        ..Options::default()
    }
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Observed order from errors at step h and h/2.
fn order(e_h: f64, e_half: f64) -> f64 {
    (e_h / e_half).log2()
}

/// Global error at t = 2 of y' = -y (exact e^-2) with fixed steps h and h/2: the error ratio
/// must show the classical orders, RK4 4, DOPRI5 5, SDIRK4 4 (theory: global error O(h^p)).
#[test]
fn observed_orders_on_the_test_equation() {
    let mut sys = Exponential { lambda: -1.0 };
    let exact = sys.exact(0.0, 1.0, 2.0);
    let run = |m: Method, h: f64, sys: &mut Exponential| {
        let opts = if m == Method::Rk4 {
            Options {
                h0: h,
                ..Options::default()
            }
        } else {
            pinned(h)
        };
        let mut s = AnySolver::new(m, 1, opts);
        let st = integrate(&mut s, sys, 0.0, &[1.0], 2.0).unwrap();
        assert_eq!(st.rejected_steps, 0);
        assert_eq!(st.steps, (2.0 / h).round() as u64);
        (s.y()[0] - exact).abs()
    };
    for (m, h, p) in [
        (Method::Rk4, 0.1, 4.0),
        (Method::Dopri5, 0.2, 5.0),
        (Method::Sdirk4, 0.1, 4.0),
    ] {
        let e1 = run(m, h, &mut sys);
        let e2 = run(m, h / 2.0, &mut sys);
        let e3 = run(m, h / 4.0, &mut sys);
        let (p1, p2) = (order(e1, e2), order(e2, e3));
        println!("{m}: errors {e1:.3e} {e2:.3e} {e3:.3e}, orders {p1:.2} {p2:.2}");
        assert!(
            (p2 - p).abs() < 0.25,
            "{m}: observed order {p2}, expected {p}"
        );
    }
}

/// Same on the harmonic oscillator (a 2x2 system with complex eigenvalues, the basic
/// vibration), exact solution x = cos(t), over one period t = 2 pi.
#[test]
fn observed_orders_on_the_harmonic_oscillator() {
    let mut sys = Harmonic { omega: 1.0 };
    let t_end = 2.0 * std::f64::consts::PI;
    let exact = sys.exact([1.0, 0.0], t_end);
    for (m, n, p) in [
        (Method::Rk4, 40.0, 4.0),
        (Method::Dopri5, 20.0, 5.0),
        (Method::Sdirk4, 40.0, 4.0),
    ] {
        let mut errs = [0.0; 3];
        for (k, e) in errs.iter_mut().enumerate() {
            let h = t_end / (n * 2f64.powi(k as i32));
            let opts = if m == Method::Rk4 {
                Options {
                    h0: h,
                    ..Options::default()
                }
            } else {
                pinned(h)
            };
            let mut s = AnySolver::new(m, 2, opts);
            integrate(&mut s, &mut sys, 0.0, &[1.0, 0.0], t_end).unwrap();
            *e = max_abs_diff(s.y(), &exact);
        }
        let p2 = order(errs[1], errs[2]);
        println!(
            "{m}: errors {:.3e} {:.3e} {:.3e}, order {p2:.2}",
            errs[0], errs[1], errs[2]
        );
        assert!(
            (p2 - p).abs() < 0.25,
            "{m}: observed order {p2}, expected {p}"
        );
    }
}

/// Dense output inside one step of size h, at its midpoint, against the exact solution of the
/// harmonic oscillator. Theory: Hairer's continuous extension of DOPRI5 has order 4, so the
/// local interpolation error is O(h^5) (ratio 32 when halving h); cubic Hermite interpolation
/// (RK4, SDIRK4) has error O(h^4) (ratio 16).
#[test]
fn dense_output_order_at_the_midpoint() {
    let mut sys = Harmonic { omega: 1.0 };
    let y0 = [1.0, 0.5];
    for (m, p) in [
        (Method::Rk4, 4.0),
        (Method::Dopri5, 5.0),
        (Method::Sdirk4, 4.0),
    ] {
        let mut errs = [0.0; 3];
        for (k, e) in errs.iter_mut().enumerate() {
            let h = 0.4 / 2f64.powi(k as i32);
            let opts = if m == Method::Rk4 {
                Options {
                    h0: h,
                    ..Options::default()
                }
            } else {
                pinned(h)
            };
            let mut s = AnySolver::new(m, 2, opts);
            s.init(&mut sys, 0.0, &y0).unwrap();
            s.step(&mut sys, 10.0).unwrap();
            assert_eq!(s.t(), h);
            let mut out = [0.0; 2];
            s.dense_output(0.5 * h, &mut out);
            *e = max_abs_diff(&out, &sys.exact(y0, 0.5 * h));
            // The interpolant reproduces the step's end points.
            s.dense_output(h, &mut out);
            assert!(max_abs_diff(&out, s.y()) < 1e-15);
            s.dense_output(0.0, &mut out);
            assert!(max_abs_diff(&out, &y0) < 1e-15);
        }
        let p2 = order(errs[1], errs[2]);
        println!(
            "{m}: midpoint errors {:.3e} {:.3e} {:.3e}, local order {p2:.2}",
            errs[0], errs[1], errs[2]
        );
        assert!(
            (p2 - p).abs() < 0.3,
            "{m}: dense output order {p2}, expected {p}"
        );
    }
}

/// Dense output over a whole adaptive run: at every step midpoint the interpolant of DOPRI5
/// (rtol 1e-8) and SDIRK4 (rtol 1e-8) stays within 1e-6 of cos/sin (the exact solution).
#[test]
fn dense_output_along_an_adaptive_run() {
    let mut sys = Harmonic { omega: 3.0 };
    let y0 = [1.0, 0.0];
    for m in [Method::Dopri5, Method::Sdirk4] {
        let mut s = AnySolver::new(m, 2, tols(1e-8, 1e-10));
        s.init(&mut sys, 0.0, &y0).unwrap();
        let mut worst: f64 = 0.0;
        let mut out = [0.0; 2];
        while s.t() < 5.0 {
            s.step(&mut sys, 5.0).unwrap();
            let tm = 0.5 * (s.t_prev() + s.t());
            s.dense_output(tm, &mut out);
            worst = worst.max(max_abs_diff(&out, &sys.exact(y0, tm)));
        }
        let st = s.stats();
        println!(
            "{m}: worst midpoint error {worst:.2e} in {} steps",
            st.steps
        );
        assert!(worst < 1e-6, "{m}: {worst}");
    }
}

/// Tolerance proportionality on the Van der Pol limit cycle (mu = 1): starting on the periodic
/// orbit through (2.00861986087484313650940188, 0), period T = 6.6632868593231301896997
/// (values used with Hairer, Norsett & Wanner's Van der Pol example; T also published by
/// Amore, arXiv:2111.12198), the solution returns to its start after one period.
/// DOPRI5 must meet the tolerance, and its error must fall with the number of steps like
/// N^-5 (log-log slope between -6.5 and -3.5, tolerances 1e-6 to 1e-10).
#[test]
fn dopri5_van_der_pol_limit_cycle() {
    let mut sys = VanDerPolClassic { mu: 1.0 };
    let y0 = [VanDerPolClassic::MU1_AMPLITUDE, 0.0];
    let mut pts = Vec::new();
    for rtol in [1e-6, 1e-8, 1e-10] {
        let mut s = Dopri5::new(2, tols(rtol, rtol));
        let st = integrate(&mut s, &mut sys, 0.0, &y0, VanDerPolClassic::MU1_PERIOD).unwrap();
        let err = max_abs_diff(s.y(), &y0);
        println!(
            "dopri5 vdp mu=1 rtol {rtol:.0e}: error {err:.2e}, {} steps, {} rejected, {} f evals",
            st.steps, st.rejected_steps, st.rhs_evals
        );
        assert!(err < 200.0 * rtol, "rtol {rtol}: error {err}");
        pts.push((st.steps as f64, err));
    }
    let slope = (pts[2].1 / pts[0].1).ln() / (pts[2].0 / pts[0].0).ln();
    println!("error vs steps slope {slope:.2}");
    assert!((-6.5..-3.5).contains(&slope), "slope {slope}");
}

/// SDIRK4 on the same limit cycle: must meet the tolerance and show order ~4 in a tolerance
/// sweep (error vs steps slope between -5.5 and -2.8).
#[test]
fn sdirk4_van_der_pol_limit_cycle() {
    let mut sys = VanDerPolClassic { mu: 1.0 };
    let y0 = [VanDerPolClassic::MU1_AMPLITUDE, 0.0];
    let mut pts = Vec::new();
    for rtol in [1e-5, 1e-7, 1e-9] {
        let mut s = Sdirk4::new(2, tols(rtol, rtol));
        let st = integrate(&mut s, &mut sys, 0.0, &y0, VanDerPolClassic::MU1_PERIOD).unwrap();
        let err = max_abs_diff(s.y(), &y0);
        println!("sdirk4 vdp mu=1 rtol {rtol:.0e}: error {err:.2e}, {st:?}");
        assert!(err < 200.0 * rtol, "rtol {rtol}: error {err}");
        pts.push((st.steps as f64, err));
    }
    let slope = (pts[2].1 / pts[0].1).ln() / (pts[2].0 / pts[0].0).ln();
    println!("error vs steps slope {slope:.2}");
    assert!((-5.5..-2.8).contains(&slope), "slope {slope}");
}

/// Mildly stiff Van der Pol, mu = 10, on [0, 20] from (2, 0). No published value at hand, so
/// this is a cross-check only: DOPRI5 at rtol 1e-9 and SDIRK4 at rtol 1e-11 must agree to 1e-6.
#[test]
fn van_der_pol_mu10_dopri5_agrees_with_sdirk4() {
    let mut sys = VanDerPolClassic { mu: 10.0 };
    let y0 = [2.0, 0.0];
    let mut a = Dopri5::new(2, tols(1e-9, 1e-9));
    let sa = integrate(&mut a, &mut sys, 0.0, &y0, 20.0).unwrap();
    let mut b = Sdirk4::new(2, tols(1e-11, 1e-11));
    let sb = integrate(&mut b, &mut sys, 0.0, &y0, 20.0).unwrap();
    let d = max_abs_diff(a.y(), b.y());
    println!(
        "mu=10: dopri5 {:?} ({} steps), sdirk4 {:?} ({} steps), diff {d:.2e}",
        a.y(),
        sa.steps,
        b.y(),
        sb.steps
    );
    assert!(d < 1e-6, "{d}");
}
