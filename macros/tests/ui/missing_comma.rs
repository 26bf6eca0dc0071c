// Fields are separated by commas.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        rotor drum { axis_point: [0.0, 0.0, 0.5] polar_inertia: 0.5 }
    }
}

fn main() {}
