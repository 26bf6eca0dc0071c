//! The modal data's own rules (`problems`): dimensions, finiteness, plausible mass properties
//! and support, the Gram identities of the elementary matrices, the geometric stiffness, the
//! points, correction load cases and support springs. Each finding names the field in the file.

use super::limits::{
    FREQUENCY_RANGE, GRAM_TOLERANCE, MASS_NORMALISATION_TOLERANCE, MASS_RANGE, MAX_EXTENT,
    MAX_PER_OMEGA2, MAX_PHI, MAX_SUPPORT_STIFFNESS, MAX_W, MOMENT_BOUND_MARGIN,
    PARTICIPATION_TOLERANCE, SUPPORT_ENERGY_TOLERANCE, UNIT_TOLERANCE,
};
use super::{ElasticBodyKind, LoadKind, ModalData, Support};
use crate::ir::V3;
use crate::ir::check;

/// The modal data's own consistency: dimensions, frequencies, mass-normalisation, points. Each
/// finding names the field inside the file; the caller adds the file and the model's path.
pub fn problems(d: &ModalData) -> Vec<String> {
    let mut out = Vec::new();
    frequencies(d, &mut out);
    mass_properties(d, &mut out);
    support(d, &mut out);
    dimensions(d, &mut out);
    correction_loads(d, &mut out);
    geometric_stiffness(d, &mut out);
    gram(d, &mut out);
    points(d, &mut out);
    basis(d, &mut out);
    support_springs(d, &mut out);
    point_names(d, &mut out);
    if out.is_empty()
        && let Some((k, e)) = d
            .support_energy()
            .into_iter()
            .enumerate()
            .find(|(_, e)| *e > 1.0 + SUPPORT_ENERGY_TOLERANCE)
    {
        out.push(format!(
            "support_springs: mode {k} would store {e:.4} of its strain energy in them (more \
             than all): the springs are not those of the FE model behind these modes"
        ));
    }
    if out.is_empty() {
        let err = d.mass_normalisation_error();
        if err > MASS_NORMALISATION_TOLERANCE {
            out.push(format!(
                "elementary.g: modes are not mass-normalised: sum dm W^T W differs from the \
                 identity by {err:.3} (allowed {MASS_NORMALISATION_TOLERANCE})"
            ));
        }
    }
    out
}

/// The frequencies: some, in range, ascending among the eigenmodes and among the correction
/// modes, and no more correction modes than modes.
fn frequencies(d: &ModalData, out: &mut Vec<String>) {
    let n = d.modes();
    if n == 0 {
        out.push("frequencies: no modes".into());
    }
    let (f_lo, f_hi) = FREQUENCY_RANGE;
    for (k, f) in d.frequencies.iter().enumerate() {
        if !(*f >= f_lo && *f <= f_hi) {
            out.push(format!(
                "frequencies[{k}]: must be positive and finite, within [{f_lo:e}, {f_hi:e}] Hz, \
                 got {f}"
            ));
        }
    }
    let corr = d.correction.as_ref().map_or(0, |c| c.modes);
    if corr > n {
        out.push(format!("correction.modes: {corr} of only {n} modes"));
    } else {
        let (eig, cor) = d.frequencies.split_at(n - corr);
        if eig.windows(2).any(|w| w[1] < w[0]) || cor.windows(2).any(|w| w[1] < w[0]) {
            out.push("frequencies: not ascending (eigenmodes, then correction modes)".into());
        }
    }
}

