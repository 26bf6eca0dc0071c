// A sensor on a body that does not exist (the drum is a rotor, not a body).
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        rotor drum { axis_point: [0.0, 0.0, 0.5], polar_inertia: 0.5 }
        sensor s { body: floor, point: [0.3, 0.0, 0.7], kind: acceleration }
    }
}

fn main() {}
