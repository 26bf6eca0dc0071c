//! The one checker. Both front ends run it: the TOML loader maps each error's path to a file line,
//! the `machine!` macro maps it to the offending token. Errors are collected, not returned at the
//! first, so a user sees every problem at once.

use super::*;
use std::collections::HashSet;
use std::fmt;

/// One step of a path into the IR, as serde names it (`springs[1].stiffness`).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Seg {
    Key(String),
    Index(usize),
}

/// Where in the model an error sits.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Path(pub Vec<Seg>);

impl Path {
    pub fn key(mut self, k: &str) -> Path {
        self.0.push(Seg::Key(k.to_string()));
        self
    }
    pub fn idx(mut self, i: usize) -> Path {
        self.0.push(Seg::Index(i));
        self
    }
    pub(crate) fn of(parts: &[&str]) -> Path {
        Path(parts.iter().map(|p| Seg::Key(p.to_string())).collect())
    }
}

impl fmt::Display for Path {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, s) in self.0.iter().enumerate() {
            match s {
                Seg::Key(k) if i == 0 => write!(f, "{k}")?,
                Seg::Key(k) => write!(f, ".{k}")?,
                Seg::Index(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

/// A checker finding: the path to the offending field and what is wrong with it, naming the item.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckError {
    pub path: Path,
    pub message: String,
}

impl fmt::Display for CheckError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

/// Collects errors; the serde_derive pattern (an error context that gathers, then reports).
#[derive(Default)]
struct Ctx {
    errors: Vec<CheckError>,
}

impl Ctx {
    fn err(&mut self, path: Path, message: impl Into<String>) {
        self.errors.push(CheckError {
            path,
            message: message.into(),
        });
    }

    fn finite(&mut self, path: &Path, what: &str, vals: &[f64]) -> bool {
        if vals.iter().all(|v| v.is_finite()) {
            true
        } else {
            self.err(path.clone(), format!("{what}: non-finite number"));
            false
        }
    }

    fn positive(&mut self, path: Path, what: &str, v: f64) {
        if self.finite(&path, what, &[v]) && v <= 0.0 {
            self.err(path, format!("{what} must be positive, got {v}"));
        }
    }

    fn non_negative(&mut self, path: Path, what: &str, v: f64) {
        if self.finite(&path, what, &[v]) && v < 0.0 {
            self.err(path, format!("{what} must not be negative, got {v}"));
        }
    }

    fn vec3(&mut self, path: Path, what: &str, v: &V3) {
        self.finite(&path, what, v);
    }
}

/// Highest drum speed a profile may ask for, rpm: household spin speeds end near 1800 rpm; the
/// bound leaves room for studies beyond, but not for a typo (a profile to 1e6 rpm displaced the
/// drum front by metres).
pub const MAX_RPM: f64 = 3000.0;
/// Steepest friction characteristic, s/m: 90 % of f_max at 6.4 um/s already, the near-Coulomb
/// end of the hard-case studies. The damper's regularised damping f_max * slope * 2/pi makes the
/// problem stiff in proportion; at 1e12 s/m the explicit methods' stable step falls below
/// 1e-12 s and a run never ends (and the run's progress budget stops runs too slow to finish).
pub const MAX_FRICTION_SLOPE: f64 = 1e6;
/// Largest unbalance as a fraction of the tub mass: the equations treat the unbalance as a small
/// addition to the suspended body (test loads are 0.3-1 kg on a 55 kg tub).
pub const MAX_UNBALANCE_FRACTION: f64 = 0.1;

/// Check a model. `Ok` means both back ends may evaluate it.
pub fn check(m: &Model) -> Result<(), Vec<CheckError>> {
    let mut c = Ctx::default();
    if m.name.trim().is_empty() {
        c.err(Path::of(&["name"]), "model name is empty");
    }
    c.vec3(Path::of(&["gravity"]), "gravity", &m.gravity);

    // Tub.
    let tub = Path::of(&["tub"]);
    c.positive(tub.clone().key("mass"), "tub: mass", m.tub.mass);
    c.vec3(tub.clone().key("cog"), "tub: cog", &m.tub.cog);
    inertia(&mut c, tub.key("inertia"), "tub", &m.tub.inertia);

    elastic(&mut c, m);

    let mut names = Names::default();

    // Rotors.
    for (i, r) in m.rotors.iter().enumerate() {
        let p = Path::of(&["rotors"]).idx(i);
        names.add(&mut c, p.clone(), "rotor", &r.name);
        let w = format!("rotor `{}`", r.name);
        c.vec3(p.clone().key("axis_point"), &w, &r.axis_point);
        if c.finite(&p.clone().key("axis"), &w, &r.axis) && norm(&r.axis) < 1e-12 {
            c.err(
                p.clone().key("axis"),
                format!("{w}: axis is the zero vector"),
            );
        }
        if c.finite(&p.clone().key("ratio"), &w, &[r.ratio]) && r.ratio == 0.0 {
            c.err(
                p.clone().key("ratio"),
                format!("{w}: ratio must not be zero"),
            );
        }
        c.non_negative(
            p.key("polar_inertia"),
            &format!("{w}: polar_inertia"),
            r.polar_inertia,
        );
    }

    // Unbalances.
    for (i, u) in m.unbalances.iter().enumerate() {
        let p = Path::of(&["unbalances"]).idx(i);
        names.add(&mut c, p.clone(), "unbalance", &u.name);
        let w = format!("unbalance `{}`", u.name);
        if !m.rotors.iter().any(|r| r.name == u.rotor) {
            c.err(
                p.clone().key("rotor"),
                format!("{w}: unknown rotor `{}`", u.rotor),
            );
        }
        c.positive(p.clone().key("mass"), &format!("{w}: mass"), u.mass);
        // Against a valid tub mass only (an invalid one is reported on its own).
        if m.tub.mass > 0.0 && u.mass > MAX_UNBALANCE_FRACTION * m.tub.mass {
            c.err(
                p.clone().key("mass"),
                format!(
                    "{w}: mass {} kg exceeds {MAX_UNBALANCE_FRACTION} x the tub mass ({} kg): the \
                     small-motion model does not hold for such a load",
                    u.mass, m.tub.mass
                ),
            );
        }
        c.vec3(p.key("position"), &w, &u.position);
    }

    // Speed profile.
    let sp = Path::of(&["speed"]);
    if m.speed.table.is_empty() {
        c.err(sp.clone().key("table"), "speed: the profile has no points");
    }
    for (i, row) in m.speed.table.iter().enumerate() {
        let p = sp.clone().key("table").idx(i);
        if !c.finite(&p, "speed", row) {
            continue;
        }
        if i > 0 && row[0] <= m.speed.table[i - 1][0] {
            c.err(
                p.clone(),
                format!(
                    "speed: time must increase strictly, but row {i} has t = {} after t = {}",
                    row[0],
                    m.speed.table[i - 1][0]
                ),
            );
        }
        if row[1] < 0.0 {
            c.err(p, format!("speed: negative rpm {} at row {i}", row[1]));
        } else if row[1] > MAX_RPM {
            c.err(
                p,
                format!(
                    "speed: {} rpm at row {i} exceeds the limit of {MAX_RPM} rpm",
                    row[1]
                ),
            );
        }
    }

    // Force elements.
    for (i, s) in m.springs.iter().enumerate() {
        let p = Path::of(&["springs"]).idx(i);
        names.add(&mut c, p.clone(), "spring", &s.name);
        let w = format!("spring `{}`", s.name);
        two_points(&mut c, &p, &w, &s.a, &s.b);
        c.positive(
            p.clone().key("stiffness"),
            &format!("{w}: stiffness"),
            s.stiffness,
        );
        c.positive(
            p.clone().key("free_length"),
            &format!("{w}: free_length"),
            s.free_length,
        );
        spring_carries(&mut c, p, &w, s, &m.gravity);
    }
    for (i, d) in m.dampers.iter().enumerate() {
        let p = Path::of(&["dampers"]).idx(i);
        names.add(&mut c, p.clone(), "damper", &d.name);
        let w = format!("damper `{}`", d.name);
        two_points(&mut c, &p, &w, &d.a, &d.b);
        c.non_negative(p.key("damping"), &format!("{w}: damping"), d.damping);
    }
    for (i, d) in m.friction_dampers.iter().enumerate() {
        let p = Path::of(&["friction_dampers"]).idx(i);
        names.add(&mut c, p.clone(), "friction damper", &d.name);
        let w = format!("friction damper `{}`", d.name);
        two_points(&mut c, &p, &w, &d.a, &d.b);
        c.non_negative(p.clone().key("f_max"), &format!("{w}: f_max"), d.f_max);
        c.positive(p.clone().key("slope"), &format!("{w}: slope"), d.slope);
        if d.slope > MAX_FRICTION_SLOPE {
            c.err(
                p.clone().key("slope"),
                format!(
                    "{w}: slope {} s/m exceeds {MAX_FRICTION_SLOPE:e} s/m (the run would be too \
                     stiff to integrate)",
                    d.slope
                ),
            );
        }
        c.non_negative(
            p.clone().key("bearing_stiffness"),
            &format!("{w}: bearing_stiffness"),
            d.bearing_stiffness,
        );
        c.non_negative(
            p.clone().key("bearing_damping"),
            &format!("{w}: bearing_damping"),
            d.bearing_damping,
        );
        if let Some(mp) = &d.moving_part {
            moving_part(&mut c, p.key("moving_part"), &w, mp);
        }
    }
    for (i, g) in m.gaskets.iter().enumerate() {
        let p = Path::of(&["gaskets"]).idx(i);
        names.add(&mut c, p.clone(), "gasket", &g.name);
        let w = format!("gasket `{}`", g.name);
        if g.a == g.b {
            c.err(
                p.clone().key("b"),
                format!("{w}: connects {} to itself", g.a.name()),
            );
        }
        c.vec3(p.clone().key("point"), &w, &g.point);
        sym_psd(
            &mut c,
            p.clone().key("stiffness"),
            &format!("{w}: stiffness"),
            &g.stiffness,
        );
        sym_psd(
            &mut c,
            p.clone().key("damping"),
            &format!("{w}: damping"),
            &g.damping,
        );
        loss_factor(&mut c, p.key("loss_factor"), &w, g.loss_factor.as_ref());
    }

    for (i, k) in m.contacts.iter().enumerate() {
        let p = Path::of(&["contacts"]).idx(i);
        names.add(&mut c, p.clone(), "contact", &k.name);
        contact(&mut c, p, k);
    }

    // Sensors.
    for (i, s) in m.sensors.iter().enumerate() {
        let p = Path::of(&["sensors"]).idx(i);
        names.add(&mut c, p.clone(), "sensor", &s.name);
        c.vec3(p.key("point"), &format!("sensor `{}`", s.name), &s.point);
    }

    // Scenes.
    let rotors: Vec<&str> = m.rotors.iter().map(|r| r.name.as_str()).collect();
    let elastic_names: Vec<&str> = m.elastic.iter().map(|e| e.name.as_str()).collect();
    let massive = m.massive_dampers();
    let mut scene_names = HashSet::new();
    for (i, s) in m.scenes.iter().enumerate() {
        let p = Path::of(&["scenes"]).idx(i);
        if !scene_names.insert(s.name.as_str()) {
            c.err(
                p.clone().key("name"),
                format!("duplicate scene name `{}`", s.name),
            );
        }
        for (j, e) in s.effects.iter().enumerate() {
            if Effect::parse(e, &rotors, &elastic_names, &massive).is_none() {
                c.err(
                    p.clone().key("effects").idx(j),
                    format!(
                        "scene `{}`: unknown effect `{e}` (known: gyroscopic, friction_dampers, \
                         gasket_damping, element_geometry, unbalance_inertia, unbalance.<rotor>, \
                         elastic.<body>, centrifugal_stiffening, damper_mass.<friction damper \
                         with a moving_part>, contact)",
                        s.name
                    ),
                );
            }
        }
        let massive = s.effects.iter().position(|e| e.starts_with("damper_mass."));
        if let Some(j) = massive.filter(|_| !s.effects.iter().any(|e| e == "friction_dampers")) {
            c.err(
                p.clone().key("effects").idx(j),
                format!(
                    "scene `{}`: `{}` needs the effect `friction_dampers`",
                    s.name, s.effects[j]
                ),
            );
        }
        if let Some(o) = s.max_order {
            c.positive(
                p.clone().key("max_order"),
                &format!("scene `{}`: max_order", s.name),
                o,
            );
        }
    }

    if c.errors.is_empty() {
        Ok(())
    } else {
        Err(c.errors)
    }
}

/// A friction damper's moving part: a body with mass and inertia on stiff bearings, its CoG
/// on the rod.
fn moving_part(c: &mut Ctx, p: Path, w: &str, mp: &crate::ir::MovingPart) {
    let w = format!("{w}: moving_part");
    c.positive(p.clone().key("mass"), &format!("{w}.mass"), mp.mass);
    c.positive(
        p.clone().key("inertia"),
        &format!("{w}.inertia"),
        mp.inertia,
    );
    c.positive(
        p.clone().key("translational_stiffness"),
        &format!("{w}.translational_stiffness"),
        mp.translational_stiffness,
    );
    if !(0.0..=1.0).contains(&mp.cog) {
        c.err(
            p.key("cog"),
            format!("{w}.cog {} is not a fraction of the rod (0 to 1)", mp.cog),
        );
    }
}

/// Largest contact exponent p: Hertz's 1.5 for a point, 10/9 to 1.5 for the laws in use; p
/// above 1 keeps the force C1 at first touch (zero slope at delta = 0).
pub const MAX_CONTACT_EXPONENT: f64 = 3.0;

/// A contact: its rules, one function each.
fn contact(c: &mut Ctx, p: Path, k: &crate::ir::Contact) {
    let w = format!("contact `{}`", k.name);
    contact_bodies(c, &p, &w, k);
    c.vec3(p.clone().key("point"), &w, &k.point);
    if let Some(b) = &k.b_point {
        c.vec3(p.clone().key("b_point"), &w, b);
    }
    contact_normal(c, p.clone().key("normal"), &w, &k.normal);
    c.non_negative(p.clone().key("gap"), &format!("{w}: gap"), k.gap);
    c.positive(
        p.clone().key("stiffness"),
        &format!("{w}: stiffness"),
        k.stiffness,
    );
    contact_exponent(c, p.clone().key("exponent"), &w, k.exponent);
    c.non_negative(p.key("alpha"), &format!("{w}: alpha (s/m)"), k.alpha);
}

/// A contact touches the tub against the cabinet (or the cabinet against the tub): two
/// different bodies, neither the drum (the drum-tub gap is watched, not a contact).
fn contact_bodies(c: &mut Ctx, p: &Path, w: &str, k: &crate::ir::Contact) {
    let allowed = |b: BodyRef| matches!(b, BodyRef::Tub | BodyRef::Cabinet);
    for (key, b) in [("a", k.a), ("b", k.b)] {
        if !allowed(b) {
            c.err(
                p.clone().key(key),
                format!(
                    "{w}: {key} is the {}; a contact is between tub and cabinet",
                    b.name()
                ),
            );
        }
    }
    if k.a == k.b && allowed(k.a) {
        c.err(
            p.clone().key("b"),
            format!("{w}: touches the {} with itself", k.a.name()),
        );
    }
}

/// The normal is a direction: finite and not the zero vector.
fn contact_normal(c: &mut Ctx, p: Path, w: &str, n: &V3) {
    if c.finite(&p, w, n) && norm(n) < 1e-12 {
        c.err(p, format!("{w}: normal is the zero vector"));
    }
}

/// 1 < p <= MAX_CONTACT_EXPONENT.
fn contact_exponent(c: &mut Ctx, p: Path, w: &str, e: f64) {
    if c.finite(&p, w, &[e]) && !(e > 1.0 && e <= MAX_CONTACT_EXPONENT) {
        c.err(
            p,
            format!(
                "{w}: exponent {e} must lie in (1, {MAX_CONTACT_EXPONENT}]: above 1 the force \
                 is C1 at first touch, which the implicit methods need (Hertz: 1.5)"
            ),
        );
    }
}

/// Item names are unique across kinds: they become CSV columns and scene keys.
#[derive(Default)]
struct Names<'a> {
    seen: HashSet<&'a str>,
}

impl<'a> Names<'a> {
    fn add(&mut self, c: &mut Ctx, p: Path, kind: &str, name: &'a str) {
        let valid = !name.is_empty()
            && name
                .chars()
                .all(|ch| ch.is_ascii_alphanumeric() || ch == '_' || ch == '-');
        if !valid {
            c.err(
                p.key("name"),
                format!("{kind} name `{name}` must be non-empty ASCII letters, digits, _ or -"),
            );
        } else if !self.seen.insert(name) {
            c.err(p.key("name"), format!("duplicate name `{name}` ({kind})"));
        }
    }
}

/// A suspension spring carries the tub: hanging in tension above it or compressed below it,
/// its force on the tub at the reference position has no large component along gravity. One
/// that pulls the tub down (a tension spring whose cabinet end lies below the tub end, e.g. a
/// mirrored coordinate) adds to the weight instead; the static start then sits far off and a
/// run drifts. Refused when the force on the tub points within 60 degrees of gravity.
fn spring_carries(c: &mut Ctx, p: Path, what: &str, s: &crate::ir::Spring, g: &V3) {
    let all = [s.a.point, s.b.point, *g];
    // Other rules report non-finite or non-positive numbers; this one needs sane ones.
    let sane = all.iter().flatten().all(|v| v.is_finite())
        && s.stiffness > 0.0
        && s.free_length > 0.0
        && s.a.body != s.b.body
        && norm(g) > 0.0;
    if !sane {
        return;
    }
    // From the tub end to the other end.
    let (tub, other, other_key) = if s.a.body == BodyRef::Tub {
        (s.a.point, s.b.point, "b")
    } else {
        (s.b.point, s.a.point, "a")
    };
    let d = [other[0] - tub[0], other[1] - tub[1], other[2] - tub[2]];
    let len = norm(&d);
    if len < 1e-9 {
        return;
    }
    // Tension (len > free length) pulls the tub end towards the other end.
    let f = s.stiffness * (len - s.free_length);
    let along_g = f * (d[0] * g[0] + d[1] * g[1] + d[2] * g[2]) / (len * norm(g));
    if along_g > 0.5 * f.abs() {
        c.err(
            p.key(other_key).key("point"),
            format!(
                "{what}: at the reference position it pulls the tub along gravity ({along_g:.1} N \
                 of its {:.1} N); a suspension spring hangs the tub in tension from above or \
                 supports it in compression from below (an end mirrored?)",
                f.abs()
            ),
        );
    }
}

/// Elastic bodies: a known body once each, damping ratios in [0, 1) (the support springs' only
/// where the data has such springs), a Rayleigh beta >= 0, and modal data that is consistent in
/// itself and describes that body.
fn elastic(c: &mut Ctx, m: &Model) {
    use modal::ElasticBodyKind as K;
    for (i, e) in m.elastic.iter().enumerate() {
        let p = Path::of(&["elastic"]).idx(i);
        let kind = match e.body() {
            Some(BodyRef::Tub) => Some(K::Tub),
            Some(BodyRef::Drum) => Some(K::Drum),
            Some(BodyRef::Cabinet) => Some(K::Cabinet),
            Some(BodyRef::DamperPart(_)) | None => {
                let other = &e.name;
                c.err(
                    p.clone().key("name"),
                    format!("elastic `{other}`: not a body; one of tub, drum, cabinet"),
                );
                None
            }
        };
        if m.elastic[..i].iter().any(|o| o.name == e.name) {
            c.err(
                p.clone().key("name"),
                format!("elastic `{}`: declared twice", e.name),
            );
        }
        let what = format!("elastic `{}`: damping", e.name);
        c.non_negative(p.clone().key("damping"), &what, e.damping);
        if e.damping >= 1.0 {
            c.err(
                p.clone().key("damping"),
                format!("{what} is a ratio of critical below 1, got {}", e.damping),
            );
        }
        if e.modes == Some(0) {
            c.err(
                p.clone().key("modes"),
                format!("elastic `{}`: modes must be at least 1", e.name),
            );
        }
        if let Some(zs) = e.support_damping {
            let what = format!("elastic `{}`: support_damping", e.name);
            c.non_negative(p.clone().key("support_damping"), &what, zs);
            if zs >= 1.0 {
                c.err(
                    p.clone().key("support_damping"),
                    format!("{what} is a ratio of critical below 1, got {zs}"),
                );
            }
        }
        c.non_negative(
            p.clone().key("stiffness_damping"),
            &format!("elastic `{}`: stiffness_damping (s)", e.name),
            e.stiffness_damping,
        );
        let Some(d) = &e.data else {
            // Not read: `modal::resolve` has reported why.
            continue;
        };
        if e.support_damping.is_some() && d.support_springs.is_empty() {
            c.err(
                p.clone().key("support_damping"),
                format!(
                    "elastic `{}`: support_damping, but {} lists no support_springs",
                    e.name, e.file
                ),
            );
        }
        for problem in modal::problems(d) {
            c.err(
                p.clone().key("file"),
                format!("elastic `{}`: {}: {problem}", e.name, e.file),
            );
        }
        if kind.is_some_and(|k| k != d.body) {
            c.err(
                p.clone().key("file"),
                format!(
                    "elastic `{}`: {}: body: the file describes the {:?}",
                    e.name, e.file, d.body
                ),
            );
        }
    }
    drum_points(c, m);
    for body in [BodyRef::Cabinet, BodyRef::Tub, BodyRef::Drum] {
        attached(c, m, body);
    }
    rotor_mounts(c, m);
    tub_mass(c, m);
    elastic_drum(c, m);
}

/// The drum carries sensors only (anywhere: a rim sensor turns with it; see `BodyRef::Drum`).
fn drum_points(c: &mut Ctx, m: &Model) {
    let drum = m.drum();
    let ends = |a: &Attach, b: &Attach| [(a.body, "a"), (b.body, "b")];
    type End<'a> = (BodyRef, &'a str);
    let mut lists: Vec<(&str, usize, String, [End; 2])> = Vec::new();
    for (i, s) in m.springs.iter().enumerate() {
        lists.push(("springs", i, s.name.clone(), ends(&s.a, &s.b)));
    }
    for (i, s) in m.dampers.iter().enumerate() {
        lists.push(("dampers", i, s.name.clone(), ends(&s.a, &s.b)));
    }
    for (i, s) in m.friction_dampers.iter().enumerate() {
        lists.push(("friction_dampers", i, s.name.clone(), ends(&s.a, &s.b)));
    }
    for (i, g) in m.gaskets.iter().enumerate() {
        lists.push(("gaskets", i, g.name.clone(), [(g.a, "a"), (g.b, "b")]));
    }
    for (list, i, name, e) in lists {
        for (body, key) in e {
            if body == BodyRef::Drum {
                c.err(
                    Path::of(&[list]).idx(i).key(key),
                    format!("{list} `{name}`: force elements attach to the tub or the cabinet; the drum carries sensors only"),
                );
            }
        }
    }
    for (i, s) in m.sensors.iter().enumerate() {
        if s.body == BodyRef::Drum && drum.is_none() {
            c.err(
                Path::of(&["sensors"]).idx(i).key("body"),
                format!(
                    "sensor `{}`: on the drum, but the model has no rotor `drum`",
                    s.name
                ),
            );
        }
    }
}

