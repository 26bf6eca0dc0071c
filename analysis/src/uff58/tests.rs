//! Files written here by the format's documentation (independent of the reader), read back;
//! every malformation refused with its dataset and field. tests/uff58.rs reads pyuff's files.

use std::path::Path;

use super::*;
use crate::uff58::error::{FieldProblem, NotTimeHistory};

/// One dataset to write.
#[derive(Clone)]
struct Spec {
    id1: &'static str,
    function: i64,
    node: i64,
    dir: i64,
    ord_type: i64,
    points: Option<usize>,
    spacing: i64,
    start: f64,
    dt: f64,
    abscissa: (i64, &'static str),
    ordinate: (i64, &'static str),
    data: Vec<f64>,
}

fn spec(data: Vec<f64>) -> Spec {
    Spec {
        id1: "tub front",
        function: 1,
        node: 101,
        dir: 3,
        ord_type: 4,
        points: None,
        spacing: 1,
        start: 0.5,
        dt: 1.0 / 1024.0,
        abscissa: (17, "s"),
        ordinate: (12, "m/s^2"),
        data,
    }
}

fn data() -> Vec<f64> {
    (0..23)
        .map(|i| (i as f64 * 0.7).sin() * 3.3 + 1e-9)
        .collect()
}

/// Records 1-11.
fn header(s: &Spec) -> String {
    let mut h = format!("{:<80}\n", s.id1);
    for id in ["run 1", "29-Nov-26 12:00:00", "NONE", "NONE"] {
        h += &format!("{id:<80}\n");
    }
    h += &format!(
        "{:5}{:10}{:5}{:10} {:<10}{:10}{:4} {:<10}{:10}{:4}\n",
        s.function, 0, 0, 0, "NONE", s.node, s.dir, "NONE", 0, 0
    );
    let n = s.points.unwrap_or(s.data.len());
    h += &format!(
        "{:10}{:10}{:10}{:>13e}{:>13e}{:>13e}\n",
        s.ord_type, n, s.spacing, s.start, s.dt, 0.0
    );
    let axes = [s.abscissa, s.ordinate, (0, "NONE"), (0, "NONE")];
    for (t, unit) in axes {
        h += &format!("{t:10}{:5}{:5}{:5} {:<20} {unit:<20}\n", 0, 0, 0, "NONE");
    }
    h
}

fn ascii(s: &Spec) -> Vec<u8> {
    let mut f = format!("    -1\n    58{:74}\n{}", "", header(s));
    for row in s.data.chunks(4) {
        row.iter().for_each(|v| f += &format!("{v:>25e}"));
        f += "\n";
    }
    f += "    -1\n";
    f.into_bytes()
}

fn binary(s: &Spec, little: bool) -> Vec<u8> {
    let single = s.ord_type == 2;
    let mut payload = Vec::new();
    for &v in &s.data {
        match (single, little) {
            (true, true) => payload.extend((v as f32).to_le_bytes()),
            (true, false) => payload.extend((v as f32).to_be_bytes()),
            (false, true) => payload.extend(v.to_le_bytes()),
            (false, false) => payload.extend(v.to_be_bytes()),
        }
    }
    let order = if little { 1 } else { 2 };
    let mut f = format!(
        "    -1\n    58b{order:6}{:6}{:12}{:12}{:6}{:6}{:12}{:12}\n{}",
        2,
        11,
        payload.len(),
        0,
        0,
        0,
        0,
        header(s)
    )
    .into_bytes();
    f.extend(payload);
    f.extend(b"    -1\n");
    f
}

fn parse_ok(bytes: &[u8]) -> Uff58File {
    parse(bytes, Path::new("rig.uff")).unwrap_or_else(|e| panic!("{e}"))
}

fn parse_err(bytes: &[u8]) -> (UffError, String) {
    let e = parse(bytes, Path::new("rig.uff")).expect_err("refused");
    let m = e.to_string();
    assert!(m.starts_with("rig.uff"), "{m}");
    (e, m)
}

#[test]
fn ascii_double_reads_bit_for_bit() {
    let s = spec(data());
    let f = parse_ok(&ascii(&s));
    let c = &f.channels[0];
    assert_eq!(c.samples, s.data);
    assert_eq!(c.name, "tub front [101+Z]");
    assert_eq!(c.response.direction.to_string(), "+Z");
    assert_eq!((c.dt, c.start_time), (s.dt, 0.5));
    assert_eq!(
        (c.precision, c.encoding),
        (Precision::Double, Encoding::Ascii)
    );
    assert_eq!(c.unit.si, Some(SiUnit::MetrePerSecondSquared));
    assert_eq!(c.quantity(), Quantity::Acceleration);
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
}

#[test]
fn binary_both_byte_orders_and_precisions() {
    for little in [true, false] {
        for ord_type in [2, 4] {
            let s = Spec {
                ord_type,
                ..spec(data())
            };
            let c = &parse_ok(&binary(&s, little)).channels[0];
            let want: Vec<f64> = if ord_type == 2 {
                s.data.iter().map(|&v| f64::from(v as f32)).collect()
            } else {
                s.data.clone()
            };
            assert_eq!(c.samples, want, "little {little}, type {ord_type}");
            let order = [Encoding::BinaryBigEndian, Encoding::BinaryLittleEndian];
            assert_eq!(c.encoding, order[little as usize]);
        }
    }
}

#[test]
fn datasets_of_other_kinds_are_skipped_and_listed() {
    let mut f = b"    -1\n   151\nmodel\n    -1\n".to_vec();
    f.extend(ascii(&spec(data())));
    // A binary dataset of another kind: passed over by its byte count (its bytes hold `-1`).
    f.extend(b"    -1\n  2414b     1     2           1           8\nheader\n    -1\n\n    -1\n");
    let mut second = spec(vec![1.0, 2.0]);
    second.id1 = "NONE";
    second.dir = -4;
    f.extend(binary(&second, true));
    f.extend(b"\r\n    -1\r\n   164\r\n    1  SI\r\n    -1\r\n");
    let r = parse_ok(&f);
    assert_eq!(r.channels.len(), 2);
    assert_eq!(r.channels[1].name, "101-RX");
    assert_eq!(r.channels[1].dataset, 4);
    let skipped: Vec<String> = r.skipped.iter().map(|s| s.number.to_string()).collect();
    assert_eq!(skipped, ["151", "2414b", "164"]);
    assert_eq!(r.skipped[2].index, 5);
}

#[test]
fn crlf_line_ends_and_a_line_end_before_the_closing_delimiter() {
    let s = spec(data());
    let text = String::from_utf8(ascii(&s)).unwrap().replace('\n', "\r\n");
    assert_eq!(parse_ok(text.as_bytes()).channels[0].samples, s.data);
    let mut b = binary(&s, true);
    let end = b.len() - b"    -1\n".len();
    b.splice(end..end, b"\r\n".iter().copied());
    assert_eq!(parse_ok(&b).channels[0].samples, s.data);
}

#[test]
fn units_to_si() {
    let g = 9.80665;
    let cases: [((i64, &'static str), f64, Option<SiUnit>); 8] = [
        ((12, "g"), g, Some(SiUnit::MetrePerSecondSquared)),
        ((12, "mm/s2"), 1e-3, Some(SiUnit::MetrePerSecondSquared)),
        ((8, "mm"), 1e-3, Some(SiUnit::Metre)),
        ((11, "in/s"), 0.0254, Some(SiUnit::MetrePerSecond)),
        ((1, "V"), 1.0, Some(SiUnit::Volt)),
        ((19, "rpm"), 1.0 / 60.0, Some(SiUnit::PerSecond)),
        ((13, "N"), 1.0, Some(SiUnit::Newton)),
        ((0, "furlong"), 1.0, None),
    ];
    for (ordinate, factor, si) in cases {
        let s = Spec {
            ordinate,
            ..spec(data())
        };
        let c = &parse_ok(&ascii(&s)).channels[0];
        assert_eq!((c.unit.factor, c.unit.si), (factor, si), "{ordinate:?}");
        let want: Vec<f64> = s.data.iter().map(|v| v * factor).collect();
        assert_eq!(c.samples, want);
        assert_eq!(c.warnings.is_empty(), si.is_some(), "{:?}", c.warnings);
    }
}

#[test]
fn unit_warnings_are_never_silent() {
    let warn = |ordinate| {
        let s = Spec {
            ordinate,
            ..spec(data())
        };
        parse_ok(&ascii(&s)).channels[0].warnings.clone()
    };
    assert_eq!(warn((12, "G")), [UffWarning::UpperCaseG]);
    let assumed = SiUnit::MetrePerSecondSquared;
    let none = [UffWarning::NoUnitLabel {
        data_type: 12,
        assumed,
    }];
    assert_eq!(warn((12, "NONE")), none);
    assert!(matches!(
        warn((8, "g"))[0],
        UffWarning::UnitDisagrees { .. }
    ));
    assert!(matches!(
        warn((12, "furlong/s^2"))[0],
        UffWarning::UnknownUnit { .. }
    ));
    assert!(matches!(warn((0, "NONE"))[0], UffWarning::NoUnit { .. }));
    let m = warn((12, "gee"))[0].to_string();
    assert!(m.contains("`gee`"), "{m}");
}

#[test]
fn milliseconds_abscissa_and_general_abscissa() {
    let s = Spec {
        abscissa: (1, "ms"),
        dt: 0.5,
        start: 2.0,
        ..spec(data())
    };
    let c = &parse_ok(&ascii(&s)).channels[0];
    assert_eq!((c.dt, c.start_time), (0.5e-3, 2e-3));
}

#[test]
fn touching_values_are_cut_at_the_field_width() {
    let s = Spec {
        ord_type: 2,
        ..spec(vec![0.0, 0.0, 0.0])
    };
    let f = format!(
        "    -1\n    58\n{}-1.23456E-100-2.00000D+000  3.00000E+00\n    -1\n",
        header(&s)
    );
    let c = &parse_ok(f.as_bytes()).channels[0];
    assert_eq!(c.samples, [-1.23456e-100, -2.0, 3.0]);
}

/// A good file with `from` replaced by `to` (once).
fn corrupt(bytes: &[u8], from: &str, to: &str) -> Vec<u8> {
    let text = String::from_utf8_lossy(bytes);
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1).into_bytes()
}

#[test]
fn missing_delimiters_refused() {
    let good = ascii(&spec(data()));
    let (e, m) = parse_err(&good[7..]);
    assert!(
        matches!(
            e,
            UffError::MissingDelimiter {
                side: Side::Start,
                ..
            }
        ),
        "{m}"
    );
    assert!(m.contains("dataset 1") && m.contains("opening"), "{m}");
    let (e, m) = parse_err(&good[..good.len() - 7]);
    assert!(
        matches!(
            e,
            UffError::MissingDelimiter {
                side: Side::End,
                ..
            }
        ),
        "{m}"
    );
    assert!(m.contains("dataset 1 (58)") && m.contains("closing"), "{m}");
    let b = binary(&spec(data()), true);
    let (e, m) = parse_err(&b[..b.len() - 7]);
    assert!(
        matches!(
            e,
            UffError::MissingDelimiter {
                side: Side::End,
                ..
            }
        ),
        "{m}"
    );
    assert!(m.contains("dataset 1 (58b)"), "{m}");
}

#[test]
fn datasets_cut_short_refused() {
    let good = ascii(&spec(data()));
    let text = String::from_utf8(good.clone()).unwrap();
    let cut: String = text.lines().take(8).map(|l| format!("{l}\n")).collect();
    let (e, m) = parse_err(format!("{cut}    -1\n").as_bytes());
    let record = Record::Header(7);
    assert!(
        matches!(e, UffError::CutShort { record: r, found: 6, .. } if r == record),
        "{m}"
    );
    assert!(m.contains("record 7"), "{m}");
    // The last data line (3 values of 25 characters) and the closing delimiter.
    let (e, m) = parse_err(&good[..good.len() - 83]);
    assert!(
        matches!(
            e,
            UffError::CutShort {
                record: Record::Data,
                ..
            }
        ),
        "{m}"
    );
    let b = binary(&spec(data()), false);
    let (e, m) = parse_err(&b[..b.len() - 20]);
    assert!(
        matches!(
            e,
            UffError::CutShort {
                record: Record::Data,
                what: "bytes",
                ..
            }
        ),
        "{m}"
    );
    assert!(m.contains("dataset 1 (58b)"), "{m}");
}

#[test]
fn header_numbers_that_do_not_parse_refused() {
    let good = ascii(&spec(data()));
    let n = format!("{:10}", data().len());
    let (e, m) = parse_err(&corrupt(&good, &n, "      2x3 "));
    let UffError::Field { field, problem, .. } = &e else {
        panic!("{m}")
    };
    assert_eq!((field.record, field.field), (Record::Header(7), 2));
    assert_eq!(problem, &FieldProblem::NotAnInteger("2x3".into()));
    assert!(m.contains("record 7, field 2 (number of points)"), "{m}");
    assert!(m.contains("dataset 1 (58)") && m.contains("line 9"), "{m}");
    let (_, m) = parse_err(&corrupt(&good, " 101   3", " 101   9"));
    assert!(m.contains("record 6, field 7 (response direction)"), "{m}");
    let (_, m) = parse_err(&corrupt(&good, "    58 ", "    5x "));
    assert!(m.contains("field 1 (dataset number)"), "{m}");
    let (_, m) = parse_err(&corrupt(&good, "        17", "      1.7 "));
    assert!(m.contains("record 8, field 1 (specific data type)"), "{m}");
}

#[test]
fn point_and_byte_counts_that_disagree_refused() {
    let s = Spec {
        points: Some(24),
        ..spec(data())
    };
    let (e, m) = parse_err(&ascii(&s));
    assert!(
        matches!(
            e,
            UffError::PointsMismatch {
                announced: 24,
                found: 23,
                ..
            }
        ),
        "{m}"
    );
    assert!(m.contains("record 7, field 2"), "{m}");
    let b = binary(&spec(data()), true);
    let (e, m) = parse_err(&corrupt(&b, "         184", "         180"));
    assert!(
        matches!(
            e,
            UffError::ByteCount {
                announced: 180,
                expected: 184,
                ..
            }
        ),
        "{m}"
    );
    assert!(
        m.contains("dataset 1 (58b)") && m.contains("field 6 (number of bytes)"),
        "{m}"
    );
}

#[test]
fn byte_order_and_float_format_refused() {
    let b = binary(&spec(data()), true);
    let (e, m) = parse_err(&corrupt(&b, "58b     1", "58b     3"));
    assert!(matches!(e, UffError::ByteOrder { value: 3, .. }), "{m}");
    assert!(m.contains("field 3 (byte ordering)"), "{m}");
    let (e, m) = parse_err(&corrupt(&b, "58b     1     2", "58b     1     1"));
    assert!(matches!(e, UffError::FloatFormat { value: 1, .. }), "{m}");
    assert!(
        m.contains("dataset 1 (58b)") && m.contains("IEEE 754"),
        "{m}"
    );
}

#[test]
fn nan_and_infinite_samples_refused() {
    let mut d = data();
    d[7] = f64::NAN;
    let (e, m) = parse_err(&ascii(&spec(d.clone())));
    assert!(matches!(e, UffError::NotFinite { sample: 7, .. }), "{m}");
    d[7] = 1.0;
    d[3] = f64::INFINITY;
    let (e, m) = parse_err(&binary(&spec(d), false));
    assert!(matches!(e, UffError::NotFinite { sample: 3, .. }), "{m}");
    assert!(m.contains("dataset 1 (58b), record 12"), "{m}");
    let (e, m) = parse_err(&corrupt(&ascii(&spec(data())), "1e-9", "1e-9x"));
    assert!(matches!(e, UffError::BadValue { .. }), "{m}");
}

#[test]
fn what_is_no_time_history_refused() {
    let refused = |s: Spec| {
        let (e, m) = parse_err(&ascii(&s));
        assert!(
            m.contains("not a time history") || m.contains("uneven"),
            "{m}"
        );
        e
    };
    let complex = refused(Spec {
        ord_type: 6,
        ..spec(data())
    });
    let reason = NotTimeHistory::Complex { code: 6 };
    assert!(matches!(complex, UffError::NotTimeHistory { reason: r, .. } if r == reason));
    let frf = refused(Spec {
        function: 4,
        ..spec(data())
    });
    assert!(
        frf.to_string().contains("frequency response function"),
        "{frf}"
    );
    let spectrum = refused(Spec {
        abscissa: (18, "Hz"),
        ..spec(data())
    });
    assert!(
        spectrum.to_string().contains("record 8, field 1"),
        "{spectrum}"
    );
    let hz = refused(Spec {
        abscissa: (0, "Hz"),
        ..spec(data())
    });
    assert!(hz.to_string().contains("record 8, field 6"), "{hz}");
    let uneven = refused(Spec {
        spacing: 0,
        ..spec(data())
    });
    assert!(
        matches!(uneven, UffError::UnevenAbscissa { .. }),
        "{uneven}"
    );
    assert!(
        uneven
            .to_string()
            .contains("record 7, field 3 (abscissa spacing)")
    );
}

#[test]
fn a_file_without_time_histories_is_refused_by_read() {
    let dir = std::env::temp_dir().join(format!("washdyn-uff-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("only151.uff");
    std::fs::write(&p, b"    -1\n   151\nmodel\n    -1\n").unwrap();
    let m = read(&p).unwrap_err().to_string();
    assert!(m.contains("no dataset 58") && m.contains("151"), "{m}");
    std::fs::write(&p, b"").unwrap();
    assert!(matches!(read(&p), Err(UffError::NoTimeHistories { .. })));
    let m = read(dir.join("absent.uff")).unwrap_err().to_string();
    assert!(m.contains("cannot read"), "{m}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Bad input never panics: every prefix of good files, and every byte replaced by a few others.
#[test]
fn mangled_files_never_panic() {
    let mut files = vec![ascii(&spec(data()[..5].to_vec()))];
    files.push(binary(&spec(data()[..5].to_vec()), true));
    for f in &files {
        for end in 0..f.len() {
            let _ = parse(&f[..end], Path::new("x"));
        }
        for i in 0..f.len() {
            for b in [b'-', b'9', b' ', b'\n', 0xB5] {
                let mut g = f.clone();
                g[i] = b;
                let _ = parse(&g, Path::new("x"));
            }
        }
    }
}
