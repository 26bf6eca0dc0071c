//! Tub-cabinet contact (a scene's effect `contact`): a stiff penalty contact of a tub point
//! against a cabinet surface, point against plane, with Hunt-Crossley damping.
//!
//! The plane's normal n (unit, global, fixed at its rest direction) points from the tub's point
//! towards the cabinet's surface, `gap` m away at rest. The surface moves with the cabinet's
//! point b (on the rigid cabinet: not at all; on the elastic cabinet: the node set it names);
//! the penetration and its rate are
//!   delta = n . ((x_a - x_b) - (a0 - b0)) - gap,   delta' = n . (v_a - v_b),
//! and while delta > 0 the normal force is (Hunt & Crossley 1975, eq. 10)
//!   F = k delta^p (1 + 3/2 alpha delta'),   clamped at F >= 0,
//! on the tub -n F and on the cabinet +n F. p = 1.5 is Hertz's exponent; any p > 1 makes the
//! force C1 at first touch (zero force and slope at delta = 0), which the implicit methods'
//! Newton iterations and the traced Jacobians need. The damping term is in phase with the
//! elastic one, so the force is continuous at touch and at release too.
//!
//! alpha (s/m) sets the loss per impact. For a mass hitting the contact at v0 the coefficient
//! of restitution e solves (the law's first integral m v dv = -k x^p (1 + lambda v) dx,
//! lambda = 3/2 alpha, taken from x = 0 in to x = 0 out; Gonthier, McPhee, Lange and Piedboeuf,
//! Multibody System Dynamics 11 (2004) 209-233, eq. 10)
//!   v0 - ln(1 + lambda v0) / lambda = -e v0 - ln(1 - lambda e v0) / lambda,
//! whatever m, k and p, as long as the clamp stays off (lambda e v0 < 1). To first order
//! e = 1 - alpha v0 (Hunt and Crossley's own estimate); Lankarani and Nikravesh (J. Mech. Des.
//! 112 (1990) 369-376) give alpha = (1 - e^2) / (2 v0) for a chosen e at the speed v0. The unit
//! test below integrates one impact against the exact relation.
//!
//! Energy: the elastic part (velocities zeroed) is k delta^p, the potential k delta^(p+1) /
//! (p+1); the rest is the dissipated part, -(F - k delta^p) delta'. Unclamped that is
//! -3/2 alpha k delta^p delta'^2 <= 0; clamped (F = 0, only where 1 + 3/2 alpha delta' < 0, so
//! delta' < 0) it is k delta^p delta' < 0: the category never gives energy back.
//!
//! Written without a branch on a value: delta^p of max(delta, 0) and the clamp as a max, so
//! the traced graph holds in and out of contact (zero force and zero Jacobian outside).

use super::Element;
use crate::equations::{Drive, Marker, MarkerDef, Wrench};
use crate::geom::{V, f};
use crate::ir;
use crate::scalar::Scalar;

#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    pub name: String,
    /// On the tub.
    pub a: MarkerDef,
    /// On the cabinet: the point whose motion the surface follows.
    pub b: MarkerDef,
    /// Unit normal from the tub's point towards the surface (global, at rest).
    pub n: [f64; 3],
    /// n . (a0 - b0): the markers' rest offset along the normal (0 at the same rest point).
    pub offset: f64,
    /// m, N/m^p, -, s/m.
    pub gap: f64,
    pub stiffness: f64,
    pub exponent: f64,
    pub alpha: f64,
}

impl Contact {
    pub fn new(c: &ir::Contact, a: MarkerDef, b: MarkerDef) -> Self {
        let n = f::unit(c.normal);
        Contact {
            name: c.name.clone(),
            offset: f::dot(n, f::sub(a.point, b.point)),
            n,
            a,
            b,
            gap: c.gap,
            stiffness: c.stiffness,
            exponent: c.exponent,
            alpha: c.alpha,
        }
    }

