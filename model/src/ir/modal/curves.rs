//! Characteristic curves of a modal body (issue 52): a nonlinear restoring force on chosen modes,
//! identified from geometrically nonlinear static FE solutions (`washdyn fe curves`).
//!
//! The force derives from a strain-energy polynomial in the chosen modal coordinates (those of
//! the body's modal data file, mass-normalised, SI: kg^0.5 m):
//!
//!   V(q) = sum over `cubic` terms c q_i q_j q_k + sum over `quartic` terms c q_i q_j q_k q_l,
//!   f_nl = dV/dq,
//!
//! added to the modal stiffness: q'' + ... + w^2 q + f_nl(q) = Q. A potential rather than free
//! force coefficients: an elastic force is the gradient of its strain energy, so the energy
//! balance's elastic category stays exact and the fit has fewer unknowns (Muravyov and Rizzi,
//! Computers & Structures 81 (2003) 1513-1523, fit the same cubic and quartic energy terms).
//! The cubic terms (quadratic forces) make the stiffness differ between the two directions: the
//! even orders under a harmonic load. A symmetric quartic alone gives odd orders only.
//!
//! File format: TOML, one file per body (`<body>.curves.toml`), written with round-trip floats.

use crate::scalar::Scalar;
use serde::{Deserialize, Serialize};

/// A body's characteristic curves.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Curves {
    /// The body they belong to (`cabinet`, `tub`, `drum`).
    pub body: String,
    /// Where they came from: the deck, the solver, the method, the load levels.
    pub source: String,
    /// The chosen modes: indices (0-based) into the modal data file's modes, before any
    /// truncation of the model.
    pub modes: Vec<usize>,
    /// Their frequencies in the modal data file the fit used, Hz: checked against the file the
    /// model reads (a regenerated file with other modes refuses the curves).
    pub frequencies: Vec<f64>,
    /// Cubic energy terms (quadratic forces).
    #[serde(default)]
    pub cubic: Vec<Term>,
    /// Quartic energy terms (cubic forces).
    #[serde(default)]
    pub quartic: Vec<Term>,
    /// How well the polynomial reproduces the FE solutions.
    pub fit: Fit,
}

/// One energy term: `c` times the product of the chosen modes' coordinates at `modes` (indices
/// into [`Curves::modes`], ascending, repeated for powers: `[0, 0, 1]` is q0^2 q1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Term {
    pub modes: Vec<usize>,
    /// J / (kg^0.5 m)^n, n the term's degree.
    pub c: f64,
}

/// The fit's quality: residuals relative to the largest nonlinear modal force of the solutions
/// compared.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fit {
    /// Load levels fitted, as the largest static modal displacement they gave (kg^0.5 m, signed).
    pub loads: Vec<f64>,
    /// Largest residual at the fitted loads, relative.
    pub residual: f64,
    /// Load levels not used in the fit, and the largest residual there, relative.
    pub unseen_loads: Vec<f64>,
    pub unseen_residual: f64,
    /// The bound both residuals must stay under (the curves are refused above it).
    pub bound: f64,
}

/// Most chosen modes of one body's curves: the derivation evaluates them on the stack.
pub const MAX_CURVE_MODES: usize = 8;