/// The modal data of an elastic body that some scene switches on (`attachments::used`).
fn modal_of(m: &Model, body: BodyRef) -> Option<&modal::ModalData> {
    m.elastic_of(body)
        .filter(|_| attachments::used(m, body))
        .and_then(|e| e.data.as_ref())
}

/// Every point the model attaches to an elastic body (`attachments::attachments`, which says
/// where each counts) is one of its modal points (an FE node set), within
/// `modal::POINT_TOLERANCE`.
fn attached(c: &mut Ctx, m: &Model, body: BodyRef) {
    let Some(data) = m.elastic_of(body).and_then(|e| e.data.as_ref()) else {
        return;
    };
    for a in attachments::attachments(m, body) {
        need_point(c, data, body, a.path, a.what, &a.point);
    }
}

/// The index of a body's `elastic` entry (for error paths).
fn position_of(m: &Model, body: BodyRef) -> Option<usize> {
    m.elastic.iter().position(|e| e.body() == Some(body))
}

/// A point on an elastic body must be one of its modal points; the message names the nearest.
fn need_point(c: &mut Ctx, d: &modal::ModalData, body: BodyRef, path: Path, what: String, p: &V3) {
    let body = body.name();
    let dist = |a: V3, b: V3| crate::geom::f::norm(crate::geom::f::sub(a, b));
    if modal::point_at(d, *p).is_none() {
        let near = d
            .points
            .iter()
            .min_by(|a, b| dist(a.position, *p).total_cmp(&dist(b.position, *p)));
        c.err(
            path,
            format!(
                "{what}: the elastic {body} has no FE node set at {p:?}{}",
                near.map_or(String::new(), |q| format!(
                    " (nearest: {} at {:?})",
                    q.name, q.position
                ))
            ),
        );
    }
}

