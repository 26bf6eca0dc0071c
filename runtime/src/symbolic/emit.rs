//! Rust source from the graph: one `let` per live operation in topological order, constants as
//! literals, inputs by the names the caller gives. LLVM does the rest (register allocation,
//! scheduling); the graph already did the algebra.

use super::{Graph, Node, Sym};
use std::fmt::Write;

/// A float as a Rust literal that reads back to the same bits.
pub fn fmt_f64(v: f64) -> String {
    if v.is_nan() {
        "f64::NAN".into()
    } else if v.is_infinite() {
        if v > 0.0 {
            "f64::INFINITY".into()
        } else {
            "f64::NEG_INFINITY".into()
        }
    } else if v < 0.0 {
        format!("(-{:?}f64)", -v)
    } else {
        format!("{v:?}f64")
    }
}

/// Emits statements for the nodes some outputs need, skipping those emitted before (so several
/// output groups in one function share their common part).
pub struct Emitter<'g> {
    g: &'g Graph,
    inputs: Vec<String>,
    done: Vec<bool>,
    pub code: String,
}

impl<'g> Emitter<'g> {
    /// `inputs[k]` is the Rust expression of input k.
    pub fn new(g: &'g Graph, inputs: Vec<String>) -> Self {
        Emitter {
            g,
            inputs,
            done: vec![false; g.nodes.len()],
            code: String::new(),
        }
    }

    /// The expression naming a node's value.
    pub fn name(&self, s: Sym) -> String {
        match self.g.nodes[s.0 as usize] {
            Node::Const(b) => fmt_f64(f64::from_bits(b)),
            Node::Input(k) => self.inputs[k as usize].clone(),
            _ => format!("v{}", s.0),
        }
    }

    /// Emit `let` statements for everything `outputs` depend on.
    pub fn need(&mut self, outputs: &[Sym]) {
        let live = self.g.live(outputs);
        for (i, &l) in live.iter().enumerate() {
            if !l || self.done[i] {
                continue;
            }
            self.done[i] = true;
            let n = |k: u32| self.name(Sym(k));
            let rhs = match self.g.nodes[i] {
                Node::Const(_) | Node::Input(_) => continue,
                Node::Add(a, b) => format!("{} + {}", n(a), n(b)),
                Node::Sub(a, b) => format!("{} - {}", n(a), n(b)),
                Node::Mul(a, b) => format!("{} * {}", n(a), n(b)),
                Node::Div(a, b) => format!("{} / {}", n(a), n(b)),
                Node::Neg(a) => format!("-{}", n(a)),
                Node::Sqrt(a) => format!("{}.sqrt()", n(a)),
                Node::Atan(a) => format!("{}.atan()", n(a)),
                Node::Sin(a) => format!("{}.sin()", n(a)),
                Node::Cos(a) => format!("{}.cos()", n(a)),
            };
            let _ = writeln!(self.code, "let v{i}: f64 = {rhs};");
        }
    }

    /// `target = output;` lines (after `need`).
    pub fn assign(&mut self, target: impl Fn(usize) -> String, outputs: &[Sym]) {
        self.need(outputs);
        for (k, s) in outputs.iter().enumerate() {
            let rhs = self.name(*s);
            let _ = writeln!(self.code, "{} = {rhs};", target(k));
        }
    }

    pub fn take(&mut self) -> String {
        std::mem::take(&mut self.code)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_round_trip() {
        for v in [0.1, -2.5e-7, 1e300, 4000.0, -0.0] {
            let s = fmt_f64(v).replace("f64", "").replace(['(', ')'], "");
            assert_eq!(s.parse::<f64>().unwrap(), v);
        }
    }
}
