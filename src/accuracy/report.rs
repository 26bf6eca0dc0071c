//! The study's report: `accuracy.md`, `accuracy.json` and the work-precision plots.

use super::{CLASSES, COMPARE_RATE, SETTLE, Study, Trial, WindowStudy};
use crate::analysis::metrics::BAND_HZ;
use crate::analysis::plot::init_fonts;
use crate::error::Error;
use crate::error_class::db;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

pub(super) fn e(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.1e}"))
}

/// For each error class, the cheapest (wall time) setting measured that reaches it.
pub fn recommend(trials: &[Trial]) -> Vec<(f64, Option<&Trial>)> {
    CLASSES
        .iter()
        .map(|&c| {
            let best = trials
                .iter()
                .filter(|t| t.accel_err.is_some_and(|e| e <= c))
                .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
            (c, best)
        })
        .collect()
}

fn setting(t: &Trial) -> String {
    if t.method == "rk4" {
        format!("rk4 --step {:e}", t.tol)
    } else {
        format!("{} --tol {:e}", t.method, t.tol)
    }
}

/// `accuracy.md` from the study.
pub fn markdown(s: &Study) -> String {
    let mut m = String::new();
    let _ = writeln!(m, "# What accuracy costs in time: model `{}`\n", s.model);
    let _ = writeln!(
        m,
        "Regenerate with `{}` (release build; every number below is from that one run, on one \
         core of the machine it ran on).\n",
        s.command
    );
    m += "Errors are against a reference at a tight tolerance (dopri5), confirmed by a second \
          method (rodas4); the difference of the two is stated. **accel** is the largest \
          relative RMS error over time of the acceleration channels; **orders** the largest \
          error in dB of the order tracks of orders 1 to 3 over all acceleration channels and \
          blocks (where the reference is within 40 dB of the track's peak). Wall time is the \
          whole run (integration and sampling at 2 kHz). rk4's `tol` column is its step in s.\n\n";
    for w in &s.windows {
        window_head(&mut m, w);
        trials(&mut m, w);
        method_extras(&mut m, w);
        model_comparisons(&mut m, w);
    }
    m
}

/// A window's title, its model's content hash, the reference and its confirmation.
fn window_head(m: &mut String, w: &WindowStudy) {
    let _ = writeln!(
        m,
        "## Scene `{}`, t = {} .. {} s\n",
        w.window.scene, w.window.t0, w.window.t1
    );
    if let Some(h) = &w.model_hash {
        let _ = writeln!(
            m,
            "Model content hash `{h}` (`error_class::content_hash`): a run reports \
             an error class from this window only for this content.\n"
        );
    }
    let _ = writeln!(
        m,
        "Reference: dopri5 at rtol {:e}, {} steps, {:.2} s. Confirmation: {} at rtol {:e}, \
         {} steps, {:.2} s; it differs from the reference by accel {} and orders {} dB.\n",
        w.reference.tol,
        w.reference.steps,
        w.reference.wall_s,
        w.confirmation.method,
        w.confirmation.tol,
        w.confirmation.steps,
        w.confirmation.wall_s,
        e(w.confirmation.accel_err),
        db(w.confirmation.order_db)
    );
}

/// The methods' trials, the work-precision plot, the cheapest setting per target.
fn trials(m: &mut String, w: &WindowStudy) {
    *m += "| method | tol | steps | rejected | f evals | Jacobians | LU | wall s | accel | orders dB | status |\n";
    *m += "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for t in &w.trials {
        let _ = writeln!(
            m,
            "| {} | {:e} | {} | {} | {} | {} | {} | {:.3} | {} | {} | {} |",
            t.method,
            t.tol,
            t.steps,
            t.rejected,
            t.rhs_evals,
            t.jacobians,
            t.lu,
            t.wall_s,
            e(t.accel_err),
            db(t.order_db),
            t.status
        );
    }
    let _ = writeln!(
        m,
        "\n![work-precision {}](accuracy_{}.png)\n",
        w.window.scene, w.window.scene
    );
    *m += "Cheapest measured setting for a target error on the accelerations:\n\n";
    *m += "| target | setting | wall s | accel | orders dB |\n|---|---|---|---|---|\n";
    for (c, t) in recommend(&w.trials) {
        match t {
            Some(t) => {
                let _ = writeln!(
                    m,
                    "| {c:.0e} | `{}` | {:.3} | {} | {} |",
                    setting(t),
                    t.wall_s,
                    e(t.accel_err),
                    db(t.order_db)
                );
            }
            None => {
                let _ = writeln!(m, "| {c:.0e} | none measured | | | |");
            }
        }
    }
    m.push('\n');
}

