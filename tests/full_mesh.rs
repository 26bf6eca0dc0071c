//! The full-mesh reference (issue 19, must-have 6): the linear machine assembled from the
//! tub's and the cabinet's full meshes in CalculiX (`*STEADY STATE DYNAMICS` at drum order 1)
//! against washdyn's Ritz model of the same machine in the frequency domain (harmonic.rs), every
//! sensor channel at eight speeds from 300 to 1400 rpm.
//!
//! ccx's 200-mode solve takes 15 to 20 min on 2 cores: the default test compares with ccx's
//! answer committed in models/fe/full-mesh.ccx.json, which it takes only for the deck the code
//! writes now (its FNV-1a hash; a changed mesh, model or deck writer fails the test). The
//! ignored test solves again and checks the committed answer (`cargo test --test integration
//! full_mesh:: -- --ignored`; needs ccx, except under CI=true, where it must run when asked).

use crate::common;

use std::path::{Path, PathBuf};
use washdyn::full_mesh::{Args, COMMITTED, COMPARED_SHARE, CcxReference, SPEEDS_RPM, Study, study};
use washdyn_fe::assembly::LinearSpec;

/// ccx's modes: 200 (to 347 Hz). With 100 (to 183 Hz) ccx's own truncation shows: its tub3_ax
/// falls 7.5 % short of the Ritz model at 1400 rpm (0.5 % with 200), the back wall's local
/// bending under the bearing load being in no coupled mode below 183 Hz, which our tub's
/// bearing correction modes carry (docs/full-mesh.md). ccx takes 778 s on one thread for 200
/// modes: mostly the eigen-solve.
const MODES: usize = 200;

fn committed() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(COMMITTED)
}

fn args(work: &Path, committed: Option<PathBuf>) -> Args {
    Args {
        model: "reference".into(),
        modes: vec![MODES],
        speeds_rpm: SPEEDS_RPM.to_vec(),
        spec: LinearSpec::default(),
        work: work.to_path_buf(),
        convergence: false,
        committed,
    }
}

#[test]
fn ritz_model_matches_the_full_mesh() {
    let work = tempfile::tempdir().unwrap();
    let s = study(&args(work.path(), Some(committed())), &mut |l| {
        println!("{l}")
    })
    .unwrap();
    holds(&s);
}

/// ccx solves the assembled machine again (15 to 20 min): the Ritz model holds against this
/// solve too, and the committed answer is this solve's to ccx's printed digits (the .dat's
/// 7 significant digits; measured on one machine: identical). Writes the answer to commit
/// into the target's scratch folder.
#[test]
#[ignore = "ccx's 200-mode solve, 15 to 20 min: run with --ignored"]
fn committed_ccx_answer_is_what_ccx_gives_now() {
    if !common::required_tool(
        washdyn_fe::ccx::available(),
        "CalculiX",
        "apt-get install calculix-ccx",
    ) {
        return;
    }
    let work = tempfile::tempdir().unwrap();
    let s = study(&args(work.path(), None), &mut |l| println!("{l}")).unwrap();
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("full-mesh");
    let wrote = washdyn::full_mesh::write(&s, &out).unwrap();
    println!("wrote {wrote:?}");
    holds(&s);
    let fresh = s.reference.as_ref().unwrap();
    let deck = work.path().join(format!("full_mesh_{MODES}.inp"));
    let deck = std::fs::read_to_string(deck).unwrap();
    let channels = fresh.channels[0].len();
    let old = CcxReference::read(&committed(), &deck, MODES, &SPEEDS_RPM, channels).unwrap();
    let mut worst = 0.0f64;
    for (a, b) in old
        .channels
        .iter()
        .flatten()
        .zip(fresh.channels.iter().flatten())
    {
        let scale = a.norm().max(1e-300);
        worst = worst.max(((a.re - b[0]).powi(2) + (a.im - b[1]).powi(2)).sqrt() / scale);
    }
    println!("committed against this solve: worst channel {worst:.1e}");
    assert!(worst < 1e-5, "{worst}");
}

/// What the Ritz model must meet against ccx's answer.
fn holds(s: &Study) {
    println!("rpm | compared | median | worst (channel) | worst complex");
    for sp in &s.speeds {
        println!(
            "{:5.0} | {:2} | {:5.2} % | {:5.2} % ({}) | {:5.2} %",
            sp.rpm,
            sp.channels.iter().filter(|c| c.compared).count(),
            100.0 * sp.median,
            100.0 * sp.worst,
            sp.worst_channel,
            100.0 * sp.worst_complex
        );
    }
    // One machine on both sides: the same mass (ccx: EMAS plus the point masses; measured
    // 2.8e-7 apart, ccx's 7 printed digits).
    let (mc, mr) = (s.mass_ccx.unwrap(), s.mass_ritz);
    assert!(
        (mc / mr - 1.0).abs() < 3e-6,
        "mass: ccx {mc} kg, Ritz {mr} kg"
    );
    // The coupled eigenfrequencies below 60 Hz, each against washdyn's nearest: a missing mode
    // (before the tub's correction modes, the drum rocking on the bearing unit at 42.3 and
    // 42.5 Hz: 1.9 and 2.4 % from the nearest) shows here.
    let worst_f = s
        .frequencies
        .iter()
        .fold(0.0f64, |m, (a, b)| m.max((b / a - 1.0).abs()));
    println!(
        "coupled eigenfrequencies below 60 Hz: worst difference {:.2} %",
        100.0 * worst_f
    );
    // Measured 0.02 % (before the tub's correction modes: 2.4 %).
    assert!(worst_f < 2e-3, "{worst_f}");
    // The target: every channel above 10 % of its speed's largest within 5 %
    // (measured with 200 ccx modes: median 0.0-0.1 %, worst 0.1 % at 300 rpm to 0.5 % at
    // 1400 rpm, tub3_ax; the moonshot's 2 % holds too).
    assert_eq!(COMPARED_SHARE, 0.1);
    for sp in &s.speeds {
        assert!(
            sp.worst <= 0.05,
            "{} rpm: {} off by {:.1} %",
            sp.rpm,
            sp.worst_channel,
            100.0 * sp.worst
        );
    }
}
