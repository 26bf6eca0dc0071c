//! `washdyn`: simulate washing-machine vibrations from the command line. `cli` holds a module
//! per command (its arguments and its printing); here the dispatch and the exit codes: every
//! command's error is a `washdyn::Error`, and [`exit_code`] maps it to the process's.

mod cli;

use clap::Parser;
use cli::{Cli, Cmd, Failure};
use std::process::ExitCode;
use washdyn::Error;
use washdyn::analysis::AnalysisError;
use washdyn::study::StudyError;
use washdyn::study::slurm::SlurmError;
use washdyn_runtime::run::RunError;

/// The exit code of an error: the one mapping (the table is `cli::EXIT_CODES`, shown by
/// `washdyn --help`, and docs/commands.md).
fn exit_code(e: &Error) -> ExitCode {
    ExitCode::from(code(e))
}

/// A refused measurement's code: its mapping file at a line 2, a file that cannot be read or
/// written 4, other refused measured data 5.
fn measured_code(m: &washdyn::measured::MeasuredError) -> u8 {
    use washdyn::measured::MeasuredError as Me;
    match m {
        Me::Mapping { .. } => 2,
        Me::Io { .. }
        | Me::Write { .. }
        | Me::Signals(AnalysisError::Io { .. })
        | Me::Uff(washdyn::analysis::uff58::UffError::Io { .. }) => 4,
        _ => 5,
    }
}

/// The code of [`exit_code`]: by the error's cause, whichever command met it (a model that
/// does not resolve is 3 under `run`, `modes`, `campbell`, `fields` and `fe reference` alike;
/// a file that cannot be written 4).
fn code(e: &Error) -> u8 {
    use washdyn::campbell::CampbellError as C;
    use washdyn::error::compare::CompareError;
    use washdyn::error::{fe::FeError, fe::FullMeshError as M, fields::FieldsError as F};
    use washdyn::modes::ModesError;
    match e {
        Error::Integration {
            source: RunError::Interrupted { .. },
            ..
        } => 130,
        Error::Integration { .. } => 1,
        Error::Settings(_)
        | Error::Analysis(AnalysisError::InvalidOptions(_))
        | Error::Study(
            StudyError::File(_)
            | StudyError::Directory { .. }
            | StudyError::Slurm(
                SlurmError::Busy { .. } | SlurmError::Path { .. } | SlurmError::Assignment { .. },
            ),
        ) => 2,
        // A command's model: the code of why it did not resolve.
        Error::Campbell(C::Model(m))
        | Error::Fields(F::Model(m))
        | Error::Modes(ModesError::Model(m))
        | Error::FullMesh(M::Model(m)) => code(m),
        Error::Model(_)
        | Error::Check { .. }
        | Error::Scene { .. }
        | Error::UnknownModel { .. }
        | Error::Fields(F::Scene(_))
        | Error::Modes(ModesError::Scene(_))
        | Error::FullMesh(M::Scene(_))
        | Error::Study(StudyError::Variants(_)) => 3,
        Error::Io(_)
        | Error::File { .. }
        | Error::Analysis(AnalysisError::Io { .. } | AnalysisError::Write { .. })
        | Error::Compare(
            CompareError::Write { .. }
            | CompareError::Read(AnalysisError::Io { .. } | AnalysisError::Write { .. }),
        )
        | Error::Campbell(C::Io(_))
        | Error::Fields(F::Io(_))
        | Error::Modes(ModesError::Io(_))
        | Error::Fe(FeError::Io(_))
        | Error::FullMesh(M::Io(_)) => 4,
        Error::Measured(m) | Error::Compare(CompareError::Measured(m)) => measured_code(m),
        Error::Analysis(_)
        | Error::Compare(_)
        | Error::Fields(_)
        | Error::Campbell(_)
        | Error::Modes(_)
        | Error::Fe(_)
        | Error::FullMesh(_)
        | Error::Reference(_)
        | Error::Plot { .. }
        | Error::Threads(_)
        | Error::OtherRun(_)
        | Error::Study(StudyError::Slurm(
            SlurmError::Missing { .. } | SlurmError::Failed { .. } | SlurmError::Answer { .. },
        )) => 5,
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match command(cli.cmd) {
        Ok(code) => code,
        Err(Failure::Printed(e)) => exit_code(&e),
        Err(Failure::Quiet(e)) => {
            eprintln!("{e}");
            exit_code(&e)
        }
        Err(Failure::Error(e)) => {
            eprintln!("error: {e}");
            exit_code(&e)
        }
    }
}

/// Each command to its module.
fn command(cmd: Cmd) -> Result<ExitCode, Failure> {
    match cmd {
        Cmd::Run(a) => cli::run::run(a),
        Cmd::Sweep(a) => cli::sweep::sweep(a),
        Cmd::Study(a) => cli::study::study(a),
        Cmd::Analyse(a) => cli::analyse::analyse(a),
        Cmd::Compare(a) => cli::compare::compare(a),
        Cmd::Fields(a) => cli::fields::fields(a),
        Cmd::Accuracy(a) => cli::accuracy::accuracy(a),
        Cmd::Modes(a) => cli::modes::modes(a),
        Cmd::Campbell(a) => cli::campbell::campbell(a),
        Cmd::Fe(a) => cli::fe::fe(a),
        Cmd::Check(a) => cli::check::check(a),
    }
}
