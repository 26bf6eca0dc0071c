//! CSV reader: good files load, malformed ones fail with the offending line.

use std::path::PathBuf;

use washdyn::analysis::{AnalysisError, Quantity, read_signals};

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// `rows` uniform rows at 2 kHz with three channels.
fn good_rows(rows: usize) -> String {
    let mut s = String::new();
    for i in 0..rows {
        let t = i as f64 / 2000.0;
        s.push_str(&format!(
            "{t:.6},{:.1},{},{},{}\n",
            100.0 + i as f64,
            i,
            -(i as i64),
            0.5
        ));
    }
    s
}

const HEADER: &str = "time_s,drum_rpm,tub1_ax,drum_front_uz,mic_left\n";

fn err(text: &str) -> (AnalysisError, String) {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "bad.csv", text);
    let e = read_signals(&p).expect_err("file should be rejected");
    let msg = e.to_string();
    (e, msg)
}

#[test]
fn reads_a_good_file() {
    let dir = tempfile::tempdir().unwrap();
    // Comment preamble, CRLF, quoted names and blanks around cells are all accepted.
    let text = format!(
        "# exported by a test\r\n\"time_s\", \"drum_rpm\",tub1_ax,drum_front_uz,mic_left\r\n{}",
        good_rows(20).replace('\n', "\r\n")
    );
    let s = read_signals(write(&dir, "good.csv", &text)).unwrap();
    assert_eq!(s.len(), 20);
    assert!((s.sample_rate - 2000.0).abs() < 1e-6, "{}", s.sample_rate);
    assert_eq!(s.drum_rpm[3], 103.0);
    let names: Vec<_> = s.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["tub1_ax", "drum_front_uz", "mic_left"]);
    assert_eq!(s.channels[0].quantity, Quantity::Acceleration);
    assert_eq!(s.channels[1].quantity, Quantity::Displacement);
    assert_eq!(s.channels[2].quantity, Quantity::Unknown);
    assert_eq!(s.channels[1].data[4], -4.0);
}

#[test]
fn missing_file_is_an_io_error() {
    let e = read_signals("/nonexistent/run.csv").unwrap_err();
    assert!(matches!(e, AnalysisError::Io { .. }), "{e}");
}

#[test]
fn misnamed_time_column() {
    let (e, msg) = err(&format!("t,drum_rpm,a_ax\n{}", good_rows(10)));
    assert!(matches!(e, AnalysisError::Header { line: 1, .. }), "{e:?}");
    assert!(
        msg.contains("line 1") && msg.contains("time_s") && msg.contains("`t`"),
        "{msg}"
    );
}

#[test]
fn misnamed_speed_column() {
    let (e, msg) = err(&format!("time_s,rpm,a_ax\n{}", good_rows(10)));
    assert!(matches!(e, AnalysisError::Header { line: 1, .. }), "{e:?}");
    assert!(msg.contains("drum_rpm") && msg.contains("`rpm`"), "{msg}");
}

#[test]
fn missing_speed_column() {
    let (e, msg) = err("time_s\n0\n0.0005\n");
    assert!(matches!(e, AnalysisError::Header { line: 1, .. }), "{e:?}");
    assert!(msg.contains("missing column 2"), "{msg}");
}

#[test]
fn header_after_comments_is_reported_at_its_line() {
    let (e, _) = err(&format!("# a\n# b\n\ntime,drum_rpm\n{}", good_rows(10)));
    assert!(matches!(e, AnalysisError::Header { line: 4, .. }), "{e:?}");
}

#[test]
fn data_without_header() {
    let (e, msg) = err(&good_rows(10));
    assert!(matches!(e, AnalysisError::Header { line: 1, .. }), "{e:?}");
    assert!(msg.contains("found a number"), "{msg}");
}

#[test]
fn duplicate_channel_name() {
    let (e, msg) = err(&format!("time_s,drum_rpm,a_ax,a_ax\n{}", good_rows(10)));
    assert!(matches!(e, AnalysisError::Header { line: 1, .. }), "{e:?}");
    assert!(msg.contains("duplicate"), "{msg}");
}

