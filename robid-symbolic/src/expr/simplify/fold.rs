//! Constant folding: numeric operands of a sum or product become one number.

use crate::expr::{Arena, Id, Num};

/// Folds the numeric operands with `op` starting at `identity`; returns the
/// folded constant and the non-numeric operands in their order.
pub(crate) fn split_constants(
    arena: &Arena,
    operands: &[Id],
    identity: Num,
    op: fn(Num, Num) -> Num,
) -> (Num, Vec<Id>) {
    let mut constant = identity;
    let mut rest = Vec::with_capacity(operands.len());
    for &x in operands {
        match arena.as_num(x) {
            Some(c) => constant = op(constant, c),
            None => rest.push(x),
        }
    }
    (constant, rest)
}

/// The square root of a number when it is exact (a rational square), or a
/// float root otherwise; `None` for negative numbers.
pub(crate) fn exact_sqrt(c: Num) -> Option<Num> {
    match c {
        Num::Rational(n, d) if n >= 0 => {
            let root = |v: i128| {
                let r = (v as f64).sqrt().round() as i128;
                (r.checked_mul(r) == Some(v)).then_some(r)
            };
            match (root(n), root(d)) {
                (Some(a), Some(b)) => Num::ratio(a, b),
                _ => Some(Num::Float(c.to_f64().sqrt())),
            }
        }
        Num::Float(x) if x >= 0.0 => Some(Num::Float(x.sqrt())),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use crate::expr::Arena;

    #[test]
    fn sums_and_products_of_numbers_fold() {
        let mut a = Arena::new();
        let e = a.parse("2 + 3*4 - 1/2").unwrap();
        assert_eq!(a.display(e), "13.5");
        let x = a.parse("0*x + 1*y + 0").unwrap();
        assert_eq!(a.display(x), "y");
    }

    #[test]
    fn exact_roots() {
        let mut a = Arena::new();
        let e = a.parse("sqrt(9/4)").unwrap();
        assert_eq!(a.display(e), "1.5");
    }
}
