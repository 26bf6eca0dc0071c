//! Cost of the periodic start (shooting) on the reference machine's scenes at constant speed:
//! one-period integrations and wall time per speed (interpreter: the generated code's speed
//! profile is the run-up). Regenerates the periodic-start rows of docs/performance.md.
//! `cargo run --release --example periodic_start [scene] [rpm]...`, e.g. `elastic 400 1400`.

use std::time::Instant;
use washdyn_runtime::periodic::periodic_state_counted;
use washdyn_runtime::system::{FirstOrder, Interpreter};

fn main() {
    let mut args = std::env::args().skip(1);
    let scene = args.next().unwrap_or_else(|| "elastic".into());
    let rpms: Vec<f64> = args.map(|a| a.parse().expect("rpm")).collect();
    let rpms = if rpms.is_empty() {
        vec![400.0, 1400.0]
    } else {
        rpms
    };
    println!("scene | rpm | coordinates | integrations of one period | wall s");
    for rpm in rpms {
        let mut m = washdyn_models::reference();
        m.speed.table = vec![[0.0, rpm], [1000.0, rpm]];
        let s = m.scene(Some(&scene)).expect("scene");
        let mut fo = FirstOrder::new(Interpreter::new(&m, &s));
        let n = fo.layout().n();
        let t = Instant::now();
        match periodic_state_counted(&mut fo, 0.0) {
            Ok((_, flows)) => println!(
                "{scene} | {rpm} | {n} | {flows} | {:.2}",
                t.elapsed().as_secs_f64()
            ),
            Err(e) => println!("{scene} | {rpm} | {n} | failed: {e}"),
        }
    }
}
