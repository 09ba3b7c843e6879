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
        let seen = self.reachable(roots);
        let mut v = vec![0.0_f64; seen.len()];
        for index in (0..seen.len()).filter(|&i| seen[i]) {
            let x = |id: &Id| v[id.index()];
            v[index] = match &self.nodes[index] {
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
        }
        Ok(roots.iter().map(|r| v[r.index()]).collect())
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
