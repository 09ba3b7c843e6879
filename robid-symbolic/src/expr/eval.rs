//! Numeric evaluation of expressions.

use super::{Arena, Id, Node, Symbol};

/// Values of symbols, for [`Arena::eval`].
#[derive(Clone, Debug, Default)]
pub struct Values {
    by_symbol: Vec<Option<f64>>,
}

impl Values {
    /// No symbol bound.
    pub fn new() -> Values {
        Values::default()
    }

    /// Binds a symbol.
    pub fn set(&mut self, symbol: Symbol, value: f64) {
        if self.by_symbol.len() <= symbol.index() {
            self.by_symbol.resize(symbol.index() + 1, None);
        }
        self.by_symbol[symbol.index()] = Some(value);
    }

    /// The value of a symbol, if bound.
    pub fn get(&self, symbol: Symbol) -> Option<f64> {
        self.by_symbol.get(symbol.index()).copied().flatten()
    }
}

/// A symbol had no value.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("symbol `{0}` has no value; bind it before evaluating")]
pub struct Unbound(pub String);

impl Arena {
    /// Evaluates several expressions at once (each shared node once).
    pub fn eval(&self, roots: &[Id], values: &Values) -> Result<Vec<f64>, Unbound> {
        let mut at = self.eval_points(roots, std::slice::from_ref(values))?;
        Ok(at.pop().expect("one point"))
    }

    /// [`Arena::eval`] at several points (`out[p]` holds the roots' values at
    /// `points[p]`), finding the nodes to evaluate once for all of them.
    ///
    /// The cost grows with the nodes reached, not with the arena: the values of a small
    /// expression in a large arena are kept by its nodes' positions among those reached.
    pub fn eval_points(&self, roots: &[Id], points: &[Values]) -> Result<Vec<Vec<f64>>, Unbound> {
        let order = self.reachable_sorted(roots);
        // by id when much of the arena is reached (direct), else by position in `order`
        let dense = order.len() * 16 >= self.nodes.len();
        let slot = |id: Id| {
            if dense {
                id.index()
            } else {
                order.binary_search(&id).expect("a child of a reached node")
            }
        };
        let mut v = vec![0.0_f64; if dense { self.nodes.len() } else { order.len() }];
        let mut out = Vec::with_capacity(points.len());
        for values in points {
            for &id in &order {
                let x = |c: &Id| v[slot(*c)];
                let value = match &self.nodes[id.index()] {
                    Node::Num(c) => c.to_f64(),
                    Node::Pi => std::f64::consts::PI,
                    Node::Sym(s) => values
                        .get(*s)
                        .ok_or_else(|| Unbound(self.symbol_name(*s).to_owned()))?,
                    Node::Add(t) => t.iter().map(x).sum(),
                    Node::Mul(f) => f.iter().map(x).product(),
                    Node::Pow(b, n) => x(b).powi(*n),
                    Node::Sin(a) => x(a).sin(),
                    Node::Cos(a) => x(a).cos(),
                    Node::Sign(a) => {
                        let s = x(a);
                        if s > 0.0 {
                            1.0
                        } else if s < 0.0 {
                            -1.0
                        } else {
                            0.0
                        }
                    }
                    Node::Sqrt(a) => x(a).sqrt(),
                };
                v[slot(id)] = value;
            }
            out.push(roots.iter().map(|r| v[slot(*r)]).collect());
        }
        Ok(out)
    }

    /// Values for symbols given by name (names not yet in the arena are created).
    pub fn values(&mut self, pairs: &[(&str, f64)]) -> Values {
        let mut values = Values::new();
        for &(name, value) in pairs {
            let s = self.symbol(name);
            values.set(s, value);
        }
        values
    }
}

#[cfg(test)]
mod tests {
    use super::Unbound;
    use crate::expr::Arena;

    /// Evaluating at several points gives what evaluating at each does, and the values
    /// of the expressions read alone, for expressions that reach few of the arena's nodes
    /// (kept by position) and most of them (by id); an unbound symbol is named.
    #[test]
    fn several_points_give_what_each_point_gives() {
        let mut a = Arena::new();
        let mut many = Vec::new();
        for k in 0..500 {
            many.push(
                a.parse(&format!("sin({k}*q) * cos(p) + {k}^2 * q"))
                    .unwrap(),
            );
        }
        let small = a.parse("sqrt(q^2 + 1) * sign(p) - q/3").unwrap();
        let points: Vec<_> = [(0.3, -1.5), (-2.0, 0.25), (1e-3, 0.0)]
            .iter()
            .map(|&(q, p)| a.values(&[("q", q), ("p", p)]))
            .collect();
        let mut all = many.clone();
        all.push(small);
        for roots in [vec![small], all] {
            let together = a.eval_points(&roots, &points).unwrap();
            assert_eq!(together.len(), points.len());
            for (values, got) in points.iter().zip(&together) {
                let expected: Vec<f64> = roots
                    .iter()
                    .map(|&r| {
                        let s = a.display(r);
                        let mut alone = Arena::new();
                        let e = alone.parse(&s).unwrap();
                        let q = alone.symbol("q");
                        let p = alone.symbol("p");
                        let mut v = super::Values::new();
                        v.set(q, values.get(a.find_symbol("q").unwrap()).unwrap());
                        v.set(p, values.get(a.find_symbol("p").unwrap()).unwrap());
                        alone.eval(&[e], &v).unwrap()[0]
                    })
                    .collect();
                // the same expression read again may order its terms otherwise
                for (g, e) in got.iter().zip(&expected) {
                    assert!((g - e).abs() <= 1e-12 * e.abs().max(1.0), "{g} against {e}");
                }
                assert_eq!(a.eval(&roots, values).unwrap(), *got);
            }
        }
        let only_q = a.values(&[("q", 1.0)]);
        assert_eq!(
            a.eval_points(&[small], &[points[0].clone(), only_q]),
            Err(Unbound("p".to_owned()))
        );
    }
}