/// Generated against interpreted, and generalized-alpha's spectral radii.
fn method_extras(m: &mut String, w: &WindowStudy) {
    if let Some((g, i)) = &w.backends {
        let _ = writeln!(
            m,
            "Generated against interpreted (dopri5, rtol 1e-6): {:.3} s against {:.3} s, \
             ratio {:.2}; the two runs differ by accel {} and orders {} dB.\n",
            g.wall_s,
            i.wall_s,
            i.wall_s / g.wall_s,
            e(i.accel_err),
            db(i.order_db)
        );
    }
    if let Some((_, t0)) = w.rho_inf.first() {
        let _ = writeln!(
            m,
            "Generalized-alpha's spectral radius at infinity (`--rho-inf`; rtol {:e}): \
             the amplitude it leaves a mode it does not resolve per step, 1 keeping such \
             modes undamped, 0 removing them in one step; the default 0.8.\n",
            t0.tol
        );
        *m += "| rho_inf | steps | rejected | wall s | accel | orders dB | status |\n|---|---|---|---|---|---|---|\n";
        for (rho, t) in &w.rho_inf {
            let _ = writeln!(
                m,
                "| {rho} | {} | {} | {:.3} | {} | {} | {} |",
                t.steps,
                t.rejected,
                t.wall_s,
                e(t.accel_err),
                db(t.order_db),
                t.status
            );
        }
        m.push('\n');
    }
}

/// The modal truncation and the other scenes.
fn model_comparisons(m: &mut String, w: &WindowStudy) {
    if !w.truncation.is_empty() {
        let _ = writeln!(
            m,
            "Modal truncation (interpreted, dopri5 rtol 1e-7, started {SETTLE} s before the \
             window, compared inside it, sampled at {COMPARE_RATE} Hz; accel in the \
             {BAND_HZ} Hz band), against all modes of the modal data \
             (docs/truncation.md: the same at constant speeds):\n"
        );
        *m += "| modes up to Hz | coordinates | wall s | accel | orders dB |\n|---|---|---|---|---|\n";
        for (c, n, t) in &w.truncation {
            let _ = writeln!(
                m,
                "| {c:.0} | {n} | {:.3} | {} | {} |",
                t.wall_s,
                e(t.accel_err),
                db(t.order_db)
            );
        }
        m.push('\n');
    }
    if !w.scenes.is_empty() {
        let _ = writeln!(
            m,
            "Scenes against `{}` (the full model), dopri5 rtol 1e-7, started {SETTLE} s \
             before the window and compared inside it, sampled at {COMPARE_RATE} Hz, \
             accel in the {BAND_HZ} Hz band, on the tub's channels (a rigid scene's \
             cabinet is fixed):\n",
            w.window.scene
        );
        *m += "| scene | wall s | accel | orders dB |\n|---|---|---|---|\n";
        for (n, t) in &w.scenes {
            let _ = writeln!(
                m,
                "| {n} | {:.3} | {} | {} |",
                t.wall_s,
                e(t.accel_err),
                db(t.order_db)
            );
        }
        m.push('\n');
    }
}

/// A plot that could not be drawn or written.
fn plot_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

