//! One body from FE model to modal data: write the deck, solve it with ccx, assemble the
//! consistent mass, keep the wanted modes, form the elementary matrices and points, and for a
//! spinning body assemble the geometric stiffness of its centrifugal prestress
//! (`prestress.rs`), and the shapes on the whole mesh for field recovery (`field.rs`). The
//! CLI's `washdyn fe modal` runs this for the built-in bodies.

use crate::consistent;
use crate::error::{Error, PipelineError, Within};
use crate::lumping::{MassProps, lump};
use crate::mesh::Mesh;
use crate::modal::{self, Keep};
use crate::prestress::{self, Centrifugal};
use nalgebra::DMatrix;
use std::path::Path;
use washdyn_model::geom::f::unit;
use washdyn_model::ir::modal::{
    Correction, ElasticBodyKind, GeometricStiffness, LoadCase, ModalData, Support, SupportSpring,
};

/// How a body spins (the drum): about `axis` through `axis_point`; its geometric stiffness comes
/// from the centrifugal prestress at `reference_speed` (rad/s).
#[derive(Clone, Debug)]
pub struct Spin {
    pub axis_point: [f64; 3],
    pub axis: [f64; 3],
    pub reference_speed: f64,
}

impl Spin {
    pub fn centrifugal(&self) -> Centrifugal {
        Centrifugal::new(self.reference_speed, self.axis_point, self.axis)
    }
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
    /// Krylov blocks of the correction modes: 1, the static give K^-1 f; 2 adds K^-1 M of it,
    /// so the dropped modes' first dynamic term (omega / omega_k)^2 is in the basis too.
    pub correction_order: usize,
    /// Also write `<name>.field.bin` for recovery on the mesh: the solves then write 3-D output,
    /// which gives the shapes and the modal stresses at once; a study of the modes alone skips it.
    pub recovery: bool,
}

impl BodySpec {
    /// Whether the solves write ccx's 3-D output: for recovery, and for a spinning body, whose
    /// geometric stiffness integrates the shapes over ccx's bricks.
    pub fn three_d(&self) -> bool {
        self.recovery || self.spin.is_some()
    }
}

/// What a build measured, for the report.
#[derive(Clone, Debug)]
pub struct Report {
    pub name: String,
    pub nodes: usize,
    pub elements: usize,
    pub solve_s: f64,
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
    /// A spinning body's centrifugal prestress.
    pub prestress: Option<PrestressReport>,
    /// The static correction modes, if any.
    pub correction: Option<CorrectionReport>,
    /// ccx's own mass totals of the structural elements (`EMAS` in the frequency solve's
    /// `.dat`), to check our integration against.
    pub emas: Option<crate::dat::Emas>,
}

/// What the prestress solve gave, beside the geometric stiffness in the modal data.
#[derive(Clone, Debug)]
pub struct PrestressReport {
    /// ccx's time for the static step, s.
    pub solve_s: f64,
    /// Bricks integrated (ccx's expanded shells and beams, and solids).
    pub bricks: usize,
    /// Of the modal data's K_G per Omega^2 (n x n, row-major), the rigid parts' share
    /// (`prestress::rigid_parts`); ccx's perturbation step has none.
    pub rigid_parts: Vec<f64>,
    /// Not in it: the initial-displacement stiffness of the static state per Omega^2
    /// (`Prestress::stiffness`), which ccx's perturbation step has.
    pub initial_displacement: Vec<f64>,
    /// The point masses' share of the spin softening S_perp per Omega^2 (n x n, row-major;
    /// `prestress::point_mass_softening`); ccx's perturbation step has none.
    pub point_mass_softening: Vec<f64>,
}

