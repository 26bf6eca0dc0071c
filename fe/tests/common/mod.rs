//! Shared by the FE tests that run CalculiX.

use washdyn_fe::ccx;

/// Whether ccx can run. Without it a test skips with a message, except under CI (`CI=true`),
/// where it fails: CI installs calculix-ccx.
pub fn have_ccx() -> bool {
    let ok = ccx::available();
    if !ok {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI must install CalculiX (apt-get install calculix-ccx)"
        );
        eprintln!("skipped: ccx not found (apt-get install calculix-ccx)");
    }
    ok
}
