// An unbalance on a rotor that is not declared.
washdyn_macros::machine! {
    m {
        tub {
            mass: 55.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        rotor drum { axis_point: [0.0, 0.0, 0.5], polar_inertia: 0.5 }
        unbalance u { rotor: drumm, mass: 0.6, position: [0.15, 0.0, 0.74] }
    }
}

fn main() {}
