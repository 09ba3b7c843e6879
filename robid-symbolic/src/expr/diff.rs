//! Symbolic differentiation (the Lagrangian form needs dL/dqd, d/dq, d/dqd).

use super::{Arena, Id, Node, Num, Symbol};

impl Arena {
    /// d(root)/d(symbol).
    pub fn diff(&mut self, root: Id, symbol: Symbol) -> Id {
        self.diff_all(&[root], symbol)[0]
    }

    /// The derivatives of several roots with respect to one symbol, sharing work.
    pub fn diff_all(&mut self, roots: &[Id], symbol: Symbol) -> Vec<Id> {
        let seen = self.reachable(roots);
        let zero = self.zero();
        let mut d: Vec<Id> = vec![zero; seen.len()];
        for index in (0..seen.len()).filter(|&i| seen[i]) {
            let node = self.nodes[index].clone();
            let children_zero = node.children().iter().all(|c| d[c.index()] == zero);
            if children_zero && !matches!(node, Node::Sym(_)) {
                continue;
            }
            d[index] = match node {
                Node::Num(_) | Node::Pi | Node::Sign(_) => zero,
                Node::Sym(s) => {
                    if s == symbol {
                        self.one()
                    } else {
                        zero
                    }
                }
                Node::Add(terms) => {
                    let dt: Vec<Id> = terms.iter().map(|t| d[t.index()]).collect();
                    self.add(&dt)
                }
                Node::Mul(factors) => {
                    let mut sum = Vec::new();
                    for (i, f) in factors.iter().enumerate() {
                        let df = d[f.index()];
                        if df == zero {
                            continue;
                        }
                        let mut product: Vec<Id> = factors.to_vec();
                        product[i] = df;
                        sum.push(self.mul(&product));
                    }
                    self.add(&sum)
                }
                Node::Pow(x, n) => {
                    let power = match n.checked_sub(1) {
                        Some(m) => self.pow(x, m),
                        None => {
                            let (p, inv) = (self.pow(x, n), self.pow(x, -1));
                            self.mul2(p, inv)
                        }
                    };
                    let c = self.num(Num::int(n as i64));
                    self.mul(&[c, power, d[x.index()]])
                }
                Node::Sin(x) => {
                    let c = self.cos(x);
                    self.mul2(c, d[x.index()])
                }
                Node::Cos(x) => {
                    let s = self.sin(x);
                    let ds = self.mul2(s, d[x.index()]);
                    self.neg(ds)
                }
                Node::Sqrt(x) => {
                    let root = self.intern(Node::Sqrt(x));
                    let inv = self.pow(root, -1);
                    let half = self.num(Num::ratio(1, 2).expect("nonzero"));
                    self.mul(&[half, inv, d[x.index()]])
                }
            };
        }
        roots.iter().map(|r| d[r.index()]).collect()
    }
}

#[cfg(test)]
mod tests {
    use crate::expr::Arena;

    #[test]
    fn derivatives_of_known_forms() {
        let mut a = Arena::new();
        let q = a.symbol("q");
        for (f, df) in [
            ("sin(q)^2", "2*sin(q)*cos(q)"),
            ("L*cos(q)", "-L*sin(q)"),
            ("q^3 + 2*q", "3*q^2 + 2"),
            ("sin(q)*cos(q)", "cos(q)^2 - sin(q)^2"),
            ("x", "0"),
        ] {
            let e = a.parse(f).unwrap();
            let expected = a.parse(df).unwrap();
            let got = a.diff(e, q);
            let (ge, gx) = (a.display(got), a.display(expected));
            let diff = a.sub(got, expected);
            assert!(a.is_zero(diff), "d/dq {f}: got {ge}, expected {gx}");
        }
    }
}
