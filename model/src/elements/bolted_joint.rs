//! A preloaded bolt joining a counterweight to the tub (issue 52; `ir::BoltedJoint`), as
//! elements on the same two markers: the bolt's axis and the interface's two tangents, and with
//! an interface diameter the clamp's tilt and twist (`BoltedJoint::elements`): on the elastic
//! tub a point joint lets the shell hinge at the bolt (tests/bare_tub.rs). The clamp is a disc
//! of uniform compliance: its moments are capped at the edge's lifting (tilt) and the slip
//! under uniform pressure (twist), both scaled by the clamp force of the moment, and both
//! without a state: beyond its cap the twist holds the limit elastically instead of slipping
//! (a known limitation; the reference's moments stay far below the caps while it is tight).
//!
//! Along the axis, the preloaded joint's characteristic curve: the bolts and the clamped
//! members act in parallel while the interface is closed, the bolts alone once the external
//! load lifts it (below).
//!
//! Across it, a stiff shear path with a Coulomb limit: the interface sticks as a spring k_t
//! and slides at mu F_m, F_m the members' clamp force of the moment, as the friction dampers'
//! elasto-plastic presliding law (`ep_rate`, Dupont et al. 2002) with the breakaway at 0.9 of
//! the limit: one law for friction with presliding in the model, rate independent, no dashpot.
//! Its state is the slip s since assembly (the elastic deflection is u_t - s), so a joint at
//! rest carries its counterweight's weight in shear from s = 0: the static start needs no
//! state of its own.
//! The bolt's shank adds its bending stiffness across, in parallel, closed or open (what keeps
//! a lifted counterweight in place). Each tangent is its own slider (the Coulomb limit a square, up to sqrt 2 over the circle in
//! a diagonal slip). The force is capped at the limit of the moment, so a clamp force that
//! falls (the joint lifting) sheds it at once; the slider's deflection beyond the new limit
//! unloads through it before the force drops (at most the limit's fall: a known limitation).
//! Why a stick path is the right default: at the reference's preload, mu F_V per bolt is kN
//! against the tens of N of a counterweight's inertia (docs/even-orders.md).
//!
//! The joint is a point: both markers sit at the bolt's rest point. Its axes turn with the tub
//! (`element_geometry`; at rest otherwise): the bolt is fixed in the tub, so a counterweight's
//! weight reaches the tilted tub as it would through a rigid link (its pendulum stiffness about
//! the tub's CoG cancels the bare tub's, as in the tub it came out of; tests/counterweights.rs).
//! The preloads of bolt and members are equal and opposite along one axis on the same two
//! bodies, so they cancel in either case. Viscous damping `damping` acts along and across.
//!
//! With the preload F_V (bolt tension = member compression at rest), the bolts' stiffness k_b
//! and the clamped members' k_m, and the joint's opening delta along the bolt axis (positive:
//! the counterweight moves away from the tub), the bolt and member forces are
//!   F_b = max(F_V + k_b delta, 0),   F_m = max(F_V - k_m delta, 0),
//! (a bolt cannot push, a member cannot pull) and the force on the counterweight along the axis
//! is F_m - F_b (towards the tub when the joint opens). At rest it is zero: the preload is
//! internal. Closed, its stiffness is k_b + k_m; the interface lifts at delta = F_V / k_m, under
//! an external load F_A = F_V (1 + k_b / k_m) = F_V / (1 - Phi), Phi = k_b / (k_b + k_m) the
//! load factor of VDI 2230 (Part 1, 2015, sec. 5.3: the bolt's share of an axial load while
//! the joint is closed); beyond it the bolts alone (k_b). Stiffer in compression than in
//! tension once lifted: under a rotating load, even orders.
//!
//! Written with `Scalar::max`, without a branch on a value, so a traced graph holds on both
//! sides of each kink.

