//! The report of a comparison over speed: compare.md (how it was made, the calibration, the
//! resonances, the level differences per speed range) and compare.json. Separate because it
//! only formats what the comparison found.

use crate::analysis::options::fmt_order;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::report::cost_table;
use super::{CompareError, SpeedComparison};

/// compare.md and compare.json into `out`.
pub(super) fn write(c: &SpeedComparison, out: &Path) -> Result<Vec<PathBuf>, CompareError> {
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
        put("compare.md", markdown(c))?,
        put("compare.json", json + "\n")?,
    ])
}

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

/// `400-800`, `1400-` (no upper edge).
fn range_name(from: f64, to: Option<f64>) -> String {
    format!(
        "{from:.0}-{}",
        to.map_or(String::new(), |t| format!("{t:.0}"))
    )
}

/// How the comparison was made and what each number means.
fn method(s: &mut String, c: &SpeedComparison) {
    let [a, b] = &c.sources;
    for (n, x) in [("A", a), ("B", b)] {
        let _ = writeln!(
            s,
            "* {n} = {} ({}, `{}`): {} samples at {} Hz, {:.3} to {:.3} s, drum {:.0} to {:.0} \
             rpm.",
            x.label,
            x.kind,
            x.path,
            x.samples,
            x.sample_rate_hz,
            x.t_start_s,
            x.t_end_s,
            x.rpm_min,
            x.rpm_max
        );
    }
    let _ = writeln!(
        s,
        "\nCompared at equal drum speed, not time: both sides' order tracks (angle domain, Hann \
         over {} revolutions, {} samples per revolution, the same options for both) are taken \
         block by block in speed order up to each side's top speed (a plateau's blocks merged), \
         each block's amplitude at its mean speed, and interpolated linearly in rpm onto a \
         common grid every {} rpm from the higher of the two lowest to the lower of the two \
         highest speeds where order 1 is resolved. **dB** = 20 log10(B / A) at a grid speed \
         where both are within {:.0} dB of their own peak on the grid; per speed range its \
         **RMS** and its **largest magnitude** (signed, with its speed). `-`: nothing compared \
         there.",
        c.order_block_revs, c.samples_per_rev, c.grid_step_rpm, -c.floor_db
    );
    let _ = writeln!(
        s,
        "\n**Resonances**: the local maxima of order 1 within {:.0} dB of its peak that stand \
         {:.0} dB above the lower ground on either side (prominence), at the vertex of the \
         parabola through the log amplitudes of the block and its neighbours; A's and B's \
         paired nearest first. **Calibration factor**: the constant on B that minimises the RMS \
         of order 1's dB over the grid (the geometric mean of A / B), as Wagner & Pfeiffer \
         scaled the measured magnitudes; {}.",
        -c.floor_db,
        c.prominence_db,
        if c.calibrate {
            "applied to B (--calibrate): every B value below and B's plots include it"
        } else {
            "reported only; `--calibrate` applies it"
        }
    );
}

/// The comparison over speed as markdown.
pub fn markdown(c: &SpeedComparison) -> String {
    let [a, b] = &c.sources;
    let mut s = String::new();
    let _ = writeln!(s, "# {} against {} over speed\n", b.label, a.label);
    method(&mut s, c);
    for (what, names) in [
        ("Only in A (not compared)", &c.only_a),
        ("Only in B (not compared)", &c.only_b),
        (
            "Zero throughout on both sides (not compared)",
            &c.zero_in_both,
        ),
    ] {
        if !names.is_empty() {
            let _ = writeln!(s, "\n{what}: {}.", names.join(", "));
        }
    }
    let _ = writeln!(s, "\n## Calibration\n");
    let _ = writeln!(
        s,
        "| channel | common speeds rpm | factor on {} | factor dB | order-1 points | applied |",
        b.label
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for ch in &c.channels {
        let k = &ch.calibration;
        let _ = writeln!(
            s,
            "| {} | {:.0}-{:.0} | {} | {} | {} | {} |",
            ch.channel,
            ch.from_rpm,
            ch.to_rpm,
            k.factor.map_or("-".into(), |f| format!("{f:.4}")),
            dbs(k.factor_db),
            k.points,
            if k.applied { "yes" } else { "no" }
        );
    }
    let _ = writeln!(s, "\n## Resonances of order 1\n");
    let _ = writeln!(
        s,
        "| channel | rpm {} | rpm {} | difference rpm | level {} | level {} |",
        a.label, b.label, a.label, b.label
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for ch in &c.channels {
        for r in &ch.resonances {
            let _ = writeln!(
                s,
                "| {} [{}] | {} | {} | {} | {} | {} |",
                ch.channel,
                ch.unit,
                rpm(r.rpm_a),
                rpm(r.rpm_b),
                r.diff_rpm.map_or("-".into(), |d| format!("{d:+.0}")),
                num(r.level_a),
                num(r.level_b)
            );
        }
    }
    let _ = writeln!(s, "\n## Level difference per speed range, dB\n");
    let _ = writeln!(
        s,
        "| channel | order | peak {} | peak {} | range rpm | points | RMS dB | largest dB (at rpm) |",
        a.label, b.label
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for ch in &c.channels {
        for o in &ch.orders {
            for (k, r) in o.ranges.iter().enumerate() {
                let (peak_a, peak_b) = if k == 0 {
                    (num(o.peak_a), num(o.peak_b))
                } else {
                    (String::new(), String::new())
                };
                let _ = writeln!(
                    s,
                    "| {} [{}] | {} | {} | {} | {} | {} | {} | {} ({}) |",
                    ch.channel,
                    ch.unit,
                    fmt_order(o.order),
                    peak_a,
                    peak_b,
                    range_name(r.from_rpm, r.to_rpm),
                    r.points,
                    r.rms_db.map_or("-".into(), |v| format!("{v:.2}")),
                    dbs(r.max_db),
                    rpm(r.max_rpm)
                );
            }
        }
    }
    let costs: Vec<_> = c.sources.iter().filter_map(|x| x.cost.clone()).collect();
    let _ = writeln!(s, "\n## Cost\n");
    s.push_str(&cost_table(&costs));
    s
}
