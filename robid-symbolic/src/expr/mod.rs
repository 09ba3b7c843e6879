//! Expressions: a hash-consed DAG in one arena.
//!
//! Nodes live in a `Vec`, children before parents, and a memo (a hash table of ids,
//! hashed by their nodes, so each node is stored once) finds a node's `Id`, so equal
//! subexpressions are one node (egg's `language.rs` without the union-find). The smart constructors in `build.rs` run the simplification
//! passes of `simplify/` on every node they create; `intern` stores a node as is.
//!
//! Text is read by [`Arena::parse`] within documented limits
//! ([`MAX_EXPRESSION_LEN`], [`MAX_NESTING`], [`MAX_EXPONENT`]). Every walk
//! over the DAG (evaluation, differentiation, simplification, reachability) is
//! a loop over node ids, not a recursion; the text form (`display.rs`)
//! recurses once per level of the DAG, which user text cannot make deeper
//! than the nesting limit allows.

mod ast;
mod build;
mod diff;
mod display;
mod eval;
mod num;
mod parse;
pub mod simplify;

pub(crate) use ast::Ast;
pub use eval::{Unbound, Values};
pub use num::Num;
pub use parse::{MAX_EXPONENT, MAX_EXPRESSION_LEN, MAX_NESTING, ParseError};

use hashbrown::HashTable;
use rustc_hash::FxHashMap;
use std::hash::BuildHasher;

/// Index of a node in an [`Arena`]. Children always have smaller ids than parents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Id(u32);

impl Id {
    /// Position in the arena.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A named symbol (joint variable, geometric length, parameter).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Symbol(u32);

impl Symbol {
    /// Position in the arena's symbol table.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// One node of the DAG.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// A number.
    Num(Num),
    /// The constant pi (DH angles are kept as exact multiples of it).
    Pi,
    /// A named symbol.
    Sym(Symbol),
    /// Sum of two or more terms, in canonical order.
    Add(Box<[Id]>),
    /// Product of two or more factors; a numeric coefficient comes first.
    Mul(Box<[Id]>),
    /// Integer power.
    Pow(Id, i32),
    /// Sine.
    Sin(Id),
    /// Cosine.
    Cos(Id),
    /// Sign: -1, 0 or 1.
    Sign(Id),
    /// Square root.
    Sqrt(Id),
}

impl Node {
    /// The children of this node.
    pub fn children(&self) -> &[Id] {
        match self {
            Node::Num(_) | Node::Pi | Node::Sym(_) => &[],
            Node::Add(terms) | Node::Mul(terms) => terms,
            Node::Pow(x, _) | Node::Sin(x) | Node::Cos(x) | Node::Sign(x) | Node::Sqrt(x) => {
                std::slice::from_ref(x)
            }
        }
    }
}

/// The arena holding every expression of a derivation.
#[derive(Debug, Default, Clone)]
pub struct Arena {
    nodes: Vec<Node>,
    /// The ids of `nodes`, hashed by their node.
    memo: HashTable<Id>,
    symbols: Vec<String>,
    symbol_ids: FxHashMap<String, Symbol>,
}

/// The memo's hash of a node (Fx: nodes are small integers and slices of them).
fn node_hash(node: &Node) -> u64 {
    rustc_hash::FxBuildHasher.hash_one(node)
}

impl Arena {
    /// An empty arena.
    pub fn new() -> Arena {
        Arena::default()
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True when no node was created yet.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node behind an id.
    pub fn node(&self, id: Id) -> &Node {
        &self.nodes[id.index()]
    }

    /// The node at a position (ids are positions; see [`Arena::reachable`]).
    pub fn node_at(&self, index: usize) -> &Node {
        &self.nodes[index]
    }

    /// The id of the node at a position.
    pub fn id_at(&self, index: usize) -> Id {
        assert!(index < self.nodes.len(), "no node at {index}");
        Id(index as u32)
    }

    /// Stores a node as it is (no simplification) and returns its id.
    pub fn intern(&mut self, node: Node) -> Id {
        let hash = node_hash(&node);
        if let Some(id) = self.find(hash, &node) {
            return id;
        }
        debug_assert!(node.children().iter().all(|c| c.index() < self.nodes.len()));
        let id = Id(u32::try_from(self.nodes.len()).expect("arena exceeds 2^32 nodes"));
        self.nodes.push(node);
        let nodes = &self.nodes;
        self.memo
            .insert_unique(hash, id, |id| node_hash(&nodes[id.index()]));
        id
    }

    /// The id of a node if it already exists, without creating it.
    pub fn lookup(&self, node: &Node) -> Option<Id> {
        self.find(node_hash(node), node)
    }

    fn find(&self, hash: u64, node: &Node) -> Option<Id> {
        self.memo
            .find(hash, |id| self.nodes[id.index()] == *node)
            .copied()
    }

    /// The symbol with this name, created on first use.
    pub fn symbol(&mut self, name: &str) -> Symbol {
        if let Some(&s) = self.symbol_ids.get(name) {
            return s;
        }
        let s = Symbol(self.symbols.len() as u32);
        self.symbols.push(name.to_owned());
        self.symbol_ids.insert(name.to_owned(), s);
        s
    }

    /// The symbol with this name, if it exists.
    pub fn find_symbol(&self, name: &str) -> Option<Symbol> {
        self.symbol_ids.get(name).copied()
    }

    /// The name of a symbol.
    pub fn symbol_name(&self, symbol: Symbol) -> &str {
        &self.symbols[symbol.index()]
    }

    /// Number of symbols.
    pub fn symbol_count(&self) -> usize {
        self.symbols.len()
    }

    /// An expression for the symbol with this name.
    pub fn var(&mut self, name: &str) -> Id {
        let s = self.symbol(name);
        self.intern(Node::Sym(s))
    }

    /// A numeric constant.
    pub fn num(&mut self, value: Num) -> Id {
        self.intern(Node::Num(value))
    }

    /// The integer `n`.
    pub fn int(&mut self, n: i64) -> Id {
        self.num(Num::int(n))
    }

    /// Zero.
    pub fn zero(&mut self) -> Id {
        self.int(0)
    }

    /// One.
    pub fn one(&mut self) -> Id {
        self.int(1)
    }

    /// The number behind an id, when it is a constant.
    pub fn as_num(&self, id: Id) -> Option<Num> {
        match self.node(id) {
            Node::Num(n) => Some(*n),
            _ => None,
        }
    }

    /// True when the expression is the constant 0.
    pub fn is_zero(&self, id: Id) -> bool {
        self.as_num(id).is_some_and(Num::is_zero)
    }

    /// True when the expression is the constant 1.
    pub fn is_one(&self, id: Id) -> bool {
        self.as_num(id).is_some_and(Num::is_one)
    }

    /// Every node reachable from `roots`, as a mask indexed by node id.
    pub fn reachable(&self, roots: &[Id]) -> Vec<bool> {
        let mut seen = vec![false; self.nodes.len()];
        let mut stack: Vec<Id> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if !std::mem::replace(&mut seen[id.index()], true) {
                stack.extend_from_slice(self.node(id).children());
            }
        }
        seen
    }