#[test]
fn non_numeric_cell_names_line_and_column() {
    let mut text = format!("{HEADER}{}", good_rows(10));
    // Line 5 = header + 4th data row; break its tub1_ax cell.
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut cells: Vec<&str> = lines[4].split(',').collect();
    cells[2] = "1.2.3";
    lines[4] = cells.join(",");
    text = lines.join("\n");
    let (e, msg) = err(&text);
    match &e {
        AnalysisError::NotANumber {
            line,
            column,
            value,
            ..
        } => {
            assert_eq!(
                (*line, column.as_str(), value.as_str()),
                (5, "tub1_ax", "1.2.3")
            );
        }
        other => panic!("wrong error {other:?}"),
    }
    assert!(msg.contains("line 5") && msg.contains("`tub1_ax`"), "{msg}");
}

#[test]
fn nan_and_empty_cells_are_rejected() {
    let text = format!("{HEADER}{}0.005,110,NaN,0,0\n", good_rows(10));
    let (e, _) = err(&text);
    assert!(
        matches!(e, AnalysisError::NotANumber { line: 12, ref column, .. } if column == "tub1_ax"),
        "{e:?}"
    );
    let text = format!("{HEADER}{}0.005,,1,0,0\n", good_rows(10));
    let (e, _) = err(&text);
    assert!(
        matches!(e, AnalysisError::NotANumber { line: 12, ref column, .. } if column == "drum_rpm"),
        "{e:?}"
    );
}

#[test]
fn ragged_row() {
    let text = format!("{HEADER}{}0.0015,101,1,2\n", good_rows(3));
    let (e, msg) = err(&text);
    assert!(
        matches!(
            e,
            AnalysisError::RaggedRow {
                line: 5,
                expected: 5,
                found: 4,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(msg.contains("line 5"), "{msg}");
}

#[test]
fn time_not_increasing() {
    let mut rows: Vec<String> = good_rows(10).lines().map(String::from).collect();
    rows[4] = rows[3].clone(); // data row 5 (file line 6) repeats the time of row 4
    let (e, msg) = err(&format!("{HEADER}{}\n", rows.join("\n")));
    assert!(
        matches!(e, AnalysisError::TimeNotIncreasing { line: 6, .. }),
        "{e:?}"
    );
    assert!(msg.contains("line 6"), "{msg}");
}

#[test]
fn time_not_uniform() {
    // Drop data row 6 (t = 0.0025): the step into file line 7 is twice the others.
    let rows: Vec<String> = good_rows(30).lines().map(String::from).collect();
    let kept: Vec<&String> = rows
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != 5)
        .map(|(_, r)| r)
        .collect();
    let text = format!(
        "{HEADER}{}\n",
        kept.iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
    let (e, msg) = err(&text);
    assert!(
        matches!(e, AnalysisError::TimeNotUniform { line: 7, .. }),
        "{e:?}"
    );
    assert!(msg.contains("line 7"), "{msg}");
}

#[test]
fn too_few_samples() {
    let (e, msg) = err(&format!("{HEADER}{}", good_rows(3)));
    assert!(
        matches!(e, AnalysisError::TooFewSamples { found: 3, .. }),
        "{e:?}"
    );
    assert!(msg.contains("too few samples"), "{msg}");
}

#[test]
fn empty_file() {
    let (e, _) = err("# only a comment\n\n");
    assert!(matches!(e, AnalysisError::EmptyFile { .. }), "{e:?}");
}

#[test]
fn quoted_names_with_commas() {
    // A measured file whose channel names hold commas: the csv crate reads the quoted field.
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "time_s,drum_rpm,\"mic, left\",tub1_ax\n{}",
        good_rows(12)
            .lines()
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                format!("{},{},{},{}\n", f[0], f[1], f[2], f[3])
            })
            .collect::<String>()
    );
    let s = read_signals(write(&dir, "q.csv", &text)).unwrap();
    let names: Vec<_> = s.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["mic, left", "tub1_ax"]);
}
