//! The fields of a [`RunSpec`](super::RunSpec) as a type, and a refusal that names one: the
//! command line prints a field as its option (`--tol`), a study file as its key (`run.tol`).

use std::fmt;

/// A field of the run specification.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Field {
    Model,
    Scene,
    Backend,
    Method,
    Tol,
    Step,
    RhoInf,
    MaxSteps,
    TStart,
    Speed,
    TEnd,
    SampleRate,
    Format,
    Start,
    ValidityStop,
    MaxProjectedWall,
    AllowLargeOutput,
    Energy,
    States,
    Force,
}

/// Who reads a refusal: the command line or a study file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spelling {
    Cli,
    File,
}

impl Field {
    /// The option of `washdyn run` (and `sweep`).
    pub fn option(self) -> &'static str {
        match self {
            Field::Model => "MODEL",
            Field::Scene => "--scene",
            Field::Backend => "--backend",
            Field::Method => "--integrator",
            Field::Tol => "--tol",
            Field::Step => "--step",
            Field::RhoInf => "--rho-inf",
            Field::MaxSteps => "--max-steps",
            Field::TStart => "--t-start",
            Field::Speed => "--speed",
            Field::TEnd => "--t-end",
            Field::SampleRate => "--sample-rate",
            Field::Format => "--format",
            Field::Start => "--start",
            Field::ValidityStop => "--no-validity-stop",
            Field::MaxProjectedWall => "--max-projected-wall",
            Field::AllowLargeOutput => "--allow-large-output",
            Field::Energy => "--energy",
            Field::States => "--states",
            Field::Force => "--force",
        }
    }

    /// The key of a study file: `model` and `scene` at its top, the others in its `[run]`
    /// table (the serde names of `RunSpec`).
    pub fn key(self) -> &'static str {
        match self {
            Field::Model => "model",
            Field::Scene => "scene",
            Field::Backend => "backend",
            Field::Method => "method",
            Field::Tol => "tol",
            Field::Step => "step",
            Field::RhoInf => "rho_inf",
            Field::MaxSteps => "max_steps",
            Field::TStart => "t_start",
            Field::Speed => "speed",
            Field::TEnd => "t_end",
            Field::SampleRate => "sample_rate",
            Field::Format => "format",
            Field::Start => "start",
            Field::ValidityStop => "validity_stop",
            Field::MaxProjectedWall => "max_projected_wall",
            Field::AllowLargeOutput => "allow_large_output",
            Field::Energy => "energy",
            Field::States => "states",
            Field::Force => "force",
        }
    }

    /// Whether a study file holds the key in its `[run]` table (else at its top).
    pub fn in_run_table(self) -> bool {
        !matches!(self, Field::Model | Field::Scene)
    }

    /// As `spelling` names it.
    pub fn name(self, spelling: Spelling) -> &'static str {
        match spelling {
            Spelling::Cli => self.option(),
            Spelling::File => self.key(),
        }
    }
}

/// What a refusal concerns: a field of the run specification, or an option a command has of
/// its own (`--jobs`, `--times`, Slurm's `--mem`), which only its command line spells.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Subject {
    Spec(Field),
    Option(&'static str),
}

impl Subject {
    /// The command line's spelling.
    pub fn option(self) -> &'static str {
        match self {
            Subject::Spec(f) => f.option(),
            Subject::Option(o) => o,
        }
    }
}

/// A command's own option by its spelling (`"--jobs"`).
impl From<&'static str> for Subject {
    fn from(o: &'static str) -> Subject {
        Subject::Option(o)
    }
}

impl From<Field> for Subject {
    fn from(f: Field) -> Subject {
        Subject::Spec(f)
    }
}

/// One refused setting, its message written for both readers (a rule names the fields it
/// mentions through its [`Spelling`], so the command line reads `--tol must be ...` and a study
/// file `tol must be ...`).
#[derive(Clone, Debug, PartialEq)]
pub struct Refusal {
    pub subject: Subject,
    cli: String,
    file: String,
}

impl Refusal {
    /// A refusal whose message `text` writes with the fields named as each reader spells them.
    pub fn new(subject: impl Into<Subject>, text: impl Fn(Spelling) -> String) -> Refusal {
        Refusal {
            subject: subject.into(),
            cli: text(Spelling::Cli),
            file: text(Spelling::File),
        }
    }

    /// A refusal whose message names no field.
    pub fn plain(subject: impl Into<Subject>, message: impl Into<String>) -> Refusal {
        let m = message.into();
        Refusal {
            subject: subject.into(),
            cli: m.clone(),
            file: m,
        }
    }

    /// The message as `spelling` reads it.
    pub fn message(&self, spelling: Spelling) -> &str {
        match spelling {
            Spelling::Cli => &self.cli,
            Spelling::File => &self.file,
        }
    }

    /// The field refused, when it is one of the specification's.
    pub fn field(&self) -> Option<Field> {
        match self.subject {
            Subject::Spec(f) => Some(f),
            Subject::Option(_) => None,
        }
    }
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.cli)
    }
}
