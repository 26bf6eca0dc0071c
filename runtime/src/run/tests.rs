use super::*;
use washdyn_ode::{OdeSystem, Stats};

/// The summary advises an implicit method when the test fired and the method stayed on
/// its stability limit, and not when it switched there (the composite method).
#[test]
fn stiffness_advice_only_for_a_method_that_did_not_switch() {
    let labels = Labels {
        model: "m".into(),
        scene: "s".into(),
        backend: "generated".into(),
    };
    let stiff = Stats {
        steps: 100,
        stiff_steps: 40,
        stiff_at: Some(0.5),
        ..Stats::default()
    };
    let mut dopri5 = Summary::new(&labels, "dopri5", (1e-6, 1e-9), (0.0, 1.0));
    dopri5.take_stats(stiff);
    assert_eq!(dopri5.warnings.len(), 1, "{:?}", dopri5.warnings);
    assert!(dopri5.warnings[0].contains("stability limit"));
    let mut auto = Summary::new(&labels, "auto", (1e-6, 1e-9), (0.0, 1.0));
    auto.take_stats(Stats {
        method_switches: 3,
        ..stiff
    });
    assert!(auto.warnings.is_empty(), "{:?}", auto.warnings);
    assert_eq!(auto.stiff_at, Some(0.5));
}

/// y' = A y, A block-diagonal with the eigenvalues -1, -4000 and the pair -10 +- 3000 i.
struct Linear;
impl OdeSystem for Linear {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -y[0];
        dy[1] = -4000.0 * y[1];
        dy[2] = -10.0 * y[2] - 3000.0 * y[3];
        dy[3] = 3000.0 * y[2] - 10.0 * y[3];
    }
}

#[test]
fn spectral_radius_of_a_known_spectrum() {
    // The largest |lambda| is 4000 by construction; the pair's modulus is 3000.02.
    let r = spectral_radius(&mut Linear, 0.0, &[0.1, 0.2, 0.3, 0.4]);
    assert!((r / 4000.0 - 1.0).abs() < 1e-3, "{r}");
}