    /// The normal force (>= 0) at penetration `delta` and rate `rate`: zero for delta <= 0.
    pub fn law<T: Scalar>(&self, delta: T, rate: T) -> T {
        let elastic = delta.max(T::zero()).powf(self.exponent) * self.stiffness;
        let factor = (rate * (1.5 * self.alpha) + 1.0).max(T::zero());
        elastic * factor
    }
}

impl Element for Contact {
    const ELASTIC: bool = true;
    const DISSIPATIVE: bool = true;

    fn name(&self) -> &str {
        &self.name
    }

    fn markers(&self) -> (&MarkerDef, &MarkerDef) {
        (&self.a, &self.b)
    }

    fn wrenches<T: Scalar>(
        &self,
        a: &Marker<T>,
        b: &Marker<T>,
        _exact: bool,
        _d: &Drive<T>,
        _z: &[T],
    ) -> (Wrench<T>, Wrench<T>) {
        // The same law in both kinematics: the normal stays at rest (the surface's tilt times
        // the tangential slide is second order in the small motion).
        let n = V::<T>::c(self.n);
        let delta = n.dot(a.pos - b.pos) - (self.offset + self.gap);
        let rate = n.dot(a.vel - b.vel);
        let fb = n.scale(self.law(delta, rate));
        (Wrench::force(-fb), Wrench::force(fb))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::equations::MarkerDef;
    use crate::ir::BodyRef;

    fn contact(alpha: f64) -> Contact {
        let c = ir::Contact {
            name: "c".into(),
            a: BodyRef::Tub,
            b: BodyRef::Cabinet,
            point: [0.3, 0.0, 0.7],
            b_point: None,
            normal: [0.0, 0.0, 2.0],
            gap: 0.02,
            stiffness: 4e5,
            exponent: 1.5,
            alpha,
        };
        let p = c.point;
        Contact::new(
            &c,
            MarkerDef::fixed(BodyRef::Tub, p),
            MarkerDef::fixed(BodyRef::Cabinet, p),
        )
    }

    /// The static force is Hertz's k delta^1.5 past the gap (closed form), zero short of it,
    /// and pushes the tub back along -n, the cabinet along +n.
    #[test]
    fn static_force_is_hertzian_past_the_gap() {
        let c = contact(0.2);
        for (d, expect) in [
            (0.0, 0.0),
            (0.019, 0.0),
            (0.02, 0.0),
            (0.025, 4e5 * 0.005f64.powf(1.5)),
        ] {
            let f = c.law(d - c.gap, 0.0);
            assert!(
                (f - expect).abs() <= 1e-12 * expect.max(1.0),
                "{d}: {f} vs {expect}"
            );
        }
        // At 5 mm past the gap: 141.4 N.
        assert!((c.law(0.005, 0.0) - 141.421_356_237_309_5).abs() < 1e-9);
        // Closing at 0.1 m/s adds 3/2 alpha v = 3 %; opening fast enough clamps at zero.
        assert!((c.law(0.005, 0.1) / c.law(0.005, 0.0) - 1.03).abs() < 1e-12);
        assert_eq!(c.law(0.005, -10.0), 0.0);
        let rest = [0.3, 0.0, 0.7];
        let mk = |pos: [f64; 3], vel: [f64; 3]| Marker::<f64> {
            pos: V::c(pos),
            vel: V::c(vel),
            rot: V::zero(),
            angvel: V::zero(),
        };
        let drive = Drive {
            phi: 0.0,
            omega: 0.0,
            omega_dot: 0.0,
        };
        let (wa, wb) = c.wrenches(
            &mk([0.3, 0.0, 0.725], [0.0; 3]),
            &mk(rest, [0.0; 3]),
            true,
            &drive,
            &[],
        );
        assert!((wa.force.0[2] + 141.421_356_237_309_5).abs() < 1e-9);
        assert_eq!(wb.force.0[2], -wa.force.0[2]);
        assert_eq!(wa.moment.0, [0.0; 3]);
        let (wa, _) = c.wrenches(
            &mk(rest, [0.0, 0.0, 5.0]),
            &mk(rest, [0.0; 3]),
            true,
            &drive,
            &[],
        );
        assert_eq!(
            wa.force.0, [0.0; 3],
            "out of contact: no force whatever the speed"
        );
    }

    /// The Jacobian is zero out of contact and at first touch (C1), and k p delta^(p-1) in it.
    #[test]
    fn slope_is_continuous_at_touch() {
        use crate::dual::Dual;
        let c = contact(0.2);
        let slope = |d: f64| c.law(Dual::<2>::seed(d, 0), Dual::seed(0.0, 1)).d;
        assert_eq!(slope(-0.001), [0.0, 0.0]);
        assert_eq!(slope(0.0), [0.0, 0.0]);
        let s = slope(0.004);
        assert!((s[0] - 4e5 * 1.5 * 0.004f64.sqrt()).abs() < 1e-8, "{s:?}");
        assert!(
            (s[1] - 4e5 * 0.004f64.powf(1.5) * 0.3).abs() < 1e-9,
            "{s:?}"
        );
    }

    /// e of the exact relation (module doc) by bisection on (0, 1).
    fn restitution_exact(lambda: f64, v0: f64) -> f64 {
        let lhs = v0 - (1.0 + lambda * v0).ln() / lambda;
        let g = |e: f64| -e * v0 - (1.0 - lambda * e * v0).ln() / lambda - lhs;
        let (mut lo, mut hi) = (0.0, 1.0f64.min(0.999_999 / (lambda * v0)));
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if g(mid) < 0.0 { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    }

    /// One impact of a 10 kg mass at v0 on the contact, integrated with RK4 at 1 us until it
    /// leaves: the coefficient of restitution is the exact relation's (Gonthier et al. 2004)
    /// within 5e-12 (measured 6.4e-13: RK4's error at 1e-6 s steps), and within (alpha v0)^2
    /// of Hunt and Crossley's e = 1 - alpha v0.
    #[test]
    fn restitution_of_one_impact_matches_hunt_crossley() {
        let m = 10.0;
        let mut worst: f64 = 0.0;
        for (alpha, v0) in [(0.05, 0.2), (0.3, 0.5), (0.6, 1.0)] {
            let c = contact(alpha);
            // x: penetration, v: its rate; starts at touch closing at v0.
            let acc = |x: f64, v: f64| -c.law(x, v) / m;
            let (mut x, mut v, h) = (0.0f64, v0, 1e-6);
            let mut steps = 0;
            loop {
                let (k1x, k1v) = (v, acc(x, v));
                let (k2x, k2v) = (v + 0.5 * h * k1v, acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
                let (k3x, k3v) = (v + 0.5 * h * k2v, acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
                let (k4x, k4v) = (v + h * k3v, acc(x + h * k3x, v + h * k3v));
                let xn = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                let vn = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
                steps += 1;
                if xn <= 0.0 {
                    // Back to x = 0 by linear interpolation in x (v nearly constant there:
                    // the force is x^1.5-small).
                    let s = x / (x - xn);
                    v += s * (vn - v);
                    break;
                }
                (x, v) = (xn, vn);
                assert!(steps < 10_000_000);
            }
            let e = -v / v0;
            let exact = restitution_exact(1.5 * alpha, v0);
            let hc = 1.0 - alpha * v0;
            worst = worst.max((e - exact).abs());
            assert!(
                (e - exact).abs() < 5e-12,
                "alpha {alpha}, v0 {v0}: {e} vs {exact}"
            );
            assert!(
                (e - hc).abs() < (alpha * v0).powi(2),
                "alpha {alpha}, v0 {v0}: {e} vs 1 - alpha v0 = {hc}"
            );
        }
        println!("restitution against the exact relation: within {worst:.1e}");
    }
}
