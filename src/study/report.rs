//! What the engineer looks at after `collect`: the Pareto plot of the two outputs the study
//! file names (`[outputs] pareto`, both minimised: peaks, levels and run time are better
//! small), and for a Saltelli design the first-order and total Sobol indices of every output
//! (SALib's estimators, `washdyn_analysis::study::sobol`) as a table, with bar charts of the
//! Pareto outputs' indices. PNG and SVG, units on the axes.

use super::dataset::Record;
use crate::error::Error;
use crate::results::{Column, Table};
use std::fmt::Write;
use std::path::{Path, PathBuf};
use washdyn_analysis::study::designs::SaltelliLayout;
use washdyn_analysis::study::pareto::Sense;
use washdyn_analysis::study::plot::{Output, PlotOptions, pareto, sobol_bars};
use washdyn_analysis::study::sobol::{SobolOptions, indices};
use washdyn_analysis::study::table;

fn plot_err(e: impl std::fmt::Display) -> Error {
    Error::File {
        message: format!("study report: {e}"),
    }
}

fn unit<'t>(t: &'t Table, name: &str) -> &'t str {
    let key = format!("unit:{name}");
    t.metadata
        .iter()
        .find(|(k, _)| *k == key)
        .map_or("-", |(_, v)| v.as_str())
}

fn numbers<'t>(t: &'t Table, name: &str) -> Option<&'t [f64]> {
    match t.column(name) {
        Some(Column::F64(v)) => Some(v),
        _ => None,
    }
}

/// The plots and the indices of the collected summary `t` (variant order) into `dir`.
pub fn write(dir: &Path, record: &Record, t: &Table) -> Result<Vec<PathBuf>, Error> {
    let mut files = Vec::new();
    let ids: Vec<&str> = match t.column("variant_id") {
        Some(Column::Text(v)) => v.iter().map(String::as_str).collect(),
        _ => return Ok(files),
    };
    let opts = PlotOptions::default();
    if let Some([a, b]) = &record.pareto
        && let (Some(x), Some(y)) = (numbers(t, a), numbers(t, b))
    {
        let x = Output {
            name: a,
            unit: unit(t, a),
            sense: Sense::Minimise,
            values: x,
        };
        let y = Output {
            name: b,
            unit: unit(t, b),
            sense: Sense::Minimise,
            values: y,
        };
        files.extend(pareto(&ids, &x, &y, &opts, &dir.join("pareto")).map_err(plot_err)?);
    }
    if record.design.get("kind").and_then(|k| k.as_str()) == Some("saltelli") {
        files.extend(sobol(dir, record, t)?);
    }
    Ok(files)
}

/// `sobol.md`: the indices of every output column; `sobol_<output>.png/.svg` for the Pareto
/// outputs. Only a complete study has them (each index needs whole base rows).
fn sobol(dir: &Path, record: &Record, t: &Table) -> Result<Vec<PathBuf>, Error> {
    let params: Vec<&str> = record.parameters.iter().map(|p| p.path.as_str()).collect();
    let base_rows = record
        .design
        .get("samples")
        .and_then(|s| s.as_u64())
        .unwrap_or(0) as usize;
    let layout = SaltelliLayout {
        base_rows,
        params: params.len(),
    };
    let mut md = format!(
        "# Sobol indices\n\nSaltelli design: {base_rows} base rows, {} parameters, {} \
         variants; first-order (S1, Saltelli 2010) and total (ST, Jansen 1999) indices, as \
         SALib's `sobol.analyze` computes them, with 95 % bootstrap intervals.\n",
        params.len(),
        layout.rows()
    );
    let mut files = Vec::new();
    if t.rows() != layout.rows() {
        let _ = writeln!(
            md,
            "\nThe study has {} of its {} variants: run it to the end for the indices.",
            t.rows(),
            layout.rows()
        );
    } else {
        // The outputs: the summary's columns before the run's status.
        let end = record
            .columns
            .iter()
            .position(|c| c == "status")
            .unwrap_or(record.columns.len());
        for name in &record.columns[..end] {
            let Some(v) = numbers(t, name) else { continue };
            let _ = writeln!(md, "\n## {name} [{}]\n", unit(t, name));
            match indices(&layout, v, &SobolOptions::default()) {
                Ok(ix) => {
                    md.push_str(&table(&params, &ix));
                    if record.pareto.iter().flatten().any(|p| p == name) {
                        let label = format!("{name} [{}]", unit(t, name));
                        let base = dir.join(format!("sobol_{name}"));
                        files.extend(
                            sobol_bars(&label, &params, &ix, &PlotOptions::default(), &base)
                                .map_err(plot_err)?,
                        );
                    }
                }
                Err(e) => {
                    let _ = writeln!(md, "no indices: {e}");
                }
            }
        }
    }
    let path = dir.join("sobol.md");
    std::fs::write(&path, md).map_err(|e| Error::io("write", &path, e))?;
    files.push(path);
    Ok(files)
}
