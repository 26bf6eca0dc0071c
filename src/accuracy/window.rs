//! One window of the accuracy study, stage by stage: the reference and its confirmation, the
//! methods' tolerance sweeps, generalized-alpha's spectral radii, the back ends, the modal
//! truncation and the other scenes.

use super::{
    COMPARE_RATE, LONG, RHO_INF, SAMPLE_RATE, SETTLE, Sim, TRUNCATION_CUTS_HZ, Trial, Window,
    WindowStudy, is_elastic, simulate, sweep, trial,
};
use crate::analysis::metrics::{Tracks, order_tracks, trim};
use crate::error::Error;
use crate::simulation::{Backend, Source};
use crate::spec::Field;
use washdyn_model::ir::EffectSet;
use washdyn_ode::Method;
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::run::Progress;
use washdyn_runtime::system::Interpreter;

/// What every stage of a window shares.
pub(super) struct Stages<'a> {
    source: &'a Source,
    scene: EffectSet,
    w: Window,
    backend: Backend,
    quick: bool,
    elastic: bool,
    /// A whole run-up: the comparisons that need their own long runs (back ends, modal
    /// truncation, scenes) are the short windows' job.
    long: bool,
    /// Each run's progress, with its label.
    progress: &'a dyn Fn(&str, Progress),
}

impl<'a> Stages<'a> {
    pub(super) fn new(
        source: &'a Source,
        scene: EffectSet,
        w: Window,
        quick: bool,
        progress: &'a dyn Fn(&str, Progress),
    ) -> Self {
        let backend = if source.built_in.is_some() {
            Backend::Generated
        } else {
            Backend::Interpreted
        };
        Stages {
            source,
            elastic: is_elastic(&scene),
            long: w.t1 - w.t0 > LONG,
            scene,
            w,
            backend,
            quick,
            progress,
        }
    }

    fn run(&self, method: Method, tol: f64, scene: &EffectSet, b: Backend) -> Result<Sim, Error> {
        simulate(
            self.source,
            scene,
            b,
            method,
            tol,
            &self.w,
            None,
            SAMPLE_RATE,
            self.progress,
        )
    }

    /// Every stage of the window.
    pub(super) fn study(&self, log: &mut dyn FnMut(&str)) -> Result<WindowStudy, Error> {
        let (r, rt, reference, confirmation) = self.reference(log)?;
        let trials = self.trials(&r.mem, &rt, log)?;
        let rho_inf = self.rho_inf(&r.mem, &rt, log)?;
        let backends = self.backends(&r.mem, &rt, log)?;
        let (truncation, scenes) = if self.elastic && !self.quick && !self.long {
            (self.truncation(log)?, self.scenes(log)?)
        } else {
            (Vec::new(), Vec::new())
        };
        Ok(WindowStudy {
            window: self.w.clone(),
            model_hash: Some(crate::error_class::content_hash(
                &self.source.model,
                &self.scene,
            )),
            reference,
            confirmation,
            trials,
            backends,
            truncation,
            scenes,
            rho_inf,
        })
    }