/// Every array's length for the number of modes, and its numbers finite.
fn dimensions(d: &ModalData, out: &mut Vec<String>) {
    let n = d.modes();
    let corr = d.correction.as_ref().map_or(0, |c| c.modes);
    let xyz = ["x", "y", "z"];
    let mut dims = |field: String, v: &[f64], len: usize| {
        if v.len() != len {
            out.push(format!(
                "{field}: expected {len} values for {n} modes, found {}",
                v.len()
            ));
        } else if v.iter().any(|x| !x.is_finite()) {
            out.push(format!("{field}: non-finite number"));
        }
    };
    let e = &d.elementary;
    for a in 0..3 {
        dims(format!("elementary.c[{}]", xyz[a]), &e.c[a], n);
        for b in 0..3 {
            dims(
                format!("elementary.s[{}][{}]", xyz[a], xyz[b]),
                &e.s[a][b],
                n,
            );
            if e.has_g() {
                dims(
                    format!("elementary.g[{}][{}]", xyz[a], xyz[b]),
                    &e.g[a][b],
                    n * n,
                );
            }
        }
    }
    for (i, p) in d.points.iter().enumerate() {
        for a in 0..3 {
            dims(
                format!("points[{i}] ({}).w[{}]", p.name, xyz[a]),
                &p.w[a],
                n,
            );
            dims(
                format!("points[{i}] ({}).phi[{}]", p.name, xyz[a]),
                &p.phi[a],
                n,
            );
        }
    }
    if let Some(k) = &d.geometric_stiffness {
        dims(
            "geometric_stiffness.per_omega2".into(),
            &k.per_omega2,
            n * n,
        );
    }
    if let Some(c) = &d.correction
        && corr <= n
    {
        dims(
            "correction.participation".into(),
            &c.participation,
            (n - corr) * c.loads.len(),
        );
    }
}

/// The correction's load cases: each names a point of `points`, a unit direction, a moment only
/// where the node set turns, and the participation stored for it is that point's.
fn correction_loads(d: &ModalData, out: &mut Vec<String>) {
    let n = d.modes();
    let Some(c) = &d.correction else {
        return;
    };
    let corr = c.modes;
    if corr > n {
        return;
    }
    let loads = c.loads.len();
    for (j, l) in c.loads.iter().enumerate() {
        let Some(p) = d.point(&l.point) else {
            out.push(format!(
                "correction.loads[{j}]: no point `{}` in `points`",
                l.point
            ));
            continue;
        };
        if !at_most(
            (crate::geom::f::norm(l.direction) - 1.0).abs(),
            UNIT_TOLERANCE,
        ) {
            out.push(format!(
                "correction.loads[{j}].direction: must be a unit vector, got {:?}",
                l.direction
            ));
        }
        if l.kind == LoadKind::Moment && p.nodes < 3 {
            out.push(format!(
                "correction.loads[{j}]: a moment at `{}`, whose {} node(s) give no rotation",
                l.point, p.nodes
            ));
        }
        // The stored generalised forces are the point's w (phi for a moment) . direction:
        // a load case that names another point or kind than it was computed with shows.
        if c.participation.len() == (n - corr) * loads && p.w[0].len() == n {
            let col: Vec<f64> = (0..n - corr)
                .map(|k| c.participation[k * loads + j])
                .collect();
            let scale = col.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let worst = (0..n - corr)
                .map(|k| (col[k] - l.participation(p, k)).abs())
                .fold(0.0, f64::max);
            if worst > PARTICIPATION_TOLERANCE * scale {
                out.push(format!(
                    "correction.participation (load {j}): differs from `{}`'s {} . direction \
                     by {:.1e} of its largest value",
                    l.point,
                    if l.kind == LoadKind::Moment {
                        "phi"
                    } else {
                        "w"
                    },
                    worst / scale
                ));
            }
        }
    }
}

/// Each point: its position, its w and phi in bounds, and no rotation where its node set
/// determines none.
fn points(d: &ModalData, out: &mut Vec<String>) {
    let xyz = ["x", "y", "z"];
    for (i, p) in d.points.iter().enumerate() {
        let at = format!("points[{i}] ({})", p.name);
        position(&format!("{at}.position"), &p.position, out);
        for (what, v, max) in [("w", &p.w, MAX_W), ("phi", &p.phi, MAX_PHI)] {
            for a in 0..3 {
                let big = v[a].iter().map(|x| x.abs()).fold(0.0, f64::max);
                if big > max {
                    out.push(format!(
                        "{at}.{what}[{}]: {big:e} per unit modal coordinate, more than {max:e}",
                        xyz[a]
                    ));
                }
            }
        }
        if p.nodes < 3 && p.phi.iter().flatten().any(|x| *x != 0.0) {
            out.push(format!(
                "{at}.phi: a set of {} node(s) determines no rotation, so phi must be zero",
                p.nodes
            ));
        }
    }
}

