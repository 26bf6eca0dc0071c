// A free parameter the generated code cannot take: the tub's mass is in M1, which it builds once.
washdyn_macros::machine! {
    m {
        free: ["springs.s.stiffness", "tub.mass"],
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        spring s { a: { body: tub, point: [0.0, 0.0, 0.6] }, b: { body: cabinet, point: [0.0, 0.0, 1.0] }, stiffness: 100.0, free_length: 0.3 }
    }
}

fn main() {}
