// Principal moments no mass distribution has: 1 + 1 < 3.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
    }
}

fn main() {}