/// On the elastic tub every rotor sits at a tub node set (its mount), on its own axis.
fn rotor_mounts(c: &mut Ctx, m: &Model) {
    if modal_of(m, BodyRef::Tub).is_none() {
        return;
    }
    for (i, r) in m.rotors.iter().enumerate() {
        let p = Path::of(&["rotors"]).idx(i);
        let key = if r.mount.is_some() {
            "mount"
        } else {
            "axis_point"
        };
        let mp = r.mount_point();
        let e = crate::geom::f::unit(r.axis);
        let off = crate::geom::f::sub(mp, r.axis_point);
        if crate::geom::f::norm(crate::geom::f::cross(off, e)) > 1e-3 {
            c.err(
                p.key(key),
                format!(
                    "rotor `{}`: mount {mp:?} is not on the rotor's axis (more than 1 mm off)",
                    r.name
                ),
            );
        }
        if !(r.mass.is_finite() && r.mass >= 0.0) {
            c.err(
                Path::of(&["rotors"]).idx(i).key("mass"),
                format!("rotor `{}`: mass must be >= 0, got {}", r.name, r.mass),
            );
        }
    }
}

/// Relative tolerance between the rigid tub's mass and the elastic tub's parts: the two
/// descriptions are one machine (rigid and elastic scenes side by side); 2 % is the agreement
/// the FE models were built to.
pub const TUB_MASS_TOLERANCE: f64 = 0.02;

