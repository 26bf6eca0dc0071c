//! A preloaded bolted joint's normal law (issue 52 point 1: the concrete counterweights on the
//! tub): the bolts and the clamped members act in parallel while the interface is closed, the
//! bolts alone once the external load lifts it. Not yet an `Element`: the counterweight bodies
//! it joins to the tub come with it.
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

use crate::scalar::Scalar;

/// The joint's normal parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalLaw {
    /// Preload of all the joint's bolts together, N.
    pub preload: f64,
    /// Axial stiffness of the bolts together, N/m.
    pub bolt_stiffness: f64,
    /// Stiffness of the clamped members (the interface's compression cone), N/m.
    pub member_stiffness: f64,
}

impl NormalLaw {
    /// The force on the counterweight along the bolt axis at opening `delta` (m): F_m - F_b.
    pub fn force<T: Scalar>(&self, delta: T) -> T {
        let bolt = (delta * self.bolt_stiffness + self.preload).max(T::zero());
        let member = (T::c(self.preload) - delta * self.member_stiffness).max(T::zero());
        member - bolt
    }

    /// The external axial load that lifts the interface, N: F_V (1 + k_b / k_m).
    pub fn separation_load(&self) -> f64 {
        self.preload * (1.0 + self.bolt_stiffness / self.member_stiffness)
    }

    /// VDI 2230's load factor Phi = k_b / (k_b + k_m).
    pub fn load_factor(&self) -> f64 {
        self.bolt_stiffness / (self.bolt_stiffness + self.member_stiffness)
    }
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
        NormalLaw {
            preload: 15e3,
            bolt_stiffness: 2e8,
            member_stiffness: 8e8,
        }
    }

    /// Closed: the bolt takes Phi of an external load F_A (VDI 2230's load factor) and the
    /// joint's stiffness is k_b + k_m; the interface lifts at F_V / (1 - Phi); beyond, the bolt
    /// alone; pressed until the bolt goes slack, the members alone.
    #[test]
    fn the_normal_law_is_the_preloaded_joint_of_vdi_2230() {
        let j = m8();
        let (kb, km, fv) = (j.bolt_stiffness, j.member_stiffness, j.preload);
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
        let amp = 2.0 * j.preload / j.member_stiffness;
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
        let small = 0.5 * j.preload / j.member_stiffness;
        let mean_small: f64 = (0..n)
            .map(|k| j.force(small * (2.0 * std::f64::consts::PI * k as f64 / n as f64).cos()))
            .sum::<f64>()
            / n as f64;
        assert!(mean_small.abs() < 1e-9 * first, "{mean_small}");
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
