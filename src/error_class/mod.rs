//! The error class a run reports (`washdyn run`, each sweep variant), from the committed study
//! only: a class is printed when the study measured the same model content (a hash of the
//! model as the scene runs it), the same scene, method and tolerance (nearest within half a
//! decade), over the same window (within [`WINDOW_SLACK`] of its length). And the warning for a
//! tolerance no class covers. Below the runners (`run`, the sweep, the study), which look it up;
//! the accuracy study (`accuracy`) writes the record it reads (`record.rs`).

use crate::simulation::Simulation;
use std::sync::OnceLock;
use washdyn_model::ir::files::content_hash as fnv1a64;
use washdyn_model::ir::{Effect, EffectSet, Model};
use washdyn_ode::Method;
use washdyn_runtime::run::Summary;

mod record;
pub use record::{Study, Trial, Window, WindowStudy};

/// Error classes a run is told it reaches (relative RMS error of the sensor accelerations).
pub const CLASSES: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// The committed study (`docs/accuracy.json`), compiled in for the error class.
const COMMITTED: &str = include_str!("../../docs/accuracy.json");

/// How far a run's window may lie from the study's at either end, as a fraction of the
/// study's window: a class measured over the 178 s run-up says nothing of its first 0.05 s
/// (nor of 150 s), but a run-up cut a second short is the same run-up.
pub const WINDOW_SLACK: f64 = 0.01;

/// An order amplitude error, dB, as the study's report prints it.
pub(crate) fn db(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.3}"))
}

/// The committed study, parsed once.
pub fn committed() -> Option<&'static Study> {
    static STUDY: OnceLock<Option<Study>> = OnceLock::new();
    STUDY
        .get_or_init(|| serde_json::from_str(COMMITTED).ok())
        .as_ref()
}

/// A run's setting as the class is looked up by.
#[derive(Clone, Debug)]
pub struct Query<'a> {
    pub scene: &'a str,
    pub method: Method,
    /// Relative tolerance; rk4: its step, s.
    pub tol: f64,
    /// The run's window (t_start, t_end), s.
    pub window: (f64, f64),
}

/// The model's content as `scene` runs it, hashed (FNV-1a, 64 bits, hex): the model's IR
/// with its modal data, less what does not enter the scene's equations: the model's name, its
/// other scenes (the scene counts as its resolved effects and mode cut-off), the contacts
/// unless the scene has `contact`, the counterweights and their bolts unless it has
/// `counterweights`, a friction damper's moving part unless the scene has its
/// `damper_mass` and the parameters of the friction law the scene does not run, and the names of the data files (their content is in the IR). Every
/// `elastic` entry stays: a rigid scene takes the drum's FE mass and inertia from its data.
pub fn content_hash(model: &Model, scene: &EffectSet) -> String {
    let mut m = model.clone();
    m.name.clear();
    m.scenes.clear();
    // Which numbers the generated code takes as inputs is not the physics.
    m.free.clear();
    if !scene.has(&Effect::Contact) {
        m.contacts.clear();
    }
    if !scene.has(&Effect::Counterweights) {
        m.counterweights.clear();
        m.bolted_joints.clear();
    }
    for d in &mut m.friction_dampers {
        let massive =
            scene.has(&Effect::FrictionDampers) && scene.has(&Effect::DamperMass(d.name.clone()));
        if !massive {
            d.moving_part = None;
        }
        // The law the scene runs, with its parameters only (the moving part's friction is
        // arctan's: its slope stays).
        d.law = scene.friction_law(d.law);
        if d.law.is_arctan() {
            (d.axial_stiffness, d.breakaway) = (None, None);
        } else if !massive {
            d.slope = 0.0;
        }
    }
    for e in &mut m.elastic {
        e.file.clear();
        // The data the scene runs: the tub's `bare` data where it bolts the counterweights on.
        let bare = e.bare_data.take();
        if scene.has(&Effect::Counterweights) && bare.is_some() {
            e.data = bare;
        }
        e.bare = None;
        // The curves are the model's only where the scene switches them on.
        e.curves = None;
        if !scene.has(&Effect::CharacteristicCurves(e.name.clone())) {
            e.curves_data = None;
        }
        // A body the scene keeps rigid takes its FE model's mass, centre of gravity and
        // inertia (and feet), not its modes: a new solve of the modes does not void a study of
        // the rigid machine.
        if let Some(d) = &mut e.data
            && !scene.has(&Effect::Elastic(e.name.clone()))
        {
            d.source.clear();
            d.frequencies.clear();
            d.elementary = washdyn_model::ir::modal::Elementary {
                c: Default::default(),
                s: Default::default(),
                g: Default::default(),
            };
            d.points.clear();
            d.geometric_stiffness = None;
            d.correction = None;
            d.basis = None;
            d.file_modes = None;
        }
    }
    m.speed.csv = None;
    let effects: Vec<String> = scene.effects.iter().map(|e| e.name()).collect();
    let text = serde_json::to_string(&(&m, &scene.name, effects, scene.mode_cutoff))
        .expect("the IR serialises");
    fnv1a64(text.as_bytes())
}