type PResult = Result<(), Box<dyn std::error::Error + Send + Sync>>;

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    w: &WindowStudy,
) -> PResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let pts: Vec<(f64, f64)> = w
        .trials
        .iter()
        .filter_map(|t| t.accel_err.map(|e| (t.wall_s.max(1e-4), e.max(1e-12))))
        .collect();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in &pts {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    if pts.is_empty() {
        (x0, x1, y0, y1) = (1e-3, 1.0, 1e-6, 1.0);
    }
    let mut chart = ChartBuilder::on(root)
        .caption(
            format!(
                "work-precision: scene {} ({} .. {} s)",
                w.window.scene, w.window.t0, w.window.t1
            ),
            ("sans-serif", 24),
        )
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(
            (x0 / 1.5..x1 * 1.5).log_scale(),
            (y0 / 3.0..y1 * 3.0).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("wall time [s]")
        .y_desc("acceleration error (relative RMS)")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .x_label_formatter(&|v| format!("{v:.2}"))
        .label_style(("sans-serif", 18))
        .axis_desc_style(("sans-serif", 20))
        .draw()?;
    let colours = [RED, BLUE, GREEN, MAGENTA, BLACK, CYAN];
    let methods = ["rk4", "dopri5", "sdirk4", "rodas4", "galpha", "auto"];
    for (k, name) in methods.iter().enumerate() {
        let mut line: Vec<(f64, f64)> = w
            .trials
            .iter()
            .filter(|t| t.method == *name)
            .filter_map(|t| t.accel_err.map(|e| (t.wall_s.max(1e-4), e.max(1e-12))))
            .collect();
        if line.is_empty() {
            continue;
        }
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        let c = colours[k % colours.len()];
        chart
            .draw_series(LineSeries::new(line.clone(), c.stroke_width(2)))?
            .label(*name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        chart.draw_series(line.iter().map(|p| Circle::new(*p, 4, c.filled())))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 18))
        .draw()?;
    Ok(())
}

/// Writes `accuracy.md`, `accuracy.json` and `accuracy_<scene>.png/.svg` into `out`.
pub fn write(s: &Study, out: &Path) -> Result<Vec<PathBuf>, Error> {
    std::fs::create_dir_all(out).map_err(|e| Error::io("create", out, e))?;
    let mut files = Vec::new();
    let md = out.join("accuracy.md");
    std::fs::write(&md, markdown(s)).map_err(|e| Error::io("write", &md, e))?;
    files.push(md);
    let js = out.join("accuracy.json");
    let text = serde_json::to_string_pretty(s).expect("study serialises");
    std::fs::write(&js, text + "\n").map_err(|e| Error::io("write", &js, e))?;
    files.push(js);
    init_fonts();
    for w in &s.windows {
        let png = out.join(format!("accuracy_{}.png", w.window.scene));
        {
            let root = BitMapBackend::new(&png, (1024, 640)).into_drawing_area();
            draw(&root, w).map_err(|e| plot_error(&png, e))?;
            root.present().map_err(|e| plot_error(&png, e))?;
        }
        let svg = out.join(format!("accuracy_{}.svg", w.window.scene));
        {
            let root = SVGBackend::new(&svg, (1024, 640)).into_drawing_area();
            draw(&root, w).map_err(|e| plot_error(&svg, e))?;
            root.present().map_err(|e| plot_error(&svg, e))?;
        }
        files.push(png);
        files.push(svg);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recommendation_takes_the_cheapest_setting_that_reaches_the_class() {
        let t = |m: &str, wall: f64, err: f64| Trial {
            method: m.into(),
            tol: 1e-6,
            backend: "generated".into(),
            steps: 0,
            rejected: 0,
            rhs_evals: 0,
            jacobians: 0,
            lu: 0,
            wall_s: wall,
            accel_err: Some(err),
            order_db: None,
            status: "ok".into(),
        };
        let trials = vec![t("a", 1.0, 5e-3), t("b", 0.5, 2e-2), t("c", 2.0, 5e-5)];
        let r = recommend(&trials);
        assert_eq!(r[0].1.unwrap().method, "a");
        assert_eq!(r[1].1.unwrap().method, "c");
        assert_eq!(r[2].1.unwrap().method, "c");
    }
}