/// The elastic tub carries the drum (its FE mass) and the other rotors' masses: together they
/// must be the rigid tub's mass, or one of the two descriptions is missing a part. The drum's
/// FE mass counts whenever the model has the drum's modal data, whether or not a scene makes
/// the drum elastic: the equations put it on the elastic tub either way (`Equations::new`).
fn tub_mass(c: &mut Ctx, m: &Model) {
    let Some(tub) = modal_of(m, BodyRef::Tub) else {
        return;
    };
    let drum_data = m.elastic_of(BodyRef::Drum).and_then(|e| e.data.as_ref());
    let drum = drum_data.map_or(0.0, |d| d.mass);
    let rotors: f64 = m
        .rotors
        .iter()
        .filter(|r| r.name != DRUM || drum_data.is_none())
        .map(|r| r.mass)
        .sum();
    let total = tub.mass + drum + rotors;
    if (total - m.tub.mass).abs() > TUB_MASS_TOLERANCE * m.tub.mass {
        let i = position_of(m, BodyRef::Tub).unwrap_or(0);
        c.err(
            Path::of(&["elastic"]).idx(i),
            format!(
                "elastic `tub`: FE tub {:.3} kg + drum {drum:.3} kg + rotors {rotors:.3} kg = \
                 {total:.3} kg, but the rigid tub has {} kg (more than {} % apart): add the \
                 drum's elastic entry or the rotors' `mass`, or correct `tub.mass`",
                tub.mass,
                m.tub.mass,
                TUB_MASS_TOLERANCE * 100.0
            ),
        );
    }
}

