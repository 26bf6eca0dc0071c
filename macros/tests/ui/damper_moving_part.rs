// A friction damper's moving part with a negative mass, and a scene that gives a damper its
// mass without the friction dampers.
washdyn_macros::machine! {
    m {
        tub {
            mass: 50.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        spring s1 {
            a: { body: tub, point: [0.0, 0.0, 0.8] },
            b: { body: cabinet, point: [0.0, 0.0, 1.0] },
            stiffness: 5.0e4,
            free_length: 0.19,
        }
        friction_damper d1 {
            a: { body: tub, point: [0.1, 0.1, 0.2] },
            b: { body: cabinet, point: [0.1, 0.2, 0.0] },
            f_max: 75.0,
            slope: 2000.0,
            bearing_stiffness: 20.0,
            bearing_damping: 0.2,
            moving_part: { mass: -0.5, inertia: 1.0e-3, translational_stiffness: 5.0e5 },
        }
        scene heavy { effects: [gyroscopic, damper_mass.d1] }
    }
}

fn main() {}
