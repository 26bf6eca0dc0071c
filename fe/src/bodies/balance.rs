//! Closing the mass balance: tub + drum + motor rotor must reproduce the suspended body of
//! reference-machine.md (55 kg, CoG (0, 0, 0.45), inertia diag(2.6, 2.3, 2.3) kg m^2 about the
//! CoG). The counterweights' thicknesses are solved for (Gauss-Newton on the consistent mass
//! properties of the meshes), over a small set of counterweight layouts; the bearing unit
//! (carrier plate and housing) is sized for stiffness, not for balance, and stays as it is.

use super::drum::Drum;
use super::tub::Tub;
use crate::lumping::{MassProps, consistent_mass_props};

/// The suspended body of reference-machine.md.
pub const TARGET: MassProps = MassProps {
    mass: 55.0,
    cog: [0.0, 0.0, 0.45],
    inertia: [[2.6, 0.0, 0.0], [0.0, 2.3, 0.0], [0.0, 0.0, 2.3]],
};

/// The motor rotor: not an FE model, a rigid 1.5 kg cylinder on the motor axis (G 6.3 estimate
/// of reference-machine.md), polar inertia 6.8e-4 kg m^2.
pub fn rotor() -> MassProps {
    MassProps {
        mass: 1.5,
        cog: [-0.05, 0.0, 0.18],
        inertia: [[6.8e-4, 0.0, 0.0], [0.0, 8.0e-4, 0.0], [0.0, 0.0, 8.0e-4]],
    }
}

/// Relative deviations from the target: mass, CoG (per 0.45 m, the CoG height), inertia
/// diagonal and products (per the target's diagonal).
pub fn deviations(p: &MassProps) -> [f64; 10] {
    let t = &TARGET;
    let l = t.cog[2];
    [
        (p.mass - t.mass) / t.mass,
        (p.cog[0] - t.cog[0]) / l,
        (p.cog[1] - t.cog[1]) / l,
        (p.cog[2] - t.cog[2]) / l,
        (p.inertia[0][0] - t.inertia[0][0]) / t.inertia[0][0],
        (p.inertia[1][1] - t.inertia[1][1]) / t.inertia[1][1],
        (p.inertia[2][2] - t.inertia[2][2]) / t.inertia[2][2],
        p.inertia[0][1] / t.inertia[1][1],
        p.inertia[0][2] / t.inertia[1][1],
        p.inertia[1][2] / t.inertia[1][1],
    ]
}

/// Tub + drum + rotor.
pub fn suspended(tub: &Tub, drum: &MassProps) -> MassProps {
    consistent_mass_props(&tub.mesh())
        .combine(drum)
        .combine(&rotor())
}

const NP: usize = 3;

fn apply(t: &Tub, p: &[f64; NP]) -> Tub {
    Tub {
        top_thickness: p[0],
        bottom_thickness: p[1],
        collar_thickness: p[2],
        ..t.clone()
    }
}

/// Mass and CoG carry the springs' preload design (the body must hang at rest where the rigid
/// model hangs): weighted 100 times the inertia terms.
const WEIGHTS: [f64; 10] = [100.0, 100.0, 100.0, 100.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0];

fn weighted(d: &[f64; 10]) -> [f64; 10] {
    std::array::from_fn(|i| d[i] * WEIGHTS[i])
}

fn cost(d: &[f64; 10]) -> f64 {
    weighted(d).iter().map(|v| v * v).sum()
}

/// Gauss-Newton on the continuous sizes of one layout; returns the sizes and deviations.
fn solve(layout: &Tub, drum: &MassProps) -> ([f64; NP], [f64; 10]) {
    let lo = [0.01, 0.01, 0.0];
    let hi = [0.15, 0.15, 0.15];
    let mut p = [
        layout.top_thickness,
        layout.bottom_thickness,
        layout.collar_thickness.max(0.005),
    ];
    let mut d = deviations(&suspended(&apply(layout, &p), drum));
    for _ in 0..15 {
        let mut jac = [[0.0; NP]; 10];
        for k in 0..NP {
            let mut q = p;
            q[k] += 1e-4;
            let dk = deviations(&suspended(&apply(layout, &q), drum));
            for i in 0..10 {
                jac[i][k] = WEIGHTS[i] * (dk[i] - d[i]) / 1e-4;
            }
        }
        let dw = weighted(&d);
        // Normal equations with a little damping.
        let mut a = nalgebra::SMatrix::<f64, NP, NP>::zeros();
        let mut b = nalgebra::SVector::<f64, NP>::zeros();
        for i in 0..10 {
            for k in 0..NP {
                b[k] -= jac[i][k] * dw[i];
                for l in 0..NP {
                    a[(k, l)] += jac[i][k] * jac[i][l];
                }
            }
        }
        for k in 0..NP {
            a[(k, k)] *= 1.0 + 1e-3;
        }
        let Some(step) = a.lu().solve(&b) else { break };
        let mut q = p;
        for k in 0..NP {
            q[k] = (p[k] + step[k]).clamp(lo[k], hi[k]);
        }
        let dq = deviations(&suspended(&apply(layout, &q), drum));
        if cost(&dq) >= cost(&d) {
            break;
        }
        p = q;
        d = dq;
    }
    (p, d)
}

/// Search the counterweight layouts (angular span, axial range) and size each; the best tub.
pub fn balanced(drum: &Drum) -> (Tub, [f64; 10]) {
    let dp = consistent_mass_props(&drum.mesh());
    let base = Tub::default();
    let mut best: Option<(Tub, [f64; 10])> = None;
    for span in (3..=12).step_by(3) {
        for top in [(0, 12), (4, 12), (8, 12)] {
            for bottom in [(0, 12), (4, 12), (0, 8)] {
                let layout = Tub {
                    top_half_span: span,
                    bottom_half_span: span,
                    top_axial: top,
                    bottom_axial: bottom,
                    ..base.clone()
                };
                let (p, d) = solve(&layout, &dp);
                if best.as_ref().is_none_or(|(_, bd)| cost(&d) < cost(bd)) {
                    best = Some((apply(&layout, &p), d));
                }
            }
        }
    }
    best.expect("at least one layout")
}