use super::{Element, friction_damper::ep_rate};
use crate::equations::{Drive, Marker, MarkerDef, Wrench};
use crate::geom::{V, f};
use crate::ir;
use crate::scalar::Scalar;

/// The joint's normal parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalLaw {
    /// The preload as the model declares it: N, or the tightening torque in N m.
    pub declared: f64,
    /// Newtons of preload per unit of `declared` (1, or the torque's per N m). Kept apart so
    /// that the traced forces multiply the declared number at run time: a free torque
    /// (`codegen::free`) reaches the generated code as a parameter, not a folded product.
    pub per_declared: f64,
    /// Axial stiffness of the bolts together, N/m.
    pub bolt_stiffness: f64,
    /// Stiffness of the clamped members (the interface's compression cone), N/m.
    pub member_stiffness: f64,
}

impl NormalLaw {
    /// A law with its preload in N.
    pub fn with_preload(preload: f64, bolt_stiffness: f64, member_stiffness: f64) -> NormalLaw {
        NormalLaw {
            declared: preload,
            per_declared: 1.0,
            bolt_stiffness,
            member_stiffness,
        }
    }

    /// The preload of all the joint's bolts together, N.
    pub fn preload<T: Scalar>(&self) -> T {
        T::c(self.declared) * self.per_declared
    }

    /// The force on the counterweight along the bolt axis at opening `delta` (m): F_m - F_b.
    pub fn force<T: Scalar>(&self, delta: T) -> T {
        let bolt = (delta * self.bolt_stiffness + self.preload::<T>()).max(T::zero());
        let member = (self.preload::<T>() - delta * self.member_stiffness).max(T::zero());
        member - bolt
    }

    /// The external axial load that lifts the interface, N: F_V (1 + k_b / k_m).
    pub fn separation_load(&self) -> f64 {
        self.preload::<f64>() * (1.0 + self.bolt_stiffness / self.member_stiffness)
    }

    /// VDI 2230's load factor Phi = k_b / (k_b + k_m).
    pub fn load_factor(&self) -> f64 {
        self.bolt_stiffness / (self.bolt_stiffness + self.member_stiffness)
    }
}

/// Which of its directions a bolted-joint element carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Direction {
    /// Along the bolt: the normal law and damping.
    Normal,
    /// Across it along `tangent` (unit): the slider, its slip at element state `state`.
    Shear { tangent: [f64; 3], state: usize },
    /// The clamped interface's resistance to the members' relative rotation about `about`
    /// (unit): a moment `stiffness` x the angle, capped at the clamp force x `lever` (the
    /// interface's edge lifting, or its twist slipping), with viscous `damping` (N m s/rad).
    Tilt {
        about: [f64; 3],
        stiffness: f64,
        lever: f64,
        damping: f64,
    },
}

/// One direction of a bolted joint (`BoltedJoint::elements` makes them).
#[derive(Clone, Debug, PartialEq)]
pub struct BoltedJoint {
    pub name: String,
    /// On the tub.
    pub a: MarkerDef,
    /// On the counterweight, at the same rest point.
    pub b: MarkerDef,
    /// The bolt's axis, from the tub into the counterweight (unit).
    pub axis: [f64; 3],
    pub law: NormalLaw,
    pub shear_stiffness: f64,
    pub bending_stiffness: f64,
    pub friction: f64,
    pub damping: f64,
    pub direction: Direction,
}

/// The slider's sliding deflection below which the interface counts as open (m): far below
/// any deflection of the model, it only keeps the law's division finite when F_m = 0.
const OPEN: f64 = 1e-15;

/// The breakaway fraction of the shear path (the friction dampers' default).
const BREAKAWAY: f64 = ir::DEFAULT_BREAKAWAY;

