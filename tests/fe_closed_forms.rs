//! The FE chain against closed forms, through CalculiX itself: deck written by code, solved by
//! ccx, frequencies read back. Without ccx the tests skip with a message, except under CI
//! (`CI=true`), where they fail: CI installs calculix-ccx.

use crate::common;
use common::have_ccx;

use std::f64::consts::PI;
use washdyn_fe::bodies::test_decks::{cantilever, plate_simply_supported};
use washdyn_fe::ccx;

fn solve(deck: &washdyn_fe::deck::Deck, dir: &std::path::Path, name: &str) -> Vec<f64> {
    let p = dir.join(format!("{name}.inp"));
    std::fs::write(&p, deck.text()).unwrap();
    let run = ccx::run(&p).unwrap_or_else(|e| panic!("{e}"));
    ccx::frequencies(&std::fs::read_to_string(run.dat()).unwrap())
}

#[test]
fn cantilever_bending_frequencies_converge_to_euler_bernoulli() {
    if !have_ccx() {
        return;
    }
    // Steel, 1 m, 20 mm square: f_i = (beta_i L)^2 / (2 pi L^2) sqrt(E I / (rho A)) with
    // beta L = 1.8751, 4.6941, 7.8548 (Euler-Bernoulli; e.g. Blevins, Formulas for Natural
    // Frequency and Mode Shape, table 8-1). The section is square, so each bending frequency
    // comes twice (y and z): ccx modes 1, 3, 5 are the three.
    let (l, a, e, rho): (f64, f64, f64, f64) = (1.0, 0.02, 210e9, 7850.0);
    let ei = e * a.powi(4) / 12.0;
    let ra = rho * a * a;
    let exact: Vec<f64> = [1.875_104_068_7, 4.694_091_132_9, 7.854_757_438_2]
        .iter()
        .map(|b: &f64| b * b / (2.0 * PI * l * l) * (ei / ra).sqrt())
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let mut errors = Vec::new();
    for n in [5, 10, 40] {
        let f = solve(&cantilever(l, a, n, 6), dir.path(), &format!("beam{n}"));
        assert_eq!(f.len(), 6, "{f:?}");
        for pair in f.chunks(2) {
            // The two bending planes agree (square section).
            assert!((pair[0] - pair[1]).abs() < 1e-6 * pair[0], "{f:?}");
        }
        let err: Vec<f64> = (0..3).map(|i| (f[2 * i] - exact[i]) / exact[i]).collect();
        eprintln!(
            "{n} elements: {:?} Hz, relative errors {err:?}",
            [f[0], f[2], f[4]]
        );
        errors.push(err);
    }
    for i in 0..3 {
        // Refinement shrinks the error of every mode ...
        assert!(
            errors[2][i].abs() < errors[0][i].abs(),
            "mode {}: {errors:?}",
            i + 1
        );
        // ... to the beam theory's own difference: ccx's B32 is a shear-deformable beam with
        // rotary inertia (Timoshenko), which lowers mode i by about (beta_i r)^2 relative
        // (r = a / sqrt(12) / L = 0.0058: 1e-4, 7e-4, 2e-3) under Euler-Bernoulli: 0.5 % holds
        // all three with the discretisation error of 40 elements. Measured at 40 elements:
        // 1.7e-3, 1.5e-4, -2.4e-3.
        assert!(errors[2][i].abs() < 5e-3, "mode {}: {errors:?}", i + 1);
    }
}

#[test]
fn errors_in_a_deck_name_their_line() {
    if !have_ccx() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // A misspelt card: ccx warns, ignores it and would go on without density.
    let text = cantilever(1.0, 0.02, 4, 2)
        .text()
        .replace("*DENSITY", "*DENSTY");
    let line = text.lines().position(|l| l == "*DENSTY").unwrap() + 1;
    let p = dir.path().join("bad.inp");
    std::fs::write(&p, &text).unwrap();
    let e = ccx::run(&p).unwrap_err().to_string();
    assert!(e.contains(&format!("bad.inp:{line}: ccx")), "{e}");
    assert!(e.contains("*DENSTY"), "{e}");
    // An unknown node in *BOUNDARY.
    let text = cantilever(1.0, 0.02, 4, 2)
        .text()
        .replace("CLAMP, 1, 6", "999, 1, 6");
    let line = text.lines().position(|l| l == "999, 1, 6").unwrap() + 1;
    std::fs::write(&p, &text).unwrap();
    let e = ccx::run(&p).unwrap_err().to_string();
    assert!(e.contains(&format!("bad.inp:{line}: ccx")), "{e}");
}

