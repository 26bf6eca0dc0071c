// A variant: an item with a new name is new and must be complete.
washdyn_macros::machine! {
    m {
        base: "ui-data/reference.toml",
        spring spring_extra { stiffness: 5000.0 }
    }
}

fn main() {}