/// The basis in the reference modes: whole rows, entries of orthonormal columns.
fn basis(d: &ModalData, out: &mut Vec<String>) {
    let n = d.modes();
    if let Some(b) = &d.basis {
        if n == 0 || b.len() % n != 0 {
            out.push(format!(
                "basis: {} values are no whole rows of {n}",
                b.len()
            ));
        }
        // Orthonormal columns (mass-normalised modes in mass-normalised modes): no entry
        // exceeds 1 beyond round-off.
        if let Some((i, v)) = b
            .iter()
            .enumerate()
            .find(|(_, v)| !at_most(v.abs(), 1.0 + GRAM_TOLERANCE))
        {
            out.push(format!(
                "basis[{i}]: {v}; the columns are orthonormal, so every entry lies in [-1, 1]"
            ));
        }
    }
}

/// The support springs: each on a one-node point, its stiffness in range.
fn support_springs(d: &ModalData, out: &mut Vec<String>) {
    for (i, s) in d.support_springs.iter().enumerate() {
        match d.point(&s.point) {
            None => out.push(format!(
                "support_springs[{i}]: no point `{}` in `points`",
                s.point
            )),
            Some(p) if p.nodes != 1 => out.push(format!(
                "support_springs[{i}]: point `{}` reads {} nodes; a spring to the ground sits \
                 on one node",
                s.point, p.nodes
            )),
            Some(_) => {}
        }
        if s.stiffness
            .iter()
            .any(|k| !(*k >= 0.0 && *k <= MAX_SUPPORT_STIFFNESS))
        {
            out.push(format!(
                "support_springs[{i}].stiffness: must be in [0, {MAX_SUPPORT_STIFFNESS:e}] N/m, \
                 got {:?}",
                s.stiffness
            ));
        }
    }
}

/// The points' node sets not empty, their names unique.
fn point_names(d: &ModalData, out: &mut Vec<String>) {
    for (i, p) in d.points.iter().enumerate() {
        if p.nodes == 0 {
            out.push(format!(
                "points[{i}] ({}): the node set has no nodes",
                p.name
            ));
        }
        if d.points[..i].iter().any(|q| q.name == p.name) {
            out.push(format!("points[{i}]: `{}` appears twice", p.name));
        }
    }
}

/// `v <= max`, and false for NaN: a rule states what a value must be, so NaN fails it.
fn at_most(v: f64, max: f64) -> bool {
    v <= max
}

/// A position (CoG, point, axis point): finite and within `MAX_EXTENT` of the origin.
fn position(field: &str, v: &V3, out: &mut Vec<String>) {
    let r = crate::geom::f::norm(*v);
    if !at_most(r, MAX_EXTENT) {
        out.push(format!(
            "{field}: {v:?} must be finite and within {MAX_EXTENT} m of the origin (SI units)"
        ));
    }
}

/// Mass, CoG and inertia: a plausible mass, a finite CoG inside the machine, and an inertia
/// tensor some mass distribution has (symmetric, positive definite, the principal moments
/// within the triangle inequality, none beyond mass x `MAX_EXTENT`^2).
fn mass_properties(d: &ModalData, out: &mut Vec<String>) {
    let (lo, hi) = MASS_RANGE;
    if !(d.mass >= lo && d.mass <= hi) {
        out.push(format!(
            "mass: must be positive, within [{lo:e}, {hi:e}] kg for a part of a washing machine, \
             got {}",
            d.mass
        ));
    }
    position("cog", &d.cog, out);
    let m = &d.inertia;
    if m.iter().flatten().any(|v| !v.is_finite()) {
        out.push(format!("inertia: non-finite number in {m:?}"));
        return;
    }
    let scale = m.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    for i in 0..3 {
        for j in i + 1..3 {
            if !at_most((m[i][j] - m[j][i]).abs(), 1e-9 * scale) {
                out.push(format!(
                    "inertia: not symmetric ([{i}][{j}] = {} but [{j}][{i}] = {})",
                    m[i][j], m[j][i]
                ));
                return;
            }
        }
    }
    let ev = check::sym_eigenvalues(m);
    if !(ev[0].is_finite() && ev[0] > 0.0) {
        out.push(format!(
            "inertia: not positive definite (principal moments {ev:?} kg m^2)"
        ));
    } else if ev[0] + ev[1] < ev[2] * (1.0 - 1e-12) {
        out.push(format!(
            "inertia: principal moments {ev:?} violate the triangle inequality (I1 + I2 >= I3), \
             no mass distribution has them"
        ));
    } else if d.mass > 0.0 && ev[2] > d.mass * MAX_EXTENT * MAX_EXTENT {
        out.push(format!(
            "inertia: principal moment {:e} kg m^2 is more than mass x ({MAX_EXTENT} m)^2",
            ev[2]
        ));
    }
}

