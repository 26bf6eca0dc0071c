//! Standard test problems with known or published solutions, one a file. They implement
//! [`OdeSystem`](super::OdeSystem) with analytic Jacobians and are public so integration tests
//! and benchmarks can use them.

pub mod blowup;
pub mod coupled;
pub mod exponential;
pub mod harmonic;
pub mod hires;
pub mod stiff_decay;
pub mod tailed;
pub mod vdpol;

pub use blowup::Blowup;
pub use coupled::Coupled;
pub use exponential::Exponential;
pub use harmonic::Harmonic;
pub use hires::Hires;
pub use stiff_decay::StiffDecay;
pub use tailed::Tailed;
pub use vdpol::{VanDerPol, VanDerPolClassic};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::OdeSystem;

    /// Each analytic Jacobian agrees with central differences of its own right-hand side
    /// (relative to the Jacobian's scale) at an arbitrary non-special point.
    fn check_jacobian<S: OdeSystem>(mut sys: S, y: &[f64]) {
        let n = sys.dim();
        let t = 0.37;
        let mut jac = vec![0.0; n * n];
        assert!(sys.jacobian(t, y, &mut jac));
        let scale = jac.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
        let mut yy = y.to_vec();
        for j in 0..n {
            let d = 1e-6 * y[j].abs().max(1e-3);
            yy[j] = y[j] + d;
            sys.rhs(t, &yy, &mut fp);
            yy[j] = y[j] - d;
            sys.rhs(t, &yy, &mut fm);
            yy[j] = y[j];
            for i in 0..n {
                let fd = (fp[i] - fm[i]) / (2.0 * d);
                let err = (fd - jac[i * n + j]).abs() / scale;
                assert!(
                    err < 1e-6,
                    "d f{i} / d y{j}: analytic {} vs {fd}",
                    jac[i * n + j]
                );
            }
        }
    }

    #[test]
    fn analytic_jacobians_match_finite_differences() {
        let y8 = [0.9, 0.1, 0.05, 0.2, 0.3, 0.4, 0.5, 0.0057];
        check_jacobian(Hires::default(), &y8);
        check_jacobian(VanDerPol { eps: 1e-3 }, &[1.5, -0.7]);
        check_jacobian(VanDerPolClassic { mu: 3.0 }, &[1.5, -0.7]);
        check_jacobian(Harmonic { omega: 2.5 }, &[0.3, 0.4]);
        check_jacobian(Exponential { lambda: -3.0 }, &[0.8]);
        check_jacobian(StiffDecay { k: 1e3 }, &[0.8]);
        check_jacobian(Blowup, &[1.7]);
        check_jacobian(
            Tailed {
                omega: 3.0,
                lambda: 50.0,
                c: 2.0,
            },
            &[0.3, 0.4, 0.1],
        );
    }

    /// Hires without the analytic Jacobian reports that it has none.
    #[test]
    fn hires_can_withhold_its_jacobian() {
        let mut sys = Hires {
            analytic_jacobian: false,
        };
        let mut jac = [0.0; 64];
        assert!(!sys.jacobian(0.0, &Hires::Y0, &mut jac));
    }
}