/// The elastic drum spins with the rotor `drum` and carries its unbalances at its node sets;
/// stiffening needs the geometric stiffness in its modal data.
fn elastic_drum(c: &mut Ctx, m: &Model) {
    let Some(i) = position_of(m, BodyRef::Drum) else {
        return;
    };
    if m.drum().is_none() {
        c.err(
            Path::of(&["elastic"]).idx(i).key("name"),
            "elastic `drum`: the model has no rotor `drum` to spin it".to_string(),
        );
    }
    let Some(d) = modal_of(m, BodyRef::Drum) else {
        return;
    };
    if d.geometric_stiffness.is_none() {
        for (j, s) in m.scenes.iter().enumerate() {
            if s.effects.iter().any(|e| e == "centrifugal_stiffening") {
                c.err(
                    Path::of(&["scenes"]).idx(j).key("effects"),
                    format!(
                        "scene `{}`: centrifugal_stiffening, but {} has no geometric_stiffness",
                        s.name, m.elastic[i].file
                    ),
                );
            }
        }
    }
}

fn norm(v: &V3) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn two_points(c: &mut Ctx, p: &Path, what: &str, a: &Attach, b: &Attach) {
    let fa = c.finite(&p.clone().key("a").key("point"), what, &a.point);
    let fb = c.finite(&p.clone().key("b").key("point"), what, &b.point);
    if a.body == b.body {
        c.err(
            p.clone().key("b").key("body"),
            format!("{what}: both ends on the {}", a.body.name()),
        );
    }
    if fa && fb {
        let d = [
            b.point[0] - a.point[0],
            b.point[1] - a.point[1],
            b.point[2] - a.point[2],
        ];
        if norm(&d) < 1e-9 {
            c.err(
                p.clone().key("b").key("point"),
                format!("{what}: both ends at the same point, the axis is undefined"),
            );
        }
    }
}

