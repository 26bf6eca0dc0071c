// A tub with negative mass.
washdyn_macros::machine! {
    m {
        tub {
            mass: -55.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
    }
}

fn main() {}
