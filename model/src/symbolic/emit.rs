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
///
/// Values are grouped by topological level, one `let` of a fixed-size array per level: every
/// `let` opens a nested lexical scope, and thousands of them overflow the debug-info builder's
/// recursion (rustc crashed in LLVM's DWARF emission). Nesting now equals the graph's depth.
pub struct Emitter<'g> {
    g: &'g Graph,
    inputs: Vec<String>,
    /// Where an emitted node lives: (group, index).
    loc: Vec<Option<(u32, u32)>>,
    level: Vec<u32>,
    groups: u32,
    /// Tables whose `static` has been written.
    tables: Vec<bool>,
    /// Prefix of every name this emitter declares, so two graphs can share one function.
    prefix: String,
    pub code: String,
}

impl<'g> Emitter<'g> {
    /// `inputs[k]` is the Rust expression of input k.
    pub fn new(g: &'g Graph, inputs: Vec<String>) -> Self {
        let mut level = vec![0u32; g.nodes.len()];
        for (i, n) in g.nodes.iter().enumerate() {
            level[i] = match n {
                Node::Const(_) | Node::Input(_) | Node::Param(_) => 0,
                // A pick is a name for an entry of its MatVec's array, not a statement.
                Node::Pick(m, _) => level[*m as usize],
                n => {
                    1 + g
                        .operands(*n)
                        .iter()
                        .map(|&o| level[o as usize])
                        .max()
                        .unwrap_or(0)
                }
            };
        }
        Emitter {
            g,
            inputs,
            loc: vec![None; g.nodes.len()],
            level,
            groups: 0,
            tables: vec![false; g.tables.len()],
            prefix: String::new(),
            code: String::new(),
        }
    }

    /// As `new`, declaring names that start with `prefix`.
    pub fn with_prefix(g: &'g Graph, inputs: Vec<String>, prefix: &str) -> Self {
        let mut e = Self::new(g, inputs);
        e.prefix = prefix.to_string();
        e
    }

    /// The expression naming a node's value.
    pub fn name(&self, s: Sym) -> String {
        match self.g.nodes[s.0 as usize] {
            Node::Const(b) => fmt_f64(f64::from_bits(b)),
            Node::Input(k) => self.inputs[k as usize].clone(),
            Node::Param(k) => format!("p[{k}]"),
            Node::Pick(m, k) => format!("{}mv{m}[{k}]", self.prefix),
            _ => {
                let (g, i) = self.loc[s.0 as usize].expect("operand emitted before use");
                format!("{}g{g}[{i}]", self.prefix)
            }
        }
    }

    fn expr(&self, i: usize) -> String {
        let n = |k: u32| self.name(Sym(k));
        match self.g.nodes[i] {
            Node::Const(_) | Node::Input(_) | Node::Param(_) => self.name(Sym(i as u32)),
            Node::Add(a, b) => format!("{} + {}", n(a), n(b)),
            Node::Sub(a, b) => format!("{} - {}", n(a), n(b)),
            Node::Mul(a, b) => format!("{} * {}", n(a), n(b)),
            Node::Div(a, b) => format!("{} / {}", n(a), n(b)),
            Node::Neg(a) => format!("-{}", n(a)),
            Node::Sqrt(a) => format!("{}.sqrt()", n(a)),
            Node::Atan(a) => format!("{}.atan()", n(a)),
            Node::Sin(a) => format!("{}.sin()", n(a)),
            Node::Cos(a) => format!("{}.cos()", n(a)),
            Node::Max(a, b) => format!("f64::max({}, {})", n(a), n(b)),
            Node::Ge(a, b) => format!("f64::from(u8::from({} >= {}))", n(a), n(b)),
            Node::Powf(a, b) => format!("{}.powf({})", n(a), n(b)),
            Node::MatVec { .. } | Node::Pick(..) => unreachable!("emitted by `mat_vec`"),
        }
    }

