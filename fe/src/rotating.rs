//! What a spinning body's reduced model does with its geometric stiffness (K_G per Omega^2,
//! assembled from ccx's static centrifugal stresses: `prestress.rs`): the frequencies of the
//! prestressed body, its Campbell diagram, and ccx's own answers to hold them against.
//!
//! ccx's perturbation stiffness about the static centrifugal state is K + Omega^2 (K_G - M_perp)
//! (measured on a radial square beam with ccx 2.20: lead-lag and flap eigenvalues part by
//! exactly Omega^2). The reduced model has diag(omega_0^2) + Omega^2 (K_G - S_perp), with
//! S_perp = sum dm W^T (E - e e^T) W from the elementary matrices (the equations' own spin
//! softening).

use crate::error::{Error, PipelineError};
use crate::frd::Frd;
use crate::mesh::Mesh;
use crate::modal::Shapes;
use crate::prestress::{Centrifugal, loaded_set, write_loads};
use nalgebra::DMatrix;
use washdyn_model::ir::modal::{Elementary, GeometricStiffness};

/// sum dm W^T (E - e e^T) W (n x n, row-major): the spin-softening matrix per Omega^2.
pub fn s_perp(elementary: &Elementary, n: usize, e: [f64; 3]) -> Vec<f64> {
    let mut s = vec![0.0; n * n];
    for a in 0..3 {
        for b in 0..3 {
            let p = if a == b { 1.0 } else { 0.0 } - e[a] * e[b];
            for (v, g) in s.iter_mut().zip(&elementary.g[a][b]) {
                *v += p * g;
            }
        }
    }
    s
}

/// ccx's own prestressed body at `c`: a `*STATIC` step with the centrifugal load
/// (`prestress::write_loads`: `CENTRIF` on every element with density, the point masses'
/// forces as `*CLOAD`s), then a `*FREQUENCY` perturbation step for `modes` eigenmodes about
/// that state. The reference the reduced model's frequencies are held against.
pub fn prestressed_deck(mesh: &Mesh, c: &Centrifugal, modes: usize) -> crate::deck::Deck {
    let mut d = mesh.model_deck();
    loaded_set(&mut d, mesh);
    d.line("*STEP").line("*STATIC");
    let dload = write_loads(&mut d, mesh, c);
    // OUTPUT=2D in the static step too: otherwise ccx 2.20 writes the perturbation modes at
    // its expanded 3-D nodes (seen on a beam: 248 nodes instead of 41).
    d.line("*NODE FILE, OUTPUT=2D")
        .line("U")
        .line("*END STEP")
        .line("*STEP, PERTURBATION")
        .line("*FREQUENCY")
        .line(&modes.to_string())
        .line("*DLOAD")
        .line(&dload);
    mesh.output_requests(&mut d, false);
    d.line("*END STEP");
    d
}

/// Solve the prestressed deck and return its modes (all of them, none dropped).
pub fn solve_prestressed(
    mesh: &Mesh,
    dir: &std::path::Path,
    job: &str,
    c: &Centrifugal,
    modes: usize,
) -> Result<(Frd, Vec<Shapes>), Error> {
    let deck = prestressed_deck(mesh, c, modes);
    let solved = crate::modal::solve_deck(mesh, &deck, dir, job)?;
    let keep = crate::modal::Keep {
        rigid_below_hz: f64::NEG_INFINITY,
        max_hz: f64::INFINITY,
        max_modes: usize::MAX,
    };
    let shapes = crate::modal::select(mesh, &solved.frd, &solved.prints, keep)?;
    Ok((solved.frd, shapes))
}