impl PrestressReport {
    /// `kg` as ccx's own prestressed `*FREQUENCY` step has it: with the initial-displacement
    /// stiffness, without the rigid parts' share, and with the point masses' spin softening
    /// added back (so that `rotating::reduced_frequencies`, which subtracts all of S_perp,
    /// leaves it out).
    pub fn as_ccx(&self, kg: &GeometricStiffness) -> GeometricStiffness {
        let mut k = kg.clone();
        for (i, v) in k.per_omega2.iter_mut().enumerate() {
            *v += self.initial_displacement[i] + self.point_mass_softening[i] - self.rigid_parts[i];
        }
        k
    }
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
pub fn build(spec: &BodySpec, dir: &Path) -> Result<(ModalData, Report), Error> {
    // One solve gives the shapes and, for recovery, the stresses (`stress.rs`); a spinning
    // body's keeps its 3-D shapes for the geometric stiffness.
    let mut solved = if spec.spin.is_some() {
        modal::solve_keeping_3d(&spec.mesh, dir, &spec.name, spec.solve_modes)?
    } else {
        modal::solve(&spec.mesh, dir, &spec.name, spec.solve_modes, spec.recovery)?
    };
    let mass = consistent::consistent(&spec.mesh);
    let mut modes = modal::select(&spec.mesh, &solved.frd, &solved.prints, spec.keep)?;
    if modes.is_empty() {
        let body = spec.name.clone();
        return Err(PipelineError::NoModeKept { body }.into());
    }
    let points: Vec<(&str, [f64; 3])> = spec.points.iter().map(|(s, p)| (s.as_str(), *p)).collect();
    let eigen = modes.len();
    let (correction, correction_solved) = match correction_modes(spec, &mass, &modes, &points, dir)?
    {
        Some((record, mut c)) => {
            modes.append(&mut c.shapes);
            (Some(record), Some(c))
        }
        None => (None, None),
    };
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
    let prestress = match &spec.spin {
        Some(spin) => {
            let (k, r) = geometric_stiffness(
                spec,
                dir,
                spin,
                &solved,
                &modes,
                eigen,
                correction_solved.as_ref(),
            )?;
            data.geometric_stiffness = Some(k);
            Some(r)
        }
        None => None,
    };
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
        all_frequencies: solved.frd.modes.iter().map(|m| m.frequency_hz).collect(),
        mass_props: mass.mass_props(&spec.mesh),
        mass_error: data.mass_normalisation_error(),
        hrz_error,
        translation_coupling,
        prestress,
        correction,
        emas: crate::dat::emas(&solved.dat, "EALL"),
    };
    // The cabinet never turns, so no equation reads its g (9 n^2 numbers: 35 of 36 MB at 406
    // modes); its mass normalisation is measured above, then g is dropped.
    if data.body == ElasticBodyKind::Cabinet {
        data.elementary.g = Default::default();
    }
    Ok((data, report))
}

/// The correction modes as the modal data and the report record them.
type CorrectionRecord = (Correction, CorrectionReport);

/// The correction modes of `spec`'s load cases, if it has any (`correction.rs`; a free body
/// gets inertia relief): their record in the modal data and the report, and the solve.
fn correction_modes(
    spec: &BodySpec,
    mass: &consistent::MassMatrix,
    modes: &[crate::modal::Shapes],
    points: &[(&str, [f64; 3])],
    dir: &Path,
) -> Result<Option<(CorrectionRecord, crate::correction::Corrected)>, Error> {
    if spec.correction.is_empty() {
        return Ok(None);
    }
    let c = crate::correction::correction_modes(
        &spec.mesh,
        mass,
        modes,
        points,
        &spec.correction,
        spec.support == Support::FreeFree,
        spec.three_d(),
        spec.correction_order,
        dir,
        &format!("{}_correction", spec.name),
    )?;
    let record = (
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
    );
    Ok(Some((record, c)))
}

