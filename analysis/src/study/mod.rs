//! Variant studies (issue 24): what a washing-machine engineer looks at after running many
//! variants of one machine. Pure functions over numbers, independent of how the variants ran:
//! - [`designs`]: which variants to run ([`designs::grid`], [`designs::lhs`],
//!   [`designs::sobol`], [`designs::saltelli`]);
//! - [`sobol`]: which parameters an output's variance comes from ([`sobol::indices`]);
//! - [`pareto`]: which variants are not beaten in every output at once ([`pareto::front`]);
//! - [`plot`]: the Pareto plot and the Sobol bar chart (PNG and SVG); [`table`]: the indices as
//!   a Markdown table.

pub mod designs;
mod normal;
pub mod pareto;
pub mod plot;
pub mod sobol;
mod table;

pub use table::table;

#[cfg(test)]
mod tests;