/// Symmetric eigenvalues of a small matrix by cyclic Jacobi rotations (sizes 3 and 6 only; the
/// checker must not depend on the back ends' numerics).
pub fn sym_eigenvalues<const N: usize>(m: &[[f64; N]; N]) -> [f64; N] {
    let mut a = *m;
    for _sweep in 0..100 {
        let mut off = 0.0;
        for i in 0..N {
            for j in i + 1..N {
                off += a[i][j] * a[i][j];
            }
        }
        if off < 1e-30 {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                if a[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let cs = 1.0 / (t * t + 1.0).sqrt();
                let sn = t * cs;
                for k in 0..N {
                    let akp = a[k][p];
                    let akq = a[k][q];
                    a[k][p] = cs * akp - sn * akq;
                    a[k][q] = sn * akp + cs * akq;
                }
                for k in 0..N {
                    let apk = a[p][k];
                    let aqk = a[q][k];
                    a[p][k] = cs * apk - sn * aqk;
                    a[q][k] = sn * apk + cs * aqk;
                }
            }
        }
    }
    let mut ev = [0.0; N];
    for i in 0..N {
        ev[i] = a[i][i];
    }
    ev.sort_by(|x, y| x.total_cmp(y));
    ev
}

fn asymmetry<const N: usize>(m: &[[f64; N]; N]) -> Option<(usize, usize)> {
    let scale = m.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    for i in 0..N {
        for j in i + 1..N {
            if (m[i][j] - m[j][i]).abs() > 1e-9 * scale.max(1e-300) {
                return Some((i, j));
            }
        }
    }
    None
}

