//! The field file's modes against the scene's: the truncation T of the modal data and the
//! turn R of each group of equal frequency (`Field::align`) that maps a field from another solve
//! onto the data's modes. Separate because it is the one check of a field against its data.

use nalgebra::DMatrix;
use washdyn_fe::field::Field;
use washdyn_model::equations::ModalBody;
use washdyn_model::ir::modal::ModalData;

/// q_file = T q_scene for a body's modal data (identity when not truncated).
fn basis(d: &ModalData, file_modes: usize) -> DMatrix<f64> {
    match &d.basis {
        Some(b) => DMatrix::from_row_slice(file_modes, b.len() / file_modes, b),
        None => DMatrix::identity(file_modes, d.modes()),
    }
}

/// The body's q index and q_field = R T q_scene: T the data's truncation, R the field's modes
/// onto the data file's (`Field::align`: identity for the same solve, a turn or flip per
/// degenerate group for another). A note when R re-projects.
pub(super) fn modal(
    b: &ModalBody,
    field: &Field,
    notes: &mut Vec<String>,
) -> Result<(usize, DMatrix<f64>), washdyn_fe::Error> {
    let al = field.align(b.data())?;
    let changed = al.changed();
    if !changed.is_empty() {
        let groups: Vec<String> = changed
            .iter()
            .map(|g| {
                if g.len() == 1 {
                    format!("{}", g.start + 1)
                } else {
                    format!("{}-{}", g.start + 1, g.end)
                }
            })
            .collect();
        notes.push(format!(
            "the field of `{}` is another solve of its modal data: modes {} turned or flipped \
             within their groups of equal frequency, re-projected (largest deviation {:.1e})",
            field.header.body,
            groups.join(", "),
            al.worst()
        ));
    }
    let t = basis(b.data(), field.modes());
    Ok((b.start, al.r * t))
}
