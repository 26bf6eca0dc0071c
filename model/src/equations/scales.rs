//! What an absolute error means for each coordinate: the integrators' tolerance per component
//! (`OdeSystem::atol_scales`). One scalar atol over metres, radians and modal coordinates held
//! the modal coordinates to an accuracy unrelated to the motion they cause, and the velocities
//! to the positions' number in other units.

use super::{Equations, MarkerDef, ModalRows, Placed};
use crate::elements::Element;

/// Both markers of every element of one kind.
fn element_markers<E: Element>(list: &[Placed<E>]) -> impl Iterator<Item = &MarkerDef> {
    list.iter().flat_map(|p| {
        let (a, b) = p.e.markers();
        [a, b]
    })
}

impl Equations {
    /// The largest translation (m) per unit of each coordinate at any marker of the scene:
    /// 1 for the rigid translations and, in radians, for the rotations; max_k |W| over the
    /// markers for a modal coordinate (1 when no marker sees it).
    pub fn coordinate_sizes(&self) -> Vec<f64> {
        let n = self.layout.n();
        let mut size = vec![0.0f64; n];
        let mut see = |r: &ModalRows| {
            for (k, w) in r.w.iter().enumerate() {
                let a = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                size[r.start + k] = size[r.start + k].max(a);
            }
        };
        let markers = element_markers(&self.springs)
            .chain(element_markers(&self.dampers))
            .chain(element_markers(&self.friction_dampers))
            .chain(element_markers(&self.damper_joints))
            .chain(element_markers(&self.gaskets))
            .chain(element_markers(&self.contacts))
            .chain(element_markers(&self.bolted_joints))
            .chain(self.sensors.iter().map(|s| &s.at))
            .chain(self.carried.iter().map(|c| &c.0))
            .chain(self.rotors.iter().map(|r| &r.mount))
            .chain(self.unbalances.iter().map(|u| &u.mount))
            .chain(self.elastic_drum().map(|d| &d.mount));
        for m in markers {
            if let Some(r) = &m.modal {
                see(r);
            }
        }
        for u in &self.unbalances {
            if let Some(r) = &u.drum {
                see(r);
            }
        }
        let (c, _) = self.bodies.floating();
        for (i, s) in size.iter_mut().enumerate() {
            if (c..c + 6).contains(&i) || *s <= 0.0 || !s.is_finite() {
                *s = 1.0;
            }
        }
        size
    }

    /// Scales of the absolute tolerance over y = [q; q'] (length 2n): a coordinate whose unit
    /// moves a marker by `size` metres gets 1/size for its position and its velocity, so atol
    /// is metres (m/s) at the markers for every coordinate. Not scaled by a frequency: the
    /// sensors' accelerations see a mode's velocity error times its frequency, and weighing
    /// velocities in the energy norm (size / omega_k) let dopri5 put 0.11 m/s^2 of kHz noise
    /// on the tub's accelerations during the first 10 s of the run-up (200x the signal there).
    pub fn atol_scales(&self, s: &mut [f64]) {
        let n = self.layout.n();
        let size = self.coordinate_sizes();
        for i in 0..n {
            s[i] = 1.0 / size[i];
            s[n + i] = 1.0 / size[i];
        }
    }
}
