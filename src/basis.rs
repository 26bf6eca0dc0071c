//! What a body's modal basis misses in the analysis band, per body and without a time run:
//! the receptances between the body's element load points (and from them to its sensors) of a
//! trial basis (the scene's cut, its static fold) against a reference basis of the same FE
//! model (every mode to 2 kHz plus the correction modes: `fe/examples/modes_2k.rs`). Both
//! with the modal damping the simulation gives each mode (`equations::modal_damping`),
//! so the comparison is of the linear body model the equations integrate, held at its frame.
//! The machine couples these receptances through its springs, dampers and gasket; a basis that
//! misses a receptance by e misses the coupled response by about e where that body dominates.

use nalgebra::Complex;
use washdyn_model::equations::modal_damping;
use washdyn_model::ir::modal::{LoadCase, ModalData, point_at};
use washdyn_model::ir::{BodyRef, EffectSet, Elastic, Model};

/// A body's data with the modal damping of each of its modes (the simulation's).
pub struct Damped<'a> {
    pub data: &'a ModalData,
    pub zeta: Vec<f64>,
}

impl<'a> Damped<'a> {
    pub fn new(e: &Elastic, data: &'a ModalData) -> Self {
        Damped {
            zeta: modal_damping(e, data),
            data,
        }
    }

    /// Receptance (m/N, rad/(N m)) at `f` Hz from unit load `input` to the motion along
    /// `output` (a `LoadCase` read as a measurement: translation or rotation along its
    /// direction): sum_k o_k i_k / (omega_k^2 - omega^2 + 2 i zeta_k omega_k omega).
    pub fn receptance(&self, output: &LoadCase, input: &LoadCase, f: f64) -> Complex<f64> {
        let d = self.data;
        let (po, pi) = (
            d.point(&output.point).expect("output point"),
            d.point(&input.point).expect("input point"),
        );
        let w = 2.0 * std::f64::consts::PI * f;
        (0..d.modes())
            .map(|k| {
                let wk = 2.0 * std::f64::consts::PI * d.frequencies[k];
                let num = output.participation(po, k) * input.participation(pi, k);
                num / Complex::new(wk * wk - w * w, 2.0 * self.zeta[k] * wk * w)
            })
            .sum()
    }
}

/// How far a trial basis's receptances lie from the reference's over (0, band] Hz.
#[derive(Clone, Debug, PartialEq)]
pub struct BasisError {
    /// sqrt(sum |H_t - H_r|^2 / sum |H_r|^2) over every pair and frequency.
    pub overall: f64,
    /// The worst output channel's max |H_t - H_r| / max |H_r|, both over its inputs and the
    /// frequencies: the error in that channel relative to its own level (a pair alone would
    /// weigh a near-zero cross receptance as much as a driving point's).
    pub worst: f64,
    /// That output, as `point:direction`.
    pub worst_output: String,
    /// Pairs compared.
    pub pairs: usize,
}

/// Frequencies of the comparison: every `step` Hz from `step` to `band` (1 Hz resolves the
/// 2 %-damped peaks above 25 Hz to within their half-power width).
pub fn grid(band: f64, step: f64) -> Vec<f64> {
    (1..=(band / step).floor() as usize)
        .map(|i| i as f64 * step)
        .collect()
}

/// `trial` against `reference` for every (output, input) pair at the frequencies `f`.
pub fn basis_error(
    reference: &Damped,
    trial: &Damped,
    outputs: &[LoadCase],
    inputs: &[LoadCase],
    f: &[f64],
) -> BasisError {
    let (mut num, mut den) = (0.0, 0.0);
    let mut worst = (0.0, String::new());
    for o in outputs {
        let (mut dmax, mut rmax) = (0.0f64, 0.0f64);
        for i in inputs {
            for &fi in f {
                let (r, t) = (reference.receptance(o, i, fi), trial.receptance(o, i, fi));
                num += (t - r).norm_sqr();
                den += r.norm_sqr();
                dmax = dmax.max((t - r).norm());
                rmax = rmax.max(r.norm());
            }
        }
        if rmax > 0.0 && dmax / rmax > worst.0 {
            worst = (dmax / rmax, format!("{}:{:?}", o.point, o.direction));
        }
    }
    BasisError {
        overall: (num / den).sqrt(),
        worst: worst.0,
        worst_output: worst.1,
        pairs: outputs.len() * inputs.len(),
    }
}

