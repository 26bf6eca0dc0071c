// A modal data file that is not valid TOML: the error names its line.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        elastic cabinet { file: "ui-data/cabinet_malformed.modal.toml" }
    }
}

fn main() {}
