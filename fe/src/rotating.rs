//! What a spinning body needs beyond its modes at rest: the geometric stiffness of the
//! centrifugal prestress, per Omega^2, in modal coordinates.
//!
//! CalculiX computes the prestressed body (`*STATIC` with a `CENTRIF` load, then a
//! `*FREQUENCY` perturbation step about that state). Its perturbation stiffness is
//! K + Omega^2 (K_G - M_perp): stress stiffening and spin softening (measured on a radial
//! square beam with ccx 2.20: lead-lag and flap eigenvalues part by exactly Omega^2). We express
//! the modes at rest Phi in the prestressed modes Psi (mass-weighted least squares, Phi ~ Psi A,
//! with more prestressed modes than kept ones) and get Phi^T K_Omega Phi = A^T Lambda A, since
//! Psi^T K_Omega Psi = Lambda for mass-normalised Psi. Then
//! K_G / Omega^2 = (A^T Lambda A - diag(omega_0^2)) / Omega^2 + S_perp, with
//! S_perp = sum dm W^T (E - e e^T) W from the elementary matrices, so that the equations' own
//! spin-softening term plus this K_G give back ccx's prestressed stiffness. The residual of the
//! fit is the truncation error, reported.

use crate::consistent::MassMatrix;
use crate::frd::Frd;
use crate::mesh::Mesh;
use crate::modal::Shapes;
use nalgebra::DMatrix;
use washdyn_runtime::geom::f::unit;
use washdyn_runtime::ir::modal::{Elementary, GeometricStiffness};

/// Define the element set `WD_SPIN` (every element with density) in `d` and return the
/// `*DLOAD` line of its centrifugal load at `omega` (rad/s) about `axis` through `axis_point`.
fn spin_load(
    d: &mut crate::deck::Deck,
    mesh: &Mesh,
    omega: f64,
    axis_point: [f64; 3],
    axis: [f64; 3],
) -> String {
    // Point masses carry no density (ccx leaves MASS elements out of the load).
    let loaded: Vec<&str> = mesh
        .parts
        .iter()
        .filter(|p| p.section.material().is_some())
        .map(|p| p.name.as_str())
        .collect();
    d.line("*ELSET, ELSET=WD_SPIN");
    for c in loaded.chunks(8) {
        d.line(&c.join(", "));
    }
    let e = unit(axis);
    format!(
        "WD_SPIN, CENTRIF, {:e}, {:e}, {:e}, {:e}, {:e}, {:e}, {:e}",
        omega * omega,
        axis_point[0],
        axis_point[1],
        axis_point[2],
        e[0],
        e[1],
        e[2]
    )
}