fn inertia(c: &mut Ctx, p: Path, who: &str, m: &M3) {
    if !c.finite(&p, &format!("{who}: inertia"), m.as_flattened()) {
        return;
    }
    if let Some((i, j)) = asymmetry(m) {
        c.err(
            // The lower entry: the one most likely mistyped.
            p.idx(j).idx(i),
            format!(
                "{who}: inertia tensor is not symmetric ([{i}][{j}] = {} but [{j}][{i}] = {})",
                m[i][j], m[j][i]
            ),
        );
        return;
    }
    let ev = sym_eigenvalues(m);
    if ev[0] <= 0.0 {
        c.err(
            p,
            format!("{who}: inertia tensor is not positive definite (principal moments {ev:?})"),
        );
    } else if ev[0] + ev[1] < ev[2] * (1.0 - 1e-12) {
        c.err(
            p,
            format!(
                "{who}: principal moments {ev:?} violate the triangle inequality (I1 + I2 >= I3), \
                 no mass distribution has them"
            ),
        );
    }
}

/// A gasket's loss factor: one number, or a list of 6 (x, y, z, rx, ry, rz); each finite and
/// >= 0 (S K S is then positive semi-definite with K).
fn loss_factor(c: &mut Ctx, p: Path, what: &str, eta: Option<&LossFactor>) {
    match eta {
        None => {}
        Some(LossFactor::Uniform(e)) => c.non_negative(p, &format!("{what}: loss_factor"), *e),
        Some(LossFactor::PerDirection(v)) if v.len() != 6 => c.err(
            p,
            format!(
                "{what}: loss_factor needs one number or 6 (x, y, z, rx, ry, rz), got a list of {}",
                v.len()
            ),
        ),
        Some(LossFactor::PerDirection(v)) => {
            for (i, e) in v.iter().enumerate() {
                c.non_negative(p.clone().idx(i), &format!("{what}: loss_factor"), *e);
            }
        }
    }
}