/// The support the equations assume for each body: the tub's modes free-free (its 6 rigid DOF
/// are the multibody's), the drum's clamped at its bearing, the cabinet's on its feet.
fn support(d: &ModalData, out: &mut Vec<String>) {
    let want = match d.body {
        ElasticBodyKind::Tub => Support::FreeFree,
        ElasticBodyKind::Drum => Support::Clamped,
        ElasticBodyKind::Cabinet => Support::OnSprings,
    };
    if d.body == ElasticBodyKind::Drum && !d.elementary.has_g() {
        out.push(
            "elementary.g: missing; the spinning drum's equations need it (sum dm W^T e~ W)".into(),
        );
    }
    if d.support != want {
        out.push(format!(
            "support: {:?} for the {:?}, whose modes the equations take as {want:?}",
            d.support, d.body
        ));
    }
}

/// The sums of `elementary` are inner products in the body's mass, so they obey Gram
/// identities whatever the modes: g[a][b][k n + l] = g[b][a][l n + k],
/// |g[a][b][k n + l]| <= sqrt(g[a][a][k n + k] g[b][b][l n + l]), and by Cauchy-Schwarz
/// |c[a][k]| <= sqrt(mass g[a][a][kk]), |s[a][b][k]| <= sqrt(J_aa g[b][b][kk]) with
/// J_aa = sum dm x_a^2 = mass cog_a^2 + tr(I) / 2 - I_aa. A value outside is no sum over a
/// body (an entry of -1e308 in an off-diagonal block hung the Campbell diagram).
fn gram(d: &ModalData, out: &mut Vec<String>) {
    let n = d.modes();
    let e = &d.elementary;
    let fine = |v: &[f64], len: usize| v.len() == len && v.iter().all(|x| x.is_finite());
    let has_g = e.has_g();
    if n == 0
        || !(0..3).all(|a| {
            fine(&e.c[a], n)
                && (0..3).all(|b| fine(&e.s[a][b], n) && (!has_g || fine(&e.g[a][b], n * n)))
        })
    {
        return; // `problems` reports the sizes and numbers
    }
    let xyz = ["x", "y", "z"];
    // Without g (the cabinet's data), a mass-normalised mode's g_aa,kk is at most its modal
    // mass, 1: c and s keep their Cauchy-Schwarz bounds.
    let diag = |a: usize, k: usize| {
        if has_g {
            e.g[a][a][k * n + k]
        } else {
            1.0 + MASS_NORMALISATION_TOLERANCE
        }
    };
    for a in (0..3).filter(|_| has_g) {
        // The three add up to the modal mass, 1 for a mass-normalised mode.
        let top = 1.0 + MASS_NORMALISATION_TOLERANCE;
        if let Some(k) = (0..n).find(|&k| !(diag(a, k) >= 0.0 && diag(a, k) <= top)) {
            out.push(format!(
                "elementary.g[{0}][{0}][{1}]: {2:e}, but sum dm W_a,k^2 of a mass-normalised \
                 mode lies in [0, {top}]",
                xyz[a],
                k * n + k,
                diag(a, k)
            ));
            return;
        }
    }
    if has_g {
        let scale = (0..3)
            .flat_map(|a| (0..n).map(move |k| (a, k)))
            .fold(0.0f64, |m, (a, k)| m.max(diag(a, k)));
        for a in 0..3 {
            for b in 0..3 {
                for k in 0..n {
                    for l in 0..n {
                        let v = e.g[a][b][k * n + l];
                        let bound = (diag(a, k) * diag(b, l)).sqrt();
                        let tol = GRAM_TOLERANCE * scale;
                        if !at_most(v.abs(), bound + tol) {
                            out.push(format!(
                                "elementary.g[{}][{}][{}]: {v:e} exceeds sqrt(g_aa,kk g_bb,ll) = \
                                 {bound:e} (sum dm W_a,k W_b,l obeys Cauchy-Schwarz)",
                                xyz[a],
                                xyz[b],
                                k * n + l
                            ));
                            return;
                        }
                        if !at_most((v - e.g[b][a][l * n + k]).abs(), tol) {
                            out.push(format!(
                                "elementary.g[{}][{}][{}]: {v:e}, but elementary.g[{}][{}][{}] = \
                                 {:e} (sum dm W_a,k W_b,l is symmetric)",
                                xyz[a],
                                xyz[b],
                                k * n + l,
                                xyz[b],
                                xyz[a],
                                l * n + k,
                                e.g[b][a][l * n + k]
                            ));
                            return;
                        }
                    }
                }
            }
        }
    }
    if !(d.mass > 0.0 && d.mass.is_finite()) || d.cog.iter().any(|x| !x.is_finite()) {
        return;
    }
    let i = &d.inertia;
    let tr = i[0][0] + i[1][1] + i[2][2];
    for a in 0..3 {
        let j = d.mass * d.cog[a] * d.cog[a] + tr / 2.0 - i[a][a];
        for k in 0..n {
            let bound = MOMENT_BOUND_MARGIN * (d.mass * diag(a, k)).sqrt();
            if !at_most(e.c[a][k].abs(), bound) {
                out.push(format!(
                    "elementary.c[{}][{k}]: {:e} exceeds sqrt(mass g_aa,kk) = {bound:e} \
                     (x{MOMENT_BOUND_MARGIN}; sum dm W obeys Cauchy-Schwarz)",
                    xyz[a], e.c[a][k]
                ));
                return;
            }
            for b in 0..3 {
                let bound = MOMENT_BOUND_MARGIN * (j.max(0.0) * diag(b, k)).sqrt();
                if !at_most(e.s[a][b][k].abs(), bound) {
                    out.push(format!(
                        "elementary.s[{}][{}][{k}]: {:e} exceeds sqrt(J_aa g_bb,kk) = {bound:e} \
                         (x{MOMENT_BOUND_MARGIN}; J from mass, cog and inertia)",
                        xyz[a], xyz[b], e.s[a][b][k]
                    ));
                    return;
                }
            }
        }
    }
}

