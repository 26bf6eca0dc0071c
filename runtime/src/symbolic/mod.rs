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
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    Sqrt(u32),
    Atan(u32),
    Sin(u32),
    Cos(u32),
}

/// The recorded graph.
#[derive(Clone, Debug, Default)]
pub struct Graph {
    pub nodes: Vec<Node>,
    map: HashMap<Node, u32>,
    pub n_inputs: u32,
}

thread_local! {
    static GRAPH: RefCell<Option<Graph>> = const { RefCell::new(None) };
}

/// Run `f` with a fresh graph and return its result together with the graph.
pub fn trace<R>(f: impl FnOnce() -> R) -> (R, Graph) {
    GRAPH.with(|g| {
        let prev = g.borrow_mut().replace(Graph::default());
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
        let v = if v == 0.0 { 0.0 } else { v };
        self.intern(Node::Const(v.to_bits()))
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
            Input(_) => self.intern(n),
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
        }
    }

    /// Evaluate the nodes needed for `outputs` at numeric inputs (tests the graph without
    /// compiling generated code).
    pub fn eval(&self, inputs: &[f64], outputs: &[Sym]) -> Vec<f64> {
        let mut v = vec![0.0; self.nodes.len()];
        let hi = outputs.iter().map(|s| s.0 as usize + 1).max().unwrap_or(0);
        for i in 0..hi {
            v[i] = match self.nodes[i] {
                Node::Const(b) => f64::from_bits(b),
                Node::Input(k) => inputs[k as usize],
                Node::Add(a, b) => v[a as usize] + v[b as usize],
                Node::Sub(a, b) => v[a as usize] - v[b as usize],
                Node::Mul(a, b) => v[a as usize] * v[b as usize],
                Node::Div(a, b) => v[a as usize] / v[b as usize],
                Node::Neg(a) => -v[a as usize],
                Node::Sqrt(a) => v[a as usize].sqrt(),
                Node::Atan(a) => v[a as usize].atan(),
                Node::Sin(a) => v[a as usize].sin(),
                Node::Cos(a) => v[a as usize].cos(),
            };
        }
        outputs.iter().map(|s| v[s.0 as usize]).collect()
    }

    /// Operation count of the nodes reachable from `outputs` (constants and inputs excluded).
    pub fn op_count(&self, outputs: &[Sym]) -> usize {
        let live = self.live(outputs);
        live.iter()
            .enumerate()
            .filter(|&(i, &l)| l && !matches!(self.nodes[i], Node::Const(_) | Node::Input(_)))
            .count()
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
            for o in operands(self.nodes[i]) {
                live[o as usize] = true;
            }
        }
        live
    }
}

/// Operand indices of a node.
pub fn operands(n: Node) -> impl Iterator<Item = u32> {
    use Node::*;
    let (a, b) = match n {
        Const(_) | Input(_) => (None, None),
        Add(a, b) | Sub(a, b) | Mul(a, b) | Div(a, b) => (Some(a), Some(b)),
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folding_and_sharing() {
        let ((a, b, z, s), g) = trace(|| {
            let x = Sym::input();
            let y = Sym::input();
            let a = x * y + Sym::c(2.0) * Sym::c(3.0);
            let b = y * x + 6.0; // same node as a: commutative ordering + folding
            let z = x * 0.0 + y * 1.0 - y; // zero
            let s = (x - x).sqrt();
            (a, b, z, s)
        });
        assert_eq!(a, b);
        assert_eq!(g.constant(z.0), Some(0.0));
        assert_eq!(g.constant(s.0), Some(0.0));
        assert_eq!(g.eval(&[2.0, 5.0], &[a]), vec![16.0]);
    }
}
