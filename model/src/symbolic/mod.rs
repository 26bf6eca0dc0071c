//! A symbolic scalar that records an expression graph as the one derivation runs over it (the
//! tracing technique of CasADi/JAX, and of Pinocchio's code generation). Nodes are hash-consed,
//! so a repeated subexpression is one node (common subexpression elimination for free);
//! constructors fold constants and prune zeros and ones, so structure known at compile time
//! (zero couplings, unit factors) costs nothing in the generated code.
//!
//! The graph lives in a thread-local arena for the duration of `trace`; `Sym` is a Copy handle.

mod diff;
mod emit;

pub use diff::derivative;
pub use emit::{Emitter, fmt_f64};

use crate::scalar::Scalar;
use std::cell::RefCell;
use std::collections::HashMap;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// One operation. Operands are node indices, always smaller than the node's own index, so the
/// node list is a topological order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// f64 bits; -0.0 is stored as 0.0.
    Const(u64),
    /// The i-th input.
    Input(u32),
    /// The i-th free parameter (`Model::free`): a number the generated code reads from its
    /// parameter array `p` instead of a literal. Structurally it is a constant (its derivative
    /// is 0), but it is never folded.
    Param(u32),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    Sqrt(u32),
    Atan(u32),
    Sin(u32),
    Cos(u32),
    /// f64::max(a, b).
    Max(u32, u32),
    /// 1 where a >= b, else 0: the derivative of `Max` picks its operand's with it.
    Ge(u32, u32),
    /// a.powf(b), b a constant (the exponent).
    Powf(u32, u32),
    /// y + A x for the constant table `table` (column-major, `Graph::tables`); `x` and `y` are
    /// operand lists (`Graph::lists`). Its value is a vector, read through `Pick`.
    MatVec {
        table: u32,
        x: u32,
        y: u32,
    },
    /// Entry i of a `MatVec`'s result.
    Pick(u32, u32),
}

/// The recorded graph.
#[derive(Clone, Debug, Default)]
pub struct Graph {
    pub nodes: Vec<Node>,
    map: HashMap<Node, u32>,
    pub n_inputs: u32,
    /// Constant tables of `MatVec` nodes (column-major), interned by their bits.
    pub tables: Vec<Vec<f64>>,
    table_map: HashMap<Vec<u64>, u32>,
    /// Operand lists of `MatVec` nodes, interned.
    pub lists: Vec<Vec<u32>>,
    list_map: HashMap<Vec<u32>, u32>,
    /// Bits of the stand-in values of the free parameters -> parameter index: a constant with
    /// these bits becomes that `Param` as the derivation hands it over.
    sentinels: HashMap<u64, u32>,
}

thread_local! {
    static GRAPH: RefCell<Option<Graph>> = const { RefCell::new(None) };
}

/// Run `f` with a fresh graph and return its result together with the graph.
pub fn trace<R>(f: impl FnOnce() -> R) -> (R, Graph) {
    trace_params(&[], f)
}

/// As [`trace`], where a constant with the bits of `sentinels[i]` is free parameter i: the
/// model's free numbers are replaced by these stand-ins before the derivation runs, and each
/// reaches the graph as a `Param` when the derivation uses it unchanged. One it changed first
/// (a precomputed product, say) arrives as some other constant; the code generator's check
/// against the derivation at other parameter values catches that.
pub fn trace_params<R>(sentinels: &[f64], f: impl FnOnce() -> R) -> (R, Graph) {
    let fresh = Graph {
        sentinels: sentinels
            .iter()
            .enumerate()
            .map(|(i, v)| (v.to_bits(), i as u32))
            .collect(),
        ..Graph::default()
    };
    GRAPH.with(|g| {
        let prev = g.borrow_mut().replace(fresh);
        assert!(prev.is_none(), "nested symbolic traces are not supported");
    });
    let r = f();
    let graph = GRAPH.with(|g| g.borrow_mut().take().expect("graph present"));
    (r, graph)
}

