//! Symbolic differentiation (the Lagrangian form needs dL/dqd, d/dq, d/dqd).

use super::{Arena, Id, Node, Num, Symbol};

impl Arena {
    /// d(root)/d(symbol).
    pub fn diff(&mut self, root: Id, symbol: Symbol) -> Id {
        self.diff_all(&[root], symbol)[0]
    }

    /// The derivatives of several roots with respect to one symbol, sharing work.
    ///
    /// Only the nodes reachable from `roots` are visited, children first, so the cost
    /// grows with the expressions, not with the arena: the regrouping takes thousands of
    /// derivatives of small expressions in an arena of a whole derivation.
    pub fn diff_all(&mut self, roots: &[Id], symbol: Symbol) -> Vec<Id> {
        let order = self.reachable_sorted(roots);
        let zero = self.zero();
        // d[k]: the derivative of node order[k]
        let mut d: Vec<Id> = vec![zero; order.len()];
        let at = |id: Id| order.binary_search(&id).expect("a child of a reached node");
        for (k, &id) in order.iter().enumerate() {
            let node = self.nodes[id.index()].clone();
            let derivative = |c: &Id| d[at(*c)];
            let children_zero = node.children().iter().all(|c| derivative(c) == zero);
            if children_zero && !matches!(node, Node::Sym(_)) {
                continue;
            }
            let d_of: Vec<Id> = node.children().iter().map(derivative).collect();
            let d_x = d_of.first().copied().unwrap_or(zero);
            d[k] = match node {
                Node::Num(_) | Node::Pi | Node::Sign(_) => zero,
                Node::Sym(s) => {
                    if s == symbol {
                        self.one()
                    } else {
                        zero
                    }
                }
                Node::Add(_) => self.add(&d_of),
                Node::Mul(factors) => {
                    let mut sum = Vec::new();
                    for (i, &df) in d_of.iter().enumerate() {
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
                    self.mul(&[c, power, d_x])
                }
                Node::Sin(x) => {
                    let c = self.cos(x);
                    self.mul2(c, d_x)
                }
                Node::Cos(x) => {
                    let s = self.sin(x);
                    let ds = self.mul2(s, d_x);
                    self.neg(ds)
                }
                Node::Sqrt(x) => {
                    let root = self.intern(Node::Sqrt(x));
                    let inv = self.pow(root, -1);
                    let half = self.num(Num::ratio(1, 2).expect("nonzero"));
                    self.mul(&[half, inv, d_x])
                }
            };
        }
        roots.iter().map(|r| d[at(*r)]).collect()
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

    /// A derivative taken in a large arena (the walk visits only the expression's nodes)
    /// equals the one taken in an arena of its own, and several roots share one walk.
    #[test]
    fn derivatives_in_a_large_arena_are_those_of_a_small_one() {
        let mut big = Arena::new();
        // unrelated nodes before and between the expressions: thousands of ids
        for k in 0..3000 {
            big.parse(&format!("sin(x{k}) * q + {k}")).unwrap();
        }
        let texts = [
            "L*cos(q)*sin(q)^3 + q^2",
            "sqrt(1 + q^2) - cos(2*q)",
            "x7 * q",
        ];
        let roots: Vec<_> = texts.iter().map(|t| big.parse(t).unwrap()).collect();
        for k in 3000..3100 {
            big.parse(&format!("cos(y{k}) + q")).unwrap();
        }
        let q = big.symbol("q");
        let together = big.diff_all(&roots, q);
        for (text, d) in texts.iter().zip(together) {
            let mut small = Arena::new();
            let e = small.parse(text).unwrap();
            let q = small.symbol("q");
            let expected = small.diff(e, q);
            // the same expression, its terms maybe in another order (they follow ids)
            let expected = big.parse(&small.display(expected)).unwrap();
            let difference = big.sub(d, expected);
            assert!(big.is_zero(difference), "d/dq {text}: {}", big.display(d));
        }
    }
}