/// A spinning body's K_G per Omega^2 on `modes` (the first `eigen` of them the eigenmodes of
/// `solved`, the rest the correction modes of `correction`): ccx's static centrifugal stresses
/// and displacements integrated over its bricks with the shapes at its 3-D nodes
/// (`prestress.rs`), plus the rigid parts' share.
fn geometric_stiffness(
    spec: &BodySpec,
    dir: &Path,
    spin: &Spin,
    solved: &modal::Solved,
    modes: &[modal::Shapes],
    eigen: usize,
    correction: Option<&crate::correction::Corrected>,
) -> Result<(GeometricStiffness, PrestressReport), Error> {
    let name = &spec.name;
    let c = spin.centrifugal();
    let (pre, _) = prestress::solve(&spec.mesh, &c, dir, &format!("{name}_prestress"))?;
    let unfolded = solved
        .unfolded
        .as_ref()
        .ok_or_else(|| PipelineError::No3dShapes { body: name.clone() })?;
    pre.same_bricks(&solved.frd.elements, &format!("{name}: the eigen solve"))?;
    let kept = modal::kept(&solved.frd, spec.keep);
    if kept.len() != eigen {
        return Err(PipelineError::KeptShapes {
            body: name.clone(),
            kept: kept.len(),
            shapes: eigen,
        }
        .into());
    }
    let mut basis: Vec<&[(usize, [f64; 3])]> =
        kept.iter().map(|&i| &unfolded.modes[i][..]).collect();
    // Each correction mode is a combination of the static solutions less the eigenmodes'
    // share: final = basis T with T = [E, -share comb; 0, comb].
    let t = match correction {
        None => None,
        Some(_) if spec.support == Support::FreeFree => {
            // Its static solutions less their rigid motion would need that motion at the 3-D
            // nodes too; no spinning body is free.
            return Err(PipelineError::FreeSpinning { body: name.clone() }.into());
        }
        Some(cor) => {
            pre.same_bricks(&cor.elements_3d, &format!("{name}: the correction solve"))?;
            basis.extend(cor.statics_3d.iter().map(|v| &v[..]));
            let (j, m) = (cor.forces.len(), cor.combination.ncols());
            let mut t = DMatrix::<f64>::zeros(eigen + j, eigen + m);
            t.view_mut((0, 0), (eigen, eigen)).fill_with_identity();
            t.view_mut((0, eigen), (eigen, m))
                .copy_from(&(-&cor.share * &cor.combination));
            t.view_mut((eigen, eigen), (j, m))
                .copy_from(&cor.combination);
            Some(t)
        }
    };
    let (rows, cols) = t.as_ref().map_or((eigen, eigen), |t| t.shape());
    if basis.len() != rows || modes.len() != cols {
        return Err(PipelineError::BasisCount { body: name.clone() }.into());
    }
    let (ks, ku) = pre.stiffness(&basis).within(|| name.clone())?;
    let (ks, ku) = match &t {
        Some(t) => (t.transpose() * ks * t, t.transpose() * ku * t),
        None => (ks, ku),
    };
    let w2 = spin.reference_speed * spin.reference_speed;
    let (ks, ku) = (ks / w2, ku / w2);
    let k_rig = prestress::rigid_parts(&spec.mesh, &pre.loads, modes)? / w2;
    let soft = prestress::point_mass_softening(&spec.mesh, modes, c.axis)?;
    let n = modes.len();
    let row_major = |m: &DMatrix<f64>| -> Vec<f64> {
        (0..n * n)
            .map(|i| 0.5 * (m[(i / n, i % n)] + m[(i % n, i / n)]))
            .collect()
    };
    // ccx's perturbation step also holds K_u; the model leaves it out: its thin sheets'
    // through-thickness gradient of u0 from the .frd's 6 digits splits the drum's degenerate
    // pairs by up to 1.4e-4 (K_G from the stresses alone keeps them to 1e-9).
    let total = &ks + &k_rig;
    Ok((
        GeometricStiffness {
            axis_point: spin.axis_point,
            axis: unit(spin.axis),
            per_omega2: row_major(&total),
            reference_speed: spin.reference_speed,
        },
        PrestressReport {
            solve_s: pre.solve_s,
            bricks: pre.bricks.len(),
            rigid_parts: row_major(&k_rig),
            initial_displacement: row_major(&ku),
            point_mass_softening: row_major(&soft),
        },
    ))
}

/// The mesh's springs to the ground (SPRING1, `Section::Ground`), each at the modal point whose
/// node set is that one node (the cabinet's FOOT_k), per point in `points` order. All or none:
/// without any such point the body records no springs (and no model can ask for their
/// damping); springs only partly at points are an error, since the strain energy of the others
/// would go missing from every mode's share.
pub fn support_springs(
    mesh: &Mesh,
    points: &[(&str, [f64; 3])],
) -> Result<Vec<SupportSpring>, PipelineError> {
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
        return Err(PipelineError::LoneSpring {
            part: part.to_string(),
            node,
        });
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
) -> Result<(), Error> {
    let eigen = data.eigenmodes();
    let points = solved
        .expanded
        .take()
        .ok_or_else(|| PipelineError::No3dOutput {
            body: spec.name.clone(),
        })?;
    let mut stress =
        crate::stress::modal_stresses(&solved.frd, points, &modes[..eigen], solved.run.wall_s)
            .within(|| spec.name.clone())?;
    if let Some(c) = correction {
        let more = crate::stress::correction_stresses(&modes[..eigen], &stress, c)
            .within(|| spec.name.clone())?;
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
            self.prestress.as_ref().map_or(String::new(), |p| format!(
                " (+ {:.1} s prestress)",
                p.solve_s
            ))
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
        if let Some(p) = &self.prestress {
            let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            writeln!(
                f,
                "  geometric stiffness over {} bricks, rigid parts' share up to {:.2e}; ccx's \
                 perturbation step adds the static displacement's stiffness (up to {:.2e}) and \
                 lacks the point masses' spin softening (up to {:.2e}) per (rad/s)^2",
                p.bricks,
                largest(&p.rigid_parts),
                largest(&p.initial_displacement),
                largest(&p.point_mass_softening)
            )?;
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
