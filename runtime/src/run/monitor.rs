//! The watch between steps (the tub's motion against the linearisation's bounds, the elements'
//! and clearances' limits, the interrupt flag, the wall-clock budget) and the spectral radius
//! estimate behind rk4's stability check.

use super::{Guard, RunError, Summary};
use std::sync::atomic::Ordering;
use std::time::Instant;
use washdyn_ode::OdeSystem;

/// Where the worst values of the run happened (indices into the guard's lists), named in the
/// summary at the end so the step loop does not allocate.
#[derive(Default)]
pub(super) struct Worst {
    pub(super) element: Option<usize>,
    pub(super) ring: Option<usize>,
    pub(super) gap: Option<usize>,
}

/// Watches a run between steps: the tub motion against the linearisation's bounds, the
/// interrupt flag, and the simulated time gained per wall-clock window.
pub(super) struct Monitor<'a> {
    guard: &'a Guard,
    warned_translation: bool,
    warned_rotation: bool,
    warned_element: bool,
    warned_ring: bool,
    warned_gap: bool,
    window_start: Instant,
    window_t: f64,
    calls: u32,
}

impl<'a> Monitor<'a> {
    pub(super) fn new(guard: &'a Guard, t0: f64, now: Instant) -> Self {
        Monitor {
            guard,
            warned_translation: false,
            warned_rotation: false,
            warned_element: false,
            warned_ring: false,
            warned_gap: false,
            window_start: now,
            window_t: t0,
            calls: 0,
        }
    }

    /// The floating frame's translation u and rotation alpha (from `Watch::frame`).
    pub(super) fn check(
        &mut self,
        t: f64,
        q: &[f64],
        summary: &mut Summary,
    ) -> Result<(), RunError> {
        let c = self.guard.watch.frame;
        if q.len() < c + 6 {
            return Ok(());
        }
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let (u, a) = (norm(&q[c..c + 3]), norm(&q[c + 3..c + 6]));
        let ex = &mut summary.validity;
        if u > ex.max_translation_m {
            ex.max_translation_m = u;
            ex.max_translation_t = t;
        }
        if a > ex.max_rotation_rad {
            ex.max_rotation_rad = a;
            ex.max_rotation_t = t;
        }
        let g = self.guard;
        for (value, bound, what, unit, warned) in [
            (
                u,
                g.translation_m,
                "tub translation",
                "m",
                &mut self.warned_translation,
            ),
            (
                a,
                g.rotation_rad,
                "tub rotation",
                "rad",
                &mut self.warned_rotation,
            ),
        ] {
            if value > bound && !*warned {
                *warned = true;
                summary.warnings.push(format!(
                    "{what} {value:.4e} {unit} at t = {t} s exceeds the {bound} {unit} bound of \
                     the small-motion linearisation"
                ));
            }
            if let Some(factor) = g.stop_factor
                && value > factor * bound
            {
                return Err(RunError::Validity {
                    t,
                    what,
                    value,
                    bound,
                    factor,
                    unit,
                });
            }
        }
        Ok(())
    }

    /// The largest deflection of an element's tub end, and a warning past the translation bound.
    pub(super) fn elements(&mut self, t: f64, q: &[f64], summary: &mut Summary, worst: &mut Worst) {
        let ex = &mut summary.validity;
        for (i, (_, m)) in self.guard.elements.iter().enumerate() {
            let d = m.displacement(q);
            let v = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if v > ex.max_element_deflection_m {
                ex.max_element_deflection_m = v;
                ex.max_element_deflection_t = t;
                worst.element = Some(i);
            }
        }
        let bound = self.guard.translation_m;
        if !self.warned_element && ex.max_element_deflection_m > bound {
            self.warned_element = true;
            let (v, name) = (
                ex.max_element_deflection_m,
                worst
                    .element
                    .map_or("", |i| self.guard.elements[i].0.as_str()),
            );
            summary.warnings.push(format!(
                "element `{name}` deflected {v:.4e} m at t = {t} s, beyond the {bound} m \
                 tub-cabinet clearance"
            ));
        }
    }

