//! Why a scene is stiff: the largest eigenvalues of its Jacobian at the static rest of the
//! run-up's start (every velocity zero, so every friction damper on its steepest slope,
//! 2 Fmax s / pi), with the friction dampers and without them, and with the cabinet's
//! eigenmodes alone (its correction modes, the static give at the element loads, left out),
//! and the step dopri5's stability boundary (about 3.3 on the negative real axis) allows there.
//! A scene whose dampers carry a state (`friction_law.elasto_plastic`) is differenced. Each
//! scene is also shown on the other friction law (`friction_law.<law>` added).
//! `cargo run --release --example stiffness -- [SCENE]` (default `elastic`; docs/performance.md
//! quotes its output).

use washdyn_model::ir::{Effect, FrictionLaw};
use washdyn_ode::OdeSystem;
use washdyn_runtime::system::{FirstOrder, Interpreter};

/// The `count` largest eigenvalues (by magnitude) of the scene's Jacobian at rest.
fn spectrum(
    m: &washdyn_model::ir::Model,
    scene: &washdyn_model::ir::EffectSet,
    count: usize,
    explicit_part: bool,
) -> (usize, Vec<(f64, f64)>) {
    let mut sys = Interpreter::new(m, scene);
    let q = washdyn_runtime::statics::static_equilibrium(&mut sys, 0.0).expect("a rest position");
    let mut fo = FirstOrder::new(sys);
    let n = fo.dim();
    let mut y = vec![0.0; n];
    y[..q.len()].copy_from_slice(&q);
    let mut jac = vec![0.0; n * n];
    if !fo.jacobian(0.0, &y, &mut jac) {
        // Element states: central differences, column by column.
        let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
        for j in 0..n {
            let e = 1e-7 * y[j].abs().max(1e-3);
            let mut yp = y.clone();
            yp[j] += e;
            fo.rhs(0.0, &yp, &mut fp);
            yp[j] -= 2.0 * e;
            fo.rhs(0.0, &yp, &mut fm);
            for i in 0..n {
                jac[i * n + j] = (fp[i] - fm[i]) / (2.0 * e);
            }
        }
    }
    if explicit_part {
        // J - J_I: the IMEX split's explicit remainder (`ode/imex.rs`), J_I = [[0, I],
        // [-M1^-1 K, -M1^-1 D]] on the coordinates, 0 on the element states.
        let nq = fo.layout().n();
        let (mut m1, mut k, mut c) = (vec![0.0; nq * nq], vec![0.0; nq], vec![0.0; nq]);
        let n1 = fo
            .linear_part(0.0, &y, &mut m1, &mut k, &mut c)
            .expect("a linear part");
        let mut minv = nalgebra::DMatrix::<f64>::identity(nq, nq);
        let m1 = nalgebra::DMatrix::from_row_slice(n1, n1, &m1[..n1 * n1]);
        let m1i = m1.try_inverse().expect("M1 invertible");
        minv.view_mut((0, 0), (n1, n1)).copy_from(&m1i);
        for i in 0..nq {
            jac[i * n + nq + i] -= 1.0;
            for j in 0..nq {
                jac[(nq + i) * n + j] += minv[(i, j)] * k[j];
                jac[(nq + i) * n + nq + j] += minv[(i, j)] * c[j];
            }
        }
    }
    let mut ev: Vec<(f64, f64)> = nalgebra::DMatrix::from_row_slice(n, n, &jac)
        .complex_eigenvalues()
        .iter()
        .map(|e| (e.re, e.im))
        .collect();
    ev.sort_by(|a, b| b.0.hypot(b.1).total_cmp(&a.0.hypot(a.1)));
    ev.truncate(count);
    (n, ev)
}

fn main() {
    let name = std::env::args().nth(1).unwrap_or_else(|| "elastic".into());
    let m = washdyn_models::reference();
    let scene = m.scene(Some(&name)).unwrap_or_else(|e| panic!("{e}"));
    let mut other_law = scene.clone();
    let law = if other_law.friction_law(FrictionLaw::Arctan) == FrictionLaw::Arctan {
        FrictionLaw::ElastoPlastic
    } else {
        FrictionLaw::Arctan
    };
    other_law
        .effects
        .retain(|e| !matches!(e, Effect::FrictionLaw(_)));
    other_law.effects.push(Effect::FrictionLaw(law));
    let mut no_dampers = scene.clone();
    no_dampers
        .effects
        .retain(|e| e.name() != "friction_dampers");
    println!("| scene | state | largest eigenvalues, 1/s | dopri5's h there |");
    println!("|---|---|---|---|");
    let mut eigen_only = m.clone();
    for e in &mut eigen_only.elastic {
        if e.name == "cabinet" {
            e.data = e.data.as_ref().map(|d| d.without_correction());
        }
    }
    for (label, model, s, explicit) in [
        (name.clone(), &m, &scene, false),
        (
            format!("{name} on friction_law.{}", law.name()),
            &m,
            &other_law,
            false,
        ),
        (
            format!("{name} without friction_dampers"),
            &m,
            &no_dampers,
            false,
        ),
        (
            format!("{name}, the cabinet's eigenmodes alone"),
            &eigen_only,
            &scene,
            false,
        ),
        (
            format!("{name}, imex's explicit part (J - J_I)"),
            &m,
            &scene,
            true,
        ),
    ] {
        let (n, ev) = spectrum(model, s, 8, explicit);
        // A conjugate pair prints once, as re ± im i.
        let list: Vec<String> = ev
            .iter()
            .filter(|(_, im)| *im >= 0.0)
            .map(|(re, im)| {
                if *im > 0.0 {
                    format!("{re:.3e} ± {im:.3e}i")
                } else {
                    format!("{re:.3e}")
                }
            })
            .collect();
        let radius = ev[0].0.hypot(ev[0].1);
        println!(
            "| {label} | {n} | {} | {:.1} us |",
            list.join(", "),
            3.3 / radius * 1e6
        );
    }
}
