//! UFF dataset 58 and 58b files written by an independent writer, pyuff (PyPI, installed by
//! CI), read back by `washdyn_analysis::uff58`: samples bit for bit against what pyuff itself
//! reads (and against the data it was given, to the text's digits), names, directions, dt and
//! start time; pyuff's files, corrupted, refused with the dataset and field named.
//! pyuff writes 58b in the machine's byte order only: the big-endian file is its little-endian
//! one with each payload byte-swapped and field 3 of the number line set to 2 (pyuff reads it
//! back as the reference). pyuff's 58b is always double (with `force_double=False` it writes
//! doubles under a single-precision byte count): binary single precision is covered by the
//! crate's unit tests. Without pyuff the tests skip with a message, except under CI.

use crate::common;

use std::path::Path;
use std::process::Command;
use washdyn_analysis::uff58::{self, Encoding, Precision, Record, SiUnit, UffError};

fn pyuff() -> bool {
    common::python_modules("pyuff")
}

/// Writes ascii_double (after a dataset 151), ascii_single, binary_le and binary_be, three
/// channels each, and for each file what pyuff reads back (`.json`, `.pyuff.bin`) and the data
/// it was given (`.orig.bin`), as little-endian f64.
const WRITE: &str = r#"
import sys, json, numpy as np, pyuff
out = sys.argv[1]
fs, t0, n = 2000.0, 0.25, 1001
x = t0 + np.arange(n) / fs
rng = np.random.default_rng(51)
channels = [("tub front", 101, 3, 12, "g", 0.3), ("tub rear", 102, -1, 12, "m/s^2", 5.0),
            ("cabinet top", 7, 2, 8, "mm", 2.0)]
def dset(i, binary, single=False):
    name, node, d, dtype, unit, amp = channels[i]
    data = amp * (np.sin(2 * np.pi * 23.5 * x + i) + 0.1 * rng.standard_normal(n))
    ds = {'type': 58, 'binary': binary, 'func_type': 1, 'id1': name, 'id2': 'run-up',
          'rsp_node': node, 'rsp_dir': d, 'ref_node': 0, 'ref_dir': 0, 'data': data, 'x': x,
          'abscissa_spacing': 1, 'abscissa_spec_data_type': 17, 'abscissa_axis_units_lab': 's',
          'ordinate_spec_data_type': dtype, 'ordinate_axis_units_lab': unit,
          'orddenom_spec_data_type': 0, 'z_axis_spec_data_type': 0}
    if single:
        ds['ord_data_type'] = 2
    return ds
header = pyuff.prepare_151(model_name='washer', description='run-up', db_app='washdyn',
                           program='pyuff')
files = {'ascii_double': ([header] + [dset(i, 0) for i in range(3)], True),
         'ascii_single': ([dset(i, 0, True) for i in range(3)], False),
         'binary_le': ([dset(i, 1) for i in range(3)], True)}
originals = {}
for name, (sets, double) in files.items():
    originals[name] = [s['data'].copy() for s in sets if s['type'] == 58]
    # mode='add' to an empty file: 'overwrite' with binary sets loses the first one (pyuff
    # 2.5.8 reopens the file with 'wb' after its header).
    open(f'{out}/{name}.uff', 'w').close()
    pyuff.UFF(f'{out}/{name}.uff').write_sets(sets, mode='add', force_double=double)
raw = open(f'{out}/binary_le.uff', 'rb').read()
be, pos = b'', 0
while (i := raw.find(b'    58b', pos)) >= 0:
    nl = raw.index(b'\n', i)
    line = raw[i:nl]
    assert line[7:13] == b'     1', line
    nbytes = int(line[31:43])
    end = nl + 1
    for _ in range(11):
        end = raw.index(b'\n', end) + 1
    payload = np.frombuffer(raw[end:end + nbytes], '<f8').astype('>f8').tobytes()
    be += raw[pos:i] + line[:7] + b'     2' + line[13:] + raw[nl:end] + payload
    pos = end + nbytes
open(f'{out}/binary_be.uff', 'wb').write(be + raw[pos:])
originals['binary_be'] = originals['binary_le']
for name in ['ascii_double', 'ascii_single', 'binary_le', 'binary_be']:
    sets = [s for s in pyuff.UFF(f'{out}/{name}.uff').read_sets() if s['type'] == 58]
    assert len(sets) == 3, name
    meta = []
    with open(f'{out}/{name}.pyuff.bin', 'wb') as fb, open(f'{out}/{name}.orig.bin', 'wb') as fo:
        for s, o in zip(sets, originals[name]):
            fb.write(np.asarray(s['data'], '<f8').tobytes())
            fo.write(np.asarray(o, '<f8').tobytes())
            keys = ['id1', 'rsp_node', 'rsp_dir', 'abscissa_min', 'abscissa_inc', 'num_pts']
            meta.append({k: s[k].item() if hasattr(s[k], 'item') else s[k] for k in keys})
    json.dump(meta, open(f'{out}/{name}.json', 'w'))
