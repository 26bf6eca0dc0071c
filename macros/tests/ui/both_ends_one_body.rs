// A spring with both ends on the tub acts on nothing.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        spring s {
            a: { body: tub, point: [0.0, 0.0, 0.6] },
            b: { body: tub, point: [0.0, 0.0, 0.8] },
            stiffness: 100.0,
            free_length: 0.1,
        }
    }
}

fn main() {}