    /// The door ring's largest displacement (warned about at the translation bound, the
    /// tub-cabinet clearance) and the drum-tub gap's largest closure (warned about at its
    /// clearance); `phi` is the drive angle at t.
    pub(super) fn clearances(
        &mut self,
        t: f64,
        phi: f64,
        q: &[f64],
        summary: &mut Summary,
        worst: &mut Worst,
    ) {
        if q.len() < 6 {
            return;
        }
        let ex = &mut summary.validity;
        let w = &self.guard.watch;
        if let Some(ring) = &w.door_ring {
            let (v, i) = ring.excursion(q);
            if v > ex.max_door_ring_m {
                ex.max_door_ring_m = v;
                ex.max_door_ring_t = t;
                worst.ring = Some(i);
            }
            let bound = self.guard.translation_m;
            if v > bound && !self.warned_ring {
                self.warned_ring = true;
                summary.warnings.push(format!(
                    "door ring point `{}` moved {v:.4e} m at t = {t} s, beyond the {bound} m \
                     tub-cabinet clearance",
                    ring.points[i].name
                ));
            }
        }
        let ex = &mut summary.validity;
        if let Some(gap) = &w.drum_gap {
            let (v, i) = gap.closure(phi, q);
            if v > ex.max_gap_closure_m {
                ex.max_gap_closure_m = v;
                ex.max_gap_closure_t = t;
                worst.gap = Some(i);
            }
            if v > gap.clearance && !self.warned_gap {
                self.warned_gap = true;
                summary.warnings.push(format!(
                    "drum edge point `{}` closed the drum-tub gap by {v:.4e} m at t = {t} s, \
                     beyond its {:.4} m clearance",
                    gap.edge[i].name, gap.clearance
                ));
            }
        }
    }

    /// The interrupt flag, every step; the wall clock, every 64th step.
    pub(super) fn progress(&mut self, t: f64, t_end: f64) -> Result<(), RunError> {
        if let Some(flag) = &self.guard.interrupt
            && flag.load(Ordering::Relaxed)
        {
            return Err(RunError::Interrupted { t });
        }
        self.calls = self.calls.wrapping_add(1);
        if !self.calls.is_multiple_of(64) {
            return Ok(());
        }
        let window_s = self.window_start.elapsed().as_secs_f64();
        if window_s < self.guard.stall_window_s {
            return Ok(());
        }
        let gained = t - self.window_t;
        let remaining = t_end - t;
        let projected_s = remaining / gained * window_s;
        // Written to catch gained = 0 (projected inf) and NaN alike.
        if projected_s.is_nan() || projected_s > self.guard.max_projected_s {
            return Err(RunError::Stalled {
                t,
                window_s,
                gained,
                remaining,
                projected_s,
                budget_s: self.guard.max_projected_s,
            });
        }
        self.window_start = Instant::now();
        self.window_t = t;
        Ok(())
    }
}

/// Largest |eigenvalue| of df/dy at (t, y), by power iteration on finite-difference products
/// J v: the mean growth of |J^k v| over the iterations after a transient of 20. A dominant
/// complex pair makes v rotate, not converge; the growth rate still tends to |lambda|. Set-up
/// code: it allocates.
pub fn spectral_radius<S: OdeSystem>(sys: &mut S, t: f64, y: &[f64]) -> f64 {
    let m = y.len();
    let mut f0 = vec![0.0; m];
    let mut f1 = vec![0.0; m];
    let mut yp = vec![0.0; m];
    sys.rhs(t, y, &mut f0);
    let ynorm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
    // A fixed pseudo-random start, so every mode has a share.
    let mut v: Vec<f64> = (0..m)
        .map(|i| ((i as f64 + 1.0) * 0.618_034).fract() - 0.5)
        .collect();
    let (mut log_sum, mut count) = (0.0, 0);
    for k in 0..120 {
        let vn = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(vn > 0.0 && vn.is_finite()) {
            break;
        }
        let eps = 1e-7 * (1.0 + ynorm) / vn;
        for i in 0..m {
            yp[i] = y[i] + eps * v[i];
        }
        sys.rhs(t, &yp, &mut f1);
        for i in 0..m {
            v[i] = (f1[i] - f0[i]) / eps;
        }
        let jn = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(jn > 0.0 && jn.is_finite()) {
            break;
        }
        if k >= 20 {
            log_sum += (jn / vn).ln();
            count += 1;
        }
        v.iter_mut().for_each(|x| *x /= jn);
    }
    if count == 0 {
        0.0
    } else {
        (log_sum / count as f64).exp()
    }
}
