//! The one checker. Both front ends run it: the TOML loader maps each error's path to a file line,
//! the `machine!` macro maps it to the offending token. Errors are collected, not returned at the
//! first, so a user sees every problem at once.
//!
//! The rules, one function each on the shared context `Ctx`, live with their concept: the rigid
//! tub, rotors and unbalances (`bodies.rs`), the speed profile (`speed.rs`), the force elements
//! (`force_elements.rs`), the elastic bodies and their modal data (`elastic.rs`), sensors and
//! scenes (`scenes.rs`); `check` runs them in one order.

mod bodies;
mod counterweights;
mod elastic;
mod force_elements;
mod scenes;
mod speed;

pub use bodies::MAX_UNBALANCE_FRACTION;
pub use elastic::TUB_MASS_TOLERANCE;
pub use force_elements::{MAX_CONTACT_EXPONENT, MAX_FRICTION_SLOPE};
pub use speed::MAX_RPM;

use super::{Model, V3};
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

/// Check a model. `Ok` means both back ends may evaluate it.
pub fn check(m: &Model) -> Result<(), Vec<CheckError>> {
    let mut c = Ctx::default();
    if m.name.trim().is_empty() {
        c.err(Path::of(&["name"]), "model name is empty");
    }
    c.vec3(Path::of(&["gravity"]), "gravity", &m.gravity);

    bodies::tub(&mut c, m);

    elastic::elastic(&mut c, m);

    let mut names = Names::default();
    bodies::rotors(&mut c, &mut names, m);
    bodies::unbalances(&mut c, &mut names, m);
    speed::speed(&mut c, m);
    force_elements::springs(&mut c, &mut names, m);
    force_elements::dampers(&mut c, &mut names, m);
    force_elements::friction_dampers(&mut c, &mut names, m);
    force_elements::gaskets(&mut c, &mut names, m);
    force_elements::contacts(&mut c, &mut names, m);
    counterweights::counterweights(&mut c, &mut names, m);
    scenes::sensors(&mut c, &mut names, m);
    scenes::scenes(&mut c, m);
    free(&mut c, m);

    if c.errors.is_empty() {
        Ok(())
    } else {
        Err(c.errors)
    }
}

/// Each free parameter names a number of the model, once.
fn free(c: &mut Ctx, m: &Model) {
    let mut seen = HashSet::new();
    if m.free.is_empty() {
        return;
    }
    for (i, r) in super::param::resolve_all(m, &m.free)
        .into_iter()
        .enumerate()
    {
        let text = &m.free[i];
        match r {
            Ok(p) if !seen.insert(p.path.clone()) => c.err(
                Path::of(&["free"]).idx(i),
                format!("free parameter `{text}` is given twice (as `{}`)", p.path),
            ),
            Ok(_) => {}
            Err(e) => c.err(Path::of(&["free"]).idx(i), e.to_string()),
        }
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

fn norm(v: &V3) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
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
