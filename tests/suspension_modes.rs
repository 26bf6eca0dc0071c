//! `washdyn modes`: the rigid modes of the suspended tub and each damper's stroke per mode,
//! against references outside `src/modes.rs`: the frequencies against M and K assembled by hand
//! from the IR (tests/common, the check of tests/rigid_physics.rs), the strokes against the
//! geometry directly, e_d . (u + alpha x s) at the tub end with the cabinet fixed, and the
//! normalisation against the door ring's points computed here.

use crate::common;

use common::*;
use washdyn::modes::rigid_modes;
use washdyn_model::ir::{Attach, BodyRef, FrictionDamper, Model};

/// The reference as the rigid machine without its unbalances (it hangs at q = 0).
fn balanced() -> Model {
    let mut m = washdyn_models::reference();
    m.unbalances.clear();
    m.elastic.clear();
    m
}

/// Issue 19's layout: four dampers from the tub at (+-0.18, +-0.18, 0.20) to the cabinet at
/// (+-0.18, +-0.27, 0.03) (DAMPER_1..4 of the plan's FE models), 75 N, bushings `kb`.
fn four_dampers(kb: f64) -> Vec<FrictionDamper> {
    let mut out = Vec::new();
    for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
        out.push(FrictionDamper {
            name: format!("damper_{}", out.len() + 1),
            a: Attach {
                body: BodyRef::Tub,
                point: [0.18 * sx, 0.18 * sy, 0.20],
            },
            b: Attach {
                body: BodyRef::Cabinet,
                point: [0.18 * sx, 0.27 * sy, 0.03],
            },
            f_max: 75.0,
            slope: 2000.0,
            bearing_stiffness: kb,
            bearing_damping: 0.05,
            moving_part: None,
            law: Default::default(),
            axial_stiffness: None,
            breakaway: None,
        });
    }
    out
}

fn hand_frequencies(m: &Model) -> Vec<f64> {
    frequencies(&mass_hand(m), &stiffness_hand(m))
}

#[test]
fn frequencies_match_the_hand_assembly_when_the_dampers_add_no_stiffness() {
    // Without dampers, and with four dampers whose friction is released and whose bushings
    // are 0: only springs (with the preloads' lateral and load stiffness) and the gasket.
    let mut m = balanced();
    m.friction_dampers.clear();
    let expect = hand_frequencies(&m);
    let mut worst: f64 = 0.0;
    for dampers in [Vec::new(), four_dampers(0.0)] {
        m.friction_dampers = dampers;
        let modes = rigid_modes(&m, Some("full")).unwrap();
        assert_eq!(modes.modes.len(), 6);
        for (md, f) in modes.modes.iter().zip(&expect) {
            worst = worst.max((md.frequency_hz / f - 1.0).abs());
        }
    }
    eprintln!("rigid modes {expect:.4?} Hz; worst relative difference {worst:e}");
    // Measured 4.6e-11 (central differences of h with a 1e-6 step).
    assert!(worst < 5e-10, "{worst:e}");
}

#[test]
fn strokes_are_the_axial_motion_of_each_damper_end_and_every_mode_strokes_the_new_layout() {
    let mut m = balanced();
    m.friction_dampers = four_dampers(20.0);
    let modes = rigid_modes(&m, Some("full")).unwrap();
    // The door ring: 8 points at x = 0.30, r = 0.25 about the drum axis (., 0, 0.45).
    let ring: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            let th = std::f64::consts::PI * k as f64 / 4.0;
            [0.30, 0.25 * th.sin(), 0.25 * th.cos()]
        })
        .collect();
    let disp = |x: &[f64; 6], s: [f64; 3]| {
        let (u, a) = (v3([x[0], x[1], x[2]]), v3([x[3], x[4], x[5]]));
        u + a.cross(&v3(s))
    };
    let mut worst: f64 = 0.0;
    let mut weakest = f64::INFINITY;
    for md in &modes.modes {
        let largest = ring
            .iter()
            .map(|p| disp(&md.shape, *p).norm())
            .fold(0.0, f64::max);
        assert!(
            (largest - 1.0).abs() < 1e-12,
            "normalised to the ring: {largest}"
        );
        for (d, st) in m.friction_dampers.iter().zip(&md.strokes) {
            let e = (v3(d.b.point) - v3(d.a.point)).normalize();
            let s = [d.a.point[0], d.a.point[1], d.a.point[2] - 0.45];
            let expect = -e.dot(&disp(&md.shape, s));
            worst = worst.max((st - expect).abs());
        }
        let most = md.strokes.iter().fold(0.0f64, |a, s| a.max(s.abs()));
        weakest = weakest.min(most);
    }
    eprintln!("strokes against the dampers' end motion: {worst:.1e}; weakest mode {weakest:.3}");
    // Measured 1.1e-16 (round-off).
    assert!(worst < 1e-15, "{worst:e}");
    // Every mode strokes some damper: measured at least 0.182 mm per mm of door ring.
    assert!(weakest > 0.1, "{weakest}");

    // The old layout (two dampers at x = 0, bushings 80 N m/rad) leaves one mode (yaw, roll
    // and lateral) nearly unstroked: measured 0.023 mm per mm on the FE inertia (0.006 on the
    // first estimate's).
    let mut m_old = balanced();
    m_old.friction_dampers = [1.0, -1.0]
        .iter()
        .map(|&sy| FrictionDamper {
            name: format!("old_{sy}"),
            a: Attach {
                body: BodyRef::Tub,
                point: [0.0, 0.18 * sy, 0.20],
            },
            b: Attach {
                body: BodyRef::Cabinet,
                point: [0.0, 0.24 * sy, 0.03],
            },
            f_max: 100.0,
            slope: 2000.0,
            bearing_stiffness: 80.0,
            bearing_damping: 0.05,
            moving_part: None,
            law: Default::default(),
            axial_stiffness: None,
            breakaway: None,
        })
        .collect();
    let old = rigid_modes(&m_old, Some("full")).unwrap();
    let weakest_old = old
        .modes
        .iter()
        .map(|md| md.strokes.iter().fold(0.0f64, |a, s| a.max(s.abs())))
        .fold(f64::INFINITY, f64::min);
    eprintln!("old layout: weakest mode {weakest_old:.3}");
    assert!(weakest_old < 0.05, "{weakest_old}");
    print!("{}", washdyn::modes::markdown(&modes));
}
