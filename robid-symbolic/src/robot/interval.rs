//! Interval arithmetic: a bound on the magnitude of an expression when each
//! symbol lies in an interval (the regrouping samples geometric symbols in
//! [`SYMBOL_SAMPLES`](super::bounds::SYMBOL_SAMPLES)).

use crate::expr::{Arena, Id, Node, Symbol};

/// An upper bound of `|root|` over symbols in `range(symbol)`; infinite when
/// the expression can be (a division by an interval holding zero).
pub(super) fn magnitude_bound(arena: &Arena, root: Id, range: impl Fn(Symbol) -> [f64; 2]) -> f64 {
    let seen = arena.reachable(&[root]);
    let mut v = vec![[0.0_f64; 2]; seen.len()];
    let everything = [f64::NEG_INFINITY, f64::INFINITY];
    for index in (0..seen.len()).filter(|&i| seen[i]) {
        let x = |id: &Id| v[id.index()];
        v[index] = match arena.node_at(index) {
            Node::Num(c) => [c.to_f64(); 2],
            Node::Pi => [std::f64::consts::PI; 2],
            Node::Sym(s) => range(*s),
            Node::Add(t) => t
                .iter()
                .map(x)
                .fold([0.0, 0.0], |a, b| [a[0] + b[0], a[1] + b[1]]),
            Node::Mul(f) => f.iter().map(x).fold([1.0, 1.0], product),
            Node::Pow(b, n) => power(x(b), *n),
            Node::Sin(_) | Node::Cos(_) | Node::Sign(_) => [-1.0, 1.0],
            Node::Sqrt(a) => match x(a) {
                [_, hi] if hi < 0.0 => everything,
                [lo, hi] => [lo.max(0.0).sqrt(), hi.sqrt()],
            },
        };
        if v[index].iter().any(|b| b.is_nan()) {
            v[index] = everything;
        }
    }
    let [lo, hi] = v[root.index()];
    lo.abs().max(hi.abs())
}

fn product(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let p = [a[0] * b[0], a[0] * b[1], a[1] * b[0], a[1] * b[1]];
    if p.iter().any(|x| x.is_nan()) {
        return [f64::NEG_INFINITY, f64::INFINITY];
    }
    [
        p.iter().copied().fold(f64::INFINITY, f64::min),
        p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    ]
}

fn power([lo, hi]: [f64; 2], n: i32) -> [f64; 2] {
    if n < 0 {
        if lo <= 0.0 && hi >= 0.0 {
            return [f64::NEG_INFINITY, f64::INFINITY];
        }
        return power([1.0 / hi, 1.0 / lo], n.saturating_neg());
    }
    let (a, b) = (lo.powi(n), hi.powi(n));
    if n % 2 == 1 || lo >= 0.0 {
        [a.min(b), a.max(b)]
    } else if hi <= 0.0 {
        [b, a]
    } else {
        [0.0, a.max(b)]
    }
}

#[cfg(test)]
mod tests {
    use super::magnitude_bound;
    use crate::expr::Arena;

    fn bound(text: &str) -> f64 {
        let mut a = Arena::new();
        let e = a.parse(text).unwrap();
        magnitude_bound(&a, e, |_| [0.2, 1.0])
    }

    #[test]
    fn bounds_over_the_sampling_box() {
        assert_eq!(bound("L1 + L2"), 2.0);
        assert_eq!(bound("1e5*L"), 1e5);
        assert!((bound("L1 - 3*L2") - 2.8).abs() < 1e-12);
        assert!((bound("L^(-3)") - 125.0).abs() < 1e-9);
        assert!((bound("(L1 - L2)^2") - 0.64).abs() < 1e-12);
        assert_eq!(bound("1/(L1 - L2)"), f64::INFINITY);
        assert_eq!(bound("-0.425"), 0.425);
        assert!((bound("pi/2 - A") - (std::f64::consts::FRAC_PI_2 - 0.2)).abs() < 1e-12);
    }
}
