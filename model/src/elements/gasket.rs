//! Door gasket: 6-D linear spring-damper with full (non-diagonal) K and D in global axes at the
//! gasket point, zero force in the reference position (seed paper: K from a static FE analysis
//! of the rubber, D fitted). Rubber bellows damp hysteretically (a loss factor eta nearly
//! independent of frequency, ~0.2), which viscous D cannot: D = 0.01 s K gave eta 0.28 at
//! 4.5 Hz but 1.46 at 23 Hz. The hysteretic part enters the time domain as the equivalent
//! viscous damping at the frequency of the dominant excitation, drum order 1 (Nastran's W4 idea
//! with a reference frequency that tracks the drum speed): D_h = S K S / max(|Omega|, floor),
//! S = diag(sqrt(eta)), so a harmonic motion at order 1 dissipates pi x^T S K S x per cycle,
//! pi eta_i K_ii X^2 along one direction: the loss factor's definition.

use super::Element;
use crate::equations::{Drive, Marker, MarkerDef, Wrench};
use crate::geom::V;
use crate::ir;
use crate::scalar::Scalar;

/// Lowest reference frequency of the hysteretic damping, rad/s (1 Hz): near the lowest rigid
/// mode of a suspended tub (the reference's is 1.06 Hz, the springs' pendulum). Below it drum
/// order 1 excites nothing; the tub's free motion (a start from rest, the first seconds of a
/// run-up) rings at its rigid modes, 1-5 Hz, where the floor gives a loss factor between eta
/// and 5 eta, instead of an infinite damping at standstill.
pub const OMEGA_FLOOR: f64 = 2.0 * std::f64::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct Gasket {
    pub name: String,
    pub a: MarkerDef,
    pub b: MarkerDef,
    pub stiffness: [[f64; 6]; 6],
    /// Viscous D; `None` when the scene leaves gasket damping out or the gasket has none.
    pub damping: Option<[[f64; 6]; 6]>,
    /// Hysteretic S K S (`ir::Gasket::hysteretic_damping`); `None` as for `damping`.
    pub hysteretic: Option<[[f64; 6]; 6]>,
}

impl Gasket {
    pub fn new(g: &ir::Gasket, a: MarkerDef, b: MarkerDef, with_damping: bool) -> Self {
        let nonzero = |m: [[f64; 6]; 6]| m.iter().flatten().any(|v| *v != 0.0).then_some(m);
        Gasket {
            name: g.name.clone(),
            a,
            b,
            stiffness: g.stiffness,
            damping: nonzero(g.damping).filter(|_| with_damping),
            hysteretic: nonzero(g.hysteretic_damping()).filter(|_| with_damping),
        }
    }
}

/// max(|omega|, OMEGA_FLOOR) without a branch on the value (the derivation is traced):
/// (a + f + |a - f|) / 2 with |x| = sqrt(x^2), which IEEE arithmetic returns exactly.
pub fn reference_speed<T: Scalar>(omega: T) -> T {
    let a = (omega * omega).sqrt();
    let d = a - OMEGA_FLOOR;
    (a + OMEGA_FLOOR + (d * d).sqrt()) * 0.5
}

impl Element for Gasket {
    const ELASTIC: bool = true;
    const DISSIPATIVE: bool = true;

    fn name(&self) -> &str {
        &self.name
    }

    fn markers(&self) -> (&MarkerDef, &MarkerDef) {
        (&self.a, &self.b)
    }

    /// Wrench on a: -K x - (D + S K S / Omega_ref) x', x = displacement and rotation of a
    /// relative to b. Linear in either geometry.
    fn wrenches<T: Scalar>(
        &self,
        a: &Marker<T>,
        b: &Marker<T>,
        _exact: bool,
        d: &Drive<T>,
        _z: &[T],
    ) -> (Wrench<T>, Wrench<T>) {
        let dx = a.pos - b.pos - (V::c(self.a.point) - V::c(self.b.point));
        let x = [dx.0, (a.rot - b.rot).0].concat_arr();
        let xd = [(a.vel - b.vel).0, (a.angvel - b.angvel).0].concat_arr();
        let mut w = [T::zero(); 6];
        for (i, wi) in w.iter_mut().enumerate() {
            for j in 0..6 {
                *wi -= x[j] * self.stiffness[i][j];
                if let Some(dm) = &self.damping {
                    *wi -= xd[j] * dm[i][j];
                }
            }
        }
        if let Some(h) = &self.hysteretic {
            let inv = T::c(1.0) / reference_speed(d.omega);
            for (i, wi) in w.iter_mut().enumerate() {
                let mut hx = T::zero();
                for j in 0..6 {
                    hx += xd[j] * h[i][j];
                }
                *wi -= hx * inv;
            }
        }
        let wa = Wrench {
            force: V([w[0], w[1], w[2]]),
            moment: V([w[3], w[4], w[5]]),
        };
        // Both markers sit at the same point, so b takes the plain reaction.
        (wa, wa.reaction())
    }
}

trait Concat<T> {
    fn concat_arr(self) -> [T; 6];
}

impl<T: Copy> Concat<T> for [[T; 3]; 2] {
    fn concat_arr(self) -> [T; 6] {
        let [a, b] = self;
        [a[0], a[1], a[2], b[0], b[1], b[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_speed_is_max_of_speed_and_floor_to_round_off() {
        for w in [0.0, 1.0, -3.0, OMEGA_FLOOR, 10.0, -146.6, 1e3] {
            let r = reference_speed(w);
            let e = f64::max(f64::abs(w), OMEGA_FLOOR);
            assert!((r - e).abs() <= 4.0 * f64::EPSILON * e, "{w}: {r} vs {e}");
        }
    }
}
