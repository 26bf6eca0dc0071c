//! A study's variants: the base model with a design point's values set (`ir::param::set`) and
//! judged by the one checker, every variant before anything runs or is written. Ids are the
//! design order, zero-padded (`0000`, `0001`, ...), so a re-run of the same study names the same
//! variant the same. Models are rebuilt from their values where they run, not kept: a study of
//! an elastic machine holds its modal data once, not once a variant.

use super::error::{BadVariant, StudyError};
use super::file::{Study, touches_speed};
use crate::error::Error;
use crate::simulation::{RunControl, Simulation};
use rayon::prelude::*;
use washdyn_model::ir::Model;
use washdyn_model::ir::check::{CheckError, check};
use washdyn_model::ir::param;

/// One design point: its id and its parameter values (the study's parameters' order).
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    pub id: String,
    pub values: Vec<f64>,
}

/// Digits of an id: four, more for a study of more than 10 000 variants.
fn width(n: usize) -> usize {
    n.saturating_sub(1).to_string().len().max(4)
}

/// The variants of `study` in design order.
pub fn variants(study: &Study) -> Vec<Variant> {
    let w = width(study.points.len());
    study
        .points
        .iter()
        .enumerate()
        .map(|(i, v)| Variant {
            id: format!("{i:0w$}"),
            values: v.clone(),
        })
        .collect()
}

impl Variant {
    /// The base model with this variant's values, checked: the checker's findings name the
    /// variant, the parameter the finding is at (every parameter where it is elsewhere) and
    /// its value.
    pub fn model(&self, study: &Study) -> Result<Model, BadVariant> {
        let params: Vec<param::Param> = study.parameters.iter().map(|p| p.param.clone()).collect();
        let bad = |named: Vec<usize>, message: String| {
            let named = if named.is_empty() {
                (0..params.len()).collect()
            } else {
                named
            };
            BadVariant {
                id: self.id.clone(),
                values: named
                    .into_iter()
                    .map(|k| (study.parameters[k].text.clone(), self.values[k]))
                    .collect(),
                message,
            }
        };
        // Numbers by their paths; a speed profile by its level's table.
        let numbers: Vec<usize> = (0..params.len())
            .filter(|&k| study.parameters[k].profiles.is_empty())
            .collect();
        let mut model = param::set(
            &study.source.model,
            &numbers
                .iter()
                .map(|&k| params[k].clone())
                .collect::<Vec<_>>(),
            &numbers.iter().map(|&k| self.values[k]).collect::<Vec<_>>(),
        )
        .map_err(|e| bad(Vec::new(), e.to_string()))?;
        for (p, &x) in study.parameters.iter().zip(&self.values) {
            if let Some(f) = p.profiles.get(x as usize) {
                model.speed.table = f.table.clone();
                model.speed.csv = None;
            }
        }
        check(&model).map_err(|errors: Vec<CheckError>| {
            let named = (0..params.len())
                .filter(|&k| {
                    let p = &params[k].path.0;
                    errors.iter().any(|e| {
                        let n = p.len().min(e.path.0.len());
                        p[..n] == e.path.0[..n]
                    })
                })
                .collect();
            let found: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
            bad(named, format!("the model checker: {}", found.join("; ")))
        })?;
        Ok(model)
    }

    /// The variant's control: the study's, the summary labelled `<model>/<id>`.
    pub fn control(&self, study: &Study) -> RunControl {
        RunControl {
            variant: Some(self.id.clone()),
            ..study.control.clone()
        }
    }
}

/// Every variant's model through the checker (and, where a parameter changes the speed
/// profile, through the settings' rules, which read it), on rayon's threads. Any refusal
/// refuses the study, naming each refused variant; nothing has been written then.
pub fn check_all(study: &Study, vars: &[Variant]) -> Result<(), Error> {
    let speed = study.parameters.iter().any(touches_speed);
    let mut bad: Vec<BadVariant> = vars
        .par_iter()
        .filter_map(|v| {
            let model = match v.model(study) {
                Ok(m) => m,
                Err(b) => return Some(b),
            };
            if !speed {
                return None;
            }
            let source = study.source.variant(model);
            Simulation::new(source, &study.spec, &v.control(study))
                .err()
                .map(|e| BadVariant {
                    id: v.id.clone(),
                    values: study
                        .parameters
                        .iter()
                        .zip(&v.values)
                        .filter(|(p, _)| touches_speed(p))
                        .map(|(p, x)| (p.text.clone(), *x))
                        .collect(),
                    message: format!("the run's settings: {e}"),
                })
        })
        .collect();
    if bad.is_empty() {
        return Ok(());
    }
    bad.sort_by(|a, b| a.id.cmp(&b.id));
    Err(StudyError::Variants(bad).into())
}

#[cfg(test)]
mod tests {
    #[test]
    fn ids_are_zero_padded_to_four_digits_or_more() {
        assert_eq!(super::width(1), 4);
        assert_eq!(super::width(10_000), 4);
        assert_eq!(super::width(10_001), 5);
    }
}