fn sym_psd(c: &mut Ctx, p: Path, what: &str, m: &M6) {
    if !c.finite(&p, what, m.as_flattened()) {
        return;
    }
    if let Some((i, j)) = asymmetry(m) {
        c.err(
            // The lower entry: the one most likely mistyped.
            p.idx(j).idx(i),
            format!(
                "{what} is not symmetric ([{i}][{j}] = {} but [{j}][{i}] = {})",
                m[i][j], m[j][i]
            ),
        );
        return;
    }
    let ev = sym_eigenvalues(m);
    let scale = ev[5].abs().max(1e-300);
    if ev[0] < -1e-12 * scale {
        c.err(
            p,
            format!(
                "{what} is not positive semi-definite (smallest eigenvalue {:e})",
                ev[0]
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_matches_closed_form_2x2_block() {
        // [[2,1],[1,2]] has eigenvalues 1 and 3 (closed form); third diagonal 5.
        let m = [[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]];
        let ev = sym_eigenvalues(&m);
        for (a, b) in ev.iter().zip([1.0, 3.0, 5.0]) {
            assert!((a - b).abs() < 1e-12, "{ev:?}");
        }
    }

    #[test]
    fn path_display() {
        let p = Path::default().key("springs").idx(2).key("stiffness");
        assert_eq!(p.to_string(), "springs[2].stiffness");
    }
}
