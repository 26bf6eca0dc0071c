// Every problem is reported at once, in source order, not only the first.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
        spring s1 {
            a: { body: tub, point: [0.0, 0.0, 0.6] },
            b: { body: cabinet, point: [0.0, 0.0, 0.8] },
            stifness: 100.0,
            free_length: 0.1,
        }
        sensor s2 { body: tub, point: [0.3, 0.0, 0.7], kind: velocity }
        sprng s3 {}
    }
}

fn main() {}
