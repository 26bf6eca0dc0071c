// A variant of a base file that the checker rejects.
washdyn_macros::machine! {
    m {
        base: "ui-data/negative_mass.toml",
    }
}

fn main() {}
