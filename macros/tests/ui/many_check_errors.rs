// Every checker finding is reported at once.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        rotor drum { axis_point: [0.0, 0.0, 0.5], polar_inertia: 0.5 }
        unbalance u { rotor: drum, mass: 0.0, position: [0.15, 0.0, 0.74] }
        spring s {
            a: { body: tub, point: [0.0, 0.0, 0.6] },
            b: { body: cabinet, point: [0.0, 0.0, 0.8] },
            stiffness: -100.0,
            free_length: 0.1,
        }
    }
}

fn main() {}
