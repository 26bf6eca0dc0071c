//! The Sobol indices of one output as a Markdown table (plain text that also renders), for a
//! report or the terminal: the numbers behind [`super::plot::sobol_bars`].

use std::fmt::Write;

use super::sobol::Indices;

/// A Markdown table with one row per parameter: `parameter | S1 | S1_conf | ST | ST_conf`
/// (SALib's column names; `_conf` the half-width of the confidence interval), four decimals,
/// and below it the confidence level, the base rows used and the failed ones left out.
///
/// # Panics
/// If `params` does not name every parameter of `indices`.
pub fn table(params: &[&str], indices: &Indices) -> String {
    assert_eq!(params.len(), indices.s1.len(), "one name per parameter");
    let width = params.iter().map(|p| p.len()).max().unwrap_or(0).max(9);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| {:<width$} | {:>7} | {:>7} | {:>7} | {:>7} |",
        "parameter", "S1", "S1_conf", "ST", "ST_conf"
    );
    let _ = writeln!(
        s,
        "| {:-<width$} | {:->6}: | {:->6}: | {:->6}: | {:->6}: |",
        "", "", "", "", ""
    );
    for (j, p) in params.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {p:<width$} | {:>7.4} | {:>7.4} | {:>7.4} | {:>7.4} |",
            indices.s1[j], indices.s1_conf[j], indices.st[j], indices.st_conf[j]
        );
    }
    let _ = write!(
        s,
        "\n_conf: half-width of the {:.0} % bootstrap confidence interval; {} base rows",
        100.0 * indices.conf_level,
        indices.base_rows
    );
    if !indices.failed_base_rows.is_empty() {
        let _ = write!(
            s,
            ", {} left out for a failed variant (base rows {:?})",
            indices.failed_base_rows.len(),
            indices.failed_base_rows
        );
    }
    s.push('\n');
    s
}
