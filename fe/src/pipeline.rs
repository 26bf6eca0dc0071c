//! One body from FE model to modal data: write the deck, solve it with ccx, lump, keep the
//! wanted modes, form the elementary matrices and points, and for a spinning body extract the
//! geometric stiffness, and the shapes on the whole mesh for field recovery (`field.rs`). The
//! CLI's `washdyn fe modal` runs this for the built-in bodies.

use crate::lumping::{MassProps, lump};
use crate::mesh::Mesh;
use crate::modal::{self, Keep};
use crate::rotating;
use std::path::Path;
use washdyn_runtime::ir::modal::{Correction, ElasticBodyKind, LoadCase, ModalData, Support};

/// How a body spins (the drum): about `axis` through `axis_point`; the prestress is computed at
/// `reference_speed` (rad/s) with `modes` prestressed modes.
#[derive(Clone, Debug)]
pub struct Spin {
    pub axis_point: [f64; 3],
    pub axis: [f64; 3],
    pub reference_speed: f64,
    pub modes: usize,
}

/// Everything needed to turn one FE model into modal data.
#[derive(Clone, Debug)]
pub struct BodySpec {
    /// File stem: `<name>.inp`, `<name>.modal.toml`.
    pub name: String,
    pub kind: ElasticBodyKind,
    pub support: Support,
    pub mesh: Mesh,
    /// Eigenmodes ccx computes (rigid ones included).
    pub solve_modes: usize,
    pub keep: Keep,
    /// (node set, point) for every marker and sensor on the body.
    pub points: Vec<(String, [f64; 3])>,
    pub spin: Option<Spin>,
    /// Unit loads at points whose static response static correction modes carry (empty: none).
    pub correction: Vec<LoadCase>,
    /// Also write `<name>.field.bin` for recovery on the mesh (a second, 3-D ccx solve for the
    /// modal stresses, and for correction modes a third); a study of the modes alone skips it.
    pub recovery: bool,
}

/// What a build measured, for the report.
#[derive(Clone, Debug)]
pub struct Report {
    pub name: String,
    pub nodes: usize,
    pub elements: usize,
    pub solve_s: f64,
    pub prestress_solve_s: Option<f64>,
    /// All of ccx's frequencies (Hz), rigid ones included.
    pub all_frequencies: Vec<f64>,
    /// The lumped body (HRZ + rigid parts).
    pub lumped: MassProps,
    /// max |sum dm W^T W - I|.
    pub lumping_error: f64,
    /// max |sum dm W| / sqrt(m) (free-free: orthogonality to translation).
    pub translation_coupling: f64,
    /// Worst relative residual of the kept modes in the prestressed basis.
    pub prestress_fit_residual: Option<f64>,
    /// Frequencies of the static correction modes (Hz) and ccx's time for them (s).
    pub correction: Option<(Vec<f64>, f64)>,
}

