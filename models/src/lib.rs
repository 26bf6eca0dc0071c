//! Built-in machine models: the reference machine as TOML data (shared/reference-machine.md).

use washdyn_runtime::ir::Model;
use washdyn_runtime::ir::toml_file::{ModelFileError, load_str};

/// The reference machine's TOML source.
pub const REFERENCE_TOML: &str = include_str!("../data/reference.toml");

/// Names of the built-in models.
pub const BUILT_IN: &[&str] = &["reference"];

/// The built-in model `name`, loaded and checked.
pub fn built_in(name: &str) -> Option<Result<Model, ModelFileError>> {
    let src = match name {
        "reference" => REFERENCE_TOML,
        _ => return None,
    };
    let base = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    Some(load_str(src, &format!("models/data/{name}.toml"), &base))
}

/// The reference machine (panics only if the shipped file is broken, which a test guards).
pub fn reference() -> Model {
    built_in("reference")
        .expect("built in")
        .expect("the shipped reference model passes the checker")
}