impl BoltedJoint {
    /// The joint's elements: normal, then the two shears with element states `first_state`
    /// and `first_state + 1`, then with an `interface_diameter` D the clamp's tilt about both
    /// tangents (k_m D^2 / 16, lifting at F_m D / 8: a disc of uniform compliance) and its
    /// twist about the axis (k_t D^2 / 8, slipping at mu F_m D / 3 under uniform pressure).
    pub fn elements(
        j: &ir::BoltedJoint,
        a: MarkerDef,
        b: MarkerDef,
        first_state: usize,
    ) -> Vec<BoltedJoint> {
        let axis = f::unit(j.axis);
        let [t1, t2] = f::normals(axis);
        let (declared, per_declared) = j.preload_parts();
        let one = |name: String, direction| BoltedJoint {
            name,
            a: a.clone(),
            b: b.clone(),
            axis,
            law: NormalLaw {
                declared,
                per_declared,
                bolt_stiffness: j.bolt_stiffness,
                member_stiffness: j.member_stiffness,
            },
            shear_stiffness: j.shear_stiffness,
            bending_stiffness: j.bolt_bending_stiffness,
            friction: j.friction,
            damping: j.damping,
            direction,
        };
        let shear = |k: usize, t| Direction::Shear {
            tangent: t,
            state: first_state + k,
        };
        let mut v = vec![
            one(format!("{} normal", j.name), Direction::Normal),
            one(format!("{} shear 1", j.name), shear(0, t1)),
            one(format!("{} shear 2", j.name), shear(1, t2)),
        ];
        let d = j.interface_diameter;
        if d > 0.0 {
            let tilt = |about, k: f64, lever, area: f64| Direction::Tilt {
                about,
                stiffness: k * area,
                lever,
                damping: j.damping * area,
            };
            let (bend, twist) = (d * d / 16.0, d * d / 8.0);
            let km = j.member_stiffness;
            v.push(one(
                format!("{} tilt 1", j.name),
                tilt(t1, km, d / 8.0, bend),
            ));
            v.push(one(
                format!("{} tilt 2", j.name),
                tilt(t2, km, d / 8.0, bend),
            ));
            let lever = j.friction * d / 3.0;
            let k = j.shear_stiffness;
            v.push(one(
                format!("{} twist", j.name),
                tilt(axis, k, lever, twist),
            ));
        }
        v
    }

    /// The members' clamp force at opening `delta`, N: max(F_V - k_m delta, 0).
    fn clamp<T: Scalar>(&self, delta: T) -> T {
        (self.law.preload::<T>() - delta * self.law.member_stiffness).max(T::zero())
    }

    /// The slider's sliding deflection mu F_m / k_t at opening `delta`.
    fn sliding<T: Scalar>(&self, delta: T) -> T {
        self.clamp(delta) * (self.friction / self.shear_stiffness)
    }

    /// Relative displacement and velocity of the counterweight's marker from the tub's.
    fn relative<T: Scalar>(a: &Marker<T>, b: &Marker<T>) -> (V<T>, V<T>) {
        (b.pos - a.pos, b.vel - a.vel)
    }

    /// A direction of the joint (its rest value `v`), turned with the tub (`exact`) to first
    /// order, as the tub marker's rotation turns it.
    fn turned<T: Scalar>(v: [f64; 3], a: &Marker<T>, exact: bool) -> V<T> {
        let v = V::<T>::c(v);
        if exact { v + a.rot.cross(v) } else { v }
    }
}

impl Element for BoltedJoint {
    const ELASTIC: bool = true;
    const DISSIPATIVE: bool = true;

    fn name(&self) -> &str {
        &self.name
    }

    fn markers(&self) -> (&MarkerDef, &MarkerDef) {
        (&self.a, &self.b)
    }

    fn state(&self) -> Option<usize> {
        match self.direction {
            Direction::Shear { state, .. } => Some(state),
            Direction::Normal | Direction::Tilt { .. } => None,
        }
    }