"#;

/// pyuff's files in `dir`.
fn write_files(dir: &Path) {
    let o = Command::new("python3")
        .args(["-c", WRITE])
        .arg(dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn f64s(path: &Path) -> Vec<f64> {
    let b = std::fs::read(path).unwrap();
    b.chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn pyuff_files_read_back_bit_for_bit() {
    if !pyuff() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    write_files(dir.path());
    let factors = [9.80665, 1.0, 1e-3];
    let units = [
        SiUnit::MetrePerSecondSquared,
        SiUnit::MetrePerSecondSquared,
        SiUnit::Metre,
    ];
    for name in ["ascii_double", "ascii_single", "binary_le", "binary_be"] {
        let file = uff58::read_file(dir.path().join(format!("{name}.uff"))).unwrap();
        let meta: Vec<serde_json::Value> = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join(format!("{name}.json"))).unwrap(),
        )
        .unwrap();
        let reference = f64s(&dir.path().join(format!("{name}.pyuff.bin")));
        let original = f64s(&dir.path().join(format!("{name}.orig.bin")));
        assert_eq!(file.channels.len(), 3, "{name}");
        let skipped: Vec<String> = file.skipped.iter().map(|s| s.number.to_string()).collect();
        assert_eq!(
            skipped,
            if name == "ascii_double" {
                vec!["151"]
            } else {
                vec![]
            }
        );
        let mut offset = 0;
        for (i, (c, m)) in file.channels.iter().zip(&meta).enumerate() {
            let n = m["num_pts"].as_u64().unwrap() as usize;
            assert_eq!(c.samples.len(), n);
            let dir_code = m["rsp_dir"].as_i64().unwrap();
            assert_eq!(c.response.node, m["rsp_node"].as_i64().unwrap());
            assert_eq!(i64::from(c.response.direction.code()), dir_code);
            let id1 = m["id1"].as_str().unwrap();
            let dir = ["-X", "", "+X", "+Y", "+Z"][(dir_code + 1) as usize];
            assert_eq!(c.name, format!("{id1} [{}{dir}]", c.response.node));
            assert_eq!(c.dt, m["abscissa_inc"].as_f64().unwrap());
            assert_eq!(c.start_time, m["abscissa_min"].as_f64().unwrap());
            assert_eq!((c.dt, c.start_time), (5e-4, 0.25));
            assert_eq!((c.unit.factor, c.unit.si), (factors[i], Some(units[i])));
            assert!(c.warnings.is_empty(), "{name}: {:?}", c.warnings);
            let (want_encoding, want_precision, digits) = match name {
                "ascii_double" => (Encoding::Ascii, Precision::Double, 1e-11),
                "ascii_single" => (Encoding::Ascii, Precision::Single, 6e-6),
                "binary_le" => (Encoding::BinaryLittleEndian, Precision::Double, 0.0),
                _ => (Encoding::BinaryBigEndian, Precision::Double, 0.0),
            };
            assert_eq!((c.encoding, c.precision), (want_encoding, want_precision));
            assert_eq!(c.dataset, i + 1 + usize::from(name == "ascii_double"));
            let pyuff_si: Vec<f64> = reference[offset..offset + n]
                .iter()
                .map(|v| v * factors[i])
                .collect();
            assert_eq!(
                c.samples, pyuff_si,
                "{name}, channel {i}: against pyuff's reading"
            );
            for (k, (&s, &o)) in c
                .samples
                .iter()
                .zip(&original[offset..offset + n])
                .enumerate()
            {
                let o = o * factors[i];
                let tol = digits * o.abs().max(1e-3 * factors[i]);
                assert!(
                    (s - o).abs() <= tol,
                    "{name}, channel {i}, sample {k}: {s} vs {o}"
                );
            }
            offset += n;
        }
    }
}

/// Where the data of the `nth` (0-based) dataset 58 with number line `tag` start.
fn data_start(bytes: &[u8], tag: &[u8], nth: usize) -> usize {
    let mut at = bytes
        .windows(tag.len())
        .enumerate()
        .filter(|(_, w)| *w == tag)
        .nth(nth)
        .unwrap()
        .0;
    // The number line and the 11 header records.
    for _ in 0..12 {
        at += bytes[at..].iter().position(|&b| b == b'\n').unwrap() + 1;
    }
    at
}

/// `bytes` with the `nth` (0-based) occurrence of `from` replaced by `to`.
fn replace_nth(bytes: &[u8], from: &[u8], to: &[u8], nth: usize) -> Vec<u8> {
    let at = bytes
        .windows(from.len())
        .enumerate()
        .filter(|(_, w)| *w == from)
        .nth(nth)
        .unwrap_or_else(|| panic!("{:?} occurs {nth} times", String::from_utf8_lossy(from)))
        .0;
    [&bytes[..at], to, &bytes[at + from.len()..]].concat()
}

#[test]
fn pyuff_files_corrupted_are_refused_naming_dataset_and_field() {
    if !pyuff() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    write_files(dir.path());
    let ascii = std::fs::read(dir.path().join("ascii_double.uff")).unwrap();
    let binary = std::fs::read(dir.path().join("binary_le.uff")).unwrap();
    let refuse = |bytes: Vec<u8>, wants: &[&str]| {
        let path = dir.path().join("bad.uff");
        std::fs::write(&path, bytes).unwrap();
        let e = uff58::read(&path).unwrap_err();
        let m = e.to_string();
        assert!(m.contains("bad.uff"), "{m}");
        for w in wants {
            assert!(m.contains(w), "`{w}` not in: {m}");
        }
        e
    };
    // The second channel, dataset 3 of the ASCII file (after the 151), dataset 2 of the binary.
    let e = refuse(
        replace_nth(&ascii, b"      1001", b"      1002", 1),
        &["dataset 3 (58)", "record 7, field 2"],
    );
    assert!(matches!(
        e,
        UffError::PointsMismatch {
            announced: 1002,
            found: 1001,
            ..
        }
    ));
    let e = refuse(
        replace_nth(&ascii, b"      1001", b"      10o1", 1),
        &[
            "dataset 3 (58)",
            "record 7, field 2 (number of points)",
            "`10o1`",
        ],
    );
    assert!(matches!(e, UffError::Field { .. }));
    let e = refuse(
        ascii[..ascii.len() - 7].to_vec(),
        &["dataset 4 (58)", "closing"],
    );
    assert!(matches!(e, UffError::MissingDelimiter { .. }));
    // The first value of the first channel's data, its exponent's last digit a letter.
    let mut bad = ascii.clone();
    bad[data_start(&ascii, b"    58 ", 0) + 19] = b'x';
    let e = refuse(bad, &["dataset 2 (58)", "line 24, record 12 (data)"]);
    assert!(matches!(e, UffError::BadValue { .. }));
    let cut = ascii[..ascii.len() - 200]
        .iter()
        .rposition(|&b| b == b'\n')
        .unwrap();
    let e = refuse(ascii[..=cut].to_vec(), &["dataset 4 (58)", "cut short"]);
    assert!(matches!(
        e,
        UffError::CutShort {
            record: Record::Data,
            ..
        }
    ));
    let e = refuse(
        replace_nth(&binary, b"        8008", b"        8000", 1),
        &["dataset 2 (58b)", "field 6 (number of bytes)"],
    );
    assert!(matches!(
        e,
        UffError::ByteCount {
            announced: 8000,
            expected: 8008,
            ..
        }
    ));
    let e = refuse(
        replace_nth(&binary, b"58b     1", b"58b     0", 1),
        &["dataset 2 (58b)", "field 3 (byte ordering)"],
    );
    assert!(matches!(e, UffError::ByteOrder { value: 0, .. }));
    let e = refuse(
        replace_nth(&binary, b"58b     1     2", b"58b     1     3", 2),
        &["dataset 3 (58b)", "field 4 (floating point format)"],
    );
    assert!(matches!(e, UffError::FloatFormat { value: 3, .. }));
    // A NaN in the second channel's payload: its first sample.
    let header_end = data_start(&binary, b"    58b", 1);
    let mut nan = binary.clone();
    nan[header_end..header_end + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    let e = refuse(nan, &["dataset 2 (58b)", "record 12", "sample 0"]);
    assert!(matches!(e, UffError::NotFinite { sample: 0, .. }));
    let e = refuse(
        binary[..binary.len() - 100].to_vec(),
        &["dataset 3 (58b)", "cut short"],
    );
    assert!(matches!(e, UffError::CutShort { what: "bytes", .. }));
}
