// A variant of a base model file that does not exist.
washdyn_macros::machine! {
    m {
        base: "data/no_such_model.toml",
        spring spring_front { stiffness: 5000.0 }
    }
}

fn main() {}