/// Build `spec` in `dir` (the deck and ccx's files land there).
pub fn build(spec: &BodySpec, dir: &Path) -> Result<(ModalData, Report), String> {
    let solved = modal::solve(&spec.mesh, dir, &spec.name, spec.solve_modes)?;
    let lumped = lump(&spec.mesh);
    let mut modes = modal::select(&spec.mesh, &solved.frd, &solved.prints, spec.keep)?;
    if modes.is_empty() {
        return Err(format!("{}: no mode kept", spec.name));
    }
    let points: Vec<(&str, [f64; 3])> = spec.points.iter().map(|(s, p)| (s.as_str(), *p)).collect();
    let mut correction = None;
    let mut correction_solved: Option<crate::correction::Corrected> = None;
    if !spec.correction.is_empty() {
        if spec.spin.is_some() || spec.support == Support::FreeFree {
            // A spinning body's K_G comes from prestressed eigenmodes, which do not span a
            // local dent; a free body has no static solution.
            return Err(format!(
                "{}: static correction modes need a non-spinning, supported body",
                spec.name
            ));
        }
        let c = crate::correction::correction_modes(
            &spec.mesh,
            &lumped,
            &modes,
            &points,
            &spec.correction,
            dir,
            &format!("{}_correction", spec.name),
        )?;
        correction = Some((
            Correction {
                loads: spec.correction.clone(),
                modes: c.shapes.len(),
                participation: c.participation.clone(),
            },
            c.shapes.iter().map(|s| s.frequency_hz).collect::<Vec<_>>(),
            c.solve_s,
        ));
        let mut c = c;
        modes.append(&mut c.shapes);
        correction_solved = Some(c);
    }
    let mut data = modal::Import {
        body: spec.kind,
        support: spec.support,
        source: format!(
            "washdyn fe: {}.inp ({} nodes, {} elements), CalculiX {}; HRZ-lumped",
            spec.name,
            spec.mesh.nodes.len(),
            spec.mesh.element_count(),
            crate::ccx::version().unwrap_or_else(|| "?".into())
        ),
        mesh: &spec.mesh,
        lumped: &lumped,
        modes: &modes,
        points: &points,
    }
    .modal_data()?;
    let correction = correction.map(|(c, f, t)| {
        data.correction = Some(c);
        (f, t)
    });
    let mut prestress_solve_s = None;
    let mut prestress_fit_residual = None;
    if let Some(s) = &spec.spin {
        let t = std::time::Instant::now();
        let (_, pre) = rotating::solve_prestressed(
            &spec.mesh,
            dir,
            &format!("{}_prestressed", spec.name),
            s.reference_speed,
            s.axis_point,
            s.axis,
            s.modes,
        )?;
        prestress_solve_s = Some(t.elapsed().as_secs_f64());
        let x = rotating::geometric_stiffness(
            &lumped,
            &modes,
            &pre,
            &data.elementary,
            s.reference_speed,
            s.axis_point,
            s.axis,
        )?;
        prestress_fit_residual = Some(x.residual.iter().copied().fold(0.0, f64::max));
        data.geometric_stiffness = Some(x.stiffness);
    }
    if spec.recovery {
        write_field(spec, dir, &modes, &data, correction_solved.as_ref())?;
    }
    let translation_coupling = data
        .elementary
        .c
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        / data.mass.sqrt();
    let report = Report {
        name: spec.name.clone(),
        nodes: spec.mesh.nodes.len(),
        elements: spec.mesh.element_count(),
        solve_s: solved.run.wall_s,
        prestress_solve_s,
        all_frequencies: solved.frd.modes.iter().map(|m| m.frequency_hz).collect(),
        lumped: lumped.mass_props(&spec.mesh),
        lumping_error: data.mass_normalisation_error(),
        translation_coupling,
        prestress_fit_residual,
        correction,
    };
    Ok((data, report))
}

/// The shapes and modal stresses on the whole mesh (`<name>.field.bin`): the eigenmodes'
/// stresses, then the correction modes'.
fn write_field(
    spec: &BodySpec,
    dir: &Path,
    modes: &[crate::modal::Shapes],
    data: &ModalData,
    correction: Option<&crate::correction::Corrected>,
) -> Result<(), String> {
    let eigen = data.eigenmodes();
    let mut stress = crate::stress::modal_stresses(
        &spec.mesh,
        dir,
        &format!("{}_stress", spec.name),
        spec.solve_modes,
        &modes[..eigen],
    )?;
    if let Some(c) = correction {
        let more = crate::stress::correction_stresses(
            &spec.mesh,
            dir,
            &format!("{}_correction_stress", spec.name),
            &modes[..eigen],
            &stress,
            c,
        )?;
        stress.per_mode.extend(more);
    }
    crate::field::Field::new(&spec.mesh, modes, data, Some(&stress))?
        .write(&dir.join(format!("{}.field.bin", spec.name)))
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = &self.lumped;
        writeln!(
            f,
            "{}: {} nodes, {} elements, ccx {:.1} s{}",
            self.name,
            self.nodes,
            self.elements,
            self.solve_s,
            self.prestress_solve_s
                .map_or(String::new(), |s| format!(" (+ {s:.1} s prestressed)"))
        )?;
        writeln!(
            f,
            "  lumped mass {:.4} kg, CoG ({:.4}, {:.4}, {:.4}) m, inertia about CoG diag ({:.4}, {:.4}, {:.4}) kg m^2",
            p.mass, p.cog[0], p.cog[1], p.cog[2], p.inertia[0][0], p.inertia[1][1], p.inertia[2][2]
        )?;
        writeln!(
            f,
            "  lumping error max|sum dm W^T W - I| = {:.2e}; max|sum dm W|/sqrt(m) = {:.2e}",
            self.lumping_error, self.translation_coupling
        )?;
        if let Some(r) = self.prestress_fit_residual {
            writeln!(f, "  prestressed-basis fit residual {r:.2e}")?;
        }
        if let Some((fr, t)) = &self.correction {
            let fr: Vec<String> = fr.iter().map(|x| format!("{x:.0}")).collect();
            writeln!(
                f,
                "  {} static correction modes (ccx {t:.1} s): {} Hz",
                fr.len(),
                fr.join(", ")
            )?;
        }
        Ok(())
    }
}
