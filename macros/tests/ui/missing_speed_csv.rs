// A speed profile read from a CSV file that does not exist.
washdyn_macros::machine! {
    m {
        tub {
            mass: 1.0,
            cog: [0.0, 0.0, 0.5],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
        speed { csv: "data/no_such_profile.csv" }
    }
}

fn main() {}
