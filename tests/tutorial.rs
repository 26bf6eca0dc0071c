//! docs/tutorial.md, run as written (issue 23, must-have 2): the page's blocks are the test's
//! script, so the page and the test cannot drift. In document order, a block fenced `sh` runs
//! in bash (`-euo pipefail`) in a fresh directory with the built `washdyn` first on the `PATH`
//! and `WASHDYN` the checkout; `LANG file=NAME` is written to NAME; `LANG source=PATH` must equal
//! that file of the checkout; `sh not-run` and `text` blocks are only shown.
//! Part 1 (a cabinet with thicker side panels: its deck through CalculiX, a model file, a
//! run-up, the order plots, a field and a comparison) needs ccx and is skipped without it,
//! except under CI; part 2 (a `machine!` crate outside the workspace) builds that crate with
//! cargo into this test's own scratch target directory.
//!
//! Beyond the exit codes, each part checks the physics the page states: the deck change
//! reaches the solver as exactly the sheet's added mass, and moves the modes as a heavier box
//! with stiffer panels should (directions and brackets from plate theory), the run-up shows the
//! side panel's resonance moving with it, and the crate's generated code gives the numbers the
//! interpreter gives on the same machine from a model file.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use washdyn_model::ir::modal::{ModalData, read_file};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fenced block of the page: its info string (`sh`, `toml file=x.toml`, ...), its text, the
/// part it belongs to (1 + the number of `## Part ` headings after the first before it) and
/// its line.
#[derive(Debug)]
struct Block {
    info: String,
    text: String,
    part: usize,
    line: usize,
}

fn blocks() -> Vec<Block> {
    let doc = std::fs::read_to_string(root().join("docs/tutorial.md")).unwrap();
    let (mut out, mut part, mut open): (Vec<Block>, usize, Option<Block>) = (Vec::new(), 0, None);
    for (i, line) in doc.lines().enumerate() {
        match open.take() {
            Some(b) if line.trim_end() == "```" => out.push(b),
            Some(mut b) => {
                b.text.push_str(line);
                b.text.push('\n');
                open = Some(b);
            }
            None if line.starts_with("```") => {
                open = Some(Block {
                    info: line.trim_start_matches('`').trim().to_string(),
                    text: String::new(),
                    part,
                    line: i + 1,
                })
            }
            None => {
                if line.starts_with("## Part ") {
                    part += 1;
                }
            }
        }
    }
    assert!(open.is_none(), "docs/tutorial.md: a block is not closed");
    out
}

/// The value of `key=` in a block's info string.
fn tag<'a>(b: &'a Block, key: &str) -> Option<&'a str> {
    b.info
        .split_whitespace()
        .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
}

/// What a block asks of the test.
#[derive(Debug, PartialEq)]
enum Kind {
    Run,
    Write(String),
    Source(String),
    Show,
}

fn kind(b: &Block) -> Kind {
    if let Some(f) = tag(b, "file") {
        Kind::Write(f.into())
    } else if let Some(f) = tag(b, "source") {
        Kind::Source(f.into())
    } else if b.info == "sh" {
        Kind::Run
    } else {
        Kind::Show
    }
}

/// Runs part `part` of the page in `dir`; returns each command block's stdout.
fn run_part(part: usize, dir: &Path) -> Vec<String> {
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_washdyn"));
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    // The crate of part 2 builds here, not in the workspace's target directory (whose lock
    // `cargo test` holds).
    let crate_target = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("my-machine");
    let mut outputs = Vec::new();
    for b in blocks().into_iter().filter(|b| b.part == part) {
        match kind(&b) {
            Kind::Write(name) => std::fs::write(dir.join(name), &b.text).unwrap(),
            Kind::Source(file) => {
                let actual = std::fs::read_to_string(root().join(&file)).unwrap();
                assert!(
                    actual == b.text,
                    "docs/tutorial.md:{}: the block shows {file} other than it is; copy the \
                     file into the page",
                    b.line
                );
            }
            Kind::Show => {}
            Kind::Run => {
                let started = Instant::now();
                let out = Command::new("bash")
                    .args(["-euo", "pipefail", "-c", &b.text])
                    .current_dir(dir)
                    .env("PATH", &path)
                    .env("WASHDYN", root())
                    .env("CARGO_TARGET_DIR", &crate_target)
                    .output()
                    .unwrap();
                let stdout = String::from_utf8_lossy(&out.stdout).to_string();
                let stderr = String::from_utf8_lossy(&out.stderr);
                eprintln!(
                    "docs/tutorial.md:{} ({:.1} s):\n{}{stdout}",
                    b.line,
                    started.elapsed().as_secs_f64(),
                    b.text
                );
                assert!(
                    out.status.success(),
                    "docs/tutorial.md:{}: the block failed ({}):\n{}\n{stdout}{stderr}",
                    b.line,
                    out.status,
                    b.text
                );
                outputs.push(stdout);
            }
        }
    }
    outputs
}