/// Does the run's window lie within [`WINDOW_SLACK`] of the study's at both ends?
pub fn same_window(study: &Window, (t0, t1): (f64, f64)) -> bool {
    let slack = WINDOW_SLACK * (study.t1 - study.t0);
    (t0 - study.t0).abs() <= slack && (t1 - study.t1).abs() <= slack
}

/// [`class_in`] of the committed study.
pub fn committed_class(q: &Query, hash: &mut dyn FnMut() -> String) -> Option<String> {
    class_in(committed()?, q, hash)
}

/// What `study` measured for this setting: the error class (the smallest class at least as
/// large as the measured error) and a sentence saying where it comes from. `None` unless the
/// study has a window of this scene over the same window, measured on a model whose content
/// hash is `hash()` (called only when everything else matches), with a run of this method
/// within half a decade of `tol`.
pub fn class_in(study: &Study, q: &Query, hash: &mut dyn FnMut() -> String) -> Option<String> {
    let w = study
        .windows
        .iter()
        .find(|w| w.window.scene == q.scene && same_window(&w.window, q.window))?;
    let t = w
        .trials
        .iter()
        .filter(|t| t.method == q.method.name() && t.accel_err.is_some())
        // The measured setting nearest in log(tol): tolerances a decade apart.
        .min_by(|a, b| {
            (a.tol.ln() - q.tol.ln())
                .abs()
                .total_cmp(&(b.tol.ln() - q.tol.ln()).abs())
        })?;
    if (t.tol.ln() - q.tol.ln()).abs() > 0.5 * 10f64.ln() {
        return None;
    }
    // A window without a hash was measured on a model nobody recorded.
    let measured_on = w.model_hash.as_deref()?;
    if hash() != measured_on {
        return None;
    }
    let err = t.accel_err?;
    let class = CLASSES
        .iter()
        .rev()
        .find(|c| err <= **c)
        .map_or_else(|| "worse than 1e-2".to_string(), |c| format!("{c:.0e}"));
    Some(format!(
        "{class} (docs/accuracy.md: {} at {:e} on scene {}, t = {} .. {} s, measured \
         acceleration error {err:.1e}, order amplitudes {} dB)",
        q.method.name(),
        t.tol,
        q.scene,
        w.window.t0,
        w.window.t1,
        db(t.order_db)
    ))
}

/// What the committed study says of a simulation's setting: the warning for a tolerance no
/// error class covers, and the class it measured for this setting. The commands that run
/// (`run`, `sweep`, `study`) look it up for their summaries; the set-up knows no report.
#[derive(Clone, Debug, Default)]
pub struct Verdict {
    pub warning: Option<String>,
    pub class: Option<String>,
}

impl Verdict {
    /// Of `sim`, before it runs.
    pub fn of(sim: &Simulation) -> Verdict {
        Verdict {
            warning: tolerance_warning(sim.method, sim.options.rtol),
            class: error_class(sim),
        }
    }

    /// Into the summary of the run: the warning first, the class only for a run that completed.
    pub fn apply(self, s: &mut Summary, completed: bool) {
        if let Some(w) = self.warning {
            s.warnings.insert(0, w);
        }
        if completed {
            s.error_class = self.class;
        }
    }
}

/// The error class the committed study measured for `sim`'s setting: the same model content,
/// scene, method, tolerance and window; none off generalized-alpha's default spectral radius
/// (the study measured that one).
pub fn error_class(sim: &Simulation) -> Option<String> {
    if sim
        .rho_inf
        .is_some_and(|r| r != washdyn_ode::Options::default().rho_inf)
    {
        return None;
    }
    committed_class(
        &Query {
            scene: &sim.scene.name,
            method: sim.method,
            tol: sim.class_tolerance(),
            window: (sim.run.t_start, sim.run.t_end),
        },
        &mut || content_hash(&sim.source.model, &sim.scene),
    )
}