impl Fit {
    /// The residuals (field, value) not within [0, `bound`] (NaN included): the one rule the
    /// fit (`washdyn_fe::curves`) and the model's checker both apply.
    pub fn beyond_bound(&self) -> impl Iterator<Item = (&'static str, f64)> + '_ {
        [
            ("residual", self.residual),
            ("unseen_residual", self.unseen_residual),
        ]
        .into_iter()
        .filter(|(_, r)| !(*r >= 0.0 && *r <= self.bound))
    }
}

impl Curves {
    /// What is wrong with these curves for `data` (the modal data file they were fitted on,
    /// before truncation), each naming its field; empty when they fit.
    pub fn problems(&self, body: &str, data: &super::ModalData) -> Vec<String> {
        let mut out = Vec::new();
        if self.body != body {
            out.push(format!("body: `{}`, but the entry is `{body}`", self.body));
        }
        let n = self.modes.len();
        if n == 0 || n > MAX_CURVE_MODES {
            out.push(format!("modes: {n} chosen, 1 to {MAX_CURVE_MODES} allowed"));
        }
        for (i, &m) in self.modes.iter().enumerate() {
            if m >= data.eigenmodes() {
                out.push(format!(
                    "modes[{i}]: mode {m}, the modal data has {} eigenmodes",
                    data.eigenmodes()
                ));
            } else if let Some(f) = self.frequencies.get(i) {
                let g = data.frequencies[m];
                let close = (f - g).abs() <= 1e-6 * g.abs();
                if !close {
                    out.push(format!(
                        "frequencies[{i}]: {f} Hz, mode {m} of the modal data is {g} Hz: the \
                         curves were fitted on other modes (regenerate them)"
                    ));
                }
            }
            if self.modes[..i].contains(&m) {
                out.push(format!("modes[{i}]: mode {m} chosen twice"));
            }
        }
        if self.frequencies.len() != n {
            out.push(format!(
                "frequencies: {} given for {n} modes",
                self.frequencies.len()
            ));
        }
        for (key, terms, degree) in [("cubic", &self.cubic, 3), ("quartic", &self.quartic, 4)] {
            for (j, t) in terms.iter().enumerate() {
                let ok = t.modes.len() == degree
                    && t.modes.windows(2).all(|w| w[0] <= w[1])
                    && t.modes.iter().all(|&m| m < n);
                if !ok {
                    out.push(format!(
                        "{key}[{j}].modes: {:?}, want {degree} ascending indices below {n}",
                        t.modes
                    ));
                }
                if !t.c.is_finite() {
                    out.push(format!("{key}[{j}].c: {} is not finite", t.c));
                }
            }
        }
        let f = &self.fit;
        if !(f.bound > 0.0 && f.bound <= 1.0) {
            out.push(format!("fit.bound: {}, want in (0, 1]", f.bound));
        }
        for (key, r) in f.beyond_bound() {
            out.push(format!(
                "fit.{key}: {r} is above the fit's bound {} (or not a number): the \
                 polynomial does not reproduce the FE solutions",
                f.bound
            ));
        }
        out
    }

    /// The nonlinear modal force on the chosen modes at their coordinates `q` (same order as
    /// [`Curves::modes`]): dV/dq, added into `f`. Over [`Scalar`], so the derivation (either
    /// back end) and the FE fit evaluate the one polynomial.
    pub fn force_into<T: Scalar>(&self, q: &[T], f: &mut [T]) {
        for t in self.cubic.iter().chain(&self.quartic) {
            // d/dq of c prod q[modes]: per position p, c times the product of the others (a
            // power counts once per position, so q0^2 gives 2 c q0).
            for p in 0..t.modes.len() {
                let mut others = T::c(t.c);
                for (i, &m) in t.modes.iter().enumerate() {
                    if i != p {
                        others = others * q[m];
                    }
                }
                f[t.modes[p]] += others;
            }
        }
    }

