//! Free parameters (`Model::free`): numbers the generated code takes from its parameter array
//! instead of folding them in, so that a study runs every variant that differs only in them on
//! one build.
//!
//! The derivation is not told about them. Each free number is replaced in the model by a
//! stand-in (its own value with a tag in the last mantissa bits), and the trace turns a
//! constant with a stand-in's bits into a `Param` node (`symbolic::trace_params`). That is
//! right only where the derivation hands the number over unchanged; one it first combines with
//! others while setting up (a rest length from the stiffness, a modal damping times a
//! frequency) arrives as an ordinary constant and would stay folded. So every free parameter is
//! proven: the traced forces and sensors, evaluated at a changed value of that parameter, must
//! equal the derivation on a model with that value, or the model is refused with the parameter's
//! name. A parameter that reaches the mass matrix or a modal table is refused outright: M1's
//! factorisation and tables are built once.

use super::GenError;
use crate::equations::{Drive, Equations};
use crate::ir::check::Path;
use crate::ir::param::{Param, get_all, resolve_all, set};
use crate::ir::{EffectSet, Model};
use crate::symbolic::{Graph, Sym};

/// The model's free parameters, their values and their stand-ins.
#[derive(Clone, Debug, Default)]
pub struct Free {
    pub params: Vec<Param>,
    pub values: Vec<f64>,
    pub stand_ins: Vec<f64>,
}

impl Free {
    pub fn of(model: &Model) -> Result<Free, GenError> {
        let params = resolve_all(model, &model.free)
            .into_iter()
            .enumerate()
            .map(|(k, r)| r.map_err(|e| GenError::free(k, e.to_string())))
            .collect::<Result<Vec<_>, _>>()?;
        if params.len() > 0x7ff {
            return Err(GenError::free(
                0x7ff,
                format!("{} free parameters; at most 2047", params.len()),
            ));
        }
        let values = get_all(model, &params).map_err(|e| GenError::free(0, e.to_string()))?;
        let stand_ins = values
            .iter()
            .enumerate()
            .map(|(i, v)| f64::from_bits((v.to_bits() & !0xfff) | 0x800 | i as u64))
            .collect();
        Ok(Free {
            params,
            values,
            stand_ins,
        })
    }

    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    /// The model with every free number replaced by its stand-in: what the trace runs on.
    pub fn stand_in_model(&self, model: &Model) -> Result<Model, GenError> {
        if self.is_empty() {
            return Ok(model.clone());
        }
        set(model, &self.params, &self.stand_ins).map_err(|e| GenError::at(Path::default(), e))
    }

    fn name(&self, k: u32) -> &str {
        &self.params[k as usize].text
    }

    /// Refuse parameters in M1 or in a table, then prove each of the others: at a changed value,
    /// the traced h and sensor channels equal the derivation's on the changed model.
    pub fn verify(
        &self,
        model: &Model,
        scene: &EffectSet,
        mh: (&Graph, &[Sym], &[Sym]),
        sensors: (&Graph, &[Sym]),
    ) -> Result<(), GenError> {
        if self.is_empty() {
            return Ok(());
        }
        let (g, m1, h) = mh;
        let refuse = |ks: Vec<u32>, what: &str| -> Result<(), GenError> {
            match ks.first() {
                Some(&k) => Err(GenError::free(
                    k as usize,
                    format!(
                        "free parameter `{}` enters {what} of scene `{}`, which the generated code \
                     builds once; fold it (remove it from `free`) and let the interpreter run \
                     its variants",
                        self.name(k),
                        scene.name
                    ),
                )),
                None => Ok(()),
            }
        };
        refuse(g.params_used(m1), "the mass matrix M1")?;
        refuse(g.params_in_tables(), "a modal table")?;
        refuse(sensors.0.params_in_tables(), "a sensor's modal table")?;
        let eq0 = Equations::new(model, scene);
        let n = eq0.layout.n();
        let n1 = eq0.layout.n1;
        // A state away from rest, with every coordinate and rate non-zero.
        let q: Vec<f64> = (0..n).map(|i| 1e-3 * (0.7 + i as f64).sin()).collect();
        let qd: Vec<f64> = (0..n).map(|i| 1e-2 * (1.3 + i as f64).cos()).collect();
        let qdd: Vec<f64> = (0..n).map(|i| 0.1 * (0.4 + i as f64).sin()).collect();
        let d = Drive {
            phi: 0.3,
            omega: 40.0,
            omega_dot: 2.0,
        };
        // Element states inside their elastic range and past it.
        let nz = eq0.layout.nz;
        let z: Vec<f64> = (0..nz).map(|i| 1e-4 * (0.9 + i as f64).sin()).collect();
        let mut inputs: Vec<f64> = q.iter().chain(&qd).copied().collect();
        inputs.extend([d.phi, d.omega, d.omega_dot]);
        inputs.extend(&z);
        let mut s_inputs: Vec<f64> = q.iter().chain(&qd).chain(&qdd).copied().collect();
        s_inputs.extend([d.phi, d.omega, d.omega_dot]);
        for k in 0..self.params.len() {
            let mut p = self.values.clone();
            p[k] = if p[k] == 0.0 { 1.0 } else { 1.25 * p[k] };
            let changed =
                set(model, &self.params, &p).map_err(|e| GenError::free(k, e.to_string()))?;
            let eq = Equations::new(&changed, scene);
            let mut m1f = vec![0.0; n1 * n1];
            let mut hf = vec![0.0; n + nz];
            let (hm, zd) = hf.split_at_mut(n);
            eq.eval_states(&d, &q, &qd, &z, &mut m1f, hm);
            eq.state_rates(&q, &qd, &z, zd);
            let mut sf = Vec::new();
            for i in 0..eq.sensors.len() {
                sf.extend(eq.sensor(i, &d, &q, &qd, &qdd));
            }
            let hg = g.eval_params(&inputs, &p, h);
            let sg = sensors.0.eval_params(&s_inputs, &p, sensors.1);
            let off = |a: &[f64], b: &[f64]| {
                let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let diff = a
                    .iter()
                    .zip(b)
                    .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
                diff / scale.max(f64::MIN_POSITIVE)
            };
            let (eh, es) = (off(&hf, &hg), off(&sf, &sg));
            if !(eh <= 1e-9 && (sf.is_empty() || es <= 1e-9)) {
                return Err(GenError::free(
                    k,
                    format!(
                        "free parameter `{}`: the generated forces of scene `{}` do not follow it \
                     (relative difference {:.1e} in h, {:.1e} in the sensors at {} instead of \
                     {}): the model combines it with other numbers before the equations use it; \
                     fold it (remove it from `free`) and let the interpreter run its variants",
                        self.name(k as u32),
                        scene.name,
                        eh,
                        es,
                        p[k],
                        self.values[k]
                    ),
                ));
            }
        }
        Ok(())
    }
}
