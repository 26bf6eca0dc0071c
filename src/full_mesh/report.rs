//! full-mesh.md and full-mesh.json: the study as a reader sees it.

use super::{COMPARED_SHARE, FullMeshError, Study};
use crate::error::FileError;
use std::path::{Path, PathBuf};

/// What the reference relies on in CalculiX 2.20, measured on small decks (issue 19).
const CCX_NOTES: &str = "
## What the reference relies on in CalculiX 2.20

Checked on small decks (tests/fe_steady_state.rs: a chain of 40 point masses against a direct
complex solve in the same modal subspace; a curved 8 x 8 S8R plate for the equations; the
scalar dofs by a script during issue 19).

- Rayleigh damping and dashpots combine in `*STEADY STATE DYNAMICS`: ccx solves
  (Lambda - w^2 + i w (beta Lambda + Phi^T C Phi)) q = Phi^T F in the `*FREQUENCY` step's modes
  (agreement 1.3e-7, the .dat's 7 digits).
- A `*DASHPOT` table's frequency is in cycles/time (Hz), interpolated linearly, held constant
  beyond its ends: the hysteretic gasket (S K S / Omega_ref) is tabulated at the study's speeds.
- `*EQUATION` on S8R mid-surface nodes adds no stiffness (plate frequencies print identically),
  a load on the dependent auxiliary node equals the consistent nodal loads R_i^T F (identical
  displacements), the auxiliary node reads the rigid fit of the printed mid-surface
  displacements (4e-6, rotation 1e-5; 1.6e-6 in steady state), and a DASHPOTA or SPRING1 on a
  scalar auxiliary dof equals the element at the node (1.4e-6; dissipation equals input power
  to 2e-6).
- `*CLOAD` is the real part of F, `*CLOAD, LOAD CASE=2` its imaginary part (one node may carry
  both); the .dat prints Re x, then Im x of (K - w^2 M + i w C) x = F: f(t) = Re[F e^{i w t}],
  x(t) = Re[x e^{i w t}] (the conjugate convention is off by 100 %).
- A MASS element on a node that is dependent in an `*EQUATION` loses its couplings (ccx:
  \"add_sm_ei: coefficient should be 0\", 9.3 million times for the drum): the drum's point masses sit on independent nodes held by penalty springs (their
  mode at 1e5 Hz). On a `*RIGID BODY` (the motor) point masses are fine. Deck numbers need a
  decimal point (`*SPRING` data `4e3` reads as a degree of freedom) and at most 20 characters.
- `*FREQUENCY` runs ARPACK with ncv = 5 nev Lanczos vectors (info = -3 when that exceeds the
  dofs: 8 modes of 40 dofs work, 9 do not) and tolerance 1e-2. The eigen-solve dominates the
  cost and grows faster than the mode count.
- The mode-acceleration correction (the static response the kept modes miss, from `*STATIC`
  steps) fails on this machine: its softest modes (0.4 Hz: without preload the tub has no
  pendulum stiffness) dominate the static response, ccx's eigenvectors reproduce that only to
  ~1e-3 (a symmetric load shows a 0.7 % antisymmetric response in the modal sum), and
  (Omega / omega_1)^2 ~ 4e3 at 1400 rpm turns it into errors larger than the response. The
  reference converges by its mode count instead (table above).
";

fn pct(x: f64) -> String {
    format!("{:+.1} %", 100.0 * x)
}

/// full-mesh.md and full-mesh.json in `out`.
pub fn write(s: &Study, out: &Path) -> Result<Vec<PathBuf>, FullMeshError> {
    let io = FileError::at::<FullMeshError>;
    std::fs::create_dir_all(out).map_err(io(out))?;
    let mut md = String::new();
    summary_section(&mut md, s);
    convergence_section(&mut md, s);
    channels_section(&mut md, s);
    md.push_str(CCX_NOTES);
    let md_path = out.join("full-mesh.md");
    std::fs::write(&md_path, md).map_err(io(&md_path))?;
    let json_path = out.join("full-mesh.json");
    let json = serde_json::to_string_pretty(s).map_err(FullMeshError::Serialise)?;
    std::fs::write(&json_path, json).map_err(io(&json_path))?;
    let mut wrote = vec![md_path, json_path];
    if let Some(r) = &s.reference {
        let path = out.join("full-mesh.ccx.json");
        let json = serde_json::to_string_pretty(r).map_err(FullMeshError::Serialise)?;
        std::fs::write(&path, json).map_err(io(&path))?;
        wrote.push(path);
    }
    Ok(wrote)
}

/// The study's summary: the machine, its mass and the agreement per speed.
fn summary_section(w: &mut String, s: &Study) {
    use std::fmt::Write as _;
    let _ = writeln!(
        w,
        "# Full-mesh reference: the linear machine in CalculiX against washdyn\n\n\
         Written by `washdyn fe reference` (src/full_mesh/); data in full-mesh.json.\n\n\
         The machine: `{}` made linear by `assembly::linear_machine` (no gravity or preload, \
         friction dampers as {:.0} N s/m linear dampers, no gyroscopic moments, the drum rigid, \
         its unbalance a prescribed rotating force, Rayleigh beta = {:.1e} s on the tub, the \
         cabinet, the springs and the gasket). CalculiX: the tub's and the cabinet's full meshes \
         ({} nodes, {} elements) assembled with the drum as rigid point masses, the springs as \
         SPRINGA, the dampers as DASHPOTA, the gasket's 6 x 6 K and D through scalar dofs, \
         solved with `*STEADY STATE DYNAMICS` at drum order 1 (fe/src/assembly/). washdyn: \
         the same machine's Ritz model (tub and cabinet modal data) in the frequency domain \
         (runtime/src/harmonic.rs). Mass: ccx {} kg, Ritz model {:.3} kg.\n",
        s.model,
        s.damper,
        s.beta,
        s.mesh_nodes,
        s.mesh_elements,
        s.mass_ccx.map_or("?".into(), |m| format!("{m:.3}")),
        s.mass_ritz
    );
    let _ = writeln!(
        w,
        "## Summary per speed\n\nAmplitude difference washdyn / ccx - 1 over the channels \
         above {:.0} % of the largest of their kind (accelerations, displacements) at that \
         speed; the complex difference |washdyn - ccx| / |ccx| includes the phase.\n\n\
         | rpm | Hz | channels | median | worst | worst channel | worst complex |\n\
         |---:|---:|---:|---:|---:|---|---:|",
        100.0 * COMPARED_SHARE
    );
    for sp in &s.speeds {
        let _ = writeln!(
            w,
            "| {:.0} | {:.2} | {} | {:.1} % | {:.1} % | {} | {:.1} % |",
            sp.rpm,
            sp.rpm / 60.0,
            sp.channels.iter().filter(|c| c.compared).count(),
            100.0 * sp.median,
            100.0 * sp.worst,
            sp.worst_channel,
            100.0 * sp.worst_complex
        );
    }
}

/// ccx's convergence with its mode count and washdyn's with its Ritz basis.
fn convergence_section(w: &mut String, s: &Study) {
    use std::fmt::Write as _;
    let _ = writeln!(
        w,
        "\n## CalculiX's convergence with its mode count\n\nWorst change of a compared \
         channel against the {}-mode solution, per speed (|a_n - a_ref| / |a_ref|).\n",
        s.ccx.last().map_or(0, |c| c.modes)
    );
    let _ = write!(w, "| modes | up to Hz | ccx s |");
    for sp in &s.speeds {
        let _ = write!(w, " {:.0} rpm |", sp.rpm);
    }
    let _ = write!(w, "\n|---:|---:|---:|");
    for _ in &s.speeds {
        let _ = write!(w, "---:|");
    }
    let _ = writeln!(w);
    for c in &s.ccx {
        let _ = write!(w, "| {} | {:.0} | {:.0} |", c.modes, c.highest_hz, c.wall_s);
        for x in &c.worst_change {
            let _ = write!(w, " {x:.1e} |");
        }
        let _ = writeln!(w);
    }
    if !s.ritz.is_empty() {
        let _ = writeln!(
            w,
            "\n## washdyn's convergence with the Ritz basis\n\nMedian / worst amplitude \
             difference to the full mesh per speed, for the tub's and the cabinet's eigenmodes \
             kept and their static correction modes (\"+ n\": with the dropped eigenmodes' \
             static share folded in; 0: eigenmodes only).\n"
        );
        let _ = write!(w, "| tub | cabinet |");
        for sp in &s.speeds {
            let _ = write!(w, " {:.0} |", sp.rpm);
        }
        let _ = write!(w, "\n|---|---|");
        for _ in &s.speeds {
            let _ = write!(w, "---:|");
        }
        let _ = writeln!(w);
        for r in &s.ritz {
            let _ = write!(
                w,
                "| {} + {} | {} + {} |",
                r.tub_modes, r.tub_correction, r.cabinet_modes, r.cabinet_correction
            );
            for (m, x) in r.median.iter().zip(&r.worst) {
                let _ = write!(w, " {:.1} / {:.1} % |", 100.0 * m, 100.0 * x);
            }
            let _ = writeln!(w);
        }
    }
}

/// The coupled machine's eigenfrequencies and every channel.
fn channels_section(w: &mut String, s: &Study) {
    use std::fmt::Write as _;
    let _ = writeln!(
        w,
        "\n## Eigenfrequencies of the coupled machine up to 60 Hz\n\nEach of ccx's with the \
         nearest of washdyn's: a mode the Ritz model lacks shows as a large difference.\n\n\
         | # | ccx Hz | washdyn Hz | difference |\n|---:|---:|---:|---:|"
    );
    for (i, (a, b)) in s.frequencies.iter().enumerate() {
        let _ = writeln!(w, "| {} | {a:.3} | {b:.3} | {} |", i + 1, pct(b / a - 1.0));
    }
    let _ = writeln!(
        w,
        "\n## Every channel\n\nAmplitude (m/s^2; m for displacements) and phase (deg, against \
         the drum angle); * marks a compared channel.\n\n| rpm | channel | ccx | washdyn | \
         amplitude | phase ccx / washdyn | complex |\n|---:|---|---:|---:|---:|---:|---:|"
    );
    for sp in &s.speeds {
        for c in &sp.channels {
            let _ = writeln!(
                w,
                "| {:.0} | {}{} | {:.4e} | {:.4e} | {} | {:.1} / {:.1} | {:.1} % |",
                sp.rpm,
                c.name,
                if c.compared { " *" } else { "" },
                c.ccx,
                c.washdyn,
                pct(c.amplitude),
                c.ccx_phase,
                c.washdyn_phase,
                100.0 * c.complex
            );
        }
    }
}