    /// The reference and its confirmation by a different method (explicit against implicit).
    fn reference(&self, log: &mut dyn FnMut(&str)) -> Result<(Sim, Tracks, Trial, Trial), Error> {
        let (w, elastic, long) = (&self.w, self.elastic, self.long);
        // A whole elastic run-up: dopri5 runs on its stability limit there, far below 1e-8.
        let (ref_tol, conf_tol) = if self.quick || (elastic && long) {
            (1e-8, 1e-7)
        } else if elastic {
            (1e-9, 1e-8)
        } else {
            (1e-10, 1e-9)
        };
        let r = self.run(Method::Dopri5, ref_tol, &self.scene, self.backend)?;
        if let Some(e) = r.error {
            return Err(Error::Reference(Box::new(e)));
        }
        let rt = order_tracks(&r.mem, w.t0, SAMPLE_RATE);
        let reference = trial("dopri5", ref_tol, &r, Some((&r.mem, &rt)));
        log(&format!(
            "{}: reference dopri5 {ref_tol:e}, {:.2} s",
            w.scene, reference.wall_s
        ));
        // A whole elastic run-up: rodas4 at 1e-7 would run for hours (it is held by accuracy
        // as dopri5 is by stability, at about 15 000 steps per simulated second) and the
        // run's stall guard stops it; dopri5 a decade looser confirms the reference there.
        let conf_method = if elastic && long {
            Method::Dopri5
        } else {
            Method::Rodas4
        };
        let c = self.run(conf_method, conf_tol, &self.scene, self.backend)?;
        let confirmation = trial(conf_method.name(), conf_tol, &c, Some((&r.mem, &rt)));
        log(&format!(
            "{}: confirmation {conf_method} {conf_tol:e}: accel {:?}, orders {:?} dB, {}",
            w.scene, confirmation.accel_err, confirmation.order_db, confirmation.status
        ));
        Ok((r, rt, reference, confirmation))
    }

    /// Each method over its tolerances.
    fn trials(
        &self,
        r: &MemorySink,
        rt: &Tracks,
        log: &mut dyn FnMut(&str),
    ) -> Result<Vec<Trial>, Error> {
        let mut trials = Vec::new();
        for (m, tols) in sweep(self.quick, self.elastic, self.long) {
            for tol in tols {
                let s = self.run(m, tol, &self.scene, self.backend)?;
                let t = trial(m.name(), tol, &s, Some((r, rt)));
                log(&format!(
                    "{}: {} {tol:e}: {} steps, {:.3} s, accel {:?}, orders {:?} dB, {}",
                    self.w.scene, m, t.steps, t.wall_s, t.accel_err, t.order_db, t.status
                ));
                trials.push(t);
            }
        }
        Ok(trials)
    }

    /// Generalized-alpha's numerical damping of the unresolved modes: each spectral radius at
    /// the tolerance of its error class 1e-3 (a whole run-up: left to the short windows).
    fn rho_inf(
        &self,
        r: &MemorySink,
        rt: &Tracks,
        log: &mut dyn FnMut(&str),
    ) -> Result<Vec<(f64, Trial)>, Error> {
        let mut rho_inf = Vec::new();
        if self.long {
            return Ok(rho_inf);
        }
        let tol = if self.elastic || self.quick {
            1e-5
        } else {
            1e-6
        };
        for rho in RHO_INF {
            let m = Method::GeneralizedAlpha;
            let (src, sc, w) = (self.source, &self.scene, &self.w);
            let s = simulate(
                src,
                sc,
                self.backend,
                m,
                tol,
                w,
                Some(rho),
                SAMPLE_RATE,
                self.progress,
            )?;
            let t = trial(m.name(), tol, &s, Some((r, rt)));
            log(&format!(
                "{}: galpha {tol:e} rho_inf {rho}: {} steps, {:.3} s, accel {:?}, orders {:?} dB, {}",
                w.scene, t.steps, t.wall_s, t.accel_err, t.order_db, t.status
            ));
            rho_inf.push((rho, t));
        }
        Ok(rho_inf)
    }

    /// Generated against interpreted, dopri5 at 1e-6.
    fn backends(
        &self,
        r: &MemorySink,
        rt: &Tracks,
        log: &mut dyn FnMut(&str),
    ) -> Result<Option<(Trial, Trial)>, Error> {
        if self.source.built_in.is_none() || self.quick || self.long {
            return Ok(None);
        }
        let g = self.run(Method::Dopri5, 1e-6, &self.scene, Backend::Generated)?;
        let i = self.run(Method::Dopri5, 1e-6, &self.scene, Backend::Interpreted)?;
        let tg = trial("dopri5", 1e-6, &g, Some((r, rt)));
        // The interpreter against the generated run at the same setting: round-off only.
        let gt = order_tracks(&g.mem, self.w.t0, SAMPLE_RATE);
        let ti = trial("dopri5", 1e-6, &i, Some((&g.mem, &gt)));
        log(&format!(
            "{}: generated {:.3} s, interpreted {:.3} s, difference {:?}",
            self.w.scene, tg.wall_s, ti.wall_s, ti.accel_err
        ));
        Ok(Some((tg, ti)))
    }