/// The drum's geometric stiffness: a unit axis through a point inside the machine, a reference
/// speed of the machine's range, K_G / Omega^2 symmetric (a stiffness) and within
/// `MAX_PER_OMEGA2`.
fn geometric_stiffness(d: &ModalData, out: &mut Vec<String>) {
    let Some(k) = &d.geometric_stiffness else {
        return;
    };
    let f = "geometric_stiffness";
    position(&format!("{f}.axis_point"), &k.axis_point, out);
    if !at_most((crate::geom::f::norm(k.axis) - 1.0).abs(), UNIT_TOLERANCE) {
        out.push(format!("{f}.axis: must be a unit vector, got {:?}", k.axis));
    }
    let top = check::MAX_RPM * std::f64::consts::PI / 30.0;
    if !(k.reference_speed > 0.0 && k.reference_speed <= top) {
        out.push(format!(
            "{f}.reference_speed: must be in (0, {top:.1}] rad/s ({} rpm), got {}",
            check::MAX_RPM,
            k.reference_speed
        ));
    }
    let n = d.modes();
    let g = &k.per_omega2;
    if g.len() != n * n || g.iter().any(|v| !v.is_finite()) {
        return; // `problems` reports it
    }
    if let Some((i, v)) = g
        .iter()
        .enumerate()
        .find(|(_, v)| !at_most(v.abs(), MAX_PER_OMEGA2))
    {
        out.push(format!(
            "{f}.per_omega2[{i}]: {v:e} exceeds {MAX_PER_OMEGA2:e} (stress stiffening per \
             Omega^2 of mass-normalised modes)"
        ));
        return;
    }
    let scale = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for r in 0..n {
        for c in r + 1..n {
            let (a, b) = (g[r * n + c], g[c * n + r]);
            if !at_most((a - b).abs(), GRAM_TOLERANCE * scale) {
                out.push(format!(
                    "{f}.per_omega2[{}]: {a:e}, but [{}] = {b:e}: a stiffness is symmetric",
                    r * n + c,
                    c * n + r
                ));
                return;
            }
        }
    }
}
