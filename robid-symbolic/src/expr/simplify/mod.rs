//! Simplification passes. Each file is one rewrite that keeps the value; the
//! smart constructors (`build.rs`) run them on every node they create, and
//! [`Arena::simplify`] re-runs them over an expression that was built raw.

pub(crate) mod collect;
pub(crate) mod fold;
pub(crate) mod order;
pub(crate) mod pythagoras;
pub(crate) mod trig;

use super::{Arena, Id, Node};

impl Arena {
    /// Rebuilds `root` bottom-up through the smart constructors, applying every pass.
    pub fn simplify(&mut self, root: Id) -> Id {
        self.simplify_all(&[root])[0]
    }

    /// [`Arena::simplify`] for several roots sharing one memo.
    pub fn simplify_all(&mut self, roots: &[Id]) -> Vec<Id> {
        let seen = self.reachable(roots);
        let mut map: Vec<Option<Id>> = vec![None; seen.len()];
        for index in (0..seen.len()).filter(|&i| seen[i]) {
            let node = self.nodes[index].clone();
            let m = |id: &Id| map[id.index()].expect("children before parents");
            let new = match node {
                Node::Num(_) | Node::Pi | Node::Sym(_) => self.intern(node),
                Node::Add(t) => {
                    let t: Vec<Id> = t.iter().map(m).collect();
                    self.add(&t)
                }
                Node::Mul(f) => {
                    let f: Vec<Id> = f.iter().map(m).collect();
                    self.mul(&f)
                }
                Node::Pow(x, n) => self.pow(m(&x), n),
                Node::Sin(x) => self.sin(m(&x)),
                Node::Cos(x) => self.cos(m(&x)),
                Node::Sign(x) => self.sign(m(&x)),
                Node::Sqrt(x) => self.sqrt(m(&x)),
            };
            map[index] = Some(new);
        }
        roots
            .iter()
            .map(|r| map[r.index()].expect("root"))
            .collect()
    }
}