    /// A model comparison's run, from SETTLE before the window (compared inside it).
    fn early(&self, method: Method, tol: f64, scene: &EffectSet, b: Backend) -> Result<Sim, Error> {
        let early = self.early_window();
        simulate(
            self.source,
            scene,
            b,
            method,
            tol,
            &early,
            None,
            COMPARE_RATE,
            self.progress,
        )
    }

    /// The window of the model comparisons' runs: from SETTLE before this one.
    fn early_window(&self) -> Window {
        Window {
            t0: (self.w.t0 - SETTLE).max(0.0),
            ..self.w.clone()
        }
    }

    /// The samples of an early run before this window.
    fn skip(&self) -> usize {
        ((self.w.t0 - self.early_window().t0) * COMPARE_RATE).round() as usize
    }

    /// Modal truncation (interpreted: any cut-off), against the finest.
    fn truncation(&self, log: &mut dyn FnMut(&str)) -> Result<Vec<(f64, usize, Trial)>, Error> {
        let (w, skip) = (&self.w, self.skip());
        let finest = EffectSet {
            mode_cutoff: None,
            ..self.scene.clone()
        };
        let f = self.early(Method::Dopri5, 1e-7, &finest, Backend::Interpreted)?;
        let fm = trim(&f.mem, skip, "");
        let ft = order_tracks(&fm, w.t0, COMPARE_RATE);
        let mut truncation = Vec::new();
        for c in TRUNCATION_CUTS_HZ {
            let sc = EffectSet {
                mode_cutoff: Some(c),
                ..self.scene.clone()
            };
            let n = Interpreter::new(&self.source.model, &sc).eq.layout.n();
            let mut s = self.early(Method::Dopri5, 1e-7, &sc, Backend::Interpreted)?;
            s.mem = trim(&s.mem, skip, "");
            s.summary.t_start = w.t0;
            let t = trial("dopri5", 1e-7, &s, Some((&fm, &ft)));
            log(&format!(
                "{}: modes to {c:.0} Hz ({n} coordinates): accel {:?}, orders {:?} dB, {:.2} s",
                w.scene, t.accel_err, t.order_db, t.wall_s
            ));
            truncation.push((c, n, t));
        }
        Ok(truncation)
    }

    /// Other scenes against this one (the full model is the elastic scene).
    fn scenes(&self, log: &mut dyn FnMut(&str)) -> Result<Vec<(String, Trial)>, Error> {
        let (w, skip, model) = (&self.w, self.skip(), &self.source.model);
        // Tub channels only: the rigid scenes' cabinet is fixed and reads zero.
        let e = self.early(Method::Dopri5, 1e-7, &self.scene, self.backend)?;
        let em = trim(&e.mem, skip, "tub");
        let et = order_tracks(&em, w.t0, COMPARE_RATE);
        let mut scenes = Vec::new();
        for other in &model.scenes {
            if other.name == w.scene {
                continue;
            }
            let sc = model
                .scene(Some(&other.name))
                .map_err(|m| Error::setting(Field::Scene, m))?;
            let mut s = self.early(Method::Dopri5, 1e-7, &sc, self.backend)?;
            s.mem = trim(&s.mem, skip, "tub");
            s.summary.t_start = w.t0;
            let t = trial("dopri5", 1e-7, &s, Some((&em, &et)));
            log(&format!(
                "{}: scene {} against it: accel {:?}, orders {:?} dB, {:.2} s",
                w.scene, other.name, t.accel_err, t.order_db, t.wall_s
            ));
            scenes.push((other.name.clone(), t));
        }
        Ok(scenes)
    }
}