    /// `let mut mv<i> = y; mat_vec(&T<table>, &x, &mut mv<i>);`, with the table's `static`
    /// before its first use. When y is exactly another MatVec's result, that array is copied.
    fn mat_vec(&mut self, i: usize) {
        let Node::MatVec { table, x, y } = self.g.nodes[i] else {
            unreachable!("a MatVec node")
        };
        let (xs, ys) = (&self.g.lists[x as usize], &self.g.lists[y as usize]);
        let (r, c) = (ys.len(), xs.len());
        if !self.tables[table as usize] {
            self.tables[table as usize] = true;
            let t = &self.g.tables[table as usize];
            let cols: Vec<String> = t
                .chunks_exact(r)
                .map(|col| {
                    let v: Vec<String> = col.iter().map(|v| fmt_f64(*v)).collect();
                    format!("[{}]", v.join(", "))
                })
                .collect();
            let _ = writeln!(
                self.code,
                "static T{p}{table}: [[f64; {r}]; {c}] = [{}];",
                cols.join(", "),
                p = self.prefix.to_uppercase()
            );
        }
        let whole = self.pick(ys[0]).and_then(|(m, _)| {
            let Node::MatVec { y: my, .. } = self.g.nodes[m as usize] else {
                unreachable!("a pick reads a MatVec")
            };
            let same = self.g.lists[my as usize].len() == r
                && ys
                    .iter()
                    .enumerate()
                    .all(|(k, &s)| self.pick(s) == Some((m, k)));
            same.then(|| format!("{}mv{m}", self.prefix))
        });
        let init = whole.unwrap_or_else(|| {
            let v: Vec<String> = ys.iter().map(|&s| self.name(Sym(s))).collect();
            format!("[{}]", v.join(", "))
        });
        let xv: Vec<String> = xs.iter().map(|&s| self.name(Sym(s))).collect();
        let _ = writeln!(
            self.code,
            "let mut {p}mv{i}: [f64; {r}] = {init};\n::washdyn_runtime::model::linalg::mat_vec(&T{pu}{table}, &[{}], &mut {p}mv{i});",
            xv.join(", "),
            p = self.prefix,
            pu = self.prefix.to_uppercase()
        );
    }

    /// Emit the statements everything `outputs` depend on.
    pub fn need(&mut self, outputs: &[Sym]) {
        let live = self.g.live(outputs);
        let mut by_level: Vec<Vec<usize>> = Vec::new();
        for (i, &l) in live.iter().enumerate() {
            let op = !matches!(
                self.g.nodes[i],
                Node::Const(_) | Node::Input(_) | Node::Param(_) | Node::Pick(..)
            );
            if l && op && self.loc[i].is_none() {
                let lv = self.level[i] as usize;
                if by_level.len() <= lv {
                    by_level.resize(lv + 1, Vec::new());
                }
                by_level[lv].push(i);
            }
        }
        for all in by_level.into_iter().filter(|v| !v.is_empty()) {
            let (mvs, nodes): (Vec<usize>, Vec<usize>) = all
                .into_iter()
                .partition(|&i| matches!(self.g.nodes[i], Node::MatVec { .. }));
            for &i in &mvs {
                self.mat_vec(i);
                self.loc[i] = Some((u32::MAX, 0));
            }
            if nodes.is_empty() {
                continue;
            }
            let gid = self.groups;
            self.groups += 1;
            let exprs: Vec<String> = nodes.iter().map(|&i| self.expr(i)).collect();
            let _ = writeln!(
                self.code,
                "let {}g{gid}: [f64; {}] = [{}];",
                self.prefix,
                nodes.len(),
                exprs.join(", ")
            );
            for (k, &i) in nodes.iter().enumerate() {
                self.loc[i] = Some((gid, k as u32));
            }
        }
    }

    /// The MatVec and row a pick reads.
    fn pick(&self, s: u32) -> Option<(u32, usize)> {
        match self.g.nodes[s as usize] {
            Node::Pick(m, i) => Some((m, i as usize)),
            _ => None,
        }
    }

    /// `target[k] = output;` lines (after `need`), with each run of outputs that are
    /// consecutive entries of one MatVec's result copied as a slice (a whole matrix from a
    /// table is one line, not one per entry).
    pub fn assign(&mut self, target: &str, outputs: &[Sym]) {
        self.need(outputs);
        let mut k = 0;
        while k < outputs.len() {
            let Some((m, i0)) = self.pick(outputs[k].0) else {
                let rhs = self.name(outputs[k]);
                let _ = writeln!(self.code, "{target}[{k}] = {rhs};");
                k += 1;
                continue;
            };
            let mut len = 1;
            while k + len < outputs.len() && self.pick(outputs[k + len].0) == Some((m, i0 + len)) {
                len += 1;
            }
            let _ = writeln!(
                self.code,
                "{target}[{k}..{}].copy_from_slice(&{}mv{m}[{i0}..{}]);",
                k + len,
                self.prefix,
                i0 + len
            );
            k += len;
        }
    }

    /// As `assign`, but only the outputs that are not the constant 0 (the target is zeroed
    /// before): sparse Jacobians stay small.
    pub fn assign_sparse(&mut self, target: impl Fn(usize) -> String, outputs: &[Sym]) {
        let keep: Vec<(usize, Sym)> = outputs
            .iter()
            .copied()
            .enumerate()
            .filter(|(_, s)| self.g.constant(s.0) != Some(0.0))
            .collect();
        let syms: Vec<Sym> = keep.iter().map(|(_, s)| *s).collect();
        self.need(&syms);
        for (k, s) in keep {
            let rhs = self.name(s);
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