#[test]
fn the_page_has_the_blocks_the_test_runs() {
    let blocks = blocks();
    let count = |part: usize, k: fn(&Kind) -> bool| {
        blocks
            .iter()
            .filter(|b| b.part == part && k(&kind(b)))
            .count()
    };
    // A mistyped info string would drop a step silently: every block is one of the kinds
    // above, and each part has the steps the page describes (counted when written).
    for b in &blocks {
        let first = b.info.split_whitespace().next().unwrap_or("");
        assert!(
            ["sh", "text", "toml", "rust"].contains(&first)
                && (b.info.split_whitespace().count() == 1
                    || tag(b, "file").is_some()
                    || tag(b, "source").is_some()
                    || b.info == "sh not-run"),
            "docs/tutorial.md:{}: unknown block `{}`",
            b.line,
            b.info
        );
    }
    assert_eq!(count(1, |k| *k == Kind::Run), 8);
    assert_eq!(count(1, |k| matches!(k, Kind::Write(_))), 1);
    assert_eq!(count(2, |k| *k == Kind::Run), 2);
    assert_eq!(count(2, |k| matches!(k, Kind::Source(_))), 2);
}

/// The area of one side panel, m^2: 2a x h with the crown b sin(pi u) sin(pi v) of the
/// built-in cabinet (fe/src/bodies/cabinet.rs), by the midpoint rule on 400 x 400 cells
/// (the same as on 1000 x 1000 cells to 3e-15: the integrand is smooth and periodic).
fn side_panel_area() -> f64 {
    let cab = washdyn_fe::bodies::cabinet::Cabinet::default();
    let (lx, lz, b) = (2.0 * cab.half, cab.height, cab.bulge);
    let n = 400;
    let pi = std::f64::consts::PI;
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (u, v) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
            let bx = b * pi / lx * (pi * u).cos() * (pi * v).sin();
            let bz = b * pi / lz * (pi * u).sin() * (pi * v).cos();
            sum += (1.0 + bx * bx + bz * bz).sqrt();
        }
    }
    sum * lx * lz / (n * n) as f64
}