fn with<R>(f: impl FnOnce(&mut Graph) -> R) -> R {
    GRAPH.with(|g| {
        f(g.borrow_mut()
            .as_mut()
            .expect("Sym used outside symbolic::trace"))
    })
}

/// A handle to a node of the current graph.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Sym(pub u32);

impl Sym {
    /// A new input variable.
    pub fn input() -> Sym {
        with(|g| {
            let i = g.n_inputs;
            g.n_inputs += 1;
            Sym(g.intern(Node::Input(i)))
        })
    }

    /// The constant value of this node, if it is one.
    pub fn as_const(self) -> Option<f64> {
        with(|g| g.constant(self.0))
    }

    fn mk(n: Node) -> Sym {
        with(|g| Sym(g.make(n)))
    }
}

impl Graph {
    fn intern(&mut self, n: Node) -> u32 {
        if let Some(&i) = self.map.get(&n) {
            return i;
        }
        let i = self.nodes.len() as u32;
        self.nodes.push(n);
        self.map.insert(n, i);
        i
    }

    pub fn constant(&self, i: u32) -> Option<f64> {
        match self.nodes[i as usize] {
            Node::Const(b) => Some(f64::from_bits(b)),
            _ => None,
        }
    }

    fn konst(&mut self, v: f64) -> u32 {
        if let Some(&i) = self.sentinels.get(&v.to_bits()) {
            return self.intern(Node::Param(i));
        }
        let v = if v == 0.0 { 0.0 } else { v };
        self.intern(Node::Const(v.to_bits()))
    }

