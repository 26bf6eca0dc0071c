//! One body from FE model to modal data: write the deck, solve it with ccx, assemble the
//! consistent mass, keep the wanted modes, form the elementary matrices and points, and for a
//! spinning body extract the geometric stiffness, and the shapes on the whole mesh for field
//! recovery (`field.rs`). The CLI's `washdyn fe modal` runs this for the built-in bodies.

use crate::consistent;
use crate::lumping::{MassProps, lump};
use crate::mesh::Mesh;
use crate::modal::{self, Keep};
use crate::rotating;
use std::path::Path;
use washdyn_runtime::ir::modal::{
    Correction, ElasticBodyKind, LoadCase, ModalData, Support, SupportSpring,
};

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
    /// Also write `<name>.field.bin` for recovery on the mesh: the solves then write 3-D output,
    /// which gives the shapes and the modal stresses at once; a study of the modes alone skips it.
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
    /// The body from the consistent mass (+ rigid parts): what the modal data holds.
    pub mass_props: MassProps,
    /// max |W^T M W - I| of the modal data (consistent M, every mode).
    pub mass_error: f64,
    /// The same for the eigenmodes with HRZ-lumped masses (the seed paper's), for comparison.
    pub hrz_error: f64,
    /// max |sum dm W| / sqrt(m) (free-free: orthogonality to translation).
    pub translation_coupling: f64,
    /// Worst relative residual of the kept modes in the prestressed basis.
    pub prestress_fit_residual: Option<f64>,
    /// The static correction modes, if any.
    pub correction: Option<CorrectionReport>,
    /// ccx's own mass totals of the structural elements (`EMAS` in the frequency solve's
    /// `.dat`), to check our integration against.
    pub emas: Option<crate::dat::Emas>,
}

/// What the static correction solve measured.
#[derive(Clone, Debug)]
pub struct CorrectionReport {
    /// The correction modes' frequencies, Hz.
    pub frequencies: Vec<f64>,
    /// ccx's time for the static steps, s.
    pub solve_s: f64,
    /// A free body's largest support reaction over its largest nodal load (inertia relief
    /// leaves the 3-2-1 support unloaded).
    pub reaction: Option<f64>,
}

