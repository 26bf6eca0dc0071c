//! The friction damper with its moving part as a body of its own (scene `damper_mass`, the seed
//! paper's "two independent bodies") against what no one here wrote into it:
//! - the part's own vibration on its bearings, the bodies held: the closed-form frequencies of
//!   a rigid rod on translational springs k (both ends across the rod, the rod's end along
//!   it) and rotary springs C (both ends);
//! - the limit of a light part on stiff bearings: the massless element (elements/
//!   friction_damper.rs, its own kinematics: rod tilt from the end points, transverse forces
//!   from the massless rod's moment balance), in its stiffness and damping at rest and in the
//!   drum's vertical motion over a run-up window.

use nalgebra::{DMatrix, SymmetricEigen};
use washdyn::commands::resolve_model;
use washdyn_model::equations::Modes;
use washdyn_model::ir::{BodyRef, Model};
use washdyn_ode::{AnySolver, Method, Options};
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::run::{Labels, RunOptions, Start, run};
use washdyn_runtime::system::{FirstOrder, Interpreter};

fn reference() -> Model {
    resolve_model("reference").unwrap().0
}

/// Each moving part's five frequencies, the tub and cabinet held (the part's block of
/// -dh/dq at rest, where the bearings are undeflected and the law is linear; its coordinates
/// are mass-normalised, so the block's eigenvalues are omega^2), equal the closed form: along
/// the rod k / m; across it, per plane, the 2 x 2 problem of a rod of mass m and inertia J on
/// springs k at distances l_a = c L and l_b = (1 - c) L from its CoG and two rotary springs C:
/// K = [[2k, k (l_b - l_a)], [k (l_b - l_a), k (l_a^2 + l_b^2) + 2 C]], M = diag(m, J).
#[test]
fn the_parts_frequencies_are_a_rigid_rod_on_its_bearings() {
    let model = reference();
    let (eq, hq, _) = crate::common::at_rest(&model, "damper_mass");
    let mut parts = 0;
    for body in &eq.bodies.list {
        let (BodyRef::DamperPart(i), Modes::Part(p)) = (body.id, &body.modes) else {
            continue;
        };
        parts += 1;
        let fd = &model.friction_dampers[i];
        let mp = fd.moving_part.as_ref().unwrap();
        let r = body.coordinates();
        let k = -hq.view((r.start, r.start), (r.len(), r.len())).into_owned();
        let mut got = SymmetricEigen::new(k).eigenvalues.as_slice().to_vec();
        got.sort_by(f64::total_cmp);

        let (kt, m, j, c) = (
            mp.translational_stiffness,
            mp.mass,
            mp.inertia,
            fd.bearing_stiffness,
        );
        let l: f64 = (0..3)
            .map(|x| (fd.b.point[x] - fd.a.point[x]).powi(2))
            .sum::<f64>()
            .sqrt();
        let (la, lb) = (mp.cog * l, (1.0 - mp.cog) * l);
        // det(K - w2 M) = 0 for the 2 x 2 plane problem.
        let (k11, k12, k22) = (2.0 * kt, kt * (lb - la), kt * (la * la + lb * lb) + 2.0 * c);
        let (a2, a1, a0) = (m * j, -(k11 * j + k22 * m), k11 * k22 - k12 * k12);
        let disc = (a1 * a1 - 4.0 * a2 * a0).sqrt();
        let (w_lo, w_hi) = ((-a1 - disc) / (2.0 * a2), (-a1 + disc) / (2.0 * a2));
        let mut want = vec![kt / m, w_lo, w_lo, w_hi, w_hi];
        want.sort_by(f64::total_cmp);
        for (g, w) in got.iter().zip(&want) {
            // Measured 2.4e-16 relative (round-off of the assembly).
            assert!(
                (g - w).abs() < 3e-15 * w,
                "{}: {got:?} vs {want:?}",
                fd.name
            );
        }
        let hz: Vec<f64> = want
            .iter()
            .map(|w| w.sqrt() / std::f64::consts::TAU)
            .collect();
        eprintln!("{} (part at {:?}): {hz:.1?} Hz", fd.name, p.cog);
    }
    assert_eq!(parts, 4);
}