    /// The strain energy of the nonlinear part, J.
    pub fn energy<T: Scalar>(&self, q: &[T]) -> T {
        let mut v = T::zero();
        for t in self.cubic.iter().chain(&self.quartic) {
            let mut term = T::c(t.c);
            for &m in &t.modes {
                term = term * q[m];
            }
            v += term;
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_mode(a2: f64, a3: f64) -> Curves {
        Curves {
            body: "cabinet".into(),
            source: "test".into(),
            modes: vec![3],
            frequencies: vec![40.0],
            cubic: vec![Term {
                modes: vec![0, 0, 0],
                c: a2 / 3.0,
            }],
            quartic: vec![Term {
                modes: vec![0, 0, 0, 0],
                c: a3 / 4.0,
            }],
            fit: Fit {
                loads: vec![],
                residual: 0.0,
                unseen_loads: vec![],
                unseen_residual: 0.0,
                bound: 0.05,
            },
        }
    }

    /// Every rule names its field: the body, modes beyond the data or chosen twice,
    /// frequencies of other modes (a regenerated file), terms of the wrong degree or order,
    /// a fit above its bound.
    #[test]
    fn curves_that_do_not_fit_their_modal_data_are_refused_by_field() {
        let d = crate::ir::modal::tests::tiny();
        let mut c = one_mode(1.0, 1.0);
        c.modes = vec![1];
        c.frequencies = vec![20.0];
        assert_eq!(c.problems("cabinet", &d), Vec::<String>::new());
        let found = |edit: &dyn Fn(&mut Curves), body: &str| {
            let mut x = c.clone();
            edit(&mut x);
            x.problems(body, &d).join("; ")
        };
        assert!(found(&|_| {}, "tub").starts_with("body: `cabinet`"));
        let e = found(&|x| x.modes = vec![2], "cabinet");
        assert!(
            e.contains("modes[0]: mode 2, the modal data has 2 eigenmodes"),
            "{e}"
        );
        let e = found(&|x| x.frequencies = vec![20.5], "cabinet");
        assert!(
            e.contains("frequencies[0]: 20.5 Hz, mode 1 of the modal data is 20 Hz"),
            "{e}"
        );
        let e = found(
            &|x| {
                x.modes = vec![1, 1];
                x.frequencies = vec![20.0, 20.0];
            },
            "cabinet",
        );
        assert!(e.contains("modes[1]: mode 1 chosen twice"), "{e}");
        let e = found(&|x| x.cubic[0].modes = vec![0, 0], "cabinet");
        assert!(
            e.contains("cubic[0].modes: [0, 0], want 3 ascending"),
            "{e}"
        );
        let e = found(&|x| x.quartic[0].modes = vec![0, 0, 0, 1], "cabinet");
        assert!(e.contains("quartic[0].modes: [0, 0, 0, 1], want 4 ascending indices below 1"));
        let e = found(&|x| x.cubic[0].c = f64::NAN, "cabinet");
        assert!(e.contains("cubic[0].c: NaN is not finite"), "{e}");
        let e = found(&|x| x.fit.unseen_residual = 0.2, "cabinet");
        assert!(
            e.contains("fit.unseen_residual: 0.2 is above the fit's bound 0.05"),
            "{e}"
        );
        let e = found(&|x| x.fit.bound = 0.0, "cabinet");
        assert!(e.contains("fit.bound: 0, want in (0, 1]"), "{e}");
    }

    /// V = a2 q^3 / 3 + a3 q^4 / 4 gives f = a2 q^2 + a3 q^3 (differentiated by hand).
    #[test]
    fn single_mode_force_is_the_energy_gradient() {
        let c = one_mode(2.0, -5.0);
        let q = [0.3];
        let mut f = [0.0];
        c.force_into(&q, &mut f);
        assert!((f[0] - (2.0 * 0.09 - 5.0 * 0.027)).abs() < 1e-15);
        assert!((c.energy(&q) - (2.0 * 0.027 / 3.0 - 5.0 * 0.0081 / 4.0)).abs() < 1e-15);
    }

    /// Two modes, V = c q0^2 q1: f0 = 2 c q0 q1, f1 = c q0^2; and the force is the energy's
    /// gradient by central differences.
    #[test]
    fn coupling_terms_are_the_energy_gradient() {
        let mut c = one_mode(1.0, 0.5);
        c.modes = vec![3, 5];
        c.frequencies = vec![40.0, 55.0];
        c.cubic.push(Term {
            modes: vec![0, 0, 1],
            c: 0.7,
        });
        c.quartic.push(Term {
            modes: vec![0, 1, 1, 1],
            c: -0.2,
        });
        let q = [0.4, -0.25];
        let mut f = [0.0; 2];
        c.force_into(&q, &mut f);
        for k in 0..2 {
            let h = 1e-6;
            let (mut qp, mut qm) = (q, q);
            qp[k] += h;
            qm[k] -= h;
            let fd = (c.energy(&qp) - c.energy(&qm)) / (2.0 * h);
            assert!((f[k] - fd).abs() < 1e-8, "{k}: {} against {fd}", f[k]);
        }
    }
}
