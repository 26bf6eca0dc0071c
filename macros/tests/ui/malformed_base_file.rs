// A variant of a base file that is not valid TOML.
washdyn_macros::machine! {
    m {
        base: "ui-data/malformed.toml",
    }
}

fn main() {}