/// Build `spec` in `dir` (the deck and ccx's files land there).
pub fn build(spec: &BodySpec, dir: &Path) -> Result<(ModalData, Report), String> {
    // One solve gives the shapes and, for recovery, the stresses (`stress.rs`).
    let mut solved = modal::solve(&spec.mesh, dir, &spec.name, spec.solve_modes, spec.recovery)?;
    let mass = consistent::consistent(&spec.mesh);
    let mut modes = modal::select(&spec.mesh, &solved.frd, &solved.prints, spec.keep)?;
    if modes.is_empty() {
        return Err(format!("{}: no mode kept", spec.name));
    }
    let points: Vec<(&str, [f64; 3])> = spec.points.iter().map(|(s, p)| (s.as_str(), *p)).collect();
    let mut correction = None;
    let mut correction_solved: Option<crate::correction::Corrected> = None;
    if !spec.correction.is_empty() {
        if spec.spin.is_some() {
            // A spinning body's K_G comes from prestressed eigenmodes, which do not span a
            // local dent.
            return Err(format!(
                "{}: static correction modes need a non-spinning body",
                spec.name
            ));
        }
        // A free body gets inertia relief (`correction.rs`).
        let c = crate::correction::correction_modes(
            &spec.mesh,
            &mass,
            &modes,
            &points,
            &spec.correction,
            spec.support == Support::FreeFree,
            spec.recovery,
            dir,
            &format!("{}_correction", spec.name),
        )?;
        correction = Some((
            Correction {
                loads: spec.correction.clone(),
                modes: c.shapes.len(),
                participation: c.participation.clone(),
            },
            CorrectionReport {
                frequencies: c.shapes.iter().map(|s| s.frequency_hz).collect(),
                solve_s: c.solve_s,
                reaction: c.reaction,
            },
        ));
        let mut c = c;
        modes.append(&mut c.shapes);
        correction_solved = Some(c);
    }
    let mut data = modal::Import {
        body: spec.kind,
        support: spec.support,
        source: format!(
            "washdyn fe: {}.inp ({} nodes, {} elements), CalculiX {}; consistent mass",
            spec.name,
            spec.mesh.nodes.len(),
            spec.mesh.element_count(),
            crate::ccx::version().unwrap_or_else(|| "?".into())
        ),
        mesh: &spec.mesh,
        mass: &mass,
        modes: &modes,
        points: &points,
    }
    .modal_data()?;
    data.support_springs = support_springs(&spec.mesh, &points)?;
    let correction = correction.map(|(c, r)| {
        data.correction = Some(c);
        r
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
            &spec.mesh,
            &mass,
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
        write_field(
            spec,
            dir,
            &modes,
            &data,
            &mut solved,
            correction_solved.as_ref(),
        )?;
    }
    let translation_coupling = data
        .elementary
        .c
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        / data.mass.sqrt();
    let eigen = data.eigenmodes();
    let hrz_error =
        consistent::hrz(&lump(&spec.mesh)).normalisation_error(&spec.mesh, &modes[..eigen])?;
    let report = Report {
        name: spec.name.clone(),
        nodes: spec.mesh.nodes.len(),
        elements: spec.mesh.element_count(),
        solve_s: solved.run.wall_s,
        prestress_solve_s,
        all_frequencies: solved.frd.modes.iter().map(|m| m.frequency_hz).collect(),
        mass_props: mass.mass_props(&spec.mesh),
        mass_error: data.mass_normalisation_error(),
        hrz_error,
        translation_coupling,
        prestress_fit_residual,
        correction,
        emas: crate::dat::emas(&solved.dat, "EALL"),
    };
    Ok((data, report))
}

/// The mesh's springs to the ground (SPRING1, `Section::Ground`), each at the modal point whose
/// node set is that one node (the cabinet's FOOT_k), per point in `points` order. All or none:
/// without any such point the body records no springs (and no model can ask for their
/// damping); springs only partly at points are an error, since the strain energy of the others
/// would go missing from every mode's share.
pub fn support_springs(
    mesh: &Mesh,
    points: &[(&str, [f64; 3])],
) -> Result<Vec<SupportSpring>, String> {
    let mut out: Vec<SupportSpring> = Vec::new();
    let mut missing = None;
    for part in &mesh.parts {
        let crate::mesh::Section::Ground { dof, k } = part.section else {
            continue;
        };
        for e in &part.elements {
            let Some(name) = points
                .iter()
                .map(|(set, _)| *set)
                .find(|set| mesh.nsets.get(*set).is_some_and(|ids| ids[..] == e[..]))
            else {
                missing = Some((part.name.as_str(), e[0]));
                continue;
            };
            let i = match out.iter().position(|s| s.point == name) {
                Some(i) => i,
                None => {
                    out.push(SupportSpring {
                        point: name.to_string(),
                        stiffness: [0.0; 3],
                    });
                    out.len() - 1
                }
            };
            out[i].stiffness[dof - 1] += k;
        }
    }
    if let Some((part, node)) = missing
        && !out.is_empty()
    {
        return Err(format!(
            "{part}: the spring to the ground at node {node} is at no one-node point, while \
             others are (add a point there, as FOOT_k)"
        ));
    }
    let order = |s: &SupportSpring| points.iter().position(|(p, _)| *p == s.point);
    out.sort_by_key(order);
    Ok(out)
}

/// The shapes and modal stresses on the whole mesh (`<name>.field.bin`): the eigenmodes'
/// stresses, then the correction modes'.
fn write_field(
    spec: &BodySpec,
    dir: &Path,
    modes: &[crate::modal::Shapes],
    data: &ModalData,
    solved: &mut modal::Solved,
    correction: Option<&crate::correction::Corrected>,
) -> Result<(), String> {
    let eigen = data.eigenmodes();
    let points = solved
        .expanded
        .take()
        .ok_or_else(|| format!("{}: the solve wrote no 3-D output", spec.name))?;
    let mut stress =
        crate::stress::modal_stresses(&solved.frd, points, &modes[..eigen], solved.run.wall_s)
            .map_err(|e| format!("{}: {e}", spec.name))?;
    if let Some(c) = correction {
        let more = crate::stress::correction_stresses(&modes[..eigen], &stress, c)
            .map_err(|e| format!("{}: {e}", spec.name))?;
        stress.per_mode.extend(more);
    }
    crate::field::Field::new(&spec.mesh, modes, data, Some(&stress))?
        .write(&dir.join(format!("{}.field.bin", spec.name)))
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = &self.mass_props;
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
            "  mass {:.4} kg, CoG ({:.4}, {:.4}, {:.4}) m, inertia about CoG diag ({:.4}, {:.4}, {:.4}) kg m^2",
            p.mass, p.cog[0], p.cog[1], p.cog[2], p.inertia[0][0], p.inertia[1][1], p.inertia[2][2]
        )?;
        writeln!(
            f,
            "  mass normalisation max|W^T M W - I| = {:.2e} (consistent M; HRZ: {:.2e}); \
             max|sum dm W|/sqrt(m) = {:.2e}",
            self.mass_error, self.hrz_error, self.translation_coupling
        )?;
        if let Some(r) = self.prestress_fit_residual {
            writeln!(f, "  prestressed-basis fit residual {r:.2e}")?;
        }
        if let Some(c) = &self.correction {
            let fr: Vec<String> = c.frequencies.iter().map(|x| format!("{x:.0}")).collect();
            writeln!(
                f,
                "  {} static correction modes (ccx {:.1} s): {} Hz{}",
                fr.len(),
                c.solve_s,
                fr.join(", "),
                c.reaction.map_or(String::new(), |r| format!(
                    "; inertia relief, 3-2-1 support reaction {r:.1e} of the largest load"
                ))
            )?;
        }
        Ok(())
    }
}