/// The reduced stiffness at `omega` (n x n, row-major): diag(omega_0^2) + Omega^2 (K_G - S_perp).
fn spinning_stiffness(
    frequencies: &[f64],
    elementary: &Elementary,
    kg: &GeometricStiffness,
    omega: f64,
) -> Vec<f64> {
    let n = frequencies.len();
    let sp = s_perp(elementary, n, kg.axis);
    let mut k: Vec<f64> = (0..n * n)
        .map(|i| omega * omega * (kg.per_omega2[i] - sp[i]))
        .collect();
    for (i, f) in frequencies.iter().enumerate() {
        k[i * n + i] += (2.0 * std::f64::consts::PI * f).powi(2);
    }
    k
}

/// Frequencies (Hz) of the reduced model spinning at `omega` without Coriolis: the eigenvalues
/// of diag(omega_0^2) + Omega^2 (K_G - S_perp) with the identity as modal mass. What ccx's
/// `*FREQUENCY` perturbation step computes, from the stored data alone.
pub fn reduced_frequencies(
    frequencies: &[f64],
    elementary: &Elementary,
    kg: &GeometricStiffness,
    omega: f64,
) -> Vec<f64> {
    let n = frequencies.len();
    let k = DMatrix::from_row_slice(
        n,
        n,
        &spinning_stiffness(frequencies, elementary, kg, omega),
    );
    let k = 0.5 * (&k + k.transpose());
    let mut ev: Vec<f64> = k
        .symmetric_eigen()
        .eigenvalues
        .iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    ev.sort_by(f64::total_cmp);
    ev
}

/// The gyroscopic matrix G (n x n, skew): G_kl = sum dm W_k . (e x W_l), from the elementary
/// sums g[a][b]. The rotating-frame equations of the reduced model are
/// q'' + 2 Omega G q' + (diag(omega_0^2) + Omega^2 (K_G - S_perp)) q = 0 (modal mass E).
pub fn gyroscopic(elementary: &Elementary, n: usize, axis: [f64; 3]) -> Vec<f64> {
    let e = axis;
    // (e x w)_a = sum_bc eps_abc e_b w_c = ex[a][c] w_c.
    let ex = [[0.0, -e[2], e[1]], [e[2], 0.0, -e[0]], [-e[1], e[0], 0.0]];
    let mut g = vec![0.0; n * n];
    for k in 0..n {
        for l in 0..n {
            let mut v = 0.0;
            for a in 0..3 {
                for c in 0..3 {
                    v += ex[a][c] * elementary.g[a][c][k * n + l];
                }
            }
            g[k * n + l] = v;
        }
    }
    g
}

/// The reduced spinning body's frequencies (Hz) at `omega` in the rotating frame, with
/// Coriolis, spin softening and stress stiffening: the positive imaginary parts of the
/// first-order system's eigenvalues. The Campbell diagram is this over speed.
pub fn campbell(
    frequencies: &[f64],
    elementary: &Elementary,
    kg: &GeometricStiffness,
    omega: f64,
) -> Vec<f64> {
    try_campbell(frequencies, elementary, kg, omega).expect("the Schur iteration converges")
}

/// Iterations of the Schur decomposition before `try_campbell` gives up (nalgebra's default
/// iterates for ever: a matrix of 1e300 entries never converged).
pub const SCHUR_ITERATIONS: usize = 10_000;

