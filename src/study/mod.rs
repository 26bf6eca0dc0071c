//! `washdyn study`: variants of one model by a design over its parameters (paths in
//! `ir::param`'s syntax), every variant checked by the one checker before anything runs, run on
//! N cores (a built-in's generated code where only its free parameters change, else the
//! interpreter), and written as one hive-partitioned Parquet dataset that a
//! re-run completes: only missing or failed variants run again. One concept a file: the study
//! file (`file.rs`), its design points (`design.rs`), the variants and their check
//! (`variants.rs`), what each variant reports (`outputs.rs`), the directory and its files
//! (`dataset.rs`), the local run (`run.rs`), the run as a Slurm job array (`slurm/`), `status`
//! and `collect` (`collect.rs`), `washdyn sweep` as a grid design (`sweep.rs`), the Pareto plot and Sobol indices (`report.rs`), the refusals
//! (`error.rs`).

pub mod collect;
pub mod dataset;
pub mod design;
pub mod error;
pub mod file;
pub mod outputs;
pub mod report;
pub mod run;
pub mod slurm;
pub mod sweep;
pub mod variants;

pub use collect::{Collected, Status, collect, status};
pub use error::{BadVariant, StudyError};
pub use file::Study;
pub use run::{
    MAX_JOBS, Outcome, Phases, Plan, backend_for, check_jobs, execute, plan, simulation,
};
pub use variants::Variant;
