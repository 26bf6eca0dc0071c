//! The report of a comparison: compare.md (how it was made, the order peaks, the RMS
//! differences, the runs' costs) and compare.json. Separate because it only formats what the
//! comparison found.

use crate::analysis::AnalysisOptions;
use crate::analysis::metrics::BAND_HZ;
use crate::analysis::options::fmt_order;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::runs::Cost;
use super::{CompareError, Comparison, DRUM_ORDERS};

/// compare.md and compare.json into `out`.
pub(super) fn write(
    c: &Comparison,
    out: &Path,
    opts: &AnalysisOptions,
) -> Result<Vec<PathBuf>, CompareError> {
    let put = |name: &str, text: String| {
        let p = out.join(name);
        std::fs::write(&p, text)
            .map(|_| p.clone())
            .map_err(|e| CompareError::Write {
                path: p,
                message: e.to_string(),
            })
    };
    let json = serde_json::to_string_pretty(c).expect("the comparison serialises");
    Ok(vec![
        put("compare.md", markdown(c, opts))?,
        put("compare.json", json + "\n")?,
    ])
}

/// A value in 4 significant digits, `-` where there is none.
fn num(v: Option<f64>) -> String {
    match v {
        Some(v) if v != 0.0 && !(1e-2..1e4).contains(&v.abs()) => format!("{v:.3e}"),
        Some(v) => format!("{v:.4}"),
        None => "-".into(),
    }
}

fn dbs(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:+.2}"))
}

fn rpm(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.0}"))
}

/// The comparison as markdown: how it was made, the order table, the RMS table, the costs.
pub fn markdown(c: &Comparison, opts: &AnalysisOptions) -> String {
    let [a, b] = &c.runs;
    let mut s = String::new();
    let _ = writeln!(s, "# {} against {}\n", b.label, a.label);
    let _ = writeln!(
        s,
        "A = {} (`{}`), B = {} (`{}`): {} samples at {} Hz, {:.3} to {:.3} s, drum up to {:.0} \
         rpm.",
        a.label,
        a.dir,
        b.label,
        b.dir,
        c.samples,
        c.sample_rate_hz,
        c.t_start_s,
        c.t_end_s,
        c.max_rpm
    );
    let _ = writeln!(
        s,
        "Order tracks as `washdyn analyse` makes them (angle domain, Hann over {} revolutions, {} \
         samples per revolution), drum orders {} and motor order 1 (drum order {}), both runs \
         with the same options. **peak**: the largest block value of the track over the run \
         (SI units, amplitude), with the drum speed of that block; **dB** = 20 log10(peak B / \
         peak A); **worst track dB**: 20 log10(B / A) where its magnitude is largest along the \
         track, over the blocks where both runs are within {:.0} dB of their track's peak (the \
         accuracy study's floor, `analysis::metrics::track_error`), with its speed. `-`: not resolved.",
        c.order_block_revs,
        c.samples_per_rev,
        DRUM_ORDERS
            .iter()
            .map(|o| fmt_order(*o))
            .collect::<Vec<_>>()
            .join(", "),
        fmt_order(opts.motor_ratio),
        -20.0 * c.floor.log10()
    );
    if let Some(n) = &c.note {
        let _ = writeln!(s, "\nNote: {n}.");
    }
    if !c.zero_in_both.is_empty() {
        let _ = writeln!(
            s,
            "\nZero throughout in both runs (not compared): {}.",
            c.zero_in_both.join(", ")
        );
    }
    let _ = writeln!(s, "\n## Order peaks\n");
    let _ = writeln!(
        s,
        "| channel | order | peak {} | peak {} | dB | at rpm {} / {} | worst track dB (at rpm) | \
         worst within 20 dB of the peak, dB |",
        a.label, b.label, a.label, b.label
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for ch in &c.channels {
        for o in &ch.orders {
            let _ = writeln!(
                s,
                "| {} [{}] | {} | {} | {} | {} | {} / {} | {} ({}) | {} |",
                ch.channel,
                ch.unit,
                fmt_order(o.order),
                num(o.peak_a),
                num(o.peak_b),
                dbs(o.db),
                rpm(o.rpm_a),
                rpm(o.rpm_b),
                dbs(o.worst_db),
                rpm(o.worst_rpm),
                dbs(o.worst_strong_db)
            );
        }
    }
    let _ = writeln!(s, "\n## RMS over the run\n");
    let _ = writeln!(
        s,
        "| channel | RMS {} | RMS {} | RMS(B - A) / RMS(A) | the same to {} Hz |",
        a.label, b.label, BAND_HZ
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    for ch in &c.channels {
        let _ = writeln!(
            s,
            "| {} [{}] | {} | {} | {} | {} |",
            ch.channel,
            ch.unit,
            num(Some(ch.rms_a)),
            num(Some(ch.rms_b)),
            ch.rms_diff.map_or("-".into(), |d| format!("{d:.3}")),
            ch.band_diff.map_or("-".into(), |d| format!("{d:.2e}"))
        );
    }
    let _ = writeln!(s, "\n## Cost\n");
    s.push_str(&cost_table(&c.runs));
    s
}

/// The runs' costs as a markdown table (scene, method, tolerance, status, steps, rejected,
/// wall time, energy closure).
pub fn cost_table(runs: &[Cost]) -> String {
    let mut s = String::from(
        "| run | scene | method | tol | status | t reached / end s | steps | rejected | wall s | \
         energy closure |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in runs {
        let o = |v: &Option<String>| v.clone().unwrap_or_else(|| "-".into());
        let status = match (&r.status, &r.error) {
            (Some(st), Some(e)) => format!("{st}: {e}"),
            (st, _) => o(st),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} / {} | {} | {} | {} | {} |",
            r.label,
            o(&r.scene),
            o(&r.method),
            r.rtol.map_or("-".into(), |t| format!("{t:.0e}")),
            status.replace('|', "/"),
            r.t_reached.map_or("-".into(), |t| format!("{t:.3}")),
            r.t_end.map_or("-".into(), |t| format!("{t:.3}")),
            r.steps.map_or("-".into(), |v| v.to_string()),
            r.rejected_steps.map_or("-".into(), |v| v.to_string()),
            r.wall_time_s.map_or("-".into(), |v| format!("{v:.2}")),
            r.energy_closure.map_or("-".into(), |v| format!("{v:.1e}"))
        );
    }
    s
}