    fn state_rate<T: Scalar>(&self, a: &Marker<T>, b: &Marker<T>, exact: bool, z: &[T]) -> T {
        let Direction::Shear { tangent, state } = self.direction else {
            return T::zero();
        };
        let (du, dv) = Self::relative(a, b);
        let t = Self::turned(tangent, a, exact);
        let delta = Self::turned(self.axis, a, exact).dot(du);
        let slip = z.get(state).copied().unwrap_or(T::zero());
        let z_ss = self.sliding(delta).max(T::c(OPEN));
        // The slip rate: the tangential velocity less the elastic deflection's rate.
        let v = t.dot(dv);
        v - ep_rate(z_ss, BREAKAWAY, t.dot(du) - slip, v)
    }

    fn state_dissipation(
        &self,
        a: &Marker<f64>,
        b: &Marker<f64>,
        exact: bool,
        z: &[f64],
        zd: &[f64],
    ) -> f64 {
        let Direction::Shear { tangent, state } = self.direction else {
            return 0.0;
        };
        let (du, _) = Self::relative(a, b);
        let z_ss = self.sliding(Self::turned(self.axis, a, exact).dot(du));
        let e = Self::turned(tangent, a, exact).dot(du) - z[state];
        // The slider's power: its force along the slip.
        -self.shear_stiffness * e.clamp(-z_ss, z_ss) * zd[state]
    }

    fn wrenches<T: Scalar>(
        &self,
        a: &Marker<T>,
        b: &Marker<T>,
        exact: bool,
        _d: &Drive<T>,
        z: &[T],
    ) -> (Wrench<T>, Wrench<T>) {
        let (du, dv) = Self::relative(a, b);
        let n = Self::turned(self.axis, a, exact);
        let delta = n.dot(du);
        // The force on the counterweight (b), along `dir`.
        let (dir, f) = match self.direction {
            Direction::Normal => (n, self.law.force(delta) - n.dot(dv) * self.damping),
            Direction::Shear { tangent, state } => {
                let t = Self::turned(tangent, a, exact);
                // The elastic deflection u_t - s capped at the limit of the moment.
                let slip = z.get(state).copied().unwrap_or(T::zero());
                let capped = within(t.dot(du) - slip, self.sliding(delta));
                let bolt = t.dot(du) * self.bending_stiffness;
                (
                    t,
                    T::zero() - capped * self.shear_stiffness - bolt - t.dot(dv) * self.damping,
                )
            }
            Direction::Tilt {
                about,
                stiffness,
                lever,
                damping,
            } => {
                // The moment on the counterweight about `about`, the angle's spring capped at
                // the clamp's limit of the moment.
                let e = Self::turned(about, a, exact);
                let limit = self.clamp(delta) * (lever / stiffness);
                let capped = within(e.dot(b.rot - a.rot), limit);
                let m = T::zero() - capped * stiffness - e.dot(b.angvel - a.angvel) * damping;
                let mb = e.scale(m);
                return (Wrench::moment(-mb), Wrench::moment(mb));
            }
        };
        let fb = dir.scale(f);
        (Wrench::force(-fb), Wrench::force(fb))
    }
}

/// `x` capped to [-limit, limit] (limit >= 0), with `Scalar::max` only: a traced graph holds on
/// both sides of each kink.
fn within<T: Scalar>(x: T, limit: T) -> T {
    let below = T::zero() - (T::zero() - x).max(T::zero() - limit);
    below.max(T::zero() - limit)
}

