//! Development aid: search the tub's counterweight layout that closes the mass balance.
fn main() {
    let t = std::time::Instant::now();
    let (tub, d) =
        washdyn_fe::bodies::balance::balanced(&washdyn_fe::bodies::drum::Drum::default());
    println!(
        "{:.1} s: {tub:?}\ndeviations {d:?}",
        t.elapsed().as_secs_f64()
    );
}