/// The tub's rigid motion and the sensors over `window` of the reference run-up, from the
/// static start, rodas4 at a tight tolerance, sampled at 500 Hz.
fn simulate(model: &Model, scene: &str, window: (f64, f64), rtol: f64) -> MemorySink {
    let s = model.scene(Some(scene)).unwrap();
    let mut sys = FirstOrder::new(Interpreter::new(model, &s));
    let n = 2 * sys.layout().n();
    let opts = Options {
        rtol,
        atol: rtol * 1e-3,
        max_steps: 5_000_000,
        ..Options::default()
    };
    let mut solver = AnySolver::new(Method::Rodas4, n, opts);
    let mut sink = MemorySink::default();
    let ro = RunOptions {
        t_start: window.0,
        t_end: window.1,
        sample_rate: 500.0,
        start: Start::Static,
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

/// Largest difference of channel `name` after `settle` s over its largest value.
fn difference(a: &MemorySink, b: &MemorySink, name: &str, settle: f64) -> f64 {
    let skip = a
        .time
        .iter()
        .take_while(|t| **t < a.time[0] + settle)
        .count();
    let (x, y) = (
        a.column_by_name(name).unwrap(),
        b.column_by_name(name).unwrap(),
    );
    let scale = x[skip..].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let d = x[skip..]
        .iter()
        .zip(&y[skip..])
        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
    d / scale
}

/// The reference with each moving part's mass and inertia times eps, its bearings' stiffness
/// over eps (the part's frequencies grow as 1 / eps).
fn lighter(base: &Model, eps: f64) -> Model {
    let mut m = base.clone();
    for d in &mut m.friction_dampers {
        let p = d.moving_part.as_mut().unwrap();
        p.mass *= eps;
        p.inertia *= eps;
        p.translational_stiffness /= eps;
    }
    m
}

/// At rest, the tub's stiffness and damping through the dampers with their parts, the parts'
/// coordinates condensed out (statically: q_p = -K_pp^-1 K_pt q_t), are the massless
/// element's, to an error that falls as eps (the bearings' compliance): the same linear
/// machine by two derivations.
#[test]
fn a_stiff_part_condenses_to_the_massless_element() {
    let base = reference();
    let (eq0, k0, c0) = crate::common::at_rest(&base, "full");
    assert_eq!(
        eq0.layout.n(),
        6,
        "the scene full has the tub's six coordinates"
    );
    let mut errs = Vec::new();
    for eps in [1.0, 1e-2, 1e-4] {
        let (eq, k, c) = crate::common::at_rest(&lighter(&base, eps), "damper_mass");
        let n = eq.layout.n();
        let np = n - 6;
        let kpp = k.view((6, 6), (np, np)).into_owned();
        let kpt = k.view((6, 0), (np, 6)).into_owned();
        let mut t = DMatrix::zeros(n, 6);
        t.view_mut((0, 0), (6, 6)).fill_with_identity();
        t.view_mut((6, 0), (np, 6))
            .copy_from(&-kpp.lu().solve(&kpt).unwrap());
        let ke = t.transpose() * &k * &t;
        let ce = t.transpose() * &c * &t;
        let ek = (&ke - &k0).amax() / k0.amax();
        let ec = (&ce - &c0).amax() / c0.amax();
        eprintln!("eps {eps:e}: stiffness {ek:.2e}, damping {ec:.2e} of the largest entry");
        errs.push(ek.max(ec));
    }
    // Measured 8.9e-4, 8.9e-6, 8.9e-8 (the stiffness; the damping 6.2e-7 .. 6.3e-11):
    // proportional to eps.
    assert!(errs[0] < 5e-3, "{errs:?}");
    assert!(errs[1] < 5e-5 && errs[1] < errs[0] / 30.0, "{errs:?}");
    assert!(errs[2] < 5e-7 && errs[2] < errs[1] / 30.0, "{errs:?}");
}

/// Over the hold at 93 rpm, where the dampers stick and slip (3 s from the static start, the
/// first 2 s left to settle), the drum's vertical motion with the lighter, stiffer parts
/// approaches the massless element's as eps. (Its motion along x, normal to the dampers'
/// planes and 30 um here, does not: it stays about 30 % apart at eps 1e-2 and 1e-3, without
/// friction too, and 8 % with linearised element geometry, while the linear matrices at rest
/// above agree to 1e-7: not explained yet, so not held here.)
#[test]
fn a_light_part_on_stiff_bearings_moves_the_drum_as_the_massless_element() {
    let window = (10.0, 13.0);
    let base = reference();
    let massless = simulate(&base, "full", window, 1e-7);
    let mut diffs = Vec::new();
    for eps in [1.0, 1e-1, 1e-2] {
        let with_mass = simulate(&lighter(&base, eps), "damper_mass", window, 1e-7);
        let d = difference(&massless, &with_mass, "drum_front_uz", 2.0);
        eprintln!("eps {eps:e}: drum_front_uz differs by {d:.3e} of its peak");
        diffs.push(d);
    }
    // Measured 1.33, 0.133, 1.31e-2.
    assert!(
        diffs[1] < diffs[0] / 5.0 && diffs[2] < diffs[1] / 5.0,
        "{diffs:?}"
    );
    assert!(diffs[2] < 5e-2, "{diffs:?}");
}
