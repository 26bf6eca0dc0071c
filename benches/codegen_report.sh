#!/usr/bin/env bash
# What the generated code of the elastic machine costs as its mode counts grow: operations,
# source size, rustc wall time and peak memory (release profile of the workspace), and ns per
# evaluation of M1 + h and of q'' against the interpreter on the same model, one binary per mode
# set. Regenerates the "Code size" table of docs/performance.md:
#   bash benches/codegen_report.sh [RUNTIME_DIR] > table.md
# RUNTIME_DIR (default: this checkout's runtime/) lets the same script measure another commit
# (git worktree add /tmp/before <commit>; bash benches/codegen_report.sh /tmp/before/runtime).
# SETS (default "6 4 6, 12 8 12, 20 12 20, 34 12 30, 100 12 30") are tub, drum, cabinet modes.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
runtime=$(cd "${1:-$root/runtime}" && pwd)
work=${WORK:-$(mktemp -d)}
mkdir -p "$work"
export CARGO_TARGET_DIR=$work/target
: > "$work/rates.txt"
IFS=',' read -ra sets <<< "${SETS:-6 4 6, 12 8 12, 20 12 20, 34 12 30, 100 12 30}"
echo "| tub drum cabinet | n1 n2 | ops M1+h | source kB | rustc s | rustc peak MB | M1+h interp/gen ns | q'' interp/gen ns | ratio M1+h, q'' |"
echo "|---|---|---|---|---|---|---|---|---|"
for set in "${sets[@]}"; do
  read -r nt nd nc <<< "$set"
  crate=$work/gen_${nt}_${nd}_${nc}
  mkdir -p "$crate/src"
  cat > "$crate/Cargo.toml" <<TOML
[package]
name = "gen_${nt}_${nd}_${nc}"
version = "0.0.0"
edition = "2024"
[dependencies]
washdyn-runtime = { path = "$runtime" }
[build-dependencies]
washdyn-runtime = { path = "$runtime" }
[profile.release]
debug = 1
codegen-units = 4
[workspace]
TOML
  cat > "$crate/build.rs" <<RS
// The reference machine with its elastic scene at these mode counts, generated as machine! does.
fn main() {
    let path = std::path::Path::new("$root/models/data/reference.toml");
    let mut m = washdyn_runtime::ir::toml_file::load_file(path).expect("reference model");
    for e in &mut m.elastic {
        let n = match e.name.as_str() { "tub" => $nt, "drum" => $nd, _ => $nc };
        e.data.as_mut().unwrap().truncate(n);
    }
    let mut effects: Vec<String> = m.scenes[0].effects.clone();
    effects.extend(["elastic.tub", "elastic.drum", "elastic.cabinet", "centrifugal_stiffening"].map(String::from));
    m.scenes.clear();
    m.scenes.push(washdyn_runtime::ir::Scene { name: "elastic".into(), effects, max_order: None });
    let (mut src, stats) = washdyn_runtime::codegen::generate_with_stats(&m).expect("generated");
    src.push_str(&format!("pub const OPS_MASS_FORCES: usize = {};\n", stats[0].ops_mass_forces));
    let out = std::path::Path::new(&std::env::var("OUT_DIR").unwrap()).join("gen.rs");
    std::fs::write(&out, src).unwrap();
    println!("cargo::rerun-if-changed=build.rs");
}
RS
  cat > "$crate/src/main.rs" <<'RS'
#![allow(clippy::all, unused)]
include!(concat!(env!("OUT_DIR"), "/gen.rs"));
use std::hint::black_box;
use std::time::Instant;
use washdyn_runtime::system::{FirstOrder, Interpreter, Mechanical};

/// Median ns per call over 15 batches.
fn per_call(mut f: impl FnMut()) -> f64 {
    let reps = 2000;
    for _ in 0..reps {
        f();
    }
    let mut v: Vec<f64> = (0..15)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..reps {
                f();
            }
            t.elapsed().as_nanos() as f64 / reps as f64
        })
        .collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[7]
}

fn main() {
    let m = model();
    let eff = m.scene(Some("elastic")).unwrap();
    let mut interp = Interpreter::new(&m, &eff);
    let mut gen_ = Elastic::new();
    let lay = interp.layout();
    let (n, n1) = (lay.n(), lay.n1);
    // The state of benches/backends.rs.
    let q: Vec<f64> = (0..n).map(|i| if i < 3 { 5e-4 } else { 1e-3 }).collect();
    let qd: Vec<f64> = (0..n).map(|i| 0.1 / (i + 1) as f64).collect();
    let (mut m1, mut h, mut qdd) = (vec![0.0; n1 * n1], vec![0.0; n], vec![0.0; n]);
    let t = 120.0;
    let mh_i = per_call(|| interp.eval(black_box(t), black_box(&q), black_box(&qd), &mut m1, &mut h));
    let mh_g = per_call(|| gen_.eval(black_box(t), black_box(&q), black_box(&qd), &mut m1, &mut h));
    let mut fa = FirstOrder::new(Interpreter::new(&m, &eff));
    let acc_i = per_call(|| fa.accelerations(black_box(t), black_box(&q), black_box(&qd), &mut qdd));
    let acc_g = per_call(|| {
        gen_.accelerations(black_box(t), black_box(&q), black_box(&qd), &mut qdd);
    });
    let ops = OPS_MASS_FORCES;
    // The machine's rate for this kind of code: a fixed-size multiply-add over a table
    // (64 x 8 axpy columns, in cache; 2 flops per entry).
    let (a, x) = ([[0.5f64; 64]; 8], [1e-3f64; 8]);
    let mut y = [0.0f64; 64];
    let axpy = per_call(|| {
        let (a, x) = (black_box(&a), black_box(&x));
        for (col, xj) in a.iter().zip(x) {
            for (yi, aij) in y.iter_mut().zip(col) {
                *yi += *xj * *aij;
            }
        }
        black_box(&mut y);
    });
    eprintln!("machine: {:.2} Gflop/s in a fixed-size axpy; generated M1+h {:.2} G operations/s", 1024.0 / axpy, ops as f64 / mh_g);
    println!("{n1} {} | {ops} | {mh_i:.0} / {mh_g:.0} | {acc_i:.0} / {acc_g:.0} | {:.2}, {:.2}", n - n1, mh_i / mh_g, acc_i / acc_g);
}
RS
  # Dependencies and the generation first, then the crate alone, timed.
  (cd "$crate" && cargo build -q --release 2>/dev/null)
  touch "$crate/src/main.rs"
  /usr/bin/time -f "%e %M" -o "$work/time.txt" bash -c "cd '$crate' && cargo build -q --release"
  read -r secs kb < "$work/time.txt"
  src=$(find "$CARGO_TARGET_DIR/release/build" -path "*gen_${nt}_${nd}_${nc}-*/out/gen.rs" | head -1)
  kbsrc=$(( $(stat -c %s "$src") / 1000 ))
  line=$("$CARGO_TARGET_DIR/release/gen_${nt}_${nd}_${nc}" 2>>"$work/rates.txt")
  IFS='|' read -r dims ops rest <<< "$line"
  echo "| $nt $nd $nc | $dims | $ops | $kbsrc | $secs | $(( kb / 1000 )) |$rest |"
done
echo
sed 's/^/    /' "$work/rates.txt"
