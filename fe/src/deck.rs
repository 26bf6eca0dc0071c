//! Writing CalculiX input decks from code: nodes, elements, sets and cards as text, in the order
//! ccx reads them. Parametric models build a `Deck`; nothing here knows a particular body.

use std::fmt::Write as _;

/// A CalculiX input deck under construction.
#[derive(Clone, Debug, Default)]
pub struct Deck {
    text: String,
}

impl Deck {
    pub fn new(title: &str) -> Deck {
        let mut d = Deck::default();
        d.line(&format!("** {title}"));
        d.line("** written by washdyn-fe; units SI (m, kg, s, N, Pa)");
        d
    }
    /// One line as it is (a card or a data line).
    pub fn line(&mut self, l: &str) -> &mut Self {
        self.text.push_str(l);
        self.text.push('\n');
        self
    }
    /// `*NODE` with `(id, [x, y, z])`.
    pub fn nodes(&mut self, nset: Option<&str>, nodes: &[(usize, [f64; 3])]) -> &mut Self {
        match nset {
            Some(n) => self.line(&format!("*NODE, NSET={n}")),
            None => self.line("*NODE"),
        };
        for (id, p) in nodes {
            let _ = writeln!(
                self.text,
                "{id}, {:.12e}, {:.12e}, {:.12e}",
                p[0], p[1], p[2]
            );
        }
        self
    }
    /// `*ELEMENT` of one type into an element set; at most 16 numbers a line as ccx wants.
    pub fn elements(
        &mut self,
        kind: &str,
        elset: &str,
        elems: &[(usize, Vec<usize>)],
    ) -> &mut Self {
        self.line(&format!("*ELEMENT, TYPE={kind}, ELSET={elset}"));
        for (id, nodes) in elems {
            let all: Vec<String> = std::iter::once(*id)
                .chain(nodes.iter().copied())
                .map(|n| n.to_string())
                .collect();
            for (k, chunk) in all.chunks(16).enumerate() {
                let sep = if (k + 1) * 16 < all.len() { "," } else { "" };
                let _ = writeln!(self.text, "{}{sep}", chunk.join(", "));
            }
        }
        self
    }
    /// `*NSET` with the given node ids.
    pub fn nset(&mut self, name: &str, ids: &[usize]) -> &mut Self {
        self.line(&format!("*NSET, NSET={name}"));
        for chunk in ids.chunks(16) {
            let s: Vec<String> = chunk.iter().map(|n| n.to_string()).collect();
            self.line(&s.join(", "));
        }
        self
    }
    /// An isotropic linear-elastic material with density.
    pub fn material(&mut self, name: &str, e: f64, nu: f64, rho: f64) -> &mut Self {
        self.line(&format!("*MATERIAL, NAME={name}"))
            .line("*ELASTIC")
            .line(&format!("{e:.9e}, {nu}"))
            .line("*DENSITY")
            .line(&format!("{rho}"))
    }
    /// A `*FREQUENCY` step for `modes` eigenmodes, mode shapes written at the original nodes
    /// (`OUTPUT=2D`: shell mid-surfaces and beam lines, not ccx's expanded 3-D nodes).
    pub fn frequency_step(&mut self, modes: usize) -> &mut Self {
        self.line("*STEP")
            .line("*FREQUENCY")
            .line(&modes.to_string())
            .line("*NODE FILE, OUTPUT=2D")
            .line("U")
            .line("*END STEP")
    }
    pub fn text(&self) -> &str {
        &self.text
    }
}
