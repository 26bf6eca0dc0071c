// A variant: changed items are checked; an inherited field's error points at the item.
washdyn_macros::machine! {
    m {
        base: "ui-data/reference.toml",
        rotor drum { ratio: 0.0 }
        spring spring_front { a: { body: cabinet } }
    }
}

fn main() {}