/// The body's ports in `data`: the scene's element loads on it (inputs) and, as outputs, the
/// same plus each sensor's three translations.
pub fn ports(
    model: &Model,
    scene: &EffectSet,
    body: BodyRef,
    data: &ModalData,
) -> (Vec<LoadCase>, Vec<LoadCase>) {
    let inputs: Vec<LoadCase> = model
        .element_loads(body, scene)
        .iter()
        .filter_map(|l| l.case(data))
        .collect();
    let mut outputs = inputs.clone();
    for s in model.sensors.iter().filter(|s| s.body == body) {
        if let Some(p) = point_at(data, s.point) {
            for a in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
                outputs.push(LoadCase::force(&p.name, a));
            }
        }
    }
    (inputs, outputs)
}

/// `data` cut as a scene with `cutoff` Hz cuts it (`ModalData::cut`, as `ModalBody::new`).
pub fn cut(data: &ModalData, cutoff: f64, inputs: &[LoadCase]) -> ModalData {
    let mut d = data.clone();
    d.cut(cutoff, inputs);
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_modes() -> (Elastic, ModalData) {
        let m = washdyn_models::reference();
        let e = m
            .elastic
            .iter()
            .find(|e| e.name == "cabinet")
            .unwrap()
            .clone();
        // Two eigenmodes, nothing folded: no correction, no loads.
        let mut d = e.data.as_ref().unwrap().without_correction();
        d.truncate(2, &[]);
        assert_eq!(d.modes(), 2);
        (e, d)
    }

    /// One port, two modes: the closed form of the receptance, and a basis that drops the
    /// second mode missing exactly that mode's term.
    #[test]
    fn receptance_is_the_modal_sum_and_the_error_is_the_dropped_term() {
        let (e, d) = two_modes();
        let r = Damped::new(&e, &d);
        let p = &d.points[0];
        let c = LoadCase::force(&p.name, [0.0, 0.0, 1.0]);
        let f = 37.0;
        let term = |k: usize| {
            let wk = 2.0 * std::f64::consts::PI * d.frequencies[k];
            let w = 2.0 * std::f64::consts::PI * f;
            p.w[2][k] * p.w[2][k] / Complex::new(wk * wk - w * w, 2.0 * r.zeta[k] * wk * w)
        };
        let h = r.receptance(&c, &c, f);
        assert!((h - term(0) - term(1)).norm() <= 1e-15 * h.norm());
        // Mode 1 alone (no fold: no load cases), one frequency: the error is |term(1)| / |h|.
        let mut one = d.clone();
        one.truncate(1, &[]);
        let t = Damped::new(&e, &one);
        let one = std::slice::from_ref(&c);
        let err = basis_error(&r, &t, one, one, &[f]);
        let expected = term(1).norm() / h.norm();
        assert!(
            (err.worst - expected).abs() <= 1e-12 * expected,
            "{err:?} vs {expected}"
        );
        assert!((err.overall - expected).abs() <= 1e-12 * expected);
    }

    /// The fold answers its own load statically: at 0.01 Hz the cut basis with the port as a
    /// load case matches the full receptance (1e-9 relative; without the fold the dropped
    /// mode's static share, 0.1 of the whole or more, is missing).
    #[test]
    fn folded_basis_is_exact_at_low_frequency() {
        let (e, d) = two_modes();
        let r = Damped::new(&e, &d);
        let c = LoadCase::force(&d.points[0].name, [0.0, 0.0, 1.0]);
        let folded = cut(&d, d.frequencies[0], std::slice::from_ref(&c));
        // The folded shape is a correction mode, not an eigenmode.
        assert_eq!((folded.eigenmodes(), folded.modes()), (1, 2));
        let folded = Damped::new(&e, &folded);
        let bare = {
            let mut b = d.clone();
            b.truncate(1, &[]);
            b
        };
        let bare = Damped::new(&e, &bare);
        let f = [0.01];
        let one = std::slice::from_ref(&c);
        let ef = basis_error(&r, &folded, one, one, &f);
        let eb = basis_error(&r, &bare, one, one, &f);
        assert!(ef.worst < 1e-9, "folded {ef:?}");
        assert!(eb.worst > 1e-3, "bare {eb:?}");
    }
}