#[test]
fn missing_ccx_says_how_to_install_it() {
    // Points WASHDYN_CCX at a program that does not exist (this test's own environment only:
    // tests run in threads, so use a child process).
    if std::env::var("WASHDYN_FE_CHILD").is_ok() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.inp");
        std::fs::write(&p, "*NODE\n").unwrap();
        let e = ccx::run(&p).unwrap_err().to_string();
        assert!(e.contains("apt-get install calculix-ccx"), "{e}");
        return;
    }
    let me = std::env::current_exe().unwrap();
    let st = std::process::Command::new(me)
        .args(["missing_ccx_says_how_to_install_it", "--exact"])
        .env("WASHDYN_FE_CHILD", "1")
        .env("WASHDYN_CCX", "/nonexistent/ccx")
        .status()
        .unwrap();
    assert!(st.success());
}

#[test]
fn simply_supported_plate_converges_to_leissa() {
    if !have_ccx() {
        return;
    }
    // 0.6 x 0.4 m steel plate, 2 mm (a cabinet panel's scale): the six lowest f_mn of Leissa's
    // closed form (NASA SP-160, 1969, section 4.1).
    let (a, b, h, e, nu, rho): (f64, f64, f64, f64, f64, f64) =
        (0.6, 0.4, 0.002, 210e9, 0.3, 7850.0);
    let d = e * h.powi(3) / (12.0 * (1.0 - nu * nu));
    let mut exact: Vec<f64> = (1..=4)
        .flat_map(|m| (1..=4).map(move |n| (m as f64, n as f64)))
        .map(|(m, n)| PI / 2.0 * (m * m / (a * a) + n * n / (b * b)) * (d / (rho * h)).sqrt())
        .collect();
    exact.sort_by(f64::total_cmp);
    let dir = tempfile::tempdir().unwrap();
    let mut worst = Vec::new();
    for (nx, ny) in [(6, 4), (24, 16)] {
        let f = solve(
            &plate_simply_supported(a, b, h, nx, ny, 6),
            dir.path(),
            &format!("plate{nx}"),
        );
        assert_eq!(f.len(), 6, "{f:?}");
        let err = f
            .iter()
            .zip(&exact)
            .map(|(f, x)| ((f - x) / x).abs())
            .fold(0.0f64, f64::max);
        eprintln!(
            "{nx} x {ny} S8R: {f:?} Hz against {:?}: worst {err:.2e}",
            &exact[..6]
        );
        worst.push(err);
    }
    // Refinement shrinks the worst error (measured 0.21 -> 1.9e-3); what is left at 24 x 16 is
    // the shell element's own (S8R: reduced integration, transverse shear): 0.5 % bounds it.
    assert!(worst[1] < worst[0] / 10.0, "{worst:?}");
    assert!(worst[1] < 5e-3, "{worst:?}");

    // The mode shapes as imported from the .frd: frequencies as in the .dat, and mode 1 is
    // Leissa's sin(pi x / a) sin(pi y / b) (modal assurance criterion against it; the bound
    // leaves 1e-4 for the discretisation).
    let frd =
        washdyn_fe::frd::parse(&std::fs::read_to_string(dir.path().join("plate24.frd")).unwrap())
            .unwrap();
    let dat = ccx::frequencies(&std::fs::read_to_string(dir.path().join("plate24.dat")).unwrap());
    assert_eq!(frd.modes.len(), 6);
    for (m, f) in frd.modes.iter().zip(&dat) {
        assert!(
            (m.frequency_hz - f).abs() < 1e-6 * f,
            "{} vs {f}",
            m.frequency_hz
        );
    }
    let pos: std::collections::HashMap<usize, [f64; 3]> = frd.nodes.iter().copied().collect();
    let (mut uv, mut uu, mut vv) = (0.0, 0.0, 0.0);
    for (id, d) in &frd.modes[0].disp {
        let p = pos[id];
        let v = (PI * p[0] / a).sin() * (PI * p[1] / b).sin();
        uv += d[2] * v;
        uu += d[2] * d[2];
        vv += v * v;
    }
    let mac = uv * uv / (uu * vv);
    eprintln!("mode 1 against sin sin: MAC {mac:.8}");
    assert!(mac > 1.0 - 1e-4, "MAC {mac}");
}