/// Preload from the tightening torque, N (VDI 2230 Part 1, eq. R13 with the thread's flank
/// angle 60 degrees): M_A = F_V (0.16 P + 0.58 d2 mu_G + mu_K D_Km / 2), with the pitch P, the
/// pitch diameter d2, the thread's and the head's friction coefficients and the head's mean
/// friction diameter D_Km (all m).
pub fn preload_from_torque(
    torque: f64,
    pitch: f64,
    d2: f64,
    mu_g: f64,
    mu_k: f64,
    dkm: f64,
) -> f64 {
    torque / (0.16 * pitch + 0.58 * d2 * mu_g + 0.5 * mu_k * dkm)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An M8 joint (estimate): k_b = 2e8 N/m, k_m = 8e8 N/m (the members about 4x the bolt,
    /// VDI 2230's typical ratio for a short clamp), F_V = 15 kN.
    fn m8() -> NormalLaw {
        NormalLaw::with_preload(15e3, 2e8, 8e8)
    }

    /// Closed: the bolt takes Phi of an external load F_A (VDI 2230's load factor) and the
    /// joint's stiffness is k_b + k_m; the interface lifts at F_V / (1 - Phi); beyond, the bolt
    /// alone; pressed until the bolt goes slack, the members alone.
    #[test]
    fn the_normal_law_is_the_preloaded_joint_of_vdi_2230() {
        let j = m8();
        let (kb, km, fv) = (j.bolt_stiffness, j.member_stiffness, j.preload::<f64>());
        let phi = j.load_factor();
        assert_eq!(phi, 0.2);
        assert_eq!(j.force(0.0), 0.0, "the preload is internal");
        // An external pull F_A < separation: delta = F_A / (kb + km), bolt force F_V + Phi F_A.
        let fa = 5e3;
        let delta = fa / (kb + km);
        assert!((j.force(delta) + fa).abs() < 1e-9 * fa);
        let bolt = fv + kb * delta;
        assert!((bolt - (fv + phi * fa)).abs() < 1e-9 * fv);
        // Separation at F_A = F_V / (1 - Phi) = 18.75 kN, delta = F_V / k_m.
        assert!((j.separation_load() - fv / (1.0 - phi)).abs() < 1e-9 * fv);
        let d_sep = fv / km;
        assert!((j.force(d_sep) + j.separation_load()).abs() < 1e-9 * fv);
        // Beyond: the bolt alone, F = -(F_V + k_b delta).
        let d = 3.0 * d_sep;
        assert!((j.force(d) + fv + kb * d).abs() < 1e-9 * fv);
        // Pressed: k_b + k_m until the bolt goes slack at -F_V / k_b, then k_m alone.
        let d = -0.5 * fv / kb;
        assert!((j.force(d) + (kb + km) * d).abs() < 1e-9 * fv);
        let d = -2.0 * fv / kb;
        assert!((j.force(d) - (fv - km * d)).abs() < 1e-9 * fv);
    }

    /// Stiffer one way than the other: a harmonic opening of amplitude 2 delta_sep about the
    /// closed rest gives a force with a mean and a second harmonic (what a rotating load turns
    /// into even orders); a symmetric law would give neither.
    #[test]
    fn a_lifting_joint_gives_even_harmonics() {
        let j = m8();
        let amp = 2.0 * j.preload::<f64>() / j.member_stiffness;
        let n = 4096;
        let (mut mean, mut c2, mut s2) = (0.0, 0.0, 0.0);
        for k in 0..n {
            let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            let f = j.force(amp * t.cos());
            mean += f / n as f64;
            c2 += 2.0 * f * (2.0 * t).cos() / n as f64;
            s2 += 2.0 * f * (2.0 * t).sin() / n as f64;
        }
        let first = (j.bolt_stiffness + j.member_stiffness) * amp;
        assert!(
            mean.abs() > 1e-3 * first && c2.abs() > 1e-3 * first,
            "{mean} {c2}"
        );
        assert!(s2.abs() < 1e-12 * first);
        // A joint that never lifts (amplitude below delta_sep) is linear: no even part.
        let small = 0.5 * j.preload::<f64>() / j.member_stiffness;
        let mean_small: f64 = (0..n)
            .map(|k| j.force(small * (2.0 * std::f64::consts::PI * k as f64 / n as f64).cos()))
            .sum::<f64>()
            / n as f64;
        assert!(mean_small.abs() < 1e-9 * first, "{mean_small}");
    }

    /// A joint on the z axis (fixed markers at the origin) with the reference's M8 bolt:
    /// preload 11.4 kN, k_b 1.9e8, k_m 7.6e8, k_t 3e8 N/m, mu 0.3, no damping; its elements,
    /// with the clamped interface `d` across.
    fn elements(d: f64) -> Vec<BoltedJoint> {
        use crate::equations::MarkerDef;
        use crate::ir::BodyRef;
        let j = ir::BoltedJoint {
            name: "b".into(),
            counterweight: "w".into(),
            point: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            preload: Some(11.4e3),
            torque: None,
            bolt_stiffness: 1.9e8,
            member_stiffness: 7.6e8,
            shear_stiffness: 3e8,
            bolt_bending_stiffness: 0.0,
            friction: 0.3,
            damping: 0.0,
            interface_diameter: d,
        };
        let m = |b| MarkerDef::fixed(b, [0.0; 3]);
        BoltedJoint::elements(&j, m(BodyRef::Tub), m(BodyRef::Counterweight(0)), 0)
    }

    /// The first shear path.
    fn joint() -> BoltedJoint {
        elements(0.0).remove(1)
    }

    /// The clamped interface as a disc of diameter D under the preload (closed forms): it tilts
    /// at k_m I / A = k_m D^2 / 16 until its edge lifts, M = F_V (I / A) / (D / 2) = F_V D / 8,
    /// and twists at k_t J / A = k_t D^2 / 8 until it slips under uniform pressure,
    /// M = mu F_V (2 / 3)(D / 2) = mu F_V D / 3; a lifted interface holds no moment.
    #[test]
    fn the_clamp_tilts_and_twists_as_a_disc() {
        let d = 0.033;
        let all = elements(d);
        let names: Vec<&str> = all.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names[3..], ["b tilt 1", "b tilt 2", "b twist"]);
        assert_eq!(elements(0.0).len(), 3, "a point joint: forces only");
        let (fv, km, kt, mu) = (11.4e3, 7.6e8, 3e8, 0.3);
        let drive = Drive {
            phi: 0.0,
            omega: 0.0,
            omega_dot: 0.0,
        };
        let moment = |e: &BoltedJoint, angle: f64, open: f64| {
            let Direction::Tilt { about, .. } = e.direction else {
                unreachable!()
            };
            let mut b = at([0.0, 0.0, open], [0.0; 3]);
            b.rot = V::c(about).scale(angle);
            let (wa, wb) = e.wrenches(&at([0.0; 3], [0.0; 3]), &b, false, &drive, &[]);
            assert!((wa.moment + wb.moment).norm() < 1e-12 * wb.moment.norm().max(1.0));
            wb.moment.dot(V::c(about))
        };
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        for (e, k, limit) in [
            (&all[3], km * d * d / 16.0, fv * d / 8.0),
            (&all[4], km * d * d / 16.0, fv * d / 8.0),
            (&all[5], kt * d * d / 8.0, mu * fv * d / 3.0),
        ] {
            let small = 0.1 * limit / k;
            assert!(rel(moment(e, small, 0.0), -k * small) < 1e-12, "{}", e.name);
            assert!(
                rel(moment(e, -10.0 * small, 0.0), limit) < 1e-12,
                "{}",
                e.name
            );
            assert_eq!(moment(e, small, 2.0 * fv / km), 0.0, "{} lifted", e.name);
        }
    }

    fn at(pos: [f64; 3], vel: [f64; 3]) -> Marker<f64> {
        Marker {
            pos: V::c(pos),
            vel: V::c(vel),
            rot: V::zero(),
            angvel: V::zero(),
        }
    }

    /// The shear path across one tangent, driven by u_t = A sin(w t) at a fixed opening,
    /// integrated with small steps: returns (the work of the force over the last cycle, the
    /// largest force). `t` is the tangent, `open` the opening along the bolt.
    fn cycle(j: &BoltedJoint, amp: f64, open: f64) -> (f64, f64) {
        let Direction::Shear { tangent, .. } = j.direction else {
            unreachable!()
        };
        let rest = at([0.0; 3], [0.0; 3]);
        let n = 20_000;
        let (mut slip, mut work, mut fmax) = (0.0f64, 0.0, 0.0f64);
        let w = 2.0 * std::f64::consts::PI;
        let dt = 1.0 / n as f64;
        for cyc in 0..3 {
            for k in 0..n {
                let t = (k as f64 + 0.5) * dt;
                let (u, v) = (amp * (w * t).sin(), amp * w * (w * t).cos());
                let b = at(
                    [tangent[0] * u, tangent[1] * u, open + tangent[2] * u],
                    [tangent[0] * v, tangent[1] * v, tangent[2] * v],
                );
                let d = Drive {
                    phi: 0.0,
                    omega: 0.0,
                    omega_dot: 0.0,
                };
                let (_, wb) = j.wrenches(&rest, &b, false, &d, &[slip]);
                let f = wb.force.dot(V::c(tangent));
                if cyc == 2 {
                    work -= f * v * dt;
                    fmax = fmax.max(f.abs());
                }
                slip += j.state_rate(&rest, &b, false, &[slip]) * dt;
            }
        }
        (work, fmax)
    }

    /// Closed: a small cycle sticks (no work, the spring k_t), a large one slides at mu F_V
    /// with the loop of a Jenkins element (Iwan 1966: a spring k_t in series with a Coulomb
    /// slider), 4 F_s (A - F_s / k_t) per cycle, less the presliding law's rounding near the
    /// limit. Open (the interface lifted), the shear path carries nothing. Measured: the large
    /// cycle's work 0.9994 of the Jenkins loop (bound: within 3 %), its force 1.00000 of mu F_V.
    #[test]
    fn the_shear_path_sticks_then_slides_at_the_coulomb_limit() {
        let j = joint();
        let fs = 0.3 * 11.4e3;
        let z_ss = fs / 3e8;
        let (work, fmax) = cycle(&j, 0.5 * z_ss, 0.0);
        assert!(work.abs() < 1e-9 * fs * z_ss, "stuck: {work}");
        assert!(
            (fmax - 0.5 * fs).abs() < 1e-3 * fs,
            "stuck: the spring {fmax}"
        );
        let amp = 5.0 * z_ss;
        let (work, fmax) = cycle(&j, amp, 0.0);
        let jenkins = 4.0 * fs * (amp - z_ss);
        eprintln!(
            "sliding: work {:.4} of the Jenkins loop, force {:.5} of mu F_V",
            work / jenkins,
            fmax / fs
        );
        assert!((work / jenkins - 1.0).abs() < 0.03, "{}", work / jenkins);
        assert!(fmax <= fs * (1.0 + 1e-9) && fmax > 0.99 * fs, "{fmax}");
        let lifted = 2.0 * 11.4e3 / 7.6e8;
        let (work, fmax) = cycle(&j, amp, lifted);
        assert_eq!(
            (work, fmax),
            (0.0, 0.0),
            "an open interface carries no shear"
        );
    }

    /// VDI 2230 (2001)'s table of preloads and torques, as a fastener catalogue reprints it
    /// (Mastik, p. 685, metric fine threads): M8 x 1, 8.8, mu_tot = 0.12: F_M = 20.2 kN at
    /// M_A = 26.1 N m. With P = 1 mm, d2 = d - 0.6495 P = 7.3505 mm and D_Km = (d_w + d_h) / 2
    /// = (11.6 + 9.0) / 2 mm (an M8 hex head on a medium clearance hole), the formula gives
    /// the table's preload of that torque (measured 0.2 % apart).
    #[test]
    fn the_preload_of_a_tightening_torque() {
        let f = preload_from_torque(26.1, 1e-3, 7.3505e-3, 0.12, 0.12, 10.3e-3);
        assert!((f - 20.2e3).abs() < 0.02 * 20.2e3, "{f}");
    }
}