/// The warning for a tolerance no error class covers: `tol` at or above the loosest class
/// (1e-2; a method's global error exceeds its local tolerance), for the methods `tol` steers
/// (not rk4). It says what the committed study measured at this method's loosest tolerance.
pub fn tolerance_warning(method: Method, tol: f64) -> Option<String> {
    let loosest = CLASSES[0];
    if method == Method::Rk4 || tol.is_nan() || tol < loosest {
        return None;
    }
    let measured = committed().and_then(|s| {
        let runs: Vec<(f64, f64)> = s
            .windows
            .iter()
            .flat_map(|w| &w.trials)
            .filter(|t| t.method == method.name())
            .filter_map(|t| Some((t.tol, t.accel_err?)))
            .collect();
        let tl = runs.iter().map(|r| r.0).reduce(f64::max)?;
        let err = runs
            .iter()
            .filter(|r| r.0 == tl)
            .map(|r| r.1)
            .reduce(f64::max)?;
        Some((tl, err))
    });
    let what = match measured {
        Some((tl, err)) => format!(
            "the study measured {} no looser than --tol {tl:e}, where its acceleration error \
             reached {err:.1e}",
            method.name()
        ),
        None => format!("the study did not measure {}", method.name()),
    };
    Some(format!(
        "--tol {tol:e} is not tighter than the loosest error class ({loosest:e}, relative RMS \
         error of the accelerations; docs/accuracy.md): no class bounds this run's error, and \
         {what}"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed study answers for the settings it measured on a window whose model it
    /// recorded, with the measured error inside the class it names, and nothing for another
    /// scene, model content, window or tolerance.
    #[test]
    fn error_class_comes_from_the_committed_study() {
        let s = committed().expect("docs/accuracy.json parses");
        let w = s
            .windows
            .iter()
            .find(|w| w.model_hash.is_some())
            .expect("a window with its model's hash");
        let hash = w.model_hash.clone().unwrap();
        let t = w.trials.iter().find(|t| t.accel_err.is_some()).unwrap();
        let q = Query {
            scene: &w.window.scene,
            method: t.method.parse().unwrap(),
            tol: t.tol,
            window: (w.window.t0, w.window.t1),
        };
        let c = committed_class(&q, &mut || hash.clone()).unwrap();
        let err = t.accel_err.unwrap();
        match CLASSES.iter().rev().find(|c| err <= **c) {
            Some(cl) => assert!(c.starts_with(&format!("{cl:.0e}")), "{c}"),
            None => assert!(c.starts_with("worse than"), "{c}"),
        }
        let none = |q: &Query, h: &str| committed_class(q, &mut || h.to_string());
        let other = Query {
            scene: "no_such_scene",
            ..q.clone()
        };
        assert_eq!(none(&other, &hash), None);
        assert_eq!(none(&q, "0000000000000000"), None);
        // Two decades off every measured tolerance: no claim.
        assert_eq!(
            none(
                &Query {
                    tol: 1e-12,
                    ..q.clone()
                },
                &hash
            ),
            None
        );
        // A window 2 % of the study's shorter: no claim; 0.5 % shorter: the same run.
        let len = w.window.t1 - w.window.t0;
        let cut = |f: f64| Query {
            window: (w.window.t0, w.window.t1 - f * len),
            ..q.clone()
        };
        assert_eq!(none(&cut(0.02), &hash), None);
        assert!(none(&cut(0.005), &hash).is_some());
    }

    /// The hash is of what the scene runs: the model's name, the other scenes and the parts
    /// only other scenes use (contacts, damper moving parts, the modes of a body it keeps
    /// rigid) leave it; a number the scene uses (a spring's stiffness, the drum's FE mass in a
    /// rigid scene, the tub's modes in an elastic one) changes it.
    #[test]
    fn content_hash_is_the_scenes_content() {
        let m = washdyn_models::reference();
        let full = m.scene(Some("full")).unwrap();
        let h = content_hash(&m, &full);
        let mut renamed = m.clone();
        renamed.name = "other".into();
        renamed.free.clear();
        renamed.scenes.retain(|s| s.name == "full");
        renamed.contacts.clear();
        for d in &mut renamed.friction_dampers {
            d.moving_part = None;
        }
        assert_eq!(content_hash(&renamed, &full), h);
        let mut stiffer = m.clone();
        stiffer.springs[0].stiffness *= 1.0 + 1e-12;
        assert_ne!(content_hash(&stiffer, &full), h);
        let mut drum = m.clone();
        let e = drum.elastic.iter_mut().find(|e| e.name == "drum").unwrap();
        e.data.as_mut().unwrap().mass += 1e-9;
        assert_ne!(content_hash(&drum, &full), h);
        // A body's modes (a new solve) count only where the scene keeps it elastic.
        let mut modes = m.clone();
        let e = modes.elastic.iter_mut().find(|e| e.name == "tub").unwrap();
        e.data.as_mut().unwrap().frequencies[0] *= 1.0 + 1e-9;
        assert_eq!(content_hash(&modes, &full), h);
        let elastic = m.scene(Some("elastic")).unwrap();
        assert_ne!(content_hash(&modes, &elastic), content_hash(&m, &elastic));
        // The contacts count where the scene has them.
        let contact = m.scene(Some("contact")).unwrap();
        let mut moved = m.clone();
        moved.contacts[0].gap += 1e-3;
        assert_ne!(content_hash(&moved, &contact), content_hash(&m, &contact));
    }

    /// 1e-2 is the loosest class: from there on a tolerance-steered method warns, rk4 (whose
    /// --tol steers nothing) does not.
    #[test]
    fn a_tolerance_beyond_every_class_warns() {
        assert!(tolerance_warning(Method::Dopri5, 1e-3).is_none());
        let w = tolerance_warning(Method::Dopri5, 1e-2).unwrap();
        assert!(w.starts_with("--tol 1e-2 is not tighter than the loosest error class"));
        assert!(tolerance_warning(Method::Auto, 5e-2).is_some());
        assert!(tolerance_warning(Method::Rk4, 5e-2).is_none());
    }
}
