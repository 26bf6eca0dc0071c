//! Built-in machine models: the reference machine as TOML data (docs/reference-machine.md),
//! and the same machine and a variant of it declared with `machine!` (compiled at build time).

#[path = "compact.rs"]
mod compact_decl;
#[path = "elastic_cabinet.rs"]
mod elastic_cabinet_decl;
#[path = "reference.rs"]
mod reference_decl;

/// The compact machine (`machine!` variant of the reference file): `compact::model()`.
pub use compact_decl::compact;
/// The reference machine with its elastic cabinet (scene `elastic`).
pub use elastic_cabinet_decl::elastic_cabinet;
/// The reference machine declared with `machine!`: `reference::model()`. (The function
/// `reference()` loads the TOML file; a module and a function may share a name.)
pub use reference_decl::reference;

use washdyn_model::ir::Model;
use washdyn_model::ir::files::{DataFiles, Embedded};
use washdyn_model::ir::toml_file::{ModelFileError, load_with};

/// The reference machine's TOML source.
pub const REFERENCE_TOML: &str = include_str!("../data/reference.toml");

/// The reference's modal data, compiled in under the names its TOML gives them, so that the
/// built-in reference reads nothing from disk (an installed binary works without its checkout).
pub const REFERENCE_DATA: &[Embedded] = &[
    Embedded {
        name: "../fe/tub.modal.toml",
        origin: "built-in models/fe/tub.modal.toml",
        text: include_str!("../fe/tub.modal.toml"),
    },
    Embedded {
        name: "../fe/tub_bare.modal.toml",
        origin: "built-in models/fe/tub_bare.modal.toml",
        text: include_str!("../fe/tub_bare.modal.toml"),
    },
    Embedded {
        name: "../fe/drum.modal.toml",
        origin: "built-in models/fe/drum.modal.toml",
        text: include_str!("../fe/drum.modal.toml"),
    },
    Embedded {
        name: "../fe/cabinet.modal.toml",
        origin: "built-in models/fe/cabinet.modal.toml",
        text: include_str!("../fe/cabinet.modal.toml"),
    },
    Embedded {
        name: "../fe/cabinet.curves.toml",
        origin: "built-in models/fe/cabinet.curves.toml",
        text: include_str!("../fe/cabinet.curves.toml"),
    },
];

/// Names of the built-in models.
pub const BUILT_IN: &[&str] = &["reference", "compact", "elastic_cabinet"];

/// The built-in model `name`: the reference from its TOML text with its compiled-in modal data
/// (checked at load), the others as their `machine!` declaration filled them (checked at
/// compile time). Nothing is read from disk.
pub fn built_in(name: &str) -> Option<Result<Model, ModelFileError>> {
    match name {
        "reference" => Some(load_with(
            REFERENCE_TOML,
            "built-in models/data/reference.toml",
            DataFiles::Embedded(REFERENCE_DATA),
        )),
        "compact" => Some(Ok(compact::model())),
        "elastic_cabinet" => Some(Ok(elastic_cabinet::model())),
        _ => None,
    }
}

/// The generated system of a built-in model's scene (`None`: unknown model or scene).
pub fn generated(
    name: &str,
    scene: &str,
) -> Option<Box<dyn washdyn_runtime::system::Mechanical + Send>> {
    match name {
        "reference" => reference::system(scene),
        "compact" => compact::system(scene),
        "elastic_cabinet" => elastic_cabinet::system(scene),
        _ => None,
    }
}

/// The generated system of a built-in model's scene for `variant`, a model that differs from
/// the built-in one in its free parameters only (`None`: unknown model or scene; `Err`: the
/// variant changes something else, which only the interpreter can run).
pub fn generated_for(
    name: &str,
    scene: &str,
    variant: &Model,
) -> Option<Result<Box<dyn washdyn_runtime::system::Mechanical + Send>, String>> {
    match name {
        "reference" => reference::system_for(scene, variant),
        "compact" => compact::system_for(scene, variant),
        "elastic_cabinet" => elastic_cabinet::system_for(scene, variant),
        _ => None,
    }
}

/// Whether a built-in model's generated code runs `variant` in `scene`, checked without
/// building the system ([`generated_for`] builds it): the scene has generated code and the
/// variant differs from the model in free parameters only (`Err`: the first other difference).
/// `None`: unknown model or scene. A study asks this for every variant before it builds one.
pub fn fits(name: &str, scene: &str, variant: &Model) -> Option<Result<(), String>> {
    type Fits = fn(&Model) -> Result<Vec<f64>, String>;
    let (scenes, fits): (&[&str], Fits) = match name {
        "reference" => (reference::SCENES, reference::fits),
        "compact" => (compact::SCENES, compact::fits),
        "elastic_cabinet" => (elastic_cabinet::SCENES, elastic_cabinet::fits),
        _ => return None,
    };
    scenes.contains(&scene).then(|| fits(variant).map(|_| ()))
}

/// The reference machine (panics only if the shipped file is broken, which a test guards).
pub fn reference() -> Model {
    built_in("reference")
        .expect("built in")
        .expect("the shipped reference model passes the checker")
}
