// A typo in a top-level field name.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        gravty: [0.0, 0.0, -9.81],
    }
}

fn main() {}