#[test]
fn part_1_a_cabinet_with_thicker_side_panels() {
    if !common::required_tool(
        washdyn_fe::ccx::available(),
        "CalculiX",
        "apt-get install calculix-ccx",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let outputs = run_part(1, d);

    // The files each step leaves (the page names them).
    for f in [
        "thick_fe/cabinet.modal.toml",
        "thick_fe/cabinet.field.bin",
        "out/base/sensors.parquet",
        "out/thick/states.parquet",
        "out/thick/analysis/cabinet2_ay_order.png",
        "out/thick/analysis/orders.parquet",
        "out/thick/fields/cabinet.pvd",
        "out/compare/compare.md",
    ] {
        assert!(d.join(f).is_file(), "{f} missing");
    }
    let frames = std::fs::read_dir(d.join("out/thick/fields"))
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().unwrap() == "vtu")
        .count();
    assert_eq!(frames, 36, "one revolution in 36 frames");

    // The deck change reaches the solver: the mass rises by exactly the sheet added,
    // 7850 kg/m^3 (the deck's STEEL) x (1.0 - 0.7) mm x both crowned side panels.
    let reference: ModalData =
        read_file(&root().join("models/fe/cabinet.modal.toml"), "reference").unwrap();
    let thick: ModalData = read_file(&d.join("thick_fe/cabinet.modal.toml"), "thick").unwrap();
    let added = 7850.0 * 0.3e-3 * 2.0 * side_panel_area();
    let dm = (thick.mass - reference.mass) / added - 1.0;
    println!(
        "mass {:.4} -> {:.4} kg (+{:.4}; rho dt A = {added:.4}): {dm:.1e} off",
        reference.mass,
        thick.mass,
        thick.mass - reference.mass
    );
    // Measured 9.0e-9 (ccx integrates the S8R's quadratic surface, the test the exact crown).
    assert!(dm.abs() < 1e-7, "{dm}");

    // The sway pair on the feet falls: more mass on the same feet (a rigid box: by
    // sqrt(m / m') = 0.961). The thicker sheets also stiffen the box's racking, which takes
    // some of that back, so the fall is smaller than the rigid box's (an engineering
    // expectation, not a theorem: the added mass sits far out at the sides).
    let rigid = (reference.mass / thick.mass).sqrt();
    for k in 0..2 {
        let r = thick.frequencies[k] / reference.frequencies[k];
        println!(
            "sway mode {}: {:.2} -> {:.2} Hz (x {r:.4}; rigid box x {rigid:.4})",
            k + 1,
            reference.frequencies[k],
            thick.frequencies[k]
        );
        // Measured x 0.9665, 0.9729.
        assert!(rigid < r && r < 1.0, "{r}");
    }
    // Above the sway pair the modes are the panels', and they rise: a flat plate's bending
    // frequency goes with its thickness (stiffness t^3, mass t), at most x 1.0 / 0.7 = 1.43;
    // the crown's membrane stiffness goes with t like the mass (no gain), and the frame and
    // feet are unchanged. Compared mode by mode (the k-th frequency of each), the top of the
    // 60 solved.
    let top = thick.frequencies[59] / reference.frequencies[59];
    println!(
        "60th mode: {:.2} -> {:.2} Hz (x {top:.4})",
        reference.frequencies[59], thick.frequencies[59]
    );
    // Measured x 1.1602.
    assert!(1.0 < top && top < 1.0 / 0.7, "{top}");
    let below = thick.frequencies[..60]
        .iter()
        .filter(|&&f| f <= reference.frequencies[59])
        .count();
    // Measured 50 of 60.
    assert!(below < 60, "{below}");
    // The side panels' first modes: the first two in which the panel's centre (MP_CAB2, the
    // sensor cabinet2) moves normal to it more than twice as far as any other point.
    let panel = |m: &ModalData| -> Vec<f64> {
        let centre = m.points.iter().find(|p| p.name == "MP_CAB2").unwrap();
        (0..60)
            .filter(|&k| {
                let frame = m
                    .points
                    .iter()
                    .filter(|p| p.name != "MP_CAB2")
                    .flat_map(|p| (0..3).map(move |i| p.w[i][k].abs()))
                    .fold(0.0, f64::max);
                centre.w[1][k].abs() > 2.0 * frame
            })
            .map(|k| m.frequencies[k])
            .take(2)
            .collect()
    };
    let (a, b) = (panel(&reference), panel(&thick));
    println!("side panel modes: {a:.2?} -> {b:.2?} Hz");
    for (fa, fb) in a.iter().zip(&b) {
        // Measured 50.08 -> 53.66, 53.92 -> 56.87 Hz (x 1.071, 1.055).
        assert!(fa < fb && *fb < fa / 0.7, "{fa} -> {fb}");
    }

    // The run-up: the side panel's order-3 resonance at cabinet2 (y, normal to the panel)
    // moves up in speed with the panel's modes (compare.json, both runs' order tracks).
    let cmp: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("out/compare/compare.json")).unwrap())
            .unwrap();
    let ch = cmp["channels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["channel"] == "cabinet2_ay")
        .unwrap();
    let o3 = ch["orders"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["order"] == 3.0)
        .unwrap();
    let (rpm_a, rpm_b) = (o3["rpm_a"].as_f64().unwrap(), o3["rpm_b"].as_f64().unwrap());
    println!(
        "cabinet2_ay order 3: {:.2} m/s^2 at {rpm_a:.0} rpm -> {:.2} m/s^2 at {rpm_b:.0} rpm",
        o3["peak_a"].as_f64().unwrap(),
        o3["peak_b"].as_f64().unwrap()
    );
    // Measured 1100 -> 1350 rpm: 55 Hz (the panel modes at 50-54 Hz) -> 67.5 Hz (67.0 Hz).
    assert!(rpm_b > rpm_a, "{rpm_a} -> {rpm_b}");

    // The field: at 1350 rpm the side panel breathes; its largest displacement is inside a
    // side panel: on its crown (|y| beyond the panels' plane at 0.300 m, up to 0.308 m at the
    // centre) and clear of the corner posts (|x| < 0.30 m).
    let fields = outputs
        .iter()
        .find(|o| o.contains("largest displacement"))
        .expect("fields' report");
    let node: usize = fields
        .split("cabinet node ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .expect("a node number");
    let deck = std::fs::read_to_string(d.join("my_cabinet.inp")).unwrap();
    let xyz: Vec<f64> = deck
        .lines()
        .skip_while(|l| !l.starts_with("*NODE"))
        .skip(1)
        .take_while(|l| !l.starts_with('*'))
        .find(|l| l.split(',').next().unwrap().trim().parse() == Ok(node))
        .map(|l| {
            l.split(',')
                .skip(1)
                .map(|v| v.trim().parse().unwrap())
                .collect()
        })
        .expect("the node in the deck");
    println!("largest displacement at node {node}, {xyz:.4?} m");
    // Measured node 654 at (0.140, -0.3036, 0.675) m.
    assert!(xyz[1].abs() > 0.3005 && xyz[0].abs() < 0.29, "{xyz:?}");
}

/// `rms CHANNEL VALUE` and `max tub translation X m at T s, rotation Y rad at T s` lines of
/// the crate's output.
fn printed(text: &str) -> (Vec<(String, f64)>, f64, f64) {
    let rms = text
        .lines()
        .filter_map(|l| l.strip_prefix("rms "))
        .map(|l| {
            let (name, v) = l.split_once(' ').unwrap();
            (name.to_string(), v.parse().unwrap())
        })
        .collect();
    let line = text
        .lines()
        .find(|l| l.starts_with("max tub translation"))
        .expect("the extremes");
    let words: Vec<&str> = line.split_whitespace().collect();
    (rms, words[3].parse().unwrap(), words[9].parse().unwrap())
}

#[test]
fn part_2_a_machine_crate_of_ones_own() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    run_part(2, d);
    let text = std::fs::read_to_string(d.join("my_machine.txt")).unwrap();
    let (rms, translation, rotation) = printed(&text);
    assert_eq!(rms.len(), 18, "{text}");

    // The same machine through the other front end and back end: the model file through the
    // TOML loader and the interpreter, its sensor file and summary.
    let (names, columns) =
        washdyn::results::read_parquet_f64(&d.join("out/my_machine/sensors.parquet")).unwrap();
    let time = &columns[0];
    let from = time.partition_point(|&t| t < 10.0);
    let mut worst = 0.0f64;
    for (name, value) in &rms {
        let c = names.iter().position(|n| n == name).unwrap();
        let x = &columns[c][from..];
        let r = (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
        worst = worst.max((r / value - 1.0).abs());
    }
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(d.join("out/my_machine/summary.json")).unwrap(),
    )
    .unwrap();
    let v = &summary["validity"];
    let extremes = [
        v["max_translation_m"].as_f64().unwrap() / translation - 1.0,
        v["max_rotation_rad"].as_f64().unwrap() / rotation - 1.0,
    ];
    println!(
        "generated vs interpreted: RMS within {worst:.1e}, extremes {:.1e} and {:.1e}",
        extremes[0], extremes[1]
    );
    // The printed 13 digits round at 5e-13; the two back ends agree to 5e-13 per evaluation
    // (tests/backend_agreement.rs) and take the same 19 171 steps. Measured 2.0e-13 (RMS),
    // 1.5e-13 and 1.2e-13 (extremes).
    assert!(worst < 1e-12, "{worst}");
    assert!(extremes.iter().all(|e| e.abs() < 1e-12), "{extremes:?}");
}
