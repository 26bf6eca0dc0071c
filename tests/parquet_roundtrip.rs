//! The result files read back by an independent reader: pyarrow (Apache Arrow's Python
//! binding, installed by CI from PyPI) must find in `sensors.parquet` exactly the f64 values the
//! run computed, bit for bit, and must read the analysis tables with their nulls.
//! Without pyarrow the test skips with a message, except under CI (`CI=true`), where it fails.

use crate::common;

use std::path::Path;
use std::process::Command;
use washdyn::commands::{Backend, RunControl, RunSpec, run_command_with};
use washdyn::results::Format;
use washdyn_ode::Method;

fn pyarrow() -> bool {
    let ok = Command::new("python3")
        .args(["-c", "import pyarrow.parquet"])
        .status()
        .is_ok_and(|s| s.success());
    common::required_tool(ok, "python3 with pyarrow", "pip install pyarrow")
}

/// A run followed by an analysis up to the band `spec`'s sample rate resolves, as `washdyn
/// run` without `--no-plots`: the samples kept.
fn analysed(spec: &RunSpec) -> RunControl {
    RunControl {
        analysis_band_hz: Some(spec.sample_rate / 2.0),
        ..RunControl::default()
    }
}

/// The reference's default scene, generated, dopri5 at 1e-6, Parquet.
fn reference_run(dir: &Path, t_end: f64, sample_rate: f64, states: bool) -> RunSpec {
    RunSpec {
        model: "reference".into(),
        t_end: Some(t_end),
        out: Some(dir.to_path_buf()),
        method: Some(Method::Dopri5),
        tol: Some(1e-6),
        step: None,
        rho_inf: None,
        backend: Some(Backend::Generated),
        scene: None,
        sample_rate,
        max_steps: None,
        format: Format::Parquet,
        states,
        energy: false,
        start: washdyn_runtime::run::Start::Static,
        ..RunSpec::default()
    }
}

#[test]
fn sensor_file_reads_back_bit_for_bit_in_pyarrow() {
    if !pyarrow() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let args = reference_run(dir.path(), 6.0, 500.0, false);
    let o = run_command_with(&args, &analysed(&args), &mut |_| {}).unwrap();
    assert!(o.error.is_none());
    let (names, cols) = o.samples.unwrap();
    // pyarrow writes every column's values as little-endian f64 bytes, one file per column.
    let raw = dir.path().join("raw");
    std::fs::create_dir(&raw).unwrap();
    let listed = common::python(
        "import sys, struct, pyarrow as pa, pyarrow.parquet as pq\n\
         t = pq.read_table(sys.argv[1])\n\
         for i, name in enumerate(t.column_names):\n\
         \x20   assert t.schema.field(i).type == pa.float64(), name\n\
         \x20   a = t.column(i).to_pylist()\n\
         \x20   open(sys.argv[2] + '/' + str(i), 'wb').write(struct.pack('<%dd' % len(a), *a))\n\
         \x20   print(name)\n\
         print('unit:tub1_ax=' + t.schema.metadata[b'unit:tub1_ax'].decode())\n",
        &[&o.sensors, &raw],
    );
    let listed: Vec<&str> = listed.lines().collect();
    assert_eq!(&listed[..names.len()], names.as_slice());
    assert_eq!(listed[names.len()], "unit:tub1_ax=m/s^2");
    let mut compared = 0;
    for (i, col) in cols.iter().enumerate() {
        let bytes = std::fs::read(raw.join(i.to_string())).unwrap();
        let back: Vec<u64> = bytes
            .chunks_exact(8)
            .map(|b| u64::from_le_bytes(b.try_into().unwrap()))
            .collect();
        let ours: Vec<u64> = col.iter().map(|v| v.to_bits()).collect();
        assert_eq!(back, ours, "column {}", names[i]);
        compared += back.len();
    }
    assert_eq!(compared, names.len() * 3001);
}

#[test]
fn analysis_tables_read_in_pyarrow() {
    if !pyarrow() {
        return;
    }
    use washdyn::analysis::{AnalysisOptions, Channel, Signals, analyse_signals};
    // A 20 s ramp 60 -> 600 rpm with order 1 only: the tables hold both channels, and the order
    // tracks are null where the order is not resolved (the first blocks, below 2 revolutions).
    let fs = 1000.0;
    let n = 20_000;
    let rpm: Vec<f64> = (0..n).map(|i| 60.0 + 27.0 * i as f64 / fs).collect();
    let mut phi = 0.0;
    let x: Vec<f64> = rpm
        .iter()
        .map(|r| {
            phi += 2.0 * std::f64::consts::PI * r / 60.0 / fs;
            phi.sin()
        })
        .collect();
    let s = Signals::from_uniform(
        0.0,
        fs,
        rpm,
        vec![Channel::new("a_ax", x.clone()), Channel::new("b_uz", x)],
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let opts = AnalysisOptions {
        plot_size: (400, 300),
        svg: false,
        ..AnalysisOptions::default()
    };
    analyse_signals(&s, dir.path(), &opts).unwrap();
    let out = common::python(
        "import sys, pyarrow.parquet as pq, pyarrow.compute as pc\n\
         s = pq.read_table(sys.argv[1])\n\
         o = pq.read_table(sys.argv[2])\n\
         print(s.column_names)\n\
         print(sorted(set(s.column('channel').to_pylist())))\n\
         o1 = o.filter(pc.and_(pc.equal(o['order'], 1.0), pc.equal(o['channel'], 'a_ax')))\n\
         a = o1.column('amplitude')\n\
         print(a.null_count > 0, len(a) - a.null_count > 5, round(pc.max(a).as_py(), 1))\n",
        &[
            &dir.path().join("spectra.parquet"),
            &dir.path().join("orders.parquet"),
        ],
    );
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[0],
        "['channel', 'time_s', 'drum_rpm', 'frequency_hz', 'order', 'amplitude', 'amplitude_energy']"
    );
    assert_eq!(lines[1], "['a_ax', 'b_uz']");
    // Unit sine in order 1: amplitude 1.0.
    assert_eq!(lines[2], "True True 1.0");
}

/// `--states` keeps one row per sample (written by a thread): the sample times, the drum angle
/// (the exact integral of the speed table: 0 at t = 0) and q, whose tub rows are what the
/// sensors' positions follow; read back through the recovery's own reader.
#[test]
fn states_file_holds_every_sample_with_the_drum_angle() {
    let dir = tempfile::tempdir().unwrap();
    let args = reference_run(dir.path(), 2.0, 1000.0, true);
    let mut o = run_command_with(&args, &analysed(&args), &mut |_| {}).unwrap();
    assert!(o.error.is_none());
    // The run writes into its own folder, renamed into place here.
    o.publish().unwrap();
    let (names, cols) = o.samples.unwrap();
    let s = washdyn::fields::States::read(&dir.path().join("states.parquet")).unwrap();
    assert_eq!(s.t, cols[0], "the same sample times");
    assert_eq!(s.q.len(), 6, "the `full` scene's rigid tub");
    let model = washdyn_models::built_in("reference").unwrap().unwrap();
    let speed = washdyn_model::speed::Speed::new(&model.speed.table);
    for (t, phi) in s.t.iter().zip(&s.phi) {
        assert_eq!(*phi, speed.drive(*t).phi);
    }
    // The tub moves (the static start, then the unbalance), and the states say so.
    assert!(s.q[2].iter().any(|z| z.abs() > 1e-5), "{:?}", &s.q[2][..4]);
    assert!(names.len() > 2);
}