    /// Every node reachable from `roots`, in increasing id order (children before
    /// parents). Its cost grows with the nodes reached, not with the arena: a walk over
    /// a small expression in a large arena (a coefficient of one base parameter among
    /// the whole derivation's nodes) stays small. The one pass over the arena is a scan
    /// of a bit set, 64 nodes a word.
    pub(crate) fn reachable_sorted(&self, roots: &[Id]) -> Vec<Id> {
        let mut seen = vec![0u64; self.nodes.len().div_ceil(64)];
        let mut count = 0;
        let mut stack: Vec<Id> = roots.to_vec();
        while let Some(id) = stack.pop() {
            let (word, bit) = (id.index() / 64, 1u64 << (id.index() % 64));
            if seen[word] & bit == 0 {
                seen[word] |= bit;
                count += 1;
                stack.extend_from_slice(self.node(id).children());
            }
        }
        let mut out = Vec::with_capacity(count);
        for (w, &bits) in seen.iter().enumerate().filter(|(_, b)| **b != 0) {
            let mut rest = bits;
            while rest != 0 {
                let index = w * 64 + rest.trailing_zeros() as usize;
                out.push(Id(
                    u32::try_from(index).expect("an arena holds fewer than 2^32 nodes")
                ));
                rest &= rest - 1;
            }
        }
        out
    }

    /// The symbols an expression depends on, in symbol order.
    pub fn free_symbols(&self, roots: &[Id]) -> Vec<Symbol> {
        let mut out: Vec<Symbol> = self
            .reachable_sorted(roots)
            .into_iter()
            .filter_map(|id| match self.nodes[id.index()] {
                Node::Sym(s) => Some(s),
                _ => None,
            })
            .collect();
        out.sort();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::Arena;

    /// The nodes reached, in increasing id order, are those of the mask, across many
    /// words of the bit set and with shared subexpressions counted once.
    #[test]
    fn the_nodes_reached_are_listed_in_id_order() {
        let mut a = Arena::new();
        let mut roots = Vec::new();
        for k in 0..400 {
            let e = a
                .parse(&format!("sin(q{}) * cos(q{}) + {k}", k % 7, k % 5))
                .unwrap();
            if k % 3 == 0 {
                roots.push(e);
            }
        }
        let mask = a.reachable(&roots);
        let listed: Vec<usize> = a
            .reachable_sorted(&roots)
            .iter()
            .map(|id| id.index())
            .collect();
        let expected: Vec<usize> = (0..a.len()).filter(|&i| mask[i]).collect();
        assert_eq!(listed, expected);
        assert!(a.reachable_sorted(&[]).is_empty());
    }
}
