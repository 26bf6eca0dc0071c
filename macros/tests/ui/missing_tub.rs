// A machine without its tub.
washdyn_macros::machine! {
    m {
        speed { table: [[0.0, 0.0], [1.0, 100.0]] }
    }
}

fn main() {}
