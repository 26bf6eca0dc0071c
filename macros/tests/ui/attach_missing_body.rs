// A friction damper anchored on a body that does not exist.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        friction_damper d {
            a: { body: tub, point: [0.0, 0.2, 0.2] },
            b: { body: floor, point: [0.0, 0.2, 0.0] },
            f_max: 100.0,
            slope: 2000.0,
            bearing_stiffness: 80.0,
            bearing_damping: 0.05,
        }
    }
}

fn main() {}
