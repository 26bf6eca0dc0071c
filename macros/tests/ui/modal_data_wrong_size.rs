// A cabinet whose modal data has a matrix of the wrong size: the error names the file and the field.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        elastic cabinet { file: "ui-data/cabinet_bad.modal.toml" }
    }
}

fn main() {}