    /// The free parameters the outputs depend on.
    pub fn params_used(&self, outputs: &[Sym]) -> Vec<u32> {
        let live = self.live(outputs);
        let mut out: Vec<u32> = (0..self.nodes.len())
            .filter(|&i| live[i])
            .filter_map(|i| match self.nodes[i] {
                Node::Param(k) => Some(k),
                _ => None,
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The free parameters whose stand-in sits in a constant table (a modal map): folded into
    /// the table, the generated code could not take them.
    pub fn params_in_tables(&self) -> Vec<u32> {
        let mut out: Vec<u32> = self
            .tables
            .iter()
            .flatten()
            .filter_map(|v| self.sentinels.get(&v.to_bits()).copied())
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    // Guards on float values read as the algebra they implement.
    #[allow(clippy::redundant_guards)]
    /// Build a node with folding: constants evaluate, x+0, x*1, x*0, 0/x, --x and x-x simplify,
    /// commutative operands are ordered so a+b and b+a are one node.
    pub fn make(&mut self, n: Node) -> u32 {
        use Node::*;
        let c = |g: &Self, i: u32| g.constant(i);
        match n {
            Const(b) => self.konst(f64::from_bits(b)),
            Input(_) | Param(_) => self.intern(n),
            Add(a, b) => match (c(self, a), c(self, b)) {
                (Some(x), Some(y)) => self.konst(x + y),
                (Some(x), _) if x == 0.0 => b,
                (_, Some(y)) if y == 0.0 => a,
                _ => self.intern(Add(a.min(b), a.max(b))),
            },
            Sub(a, b) => match (c(self, a), c(self, b)) {
                (Some(x), Some(y)) => self.konst(x - y),
                (_, Some(y)) if y == 0.0 => a,
                (Some(x), _) if x == 0.0 => self.make(Neg(b)),
                _ if a == b => self.konst(0.0),
                _ => self.intern(n),
            },
            Mul(a, b) => match (c(self, a), c(self, b)) {
                (Some(x), Some(y)) => self.konst(x * y),
                (Some(x), _) | (_, Some(x)) if x == 0.0 => self.konst(0.0),
                (Some(x), _) if x == 1.0 => b,
                (_, Some(y)) if y == 1.0 => a,
                (Some(x), _) if x == -1.0 => self.make(Neg(b)),
                (_, Some(y)) if y == -1.0 => self.make(Neg(a)),
                _ => self.intern(Mul(a.min(b), a.max(b))),
            },
            Div(a, b) => match (c(self, a), c(self, b)) {
                (Some(x), Some(y)) => self.konst(x / y),
                (Some(x), _) if x == 0.0 => self.konst(0.0),
                (_, Some(y)) if y == 1.0 => a,
                (_, Some(y)) if y == -1.0 => self.make(Neg(a)),
                _ => self.intern(n),
            },
            Neg(a) => match (c(self, a), self.nodes[a as usize]) {
                (Some(x), _) => self.konst(-x),
                (_, Neg(inner)) => inner,
                _ => self.intern(n),
            },
            Sqrt(a) => match c(self, a) {
                Some(x) => self.konst(x.sqrt()),
                None => self.intern(n),
            },
            Atan(a) => match c(self, a) {
                Some(x) => self.konst(x.atan()),
                None => self.intern(n),
            },
            Sin(a) => match c(self, a) {
                Some(x) => self.konst(x.sin()),
                None => self.intern(n),
            },
            Cos(a) => match c(self, a) {
                Some(x) => self.konst(x.cos()),
                None => self.intern(n),
            },
            Max(a, b) => match (c(self, a), c(self, b)) {
                (Some(x), Some(y)) => self.konst(x.max(y)),
                _ if a == b => a,
                _ => self.intern(Max(a.min(b), a.max(b))),
            },
            Ge(a, b) => match (c(self, a), c(self, b)) {
                (Some(x), Some(y)) => self.konst(if x >= y { 1.0 } else { 0.0 }),
                _ if a == b => self.konst(1.0),
                _ => self.intern(n),
            },
            Powf(a, b) => match (c(self, a), c(self, b)) {
                (Some(x), Some(y)) => self.konst(x.powf(y)),
                (_, Some(y)) if y == 1.0 => a,
                (_, Some(y)) if y == 0.0 => self.konst(1.0),
                _ => self.intern(n),
            },
            MatVec { .. } | Pick(..) => self.intern(n),
        }
    }

    fn list(&mut self, l: Vec<u32>) -> u32 {
        if let Some(&i) = self.list_map.get(&l) {
            return i;
        }
        let i = self.lists.len() as u32;
        self.lists.push(l.clone());
        self.list_map.insert(l, i);
        i
    }

    fn table(&mut self, t: Vec<f64>) -> u32 {
        let key: Vec<u64> = t.iter().map(|v| v.to_bits()).collect();
        if let Some(&i) = self.table_map.get(&key) {
            return i;
        }
        let i = self.tables.len() as u32;
        self.tables.push(t);
        self.table_map.insert(key, i);
        i
    }

    /// The nodes of y + A x (A column-major, `y.len()` rows), folded: columns whose x is the
    /// constant 0 or whose entries are all 0 are dropped, and so are rows left all 0 (their
    /// result is y itself); a single column becomes scalar multiply-adds. What is left is one
    /// `MatVec` node over the remaining table and a `Pick` per row.
    pub fn mat_vec(&mut self, a: &[f64], x: &[u32], y: &[u32]) -> Vec<u32> {
        let r = y.len();
        assert_eq!(a.len(), r * x.len(), "table of y.len() x x.len()");
        let col = |j: usize| &a[j * r..(j + 1) * r];
        let cols: Vec<usize> = (0..x.len())
            .filter(|&j| self.constant(x[j]) != Some(0.0) && col(j).iter().any(|v| *v != 0.0))
            .collect();
        let rows: Vec<usize> = (0..r)
            .filter(|&i| cols.iter().any(|&j| col(j)[i] != 0.0))
            .collect();
        if cols.len() <= 1 {
            let mut out = y.to_vec();
            for &j in &cols {
                for &i in &rows {
                    let k = self.konst(col(j)[i]);
                    let p = self.make(Node::Mul(x[j], k));
                    out[i] = self.make(Node::Add(out[i], p));
                }
            }
            return out;
        }
        let table: Vec<f64> = cols
            .iter()
            .flat_map(|&j| rows.iter().map(move |&i| col(j)[i]))
            .collect();
        let node = Node::MatVec {
            table: self.table(table),
            x: self.list(cols.iter().map(|&j| x[j]).collect()),
            y: self.list(rows.iter().map(|&i| y[i]).collect()),
        };
        let id = self.intern(node);
        let mut out = y.to_vec();
        for (p, &i) in rows.iter().enumerate() {
            out[i] = self.intern(Node::Pick(id, p as u32));
        }
        out
    }

    /// Operands of node `n`: a `MatVec`'s lists, x then y.
    pub fn operands(&self, n: Node) -> Vec<u32> {
        match n {
            Node::MatVec { x, y, .. } => {
                let mut v = self.lists[x as usize].clone();
                v.extend(&self.lists[y as usize]);
                v
            }
            n => operands(n).collect(),
        }
    }

    /// Which nodes depend on an input in `inputs` (a forward pass: the dependency analysis that
    /// shows M1 free of q and q' without differentiating it).
    pub fn depends_on(&self, inputs: std::ops::Range<u32>) -> Vec<bool> {
        let mut dep = vec![false; self.nodes.len()];
        for i in 0..self.nodes.len() {
            dep[i] = match self.nodes[i] {
                Node::Input(k) => inputs.contains(&k),
                n => self.operands(n).iter().any(|&o| dep[o as usize]),
            };
        }
        dep
    }

    /// Evaluate the nodes needed for `outputs` at numeric inputs (tests the graph without
    /// compiling generated code).
    pub fn eval(&self, inputs: &[f64], outputs: &[Sym]) -> Vec<f64> {
        self.eval_params(inputs, &[], outputs)
    }

    /// [`Graph::eval`] with the free parameters' values.
    pub fn eval_params(&self, inputs: &[f64], params: &[f64], outputs: &[Sym]) -> Vec<f64> {
        let mut v = vec![0.0; self.nodes.len()];
        let mut vectors: HashMap<u32, Vec<f64>> = HashMap::new();
        let hi = outputs.iter().map(|s| s.0 as usize + 1).max().unwrap_or(0);
        for i in 0..hi {
            v[i] = match self.nodes[i] {
                Node::MatVec { table, x, y } => {
                    let vals = |l: u32| -> Vec<f64> {
                        self.lists[l as usize]
                            .iter()
                            .map(|&k| v[k as usize])
                            .collect()
                    };
                    let mut out = vals(y);
                    f64::mat_vec(&self.tables[table as usize], &vals(x), &mut out);
                    vectors.insert(i as u32, out);
                    0.0
                }
                Node::Pick(m, k) => vectors[&m][k as usize],
                Node::Const(b) => f64::from_bits(b),
                Node::Input(k) => inputs[k as usize],
                Node::Param(k) => params[k as usize],
                Node::Add(a, b) => v[a as usize] + v[b as usize],
                Node::Sub(a, b) => v[a as usize] - v[b as usize],
                Node::Mul(a, b) => v[a as usize] * v[b as usize],
                Node::Div(a, b) => v[a as usize] / v[b as usize],
                Node::Neg(a) => -v[a as usize],
                Node::Sqrt(a) => v[a as usize].sqrt(),
                Node::Atan(a) => v[a as usize].atan(),
                Node::Sin(a) => v[a as usize].sin(),
                Node::Cos(a) => v[a as usize].cos(),
                Node::Max(a, b) => v[a as usize].max(v[b as usize]),
                Node::Ge(a, b) => f64::from(u8::from(v[a as usize] >= v[b as usize])),
                Node::Powf(a, b) => v[a as usize].powf(v[b as usize]),
            };
        }
        outputs.iter().map(|s| v[s.0 as usize]).collect()
    }

    /// Operation count of the nodes reachable from `outputs` (constants, inputs and picks
    /// excluded; a `MatVec` counts its multiplies and adds).
    pub fn op_count(&self, outputs: &[Sym]) -> usize {
        let live = self.live(outputs);
        live.iter()
            .enumerate()
            .filter(|&(_, &l)| l)
            .map(|(i, _)| match self.nodes[i] {
                Node::Const(_) | Node::Input(_) | Node::Param(_) | Node::Pick(..) => 0,
                Node::MatVec { table, .. } => 2 * self.tables[table as usize].len(),
                _ => 1,
            })
            .sum()
    }

    /// Which nodes the outputs depend on.
    pub fn live(&self, outputs: &[Sym]) -> Vec<bool> {
        let mut live = vec![false; self.nodes.len()];
        for s in outputs {
            live[s.0 as usize] = true;
        }
        for i in (0..self.nodes.len()).rev() {
            if !live[i] {
                continue;
            }
            for o in self.operands(self.nodes[i]) {
                live[o as usize] = true;
            }
        }
        live
    }
}

/// Operand indices of a scalar node (a `MatVec`'s are in its lists: `Graph::operands`).
fn operands(n: Node) -> impl Iterator<Item = u32> {
    use Node::*;
    let (a, b) = match n {
        Const(_) | Input(_) | Param(_) | MatVec { .. } => (None, None),
        Pick(m, _) => (Some(m), None),
        Add(a, b) | Sub(a, b) | Mul(a, b) | Div(a, b) | Max(a, b) | Ge(a, b) | Powf(a, b) => {
            (Some(a), Some(b))
        }
        Neg(a) | Sqrt(a) | Atan(a) | Sin(a) | Cos(a) => (Some(a), None),
    };
    a.into_iter().chain(b)
}

macro_rules! binop {
    ($tr:ident, $m:ident, $node:ident, $atr:ident, $am:ident, $op:tt) => {
        impl $tr for Sym {
            type Output = Sym;
            fn $m(self, o: Sym) -> Sym {
                Sym::mk(Node::$node(self.0, o.0))
            }
        }
        impl $tr<f64> for Sym {
            type Output = Sym;
            fn $m(self, o: f64) -> Sym {
                self $op Sym::c(o)
            }
        }
        impl $atr for Sym {
            fn $am(&mut self, o: Sym) {
                *self = *self $op o;
            }
        }
    };
}
binop!(Add, add, Add, AddAssign, add_assign, +);
binop!(Sub, sub, Sub, SubAssign, sub_assign, -);
binop!(Mul, mul, Mul, MulAssign, mul_assign, *);
binop!(Div, div, Div, DivAssign, div_assign, /);

use std::ops::{DivAssign, MulAssign};

impl Neg for Sym {
    type Output = Sym;
    fn neg(self) -> Sym {
        Sym::mk(Node::Neg(self.0))
    }
}

impl Scalar for Sym {
    fn c(v: f64) -> Self {
        Sym::mk(Node::Const(v.to_bits()))
    }
    fn sqrt(self) -> Self {
        Sym::mk(Node::Sqrt(self.0))
    }
    fn atan(self) -> Self {
        Sym::mk(Node::Atan(self.0))
    }
    fn sin(self) -> Self {
        Sym::mk(Node::Sin(self.0))
    }
    fn cos(self) -> Self {
        Sym::mk(Node::Cos(self.0))
    }
    fn max(self, o: Self) -> Self {
        Sym::mk(Node::Max(self.0, o.0))
    }
    fn powf(self, e: f64) -> Self {
        Sym::mk(Node::Powf(self.0, Sym::c(e).0))
    }
    fn mat_vec(a: &[f64], x: &[Sym], y: &mut [Sym]) {
        let xs: Vec<u32> = x.iter().map(|s| s.0).collect();
        let ys: Vec<u32> = y.iter().map(|s| s.0).collect();
        let out = with(|g| g.mat_vec(a, &xs, &ys));
        for (yi, o) in y.iter_mut().zip(out) {
            *yi = Sym(o);
        }
    }
}

#[cfg(test)]
mod tests;