/// sum dm W^T (E - e e^T) W (n x n, row-major): the spin-softening matrix per Omega^2.
fn s_perp(elementary: &Elementary, n: usize, e: [f64; 3]) -> Vec<f64> {
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

/// The deck of the prestressed body at `omega` (rad/s) about `axis` through `axis_point`:
/// a `*STATIC` step with the centrifugal load on every element with density, then a
/// `*FREQUENCY` perturbation step for `modes` eigenmodes about that state.
pub fn prestressed_deck(
    mesh: &Mesh,
    omega: f64,
    axis_point: [f64; 3],
    axis: [f64; 3],
    modes: usize,
) -> crate::deck::Deck {
    let mut d = mesh.model_deck();
    let load = spin_load(&mut d, mesh, omega, axis_point, axis);
    // OUTPUT=2D in the static step too: otherwise ccx 2.20 writes the perturbation modes at
    // its expanded 3-D nodes (seen on a beam: 248 nodes instead of 41).
    d.line("*STEP")
        .line("*STATIC")
        .line("*NODE FILE, OUTPUT=2D")
        .line("U")
        .line("*DLOAD")
        .line(&load)
        .line("*END STEP")
        .line("*STEP, PERTURBATION")
        .line("*FREQUENCY")
        .line(&modes.to_string())
        .line("*DLOAD")
        .line(&load);
    mesh.output_requests(&mut d, false);
    d.line("*END STEP");
    d
}

/// Solve the prestressed deck and return its modes (all of them, none dropped).
pub fn solve_prestressed(
    mesh: &Mesh,
    dir: &std::path::Path,
    job: &str,
    omega: f64,
    axis_point: [f64; 3],
    axis: [f64; 3],
    modes: usize,
) -> Result<(Frd, Vec<Shapes>), String> {
    let deck = prestressed_deck(mesh, omega, axis_point, axis, modes);
    let solved = crate::modal::solve_deck(mesh, &deck, dir, job)?;
    let keep = crate::modal::Keep {
        rigid_below_hz: f64::NEG_INFINITY,
        max_hz: f64::INFINITY,
        max_modes: usize::MAX,
    };
    let shapes = crate::modal::select(mesh, &solved.frd, &solved.prints, keep)?;
    Ok((solved.frd, shapes))
}

/// The extraction's result: K_G per Omega^2 and how well the prestressed modes span the kept
/// ones (per kept mode, the mass-weighted relative residual of Phi ~ Psi A).
pub struct Extracted {
    pub stiffness: GeometricStiffness,
    pub residual: Vec<f64>,
}

/// K_G / Omega^2 from the kept modes at rest `base` and the prestressed modes `pre` at `omega`.
/// The fit Phi ~ Psi A is least squares in the mass `mass` (the consistent one):
/// A = (Psi^T M Psi)^-1 Psi^T M Phi, residual |Phi - Psi A|_M / |Phi|_M per kept mode.
#[allow(clippy::too_many_arguments)]
pub fn geometric_stiffness(
    mesh: &Mesh,
    mass: &MassMatrix,
    base: &[Shapes],
    pre: &[Shapes],
    elementary: &Elementary,
    omega: f64,
    axis_point: [f64; 3],
    axis: [f64; 3],
) -> Result<Extracted, String> {
    let (n, m) = (base.len(), pre.len());
    if m < n {
        return Err(format!(
            "{m} prestressed modes cannot represent {n} kept modes"
        ));
    }
    let g = mass.inner(mesh, pre, pre)?;
    let b = mass.inner(mesh, pre, base)?;
    let pp = mass.inner(mesh, base, base)?;
    let a = g
        .clone()
        .svd(true, true)
        .solve(&b, 1e-12)
        .map_err(|e| e.to_string())?;
    // |Phi - Psi A|^2 = Phi^T M Phi - 2 A^T B + A^T G A (per column).
    let ga = &g * &a;
    let residual = (0..n)
        .map(|k| {
            let r2 =
                pp[(k, k)] - 2.0 * a.column(k).dot(&b.column(k)) + a.column(k).dot(&ga.column(k));
            (r2.max(0.0) / pp[(k, k)]).sqrt()
        })
        .collect();
    let lambda = DMatrix::from_diagonal(&nalgebra::DVector::from_iterator(
        m,
        pre.iter()
            .map(|s| (2.0 * std::f64::consts::PI * s.frequency_hz).powi(2)),
    ));
    let k_omega = a.transpose() * lambda * &a;
    let e = unit(axis);
    let sp = s_perp(elementary, n, e);
    let mut per = vec![0.0; n * n];
    for k in 0..n {
        for l in 0..n {
            let w0 = if k == l {
                (2.0 * std::f64::consts::PI * base[k].frequency_hz).powi(2)
            } else {
                0.0
            };
            let sym = 0.5 * (k_omega[(k, l)] + k_omega[(l, k)]);
            per[k * n + l] = (sym - w0) / (omega * omega) + sp[k * n + l];
        }
    }
    // Symmetric by construction of both parts; make the round-off so too.
    for k in 0..n {
        for l in 0..k {
            let v = 0.5 * (per[k * n + l] + per[l * n + k]);
            per[k * n + l] = v;
            per[l * n + k] = v;
        }
    }
    Ok(Extracted {
        stiffness: GeometricStiffness {
            axis_point,
            axis: e,
            per_omega2: per,
            reference_speed: omega,
        },
        residual,
    })
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
) -> Result<Vec<f64>, String> {
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
        return Err("the reduced matrices are not finite".into());
    }
    let schur = nalgebra::linalg::Schur::try_new(a, f64::EPSILON, SCHUR_ITERATIONS)
        .ok_or("the eigenvalue iteration did not converge")?;
    let mut f: Vec<f64> = schur
        .complex_eigenvalues()
        .iter()
        .filter(|z| z.im > 0.0)
        .map(|z| z.im / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    Ok(f)
}

/// ccx's reference for the Campbell diagram: the prestressed body at `omega` (`*STATIC`
/// CENTRIF), its `modes` real eigenmodes (`*FREQUENCY, STORAGE=YES`), then
/// `*COMPLEX FREQUENCY, CORIOLIS` on them; returns the complex frequencies (Hz) and the turning
/// directions ('F' forward, 'B' backward) that ccx prints.
pub fn coriolis_reference(
    mesh: &Mesh,
    dir: &std::path::Path,
    job: &str,
    omega: f64,
    axis_point: [f64; 3],
    axis: [f64; 3],
    modes: usize,
) -> Result<Vec<(f64, char)>, String> {
    let mut d = mesh.model_deck();
    let load = spin_load(&mut d, mesh, omega, axis_point, axis);
    d.line("*STEP")
        .line("*STATIC")
        .line("*DLOAD")
        .line(&load)
        .line("*END STEP")
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
    std::fs::write(&deck, d.text()).map_err(|e| format!("{}: {e}", deck.display()))?;
    let run = crate::ccx::run(&deck).map_err(|e| e.to_string())?;
    let dat = std::fs::read_to_string(run.dat()).map_err(|e| e.to_string())?;
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