/// [`campbell`], or an error when the eigenvalue iteration does not converge (non-finite or
/// absurdly scaled data) instead of iterating for ever.
pub fn try_campbell(
    frequencies: &[f64],
    elementary: &Elementary,
    kg: &GeometricStiffness,
    omega: f64,
) -> Result<Vec<f64>, PipelineError> {
    let n = frequencies.len();
    let g = gyroscopic(elementary, n, kg.axis);
    let k = spinning_stiffness(frequencies, elementary, kg, omega);
    let mut a = DMatrix::<f64>::zeros(2 * n, 2 * n);
    for i in 0..n {
        a[(i, n + i)] = 1.0;
        for j in 0..n {
            a[(n + i, j)] = -k[i * n + j];
            a[(n + i, n + j)] = -2.0 * omega * g[i * n + j];
        }
    }
    if a.iter().any(|v| !v.is_finite()) {
        return Err(PipelineError::NotFinite);
    }
    let schur = nalgebra::linalg::Schur::try_new(a, f64::EPSILON, SCHUR_ITERATIONS)
        .ok_or(PipelineError::NoConvergence)?;
    let mut f: Vec<f64> = schur
        .complex_eigenvalues()
        .iter()
        .filter(|z| z.im > 0.0)
        .map(|z| z.im / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    Ok(f)
}

/// ccx's reference for the Campbell diagram: the prestressed body at `c` (`*STATIC` with the
/// loads of `prestress::write_loads`), its `modes` real eigenmodes (`*FREQUENCY, STORAGE=YES`), then
/// `*COMPLEX FREQUENCY, CORIOLIS` on them; returns the complex frequencies (Hz) and the turning
/// directions ('F' forward, 'B' backward) that ccx prints.
pub fn coriolis_reference(
    mesh: &Mesh,
    dir: &std::path::Path,
    job: &str,
    c: &Centrifugal,
    modes: usize,
) -> Result<Vec<(f64, char)>, Error> {
    let mut d = mesh.model_deck();
    loaded_set(&mut d, mesh);
    d.line("*STEP").line("*STATIC");
    let load = write_loads(&mut d, mesh, c);
    d.line("*END STEP")
        .line("*STEP, PERTURBATION")
        .line("*FREQUENCY, STORAGE=YES")
        .line(&modes.to_string())
        .line("*DLOAD")
        .line(&load)
        .line("*END STEP")
        .line("*STEP, PERTURBATION")
        .line("*COMPLEX FREQUENCY, CORIOLIS")
        .line(&modes.to_string())
        .line("*DLOAD")
        .line(&load)
        .line("*END STEP");
    let deck = dir.join(format!("{job}.inp"));
    std::fs::write(&deck, d.text()).map_err(Error::io(&deck))?;
    let run = crate::ccx::run(&deck)?;
    let dat = std::fs::read_to_string(run.dat())?;
    Ok(parse_complex(&dat))
}

/// The `*COMPLEX FREQUENCY` table (the eigenvalue table whose header has no EIGENVALUE column:
/// mode, rad/time, cycles/time, imaginary part) and the turning directions.
pub fn parse_complex(dat: &str) -> Vec<(f64, char)> {
    let lines: Vec<&str> = dat.lines().collect();
    let mut freqs = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        if !l.contains("E I G E N V A L U E   O U T P U T") {
            continue;
        }
        let header = lines.get(i + 2).copied().unwrap_or("");
        if header.contains("EIGENVALUE") {
            continue;
        }
        freqs.clear();
        for l in &lines[i + 1..] {
            let f: Vec<&str> = l.split_whitespace().collect();
            match f.first().map(|s| s.parse::<usize>()) {
                Some(Ok(_)) if f.len() == 4 => {
                    if let Ok(hz) = f[2].parse::<f64>() {
                        freqs.push(hz);
                    }
                }
                Some(Ok(_)) => break,
                _ if !freqs.is_empty() && !l.trim().is_empty() => break,
                _ => {}
            }
        }
    }
    let mut dirs = Vec::new();
    if let Some(i) = lines
        .iter()
        .position(|l| l.contains("T U R N I N G   D I R E C T I O N"))
    {
        for l in &lines[i + 1..] {
            let f: Vec<&str> = l.split_whitespace().collect();
            if f.len() == 2 && f[0].parse::<usize>().is_ok() {
                dirs.push(f[1].chars().next().unwrap_or('?'));
            } else if !dirs.is_empty() && !l.trim().is_empty() {
                break;
            }
        }
    }
    freqs
        .into_iter()
        .enumerate()
        .map(|(k, f)| (f, dirs.get(k).copied().unwrap_or('?')))
        .collect()
}
