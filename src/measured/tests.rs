//! The mapping on a CSV measurement (no pyuff needed; tests/measured.rs reads UFF files), the
//! speed table's decimation and the mapping's refusals at their lines.

use super::*;
use std::path::PathBuf;

/// A CSV run-up: 1 kHz, 2 s, drum_rpm = 600 + 30 t, `acc` in m/s^2 (the format's SI),
/// `u` a displacement column in m (named so), and a mapping `text` beside it.
fn setup(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::from("time_s,drum_rpm,tub_az,tub_uz\n");
    for i in 0..2001 {
        let t = i as f64 / 1000.0;
        csv.push_str(&format!(
            "{t},{},{},{}\n",
            600.0 + 30.0 * t,
            (7.0 * t).sin(),
            1e-3 * t
        ));
    }
    std::fs::write(dir.path().join("run.csv"), csv).unwrap();
    let map = dir.path().join("measurement.toml");
    std::fs::write(&map, text).unwrap();
    (dir, map)
}

const MAP: &str = r#"files = ["run.csv"]
speed = { rpm = "drum_rpm" }

[[channel]]
measured = "tub_az"
sensor = "tub_front_az"
flip = true
"#;

#[test]
fn a_csv_measurement_maps_and_flips() {
    let (_d, map) = setup(MAP);
    let m = load(&map).unwrap();
    let s = &m.signals;
    assert_eq!(s.channels.len(), 1);
    assert_eq!(s.channels[0].name, "tub_front_az");
    assert_eq!(s.channels[0].data[500], -(7.0f64 * 0.5).sin());
    // 600 + 30 t, through rpm / 60 and back: to rounding.
    assert!((s.drum_rpm[1000] - 630.0).abs() < 1e-9);
    assert!(matches!(m.speed, SpeedFrom::Rpm { .. }));
    assert!(format!("{m}").contains("tub_front_az <- "));
}

#[test]
fn the_speed_table_of_a_ramp_is_its_ends() {
    let (_d, map) = setup(MAP);
    let m = load(&map).unwrap();
    // A straight line: the first and last samples.
    let t = speed_table(&m, 100);
    assert_eq!(t.len(), 2);
    let close =
        |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-9;
    assert!(
        close(t[0], [0.0, 600.0]) && close(t[1], [2.0, 660.0]),
        "{t:?}"
    );
    // A sine of 5 rpm over 2 s at 0.05 s: many points at 0.05 rpm, capped by max_points.
    let mut m2 = m.clone();
    for (r, &t) in m2.signals.drum_rpm.iter_mut().zip(&m.signals.time) {
        *r = 600.0 + 5.0 * (3.0 * t).sin();
    }
    let fine = speed_table(&m2, 1000);
    let capped = speed_table(&m2, 8);
    assert!(
        fine.len() > 8 && capped.len() <= 8,
        "{} {}",
        fine.len(),
        capped.len()
    );
    assert!((capped.last().unwrap()[0] - 2.0).abs() < 1e-12);
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("s.csv");
    write_speed_csv(&p, &fine).unwrap();
    let back = washdyn_model::ir::toml_file::read_speed_csv(&p).unwrap();
    assert_eq!(back, fine);
}

#[test]
fn mapping_refusals_name_line_and_field() {
    let cases = [
        // A unit the reader does not know: the `unit` line.
        (
            MAP.replace("flip = true", "unit = \"furlong\""),
            7,
            "channel[0].unit",
        ),
        // A displacement unit for an acceleration sensor.
        (
            MAP.replace("\"tub_az\"", "\"tub_uz\""),
            6,
            "channel[0].sensor",
        ),
        // Neither tacho nor rpm.
        (
            MAP.replace("speed = { rpm = \"drum_rpm\" }", "speed = {}"),
            2,
            "speed",
        ),
        // A motor tacho without its ratio.
        (
            MAP.replace(
                "speed = { rpm = \"drum_rpm\" }",
                "speed = { tacho = { channel = \"tub_az\", side = \"motor\" } }",
            ),
            2,
            "speed.tacho.ratio",
        ),
        // An unknown key: serde's message at its line.
        (MAP.replace("flip = true", "flipp = true"), 7, "mapping"),
        (MAP.replace("run.csv", "gone.csv"), 1, "files[0]"),
    ];
    for (text, line, field) in cases {
        let (_d, map) = setup(&text);
        match load(&map) {
            Err(MeasuredError::Mapping { at, message }) => {
                assert_eq!((at.line, at.field.as_str()), (line, field), "{message}")
            }
            other => panic!("{field}: {other:?}"),
        }
    }
}

#[test]
fn directions_parse_as_the_format_writes_them() {
    let d = |s| sources::parse_direction(s).map(|d| d.code());
    assert_eq!(
        [d("+Z"), d("-x"), d("Y"), d("+RZ"), d("W")],
        [Some(3), Some(-1), Some(2), Some(6), None]
    );
}
